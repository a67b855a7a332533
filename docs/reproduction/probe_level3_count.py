"""Does the third level of chapter 6 raise F~_A, and on what does that depend?  (Fig. 6-5, L1197.)

On the shipped clustered parts (Fig. 6-3 layout, 40 x 40 sub-pillars, clusters of 5 x 5 and 4 x 4,
so N1 = 25, N2 = 16 and N3 = 4 level-3 clusters in a 2 x 2 square) two and three levels give the
same plateau to the last digit.  A series spring under displacement control does not change the
pull-off force of a structure it carries, and the 2 x 2 level-3 clusters are equal by symmetry:
their springs shift all four alike.  Level 3 can only share load between level-3 clusters that
are loaded unequally, i.e. when there are more of them (the thesis states N1, N2, N3 nowhere;
L1224 only names them).  This probe runs one and three levels on the clustered layout with
clusters of 5 x 5 and 2 x 2 (N1 = 25, N2 = 4, N3 = 16: a 4 x 4 square of level-3 clusters) at the
plateau point sigma~ = 0.04, F~_P = 14.3, with the shipped parts' seeds.

Every finished case is written at once, atomically, to ``probe_level3_count.csv`` beside this file (one
row a structure and seed: F~_A by the nominal F_c of eq. 6.23, CPU seconds); a rerun skips the cases
already there, so a stopped run resumes.  Run from the repository root:
``python docs/reproduction/probe_level3_count.py [SEEDS]`` (default 3; 60-90 CPU-s a case).
"""

from __future__ import annotations

import math
import statistics
import sys
import time
from pathlib import Path

import pandas as pd

import brushbem
from brushbem.io import atomic_path

F_C, D_C = 0.00331177, 0.00293498  # eq. 6.23 at phi = 0.0243, L = 1 (the shipped parts' headers)
OUTPUT = Path(__file__).with_suffix(".csv")

def _seeds(count: int) -> list[int]:
    """The case seeds of the shipped sweeps' realisations (brushbem.sweep: SeedSequence(5), one per realisation)."""
    from brushbem.sweep.spec import load_sweep
    from brushbem.studies.base import SWEEPS_DIR

    cases = load_sweep(SWEEPS_DIR / "hierarchy.clustered_three.sampled.toml").cases
    return [int(case.seed) for case in cases][:count]

def config(levels: list[dict], seed: int) -> dict:
    return {
        "halfspace": {"contact_modulus": 1.0, "work_of_adhesion": 1e-4},
        "grid": {"size": 1.0, "elements": 1024},
        "indenter": {"shape": "brush", "layout": "clustered", "region": "square", "pillars_per_side": 40,
                     "filling_factors": [0.12, 0.45, 0.45], "stiffness_ratio": 1e-3, "seed": seed,
                     "roughness": {"sigma": 0.04 * D_C}, "levels": levels},
        "protocol": {"method": "events", "preload_force": 14.3 * F_C},
    }

def main() -> None:
    count = int(sys.argv[1]) if len(sys.argv) > 1 else 3
    structures = {
        "one level (clusters 5, 2 rigid)": [{"cluster": 5, "stiffness": math.inf}, {"cluster": 2, "stiffness": math.inf}],
        "three levels (k~2 = 9e-3, k~3 = 2e-2)": [{"cluster": 5, "stiffness_ratio": 9e-3},
                                                  {"cluster": 2, "stiffness_ratio": 2e-2}],
    }
    rows = pd.read_csv(OUTPUT).to_dict("records") if OUTPUT.exists() else []
    print("| structure | N1, N2, N3 | seeds | F~_A (mean +- standard error) | CPU s a case |")
    print("| --- | --- | --- | --- | --- |")
    for name, levels in structures.items():
        for seed in _seeds(count):
            if any(r["structure"] == name and r["seed"] == seed for r in rows):
                continue
            start = time.process_time()
            result = brushbem.run(config(levels, seed))
            rows.append({"structure": name, "n1": 25, "n2": 4, "n3": 16, "seed": seed,
                         "adhesive_force_tilde": result.adhesive_force / F_C, "converged": bool(result.converged),
                         "cpu_s": time.process_time() - start})
            with atomic_path(OUTPUT) as path:
                pd.DataFrame(rows).to_csv(path, index=False)
        done = [r for r in rows if r["structure"] == name]
        forces, seconds = [r["adhesive_force_tilde"] for r in done], [r["cpu_s"] for r in done]
        error = statistics.stdev(forces) / math.sqrt(len(forces)) if len(forces) > 1 else 0.0
        print(f"| {name} | 25, 4, 16 | {len(forces)} | {statistics.mean(forces):.4f} +- {error:.4f} | "
              f"{statistics.median(seconds):.0f} |", flush=True)

if __name__ == "__main__":
    main()
