"""The `State` records that the load paths make of a tracker's state (`record_state`, `total_force`).

Of its equilibrium, of a separation or of an exhausted step budget.  Every
pressure and contact set of a path lies in the tracker's working window (it
always holds the contact): the sums are taken there.
"""

from __future__ import annotations

from brushbem.numerics.solver import Equilibrium
from brushbem.protocol.problem import State


def _on_window(tracker, array):
    """``array`` (full grid) restricted to the tracker's window (the whole of it before the first solve)."""
    window = tracker.state.working.window
    return array if window is None else array[window.slices]


def total_force(tracker, pressure=None) -> float:
    """The total force of the tracker's pressure, or of ``pressure`` (full grid; compressive positive)."""
    p = tracker.state.pressure if pressure is None else pressure
    return tracker.h2 * float(tracker.xp.sum(_on_window(tracker, p)))


def attached_pillars(tracker, contact=None) -> int:
    """How many pillars touch in the tracker's contact set, or in ``contact`` (full grid)."""
    c = tracker.state.contact if contact is None else contact
    if tracker.n_pillars == 1:
        return int(bool(tracker.xp.any(_on_window(tracker, c))))
    labels = tracker.pillar[c]
    if labels.shape[0] == 0:
        return 0
    return int(tracker.xp.unique_values(labels).shape[0])


def record_state(tracker, displacement, loading, kind, trial_force, iterations, solves, converged, reason,
                 pressure=None, contact=None) -> State:
    """The `State` at ``displacement`` of the given pressure and contact (default: the tracker's).

    Why these parameters: one per field of `State` that the caller knows (the rest are computed here).
    Raises the tracker's ``length_scale`` (the largest |d| reached) to ``displacement``.
    """
    p = tracker.state.pressure if pressure is None else pressure
    c = tracker.state.contact if contact is None else contact
    tracker.length_scale = max(tracker.length_scale, abs(float(displacement)))
    return State(
        displacement=float(displacement),
        force=total_force(tracker, p),
        contact_area=tracker.h2 * int(tracker.xp.count_nonzero(_on_window(tracker, c))),
        attached_pillars=attached_pillars(tracker, c),
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


def _eq_state(tracker, eq: Equilibrium, loading: bool, kind="equilibrium") -> State:
    """The state of the tracker's equilibrium ``eq`` (its work, convergence and reason)."""
    trial = tracker.h2 * eq.trial_force_sum
    return record_state(tracker, eq.displacement, loading, kind, trial, eq.cg_iterations, eq.n_solves, eq.converged,
                        eq.reason)


def _separated(tracker, d: float, eq: Equilibrium) -> State:
    """Complete separation at ``d``, reached by the converged equilibrium ``eq`` (no contact left)."""
    return record_state(tracker, d, False, "separated", tracker.h2 * eq.trial_force_sum, eq.cg_iterations,
                        eq.n_solves, True, "complete separation")


def _budget_exhausted(tracker, d, loading, path) -> State:
    """A state at ``d`` that ends the branch: ``path.max_steps`` reached (not converged)."""
    return record_state(tracker, d, loading, "equilibrium", total_force(tracker), 0, 0, False,
                        f"LoadPath.max_steps = {path.max_steps} reached before the end of the branch")
