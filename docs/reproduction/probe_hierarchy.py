"""One case of each hierarchy sweep at the thesis's grid: the chapter-6 plateau (sigma~ = 0.04, F~_P = 20, seed 0).

The thesis's main chapter-6 numbers are the plateaus of one, two and three
levels at sigma~ = 0.04 (1.6, 1.65, 1.9; Fig. 6-4).  The full sweeps
(``hierarchy.{one,two,three}.toml``, N = 1024, 40 x 40 pillars, 810 cases
each) are hundreds of CPU-hours; this runs the case of each that carries the
plateau, for the first R realisations (the sweep's own seeds and case ids),
and prints F~_A = F_A / F_c with its wall time, then the mean and standard
error per part.

    python docs/reproduction/probe_hierarchy.py R one two three
"""

from __future__ import annotations

import statistics
import sys
import time

import brushbem
from brushbem.studies import SWEEPS_DIR
from brushbem.sweep import load_sweep

SIGMA, PRELOAD = 0.000117399, 0.0662355  # sigma~ = 0.04, F~_P = 20 (the sweeps' header: F_c, d_c)
F_C = 0.00331177


def main(realizations: int, parts: list[str]) -> None:
    for part in parts:
        sweep = load_sweep(SWEEPS_DIR / f"hierarchy.{part}.toml")
        values = []
        for case in sweep.cases:
            if not (case.realization < realizations and abs(case.values["indenter.roughness.sigma"] - SIGMA) < 1e-12
                    and abs(case.values["protocol.preload_force"] - PRELOAD) < 1e-9):
                continue
            start = time.perf_counter()
            result = brushbem.run(case.config)
            normalized = result.summary.get("normalized") or {}
            values.append(float(normalized.get("force_by_rigid_brush", float("nan"))))
            print(f"{part}: case {case.case_id}, F_A / F_c (nominal) = {result.adhesive_force / F_C:.4f}, "
                  f"F~_A (rasterised F_c) = {values[-1]:.4f}, converged {result.converged}, "
                  f"{time.perf_counter() - start:.0f} s", flush=True)
        error = statistics.stdev(values) / len(values) ** 0.5 if len(values) > 1 else float("nan")
        print(f"{part}: mean F~_A = {statistics.fmean(values):.4f} +- {error:.4f} over {len(values)} realisations",
              flush=True)


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 1, sys.argv[2:] or ["one", "two", "three"])
