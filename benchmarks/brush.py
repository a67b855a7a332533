"""Full pull-off of a regular brush of flat pillars on springs, against the pillar stiffness.

An n x n lattice filling the 1 x 1 domain (spacing 1/n), pillar radius chosen
for a filling factor phi (0.12 by default, the thesis's chapter 4), E* = 1,
work of adhesion 1e-4, pressed to d = 0.3 |d_c| beyond first contact and pulled
off to complete separation with the event-driven path.  For every
k~ = k / (E* L) it prints one JSON line: the wall time (median of --repeat
runs), the time relative to the rigid brush measured in the same run, solves,
CG iterations (total and per solve, also relative to the rigid brush),
F~ = F_A / F_K(compact punch of the same real area) (eq. 4.11) and the work of
separation.  ``--cascade global`` runs every detachment round as a global
solve (the thesis's loop) instead of the default local pillar rounds.

    python benchmarks/brush.py --elements 512 --pillars-per-side 16 \
        --stiffness-ratios inf 10 1 0.455 0.1 0.01 0.005 0.001 1e-4 1e-5
"""

from __future__ import annotations

import argparse
import json
import math
import statistics
import time

from brushbem.physics import theory
from brushbem.runs.case import brush_scales
from brushbem.protocol import ContactProblem, LoadPath, record_pull_off
from brushbem.physics.structure import Grid, brush


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--elements", type=int, default=512)
    parser.add_argument("--pillars-per-side", type=int, default=16)
    parser.add_argument("--filling-factor", type=float, default=0.12)
    parser.add_argument("--stiffness-ratios", type=float, nargs="+",
                        default=[math.inf, 10, 1, 0.1, 1e-2, 1e-3, 1e-4, 1e-5])
    parser.add_argument("--method", choices=["events", "fixed"], default="events")
    parser.add_argument("--step", type=float, default=None, help="fixed step; default |d_c| / 100")
    parser.add_argument("--cascade", choices=["local", "global"], default="local")
    parser.add_argument("--repeat", type=int, default=1)
    args = parser.parse_args()
    n = args.pillars_per_side
    grid = Grid(1.0, args.elements)
    radius = math.sqrt(args.filling_factor / math.pi) / n
    modulus, dgamma = 1.0, 1e-4
    baseline = None
    for ratio in args.stiffness_ratios:
        indenter = brush(grid, layout="square", pillars_per_side=n, pillar_radius=radius,
                         contact_modulus=modulus, work_of_adhesion=dgamma, stiffness=ratio * modulus * grid.size)
        problem = ContactProblem(grid, indenter, contact_modulus=modulus, work_of_adhesion=dgamma)
        scales = brush_scales(problem)
        d_c = scales["rigid_brush_displacement"]
        path = LoadPath(method=args.method, preload_displacement=0.3 * d_c,
                        step=args.step or d_c / 100, max_steps=1_000_000, cascade=args.cascade)
        times, record = [], None
        for _ in range(args.repeat):
            start = time.perf_counter()
            record = record_pull_off(problem, path)
            times.append(time.perf_counter() - start)
        s = record.summary
        seconds = statistics.median(times)
        per_solve = s["n_cg_iterations"] / max(s["n_solves"], 1)
        if baseline is None:
            baseline = (seconds, per_solve)
        print(json.dumps({
            "elements": args.elements,
            "pillars": indenter.n_pillars,
            "filling_factor": round(indenter.description["filling_factor"], 4),
            "stiffness_ratio": ratio,
            "method": args.method,
            "cascade": args.cascade,
            "seconds": round(seconds, 3),
            "seconds_vs_first": round(seconds / baseline[0], 3),
            "states": s["n_states"],
            "solves": s["n_solves"],
            "cg_iterations": s["n_cg_iterations"],
            "cg_per_solve": round(per_solve, 2),
            "cg_per_solve_vs_first": round(per_solve / baseline[1], 3),
            "converged": s["converged"],
            "force_by_compact_punch": s["adhesive_force"] / scales["compact_punch_force"],
            "work_of_separation": s["work_of_separation"],
            "rigid_estimate": float(theory.rigid_brush_enhancement(scales["filling_factor"])),
        }), flush=True)


if __name__ == "__main__":
    main()
