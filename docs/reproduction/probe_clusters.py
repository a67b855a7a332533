"""Chapter 6: how much the three-level plateau depends on the cluster sizes the thesis leaves open.

The thesis states phi1 phi2 phi3, k~1, k~2, k~3 and k~1' = 0.4e-4 (eq. 6.28),
which pins only N1 N2 ~ 400 (pillars per level-2 cluster times level-2
clusters per level-3 cluster); the shipped sweeps cluster the 40 x 40 lattice
5 x 5 (N1 = 25) then 4 x 4 (N2 = 16).  This runs the sampled plateau case
(sigma~ = 0.04, F~_P = 20, the first R seeds) of the three-level sweep with
the other clusterings of 40 x 40 that give N1 N2 = 400, and prints F~_A
(by the rasterised F_c) beside eq. 6.28's k~1'.

    python docs/reproduction/probe_clusters.py [R]
"""

from __future__ import annotations

import sys
import time

import brushbem
from brushbem.studies import SWEEPS_DIR
from brushbem.sweep import load_sweep

#: (pillars per side of a level-2 cluster, level-2 clusters per side of a level-3 cluster)
CLUSTERINGS = ((5, 4), (4, 5), (2, 10), (10, 2))


def run_clustered(case, first: int, second: int) -> tuple[brushbem.PullOff, float]:
    """Run a three-level sweep case with clusters ``first`` x ``first`` (level 2), then ``second`` x
    ``second`` (level 3); returns the result and its wall time in seconds."""
    config = case.config.model_dump(mode="json", exclude_unset=True)
    levels = config["indenter"]["levels"]
    levels[0]["cluster"], levels[1]["cluster"] = first, second
    start = time.perf_counter()
    result = brushbem.run(config)
    return result, time.perf_counter() - start


def main(realizations: int) -> None:
    sweep = load_sweep(SWEEPS_DIR / "hierarchy.three.sampled.toml")
    cases = [case for case in sweep.cases if case.realization < realizations
             and abs(case.values["protocol.preload_force"] - 0.0662355) < 1e-9]
    for first, second in CLUSTERINGS:
        for case in cases:
            result, seconds = run_clustered(case, first, second)
            normalized = result.summary.get("normalized") or {}
            print(f"clusters {first} x {first}, then {second} x {second} (N1 N2 = {(first * second) ** 2}); "
                  f"seed {case.seed}: F~_A = {normalized.get('force_by_rigid_brush'):.4f}, k~1' (eq. 6.28) = "
                  f"{normalized.get('equivalent_single_level_stiffness_ratio'):.3g}, converged {result.converged}, "
                  f"{seconds:.0f} s", flush=True)


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 1)
