"""Solvers: conjugate gradients on a contact set, and the adhesive equilibrium.

``conjugate_gradient`` solves A_S p = rhs on a fixed contact set S (A symmetric
positive definite on S), warm-started, and returns a frozen ``SolveResult``.

``equilibrium`` finds the state at a fixed base displacement d with the
Pohrt-Popov detachment criterion (thesis sec. 2.2.2, 3.4): solve on S; detach
every element whose tension exceeds the critical stress
Sigma_c = sqrt(E* dgamma / (0.473201 h)) (eq. 2.14); attach every footprint
element that the tip penetrates; repeat until S is stable.  Detachment rule:
all violators of one solve leave together (the thesis's rule, "exclude those
elements ... whose tensile stress are larger than Sigma_c"); the rule changes
the post-peak tail of very soft brushes, not the peak.

Without adhesion (dgamma = 0) the problem is a convex linear complementarity
problem with a unique solution; ``polonsky_keer`` solves it in one constrained
CG loop (Polonsky & Keer 1999), which is much cheaper than the active-set
loop.

Modules: `cache` (`SolverCache`: what the solves on one indenter reuse, owned by
the caller and passed in), `cg` (conjugate gradients, `SolveResult`), `preconditioners`
(shifted Laplacian, springs, pillar blocks) and `equilibria` (the solve on a
contact set, the local cascade, `equilibrium`, `polonsky_keer`).
"""

from __future__ import annotations

from brushbem.numerics.solver.cache import PillarCache, SolverCache
from brushbem.numerics.solver.cg import (
    ROUNDING_FLOOR,
    WARM_START_WITHIN_TOLERANCE,
    CallableOperator,
    ProductLedger,
    SetOperator,
    SolveResult,
    conjugate_gradient,
)
from brushbem.numerics.solver.equilibria import (
    Equilibrium,
    Settings,
    Start,
    equilibrium,
    local_cascade,
    penetration,
    polonsky_keer,
    solve_on_set,
    tip_deflection,
)
from brushbem.numerics.solver.preconditioners import (
    BLOCK_LIMIT,
    MAX_BLOCK_PILLARS,
    PRECONDITIONER_SHIFT,
    contact_preconditioner,
    laplacian_preconditioner,
    pillar_block_preconditioner,
    spring_preconditioner,
)

__all__ = [
    "BLOCK_LIMIT",
    "MAX_BLOCK_PILLARS",
    "PRECONDITIONER_SHIFT",
    "ROUNDING_FLOOR",
    "WARM_START_WITHIN_TOLERANCE",
    "CallableOperator",
    "Equilibrium",
    "PillarCache",
    "ProductLedger",
    "SetOperator",
    "Settings",
    "SolveResult",
    "SolverCache",
    "Start",
    "conjugate_gradient",
    "contact_preconditioner",
    "equilibrium",
    "laplacian_preconditioner",
    "local_cascade",
    "penetration",
    "pillar_block_preconditioner",
    "polonsky_keer",
    "solve_on_set",
    "spring_preconditioner",
    "tip_deflection",
]
