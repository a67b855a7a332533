"""The `State` records that the load paths make of a tracker's equilibrium, of a separation or of an exhausted step budget."""

from __future__ import annotations

from brushbem.numerics.solver import Equilibrium
from brushbem.protocol.problem import State


def _eq_state(tracker, eq: Equilibrium, loading: bool, kind="equilibrium") -> State:
    """The state of the tracker's equilibrium ``eq`` (its work, convergence and reason)."""
    trial = tracker.h2 * eq.trial_force_sum
    return tracker.state(eq.displacement, loading, kind, trial, eq.cg_iterations, eq.n_solves, eq.converged, eq.reason)


def _separated(tracker, d: float, eq: Equilibrium) -> State:
    """Complete separation at ``d``, reached by the converged equilibrium ``eq`` (no contact left)."""
    return tracker.state(d, False, "separated", tracker.h2 * eq.trial_force_sum, eq.cg_iterations, eq.n_solves,
                         True, "complete separation")


def _budget_exhausted(tracker, d, loading, path) -> State:
    """A state at ``d`` that ends the branch: ``path.max_steps`` reached (not converged)."""
    return tracker.state(d, loading, "equilibrium", tracker.force(), 0, 0, False,
                         f"LoadPath.max_steps = {path.max_steps} reached before the end of the branch")
