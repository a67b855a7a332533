"""The `State` records that the load paths make of a tracker's equilibrium or of an exhausted step budget."""

from __future__ import annotations

from ..solver import Equilibrium
from .problem import State


def _eq_state(tracker, eq: Equilibrium, loading: bool, kind="equilibrium") -> State:
    trial = tracker.h2 * eq.trial_force_sum
    return tracker.state(eq.displacement, loading, kind, trial, eq.cg_iterations, eq.n_solves, eq.converged, eq.reason)


def _budget_exhausted(tracker, d, loading, path) -> State:
    return tracker.state(d, loading, "equilibrium", tracker.force(), 0, 0, False,
                         f"LoadPath.max_steps = {path.max_steps} reached before the end of the branch")
