"""Graded and viscoelastic brushes against the elastic brush at the same grid (time per pull-off).

A 16 x 16 square brush of phi = 0.12 at N = 512 (default), E* = 1, dgamma =
1e-4, k~ = 0.01:

* ``graded``: a radial gradient k_n = k (1 + a (r_n / R)^2), a = -0.5, pressed
  to 2 N F_K and pulled off by the event path, against the uniform brush;
* ``viscoelastic``: standard-linear-solid connections (k_0 = 10 k_inf, tau =
  1) pulled at three speeds v tau / |d_c| = 0.01, 1, 100 by fixed steps of
  |d_c| / 40 to d = 0.5 |d_c|, against the elastic brush on the same fixed
  steps.

One JSON line per case: the median wall time of --repeat runs, its ratio to
the baseline measured in the same run, solves, F~ = F_A / (N F_K) and the
work of separation.

    python benchmarks/beyond.py --elements 512 --pillars-per-side 16 --repeat 3
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import statistics
import time

from brushbem.runs.case import brush_scales
from brushbem.protocol import ContactProblem, LoadPath, record_pull_off
from brushbem.physics.structure import Grading, Grid, brush
from brushbem.physics.viscoelastic import Viscoelastic


def _timed(problem, path, repeat):
    times, record = [], None
    for _ in range(repeat):
        start = time.perf_counter()
        record = record_pull_off(problem, path)
        times.append(time.perf_counter() - start)
    return statistics.median(times), record.summary


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--elements", type=int, default=512)
    parser.add_argument("--pillars-per-side", type=int, default=16)
    parser.add_argument("--repeat", type=int, default=1)
    args = parser.parse_args()
    n = args.pillars_per_side
    grid = Grid(1.0, args.elements)
    radius = math.sqrt(0.12 / math.pi) / n
    dgamma, k = 1e-4, 0.01

    def make(**extra):
        indenter = brush(grid, layout="square", pillars_per_side=n, pillar_radius=radius, contact_modulus=1.0,
                         work_of_adhesion=dgamma, stiffness=k, **extra)
        return ContactProblem(grid, indenter, contact_modulus=1.0, work_of_adhesion=dgamma)

    uniform = make()
    scales = brush_scales(uniform)
    ideal, d_c = scales["ideal_sharing_force"], scales["rigid_brush_displacement"]

    def line(case, seconds, baseline, summary, **extra):
        print(json.dumps({
            "case": case, "elements": args.elements, "pillars": n * n, **extra,
            "seconds": round(seconds, 3), "seconds_vs_baseline": round(seconds / baseline, 3),
            "solves": summary["n_solves"], "converged": summary["converged"],
            "force_by_ideal_sharing": summary["adhesive_force"] / ideal,
            "work_of_separation": summary["work_of_separation"],
        }), flush=True)

    events = LoadPath(method="events", preload_force=2 * ideal, max_steps=10**6)
    base, summary = _timed(uniform, events, args.repeat)
    line("uniform (events)", base, base, summary)
    graded, summary = _timed(make(grading=Grading("radial", -0.5, 2.0)), events, args.repeat)
    line("graded a = -0.5 (events)", graded, base, summary)

    fixed = LoadPath(method="fixed", preload_displacement=0.5 * d_c, step=d_c / 40, max_steps=10**6)
    base, summary = _timed(uniform, fixed, args.repeat)
    line("elastic (fixed steps)", base, base, summary)
    rheology = Viscoelastic("standard_linear_solid", 1.0, 10.0)
    problem = dataclasses.replace(uniform, indenter=dataclasses.replace(uniform.indenter, viscoelastic=rheology))
    for speed in (0.01, 1.0, 100.0):
        seconds, summary = _timed(problem, dataclasses.replace(fixed, speed=speed * d_c), args.repeat)
        line("viscoelastic (fixed steps)", seconds, base, summary, speed_by_dc_over_tau=speed)


if __name__ == "__main__":
    main()
