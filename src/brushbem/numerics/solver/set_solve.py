"""The solve on a fixed contact set: preconditioned CG on S, on the pillar blocks where they apply.

`solve_on_set` runs the CG either on the |S| values of S with the pillar-block
preconditioner (brushes of a few pillars, NumPy) or on the window's arrays with
the contact preconditioner.  On the pillar blocks it keeps the solution's tip
deflection in step with the iterations (`BlockDeflection`) and reuses the
system and preconditioner of the last solve on the same set and window
(`_set_solver`), both in the caller's `SolverCache`.  ``Switches.reuse_set_solver``, ``Switches.keep_solution_deflection`` and
``Switches.single_products`` (the late iterations' products in single precision) switch
these off (`brushbem.settings.using`, for tests and benchmarks).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from brushbem import backend, settings
from brushbem.numerics.operator import SINGLE_ERROR, ContactOperator, MaskedOperator
from brushbem.numerics.solver.block_deflection import BlockDeflection
from brushbem.numerics.solver.cache import SolverCache
from brushbem.numerics.solver.cg import ProductLedger, SolveResult, _norm, conjugate_gradient
from brushbem.numerics.solver.preconditioners import MAX_BLOCK_PILLARS, contact_preconditioner, pillar_block_preconditioner

__all__ = ["solve_on_set"]


def solve_on_set(operator: ContactOperator, mask, rhs, initial=None, initial_product=None,
                 tolerance: float = 1e-8, max_iterations: int = 10000, preconditioner=None,
                 ledger: ProductLedger | None = None, cache: SolverCache | None = None) -> SolveResult:
    """Solve A_S p = rhs on the set ``mask`` of the operator's window by preconditioned CG.

    On a brush of 2 to ``MAX_BLOCK_PILLARS`` pillars whose contacts have at
    most ``BLOCK_LIMIT`` elements each, the CG runs on the |S| values of S
    (`ContactSystem`) with `pillar_block_preconditioner`; otherwise on the
    window's arrays with ``preconditioner`` (M^-1 on window arrays) or, by
    default, `contact_preconditioner`.  A single body (a punch, a sphere)
    always takes the window path: its contact changes shape at every event,
    and a fresh block inverse per event costs more than the extra iterations.
    So does every array namespace other than NumPy (a GPU): the pillar blocks
    are dense host matrices, and the window path keeps every iteration on
    the device.
    ``rhs``, ``initial`` and ``initial_product`` (A applied to ``initial``,
    if known) are window-shaped; so is the solution.  On the pillar blocks,
    the solution's tip deflection on the whole window is kept in step with
    the iterations (`BlockDeflection`) and kept in ``cache`` (the caller's
    `SolverCache`; None: a fresh one), whose ``tip_deflection`` of the
    solution returns it without a transform; ``initial_product`` must
    then be `ContactOperator.tip_deflection` of ``initial`` restricted to S
    on the whole window, not only its values on S (as both callers, the
    equilibrium and the event path's unit response, have it).  With a
    ``ledger`` (the chain of kept deflections this solve continues), the
    late iterations there take their products in single precision
    (``Switches.single_products``, `ProductLedger`); a solve that leaves the chain's
    error due for a refresh does not keep its deflection.
    """
    xp = operator.xp
    cache = SolverCache() if cache is None else cache
    if (preconditioner is None and 2 <= operator.indenter.n_pillars <= MAX_BLOCK_PILLARS
            and backend.is_numpy_namespace(xp)):
        system, blocked = _set_solver(operator, mask, cache)
        if blocked is not None:
            rhs_on_set = system.gather(rhs)
            initial_on_set = None if initial is None else system.gather(initial)

            def reference(v):
                return _norm(xp, rhs_on_set - system.spring_deflection(v))

            keeps = settings.switches().keep_solution_deflection and system.gives_block_deflection
            single = settings.switches().single_products and ledger is not None and keeps
            if single and initial_product is not None and initial_on_set is not None and ledger.carried:
                scale = tolerance * min(_norm(xp, rhs_on_set), reference(initial_on_set))
                if not ledger.admits(scale):
                    # The start's kept deflection carries more error than this solve tolerates (its
                    # residual is far below the chain's earlier ones): the CG's first product replaces it.
                    initial_product = None
                    ledger.carried = 0.0
            tracked = BlockDeflection(system, initial_on_set, initial_product) if keeps else None
            result = conjugate_gradient(
                system if tracked is None else tracked,
                rhs_on_set,
                initial=initial_on_set,
                tolerance=tolerance,
                max_iterations=max_iterations,
                preconditioner=blocked,
                initial_product=None if initial_product is None else system.gather(initial_product),
                reference=reference,
                on_step=None if tracked is None else tracked.moved,
                inexact=SINGLE_ERROR if single else None,
                ledger=ledger,
            )
            solution = system.scatter(result.solution)
            kept = None if tracked is None or not result.converged else tracked.tip_deflection(result.solution)
            if single and ledger.due():
                # The chain's deflection is transformed afresh by the caller (`ProductLedger`).
                kept = None
                ledger.carried = 0.0
            if kept is not None:
                cache.remember_solution(operator, xp.asarray(solution, copy=True), kept)
            return dataclasses.replace(result, solution=solution)
    restricted = MaskedOperator(operator, mask)
    return conjugate_gradient(
        restricted,
        rhs,
        initial=initial,
        tolerance=tolerance,
        max_iterations=max_iterations,
        preconditioner=contact_preconditioner(operator, mask) if preconditioner is None else preconditioner,
        initial_product=initial_product,
        reference=(lambda x: _norm(xp, (rhs - operator.spring_deflection(x)) * restricted.weights))
        if operator.has_springs else None,
    )



def _set_solver(operator: ContactOperator, mask, cache: SolverCache):
    """The `ContactSystem` of ``mask`` and its `pillar_block_preconditioner` (None where it does not apply).

    A unit response follows the equilibrium on the same contact set: when
    ``mask`` is the set of the last call on the operator's window (``cache``) and no other pillar-block
    preconditioner was built on the indenter since (its coarse matrix is
    still the cached one), the pair is the one a rebuild would make.
    """
    mask_host = np.asarray(backend.to_numpy(mask), dtype=bool)
    last = cache.set_solvers.get(operator.window)
    if (settings.switches().reuse_set_solver and last is not None and last[3] is cache.pillars.coarse
            and last[0].shape == mask_host.shape and np.array_equal(last[0], mask_host)):
        return last[1], last[2]
    system = operator.system(mask)
    blocked = pillar_block_preconditioner(system, cache=cache)
    cache.set_solvers[operator.window] = (mask_host.copy(), system, blocked, cache.pillars.coarse)
    return system, blocked
