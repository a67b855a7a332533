"""CG iterations of one solve A_S p = d - g with no, the Laplacian, the spring and the pillar-block preconditioner.

A flat punch (contact 20-160 elements wide) and a rough 16 x 16 brush (phi =
0.12) whose contact set is 80 % of its footprint, for pillar stiffnesses
k~ = k / (E* L) from rigid to 1e-5; relative tolerance 1e-8, cold start.
Prints one JSON line per case with the iterations of each preconditioner and
their ratio to the unpreconditioned count measured in the same run.  The
pillar-block preconditioner (exact blocks + coarse pillar coupling) runs on the
contact set's values (``ContactSystem``); it does not apply to the punches
wider than its block limit.

    python benchmarks/preconditioner.py --elements 256
"""

from __future__ import annotations

import argparse
import json
import math

import numpy as np

from brushbem.physics.halfspace import HalfSpace
from brushbem.numerics.operator import ContactOperator, MaskedOperator, Window
from brushbem.numerics.solver import (
    conjugate_gradient,
    laplacian_preconditioner,
    pillar_block_preconditioner,
    spring_preconditioner,
)
from brushbem.physics.structure import Grid, brush, flat_punch


def iterations(operator, mask, rhs, preconditioner) -> int:
    result = conjugate_gradient(MaskedOperator(operator, mask), rhs, initial=np.zeros(mask.shape),
                                tolerance=1e-8, max_iterations=20000, preconditioner=preconditioner)
    if not result.converged:
        raise RuntimeError(result.reason)
    return result.iterations


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--elements", type=int, default=256)
    args = parser.parse_args()
    n = args.elements
    grid = Grid(1.0, n)
    halfspace = HalfSpace(n, grid.element_size, 1.0)
    window = Window.full(n)
    cases = [(f"punch a/h = {w}", flat_punch(grid, w * grid.element_size)) for w in (10, 40, 80)]
    radius = math.sqrt(0.12 / math.pi) / 16
    for ratio in (math.inf, 1.0, 1e-2, 1e-3, 1e-5):
        cases.append((f"brush 16x16 k~ = {ratio:g}",
                      brush(grid, layout="square", pillars_per_side=16, pillar_radius=radius, contact_modulus=1.0,
                            work_of_adhesion=1e-4, stiffness=ratio, roughness=1e-3, seed=1)))
    rng = np.random.default_rng(0)
    keep = rng.random((n, n)) < 0.8
    for name, indenter in cases:
        operator = ContactOperator(halfspace, indenter, window)
        mask = indenter.footprint & (keep if indenter.n_pillars > 1 else True)
        rhs = np.where(mask, 1e-3 - np.where(mask, indenter.height, 0.0), 0.0)
        plain = iterations(operator, mask, rhs, None)
        laplacian = iterations(operator, mask, rhs, laplacian_preconditioner(mask))
        row = {"case": name, "none": plain, "laplacian": laplacian, "laplacian_vs_none": round(laplacian / plain, 3)}
        if operator.has_springs:
            spring = iterations(operator, mask, rhs, spring_preconditioner(operator, mask))
            row.update(spring=spring, spring_vs_none=round(spring / plain, 3))
        system = operator.system(mask)
        blocked = pillar_block_preconditioner(system)
        if blocked is not None:
            result = conjugate_gradient(system, system.gather(rhs),
                                        tolerance=1e-8, max_iterations=20000, preconditioner=blocked)
            if not result.converged:
                raise RuntimeError(result.reason)
            row.update(pillar_blocks=result.iterations, pillar_blocks_vs_none=round(result.iterations / plain, 3))
        print(json.dumps(row), flush=True)


if __name__ == "__main__":
    main()
