"""One case of each hierarchy sweep at the thesis's grid: the chapter-6 plateau (sigma~ = 0.04, F~_P = 20, seed 0).

The thesis's main chapter-6 numbers are the plateaus of one, two and three
levels at sigma~ = 0.04 (1.6, 1.65, 1.9; Fig. 6-4).  The full sweeps
(``hierarchy.{one,two,three}.toml``, N = 1024, 40 x 40 pillars, 810 cases
each) are hundreds of CPU-hours; this runs the one case of each that carries
the plateau, realisation 0 (the sweep's own seed and case id), and prints
F~_A = F_A / F_c with its wall time.

    python docs/reproduction/probe_hierarchy.py three one two
"""

from __future__ import annotations

import sys
import time

import brushbem
from brushbem.studies import SWEEPS_DIR
from brushbem.sweep import load_sweep

SIGMA, PRELOAD = 0.000117399, 0.0662355  # sigma~ = 0.04, F~_P = 20 (the sweeps' header: F_c, d_c)
F_C = 0.00331177


def main(parts: list[str]) -> None:
    for part in parts:
        sweep = load_sweep(SWEEPS_DIR / f"hierarchy.{part}.toml")
        case = next(c for c in sweep.cases if c.realization == 0
                    and abs(c.values["indenter.roughness.sigma"] - SIGMA) < 1e-12
                    and abs(c.values["protocol.preload_force"] - PRELOAD) < 1e-9)
        start = time.perf_counter()
        result = brushbem.run(case.config)
        normalized = result.summary.get("normalized") or {}
        print(f"{part}: case {case.case_id}, F_A / F_c (nominal) = {result.adhesive_force / F_C:.4f}, "
              f"F~_A (rasterised F_c) = {normalized.get('force_by_rigid_brush', float('nan')):.4f}, "
              f"converged {result.converged}, {time.perf_counter() - start:.0f} s", flush=True)


if __name__ == "__main__":
    main(sys.argv[1:] or ["one", "two", "three"])
