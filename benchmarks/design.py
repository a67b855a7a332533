"""Time to design and verify a brush for equal load sharing (``brushbem design``), against one pull-off.

Circular region, phi = 0.06 (thesis ch. 7), k~ = 6e-4, E* = 1, dgamma = 1e-4,
pressed to 2 N F_K.  For every --pillars-per-side it prints one JSON line:
the wall time of the design (direct solve and --iterations verifying
pull-offs), its ratio to one ordinary pull-off of the flat brush measured in
the same run, the predicted and verified F~ = F_A / (N F_K) and the flat
brush's F~, and the spread of the pillars' detachment displacements over |d_c|.

    python benchmarks/design.py --elements 512 --pillars-per-side 16 32 [--bound]
"""

from __future__ import annotations

import argparse
import json
import math
import time

from brushbem.runs.case import brush_scales
from brushbem.design import design
from brushbem.protocol import ContactProblem, LoadPath, record_pull_off
from brushbem.physics.structure import Grid, brush


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--elements", type=int, default=512)
    parser.add_argument("--pillars-per-side", type=int, nargs="+", default=[16, 32])
    parser.add_argument("--filling-factor", type=float, default=0.06)
    parser.add_argument("--stiffness-ratio", type=float, default=6e-4)
    parser.add_argument("--iterations", type=int, default=2)
    parser.add_argument("--bound", action="store_true",
                        help="also the load-sharing bound (brushbem.design.sharing_bound; one solve per pillar)")
    args = parser.parse_args()
    grid = Grid(1.0, args.elements)
    for n in args.pillars_per_side:
        radius = math.sqrt(args.filling_factor / math.pi) / n
        indenter = brush(grid, layout="square", region="circle", pillars_per_side=n, pillar_radius=radius,
                         contact_modulus=1.0, work_of_adhesion=1e-4, stiffness=args.stiffness_ratio)
        problem = ContactProblem(grid, indenter, contact_modulus=1.0, work_of_adhesion=1e-4)
        ideal = brush_scales(problem)["ideal_sharing_force"]
        path = LoadPath(method="events", preload_force=2 * ideal, max_steps=10**6)
        start = time.perf_counter()
        flat = record_pull_off(problem, path).summary
        baseline = time.perf_counter() - start
        start = time.perf_counter()
        result = design(problem, path, iterations=args.iterations, bound=args.bound)
        seconds = time.perf_counter() - start
        print(json.dumps({
            "elements": args.elements, "pillars": indenter.n_pillars, "filling_factor": args.filling_factor,
            "stiffness_ratio": args.stiffness_ratio, "design_seconds": round(seconds, 2),
            "design_vs_one_pull_off": round(seconds / baseline, 2), "pull_off_seconds": round(baseline, 2),
            "predicted_force_ratio": result.predicted_force_ratio, "verified_force_ratio": result.verified_force_ratio,
            "flat_force_ratio": flat["adhesive_force"] / ideal, "verification_pull_offs": len(result.history),
            "detachment_spread_by_dc": result.spread, "bound_force_ratio": result.bound_force_ratio,
            "converged": result.converged,
        }), flush=True)


if __name__ == "__main__":
    main()
