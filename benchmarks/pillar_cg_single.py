"""The pillar model's CG with and without single-precision far fields in its late iterations, solve by solve.

On the ``size`` study's sigma~ = 0.1 brush of ``benchmarks/large_brush.py``
(phi = 0.12, k~ = 1e-2, ``--per-side`` pillars a side), a scattered contact
set (a random ``--share`` of the lattice attached: boundary share 1, the
near-field preconditioner with recycled vectors, as in that brush's pull-off)
loses ``--leaving`` random pillars a solve, and every solve is warm-started
from the last, as the path does.  The same sequence of sets is solved twice
on one model, by two solvers, one with ``Switches.single_pillar_products``
and one without, solve by solve in alternation (so that a change of the
machine's load falls on both); printed: the median CPU seconds a solve of
each and their ratio, the iterations, the single products, the restarts
and the largest difference of the solutions (relative to the largest
amplitude).

    nice python benchmarks/pillar_cg_single.py --per-side 316 --solves 20

Measured (load about 3): at 316 x 316 (17974 attached at the start;
before the products' near blocks were limited to the attached pillars,
which both solvers share) 1.56 against 1.28 CPU-s a solve (1.22x), 380 and
381 iterations, 266 of 401 products single, no restart, the solutions equal
to 7e-11 of the largest amplitude; at 100 x 100 0.081 against 0.069
(1.17x), 234 iterations each, 160 of 259 products single, 1.2e-12.
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--per-side", type=int, default=100)
    parser.add_argument("--solves", type=int, default=30)
    parser.add_argument("--share", type=float, default=0.18, help="share of the lattice attached at the start")
    parser.add_argument("--leaving", type=int, default=3, help="pillars that leave before every solve")
    args = parser.parse_args()
    from threadpoolctl import ThreadpoolController

    with ThreadpoolController().limit(limits=1, user_api="blas"):  # as the pillar model's path runs
        _run(args)


def _run(args) -> None:
    """The two solvers' sequence (module docstring); prints one JSON line."""

    from large_brush import _size_problem

    from brushbem import pillars, settings
    from brushbem.pillars import cg as pillar_cg

    start = time.process_time()
    problem, _ = _size_problem(args.per_side, 0.01, 0.1, 0)
    model = pillars.PillarModel(problem)
    built = time.process_time() - start
    rng = np.random.default_rng(0)
    attached = rng.random(model.M) < args.share
    rhs = np.stack([model.force, model.force * model.g], axis=1)
    solvers = {single: pillar_cg.LatticeCG(model) for single in (False, True)}
    last = {single: None for single in solvers}
    seconds = {single: [] for single in solvers}
    worst = 0.0
    for _ in range(args.solves):
        for single, solver in solvers.items():
            with settings.using(single_pillar_products=single):
                tick = time.process_time()
                last[single], _ = solver.solve(attached, rhs, start=last[single])
                seconds[single].append(time.process_time() - tick)
        worst = max(worst, float(np.abs(last[True] - last[False]).max() / np.abs(last[False]).max()))
        attached[rng.choice(np.flatnonzero(attached), args.leaving, replace=False)] = False
    median = {single: statistics.median(values) for single, values in seconds.items()}
    print(json.dumps({"pillars": model.M, "attached_at_start": int(round(args.share * model.M)),
                      "solves": args.solves, "build_cpu_seconds": round(built, 1),
                      "cpu_seconds_a_solve_double": round(median[False], 3),
                      "cpu_seconds_a_solve_single": round(median[True], 3),
                      "ratio_double_over_single": round(median[False] / median[True], 3),
                      "iterations_double": solvers[False].iterations, "iterations_single": solvers[True].iterations,
                      "products_single": [solvers[True].single_products, solvers[True].products],
                      "restarts": solvers[True].restarts, "largest_difference": worst}))


if __name__ == "__main__":
    main()
