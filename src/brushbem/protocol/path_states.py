"""The `State` records that the load paths make of the path's state (`record_state`, `total_force`).

Of its equilibrium, of a separation or of an exhausted step budget.  Every
pressure and contact set of a path lies in the working window of its state
(it always holds the contact): the sums are taken there.  ``context`` is the
path's `brushbem.protocol.steps.PathContext` (the element area, the pillar of
every element; a record raises its length scale), ``state`` its
`brushbem.protocol.values.PathState`.
"""

from __future__ import annotations

from brushbem.numerics.solver import Equilibrium
from brushbem.protocol.problem import State


def _on_window(state, array):
    """``array`` (full grid) restricted to the state's window (the whole of it before the first solve)."""
    window = state.working.window
    return array if window is None else array[window.slices]


def total_force(context, state, pressure=None) -> float:
    """The total force of the state's pressure, or of ``pressure`` (full grid; compressive positive)."""
    p = state.pressure if pressure is None else pressure
    return context.h2 * float(context.xp.sum(_on_window(state, p)))


def attached_pillars(context, state, contact=None) -> int:
    """How many pillars touch in the state's contact set, or in ``contact`` (full grid)."""
    c = state.contact if contact is None else contact
    if context.n_pillars == 1:
        return int(bool(context.xp.any(_on_window(state, c))))
    labels = context.pillar[c]
    if labels.shape[0] == 0:
        return 0
    return int(context.xp.unique_values(labels).shape[0])


def record_state(context, state, displacement, loading, kind, trial_force, iterations, solves, converged, reason,
                 pressure=None, contact=None) -> State:
    """The `State` at ``displacement`` of the given pressure and contact (default: the state's).

    Why these parameters: one per field of `State` that the caller knows (the rest are computed here).
    Raises the context's ``length_scale`` (the largest |d| reached) to ``displacement``.
    """
    p = state.pressure if pressure is None else pressure
    c = state.contact if contact is None else contact
    context.length_scale = max(context.length_scale, abs(float(displacement)))
    return State(
        displacement=float(displacement),
        force=total_force(context, state, p),
        contact_area=context.h2 * int(context.xp.count_nonzero(_on_window(state, c))),
        attached_pillars=attached_pillars(context, state, c),
        loading=loading,
        kind=kind,
        trial_force=float(trial_force),
        cg_iterations=int(iterations),
        n_solves=int(solves),
        converged=bool(converged),
        reason=reason,
        pressure=p,
        contact=c,
    )


def _eq_state(context, state, eq: Equilibrium, loading: bool, kind="equilibrium") -> State:
    """The record of ``state``, the state of the equilibrium ``eq`` (its work, convergence and reason)."""
    trial = context.h2 * eq.trial_force_sum
    return record_state(context, state, eq.displacement, loading, kind, trial, eq.cg_iterations, eq.n_solves, eq.converged,
                        eq.reason)


def _separated(context, state, d: float, eq: Equilibrium) -> State:
    """Complete separation at ``d``, reached by the converged equilibrium ``eq`` (no contact left)."""
    return record_state(context, state, d, False, "separated", context.h2 * eq.trial_force_sum, eq.cg_iterations,
                        eq.n_solves, True, "complete separation")


def _budget_exhausted(context, state, d, loading, path) -> State:
    """A record at ``d`` that ends the branch: ``path.max_steps`` reached (not converged)."""
    return record_state(context, state, d, loading, "equilibrium", total_force(context, state), 0, 0, False,
                        f"LoadPath.max_steps = {path.max_steps} reached before the end of the branch")
