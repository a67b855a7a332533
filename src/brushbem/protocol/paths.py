"""The load paths: the public drivers (`pull_off`, `indent`), fixed steps and the event-driven path.

See `brushbem.protocol` for the methods.  The drivers are here (`_fixed`,
`_unload`, `_events`, the force search of the fixed loading); the location of
events inside a fixed step and the event path's step are in
`brushbem.protocol.events`, a brush's loading as contact problems in
`brushbem.protocol.contact_loading`, and the pillar-level model in
`brushbem.pillars`.  Each driver hands the path's state
(`brushbem.protocol.values.PathState`) from step to step
(`brushbem.protocol.steps`): a step takes one and gives the next.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Iterator

import numpy as np

from brushbem.errors import raise_first
from brushbem.physics.pillar_laws import law_path_problems
from brushbem.physics.viscoelastic import time_stepping_problems
from brushbem.protocol.contact_loading import (
    LOADING_SAMPLES,
    _contact_loading,
    _press_as_contact_problems,
)
from brushbem.protocol.events import _event_step, _events_in_step
from brushbem.protocol.path_states import _budget_exhausted, _eq_state, _separated, total_force
from brushbem.protocol.problem import ContactProblem, LoadPath, State, check_preload
from brushbem.protocol.steps import PathContext, commit_history, restored, solve_from, step_from

__all__ = ["LOADING_SAMPLES", "indent", "pull_off"]


def indent(problem: ContactProblem, displacement: float, tolerance: float = 1e-8,
           max_iterations: int = 20000) -> State:
    """Equilibrium at one base displacement, pressed from no contact in one step.

    The thesis's way of applying a preload ("pressed by a general
    displacement d"); without adhesion it is the unique solution of the
    contact problem (Polonsky-Keer).
    """
    path = LoadPath(method="fixed", preload_displacement=max(displacement, 1e-300), tolerance=tolerance,
                    max_iterations=max_iterations)
    context = PathContext(problem, path)
    state, eq = solve_from(context, context.state, displacement)
    return _eq_state(context, state, eq, True)


def pull_off(problem: ContactProblem, path: LoadPath, stop=None) -> Iterator[State]:
    """Yield the states of a press-and-pull-off (module docstring).

    The last state has ``kind == "separated"`` when the indenter came off, or
    ``converged == False`` with the reason when a solve failed or the step
    budget ran out.  ``stop`` (callable or None): the pillar model asks it in
    every round of its long steps and ends the path there when it returns
    True (the element paths end between states, where the caller asks it).
    """
    if path.method == "pillars":
        from brushbem.pillars import pull_off as pillar_pull_off

        yield from pillar_pull_off(problem, path, stop=stop)
        return
    indenter = problem.indenter
    preload = {"preload_displacement": path.preload_displacement, "preload_force": path.preload_force}
    raise_first(time_stepping_problems(indenter.viscoelastic is not None, method=path.method, speed=path.speed,
                                       **preload))
    raise_first(law_path_problems(indenter.pillar_law, method=path.method,
                                  viscoelastic=indenter.viscoelastic is not None, **preload))
    if indenter.viscoelastic is not None:
        path = _time_stepped(path)
    context = PathContext(problem, path)
    check_preload(problem.indenter, path)
    states = (_fixed if path.method == "fixed" else _events)(context, context.state, path)
    preload = None
    for state in states:
        if state.loading:
            preload = state
        elif preload is not None and preload.converged and preload.contact_area == 0:
            # Pressed to the preload without touching: no pull-off to follow.
            states.close()
            yield dataclasses.replace(preload, converged=False, n_solves=0, cg_iterations=0, reason=(
                f"no contact at the end of the loading branch (d = {preload.displacement:.6g}): the "
                f"penetration there is within the solver's tolerance (LoadPath.tolerance = {path.tolerance:g} "
                "of the path's length scale); raise the preload or lower LoadPath.tolerance"
            ))
            return
        yield state


def _time_stepped(path: LoadPath) -> LoadPath:
    """The path of viscoelastic pillars (`time_stepping_problems` holds): one step size to the preload.

    The step is shortened so that the preload is a whole number of steps: the
    time step, and with it the connections' step stiffness, is then the same
    along the whole path (`brushbem.physics.viscoelastic`).
    """
    steps = max(1, math.ceil(path.preload_displacement / path.step - 1e-9))
    return dataclasses.replace(path, step=path.preload_displacement / steps)


def _fixed(context: PathContext, state, path: LoadPath) -> Iterator[State]:
    step = path.step
    d = 0.0
    count = 0
    done = False
    if not state.connections.has_state and _press_as_contact_problems(context, state):
        # A brush is pressed as contact problems (`_contact_loading`): the
        # exact loading branch, which adhesive steps approach only slowly (an
        # element that joins overlapping may be held in tension where the
        # exact path never lets it touch).
        outcome = yield from _contact_loading(context, state, path)
        if outcome is None:
            return
        state, d, done = outcome
    # Loading (from where the contact problems stopped).
    if done:
        pass
    elif path.preload_displacement is not None:
        n_steps = max(1, math.ceil((path.preload_displacement - d) / step - 1e-9))
        start = d
        for k in range(1, min(n_steps, path.max_steps) + 1):
            d = min(start + k * step, path.preload_displacement)
            state, eq = step_from(context, state, d)
            yield _eq_state(context, state, eq, True)
            if not eq.converged:
                return
            state = commit_history(context, state)
        if n_steps > path.max_steps:
            yield _budget_exhausted(context, state, d, True, path)
            return
    else:
        target = path.preload_force
        previous = (d, total_force(context, state))
        while True:
            count += 1
            if count > path.max_steps:
                yield _budget_exhausted(context, state, d, True, path)
                return
            d += step
            saved = state.replace(displacement=previous[0])
            state, eq = solve_from(context, state, d)
            force = total_force(context, state)
            if not eq.converged:
                yield _eq_state(context, state, eq, True)
                return
            if force >= target:
                state, eq, d = _reach_force(context, state, saved, previous, (d, force, eq), target)
                yield _eq_state(context, state, eq, True)
                break
            yield _eq_state(context, state, eq, True)
            previous = (d, force)
    yield from _unload(context, state, path, d)


def _unload(context: PathContext, state, path: LoadPath, d_max: float) -> Iterator[State]:
    """Fixed steps down from ``d_max``, every event inside a step located (`_events_in_step`)."""
    step = path.step
    d = d_max
    for k in range(1, path.max_steps + 1):
        d = d_max - k * step
        before = state.replace(displacement=d + step)
        state, eq = step_from(context, state, d)
        state, eq = yield from _events_in_step(context, state, before, eq, d)
        if eq is None:  # separated at an event inside the step
            return
        if not eq.converged:
            yield _eq_state(context, state, eq, False)
            return
        state = commit_history(context, state)
        if not bool(context.xp.any(state.contact)):
            yield _separated(context, state, d, eq)
            return
        yield _eq_state(context, state, eq, False)
    yield _budget_exhausted(context, state, d, False, path)


def _reach_force(context: PathContext, state, saved, below, above, target: float):
    """The smallest displacement at which the loading force reaches ``target``.

    ``state`` is ``above``'s.  ``below = (d, F)`` with F < target and ``above = (d, F, eq)`` with F >=
    target bracket it; every trial solves from ``saved`` (a saved `PathState`), the contact state at
    ``below``, so the history of the contact set is kept.  False position,
    with a bisection whenever a step fails to halve the bracket, ends when the
    force at the upper end is within 1e-6 of the target, or when the bracket
    has shrunk to rounding: then the force jumps past the target there (an
    adhesive snap-in) and the state just past the jump is the preload.
    Returns (the state at the upper end, its equilibrium with the work of every solve here
    and of ``above``'s, its displacement).
    """
    lo, f_lo = below
    hi, f_hi, eq = above
    at_hi = state.replace(displacement=hi)
    bisect = False
    solves, iterations = eq.n_solves, eq.cg_iterations
    for _ in range(200):
        if f_hi - target <= 1e-6 * target or hi - lo <= 4 * np.finfo(float).eps * abs(hi):
            break
        width = hi - lo
        if bisect or f_hi == f_lo:
            trial = 0.5 * (lo + hi)
        else:
            trial = lo + (target - f_lo) * width / (f_hi - f_lo)
            trial = min(max(trial, lo + 1e-3 * width), hi - 1e-3 * width)
        state, trial_eq = solve_from(context, restored(state, saved), trial)
        solves += trial_eq.n_solves
        iterations += trial_eq.cg_iterations
        if not trial_eq.converged:
            return state, trial_eq, trial
        f = total_force(context, state)
        if f < target:
            lo, f_lo = trial, f
        else:
            hi, f_hi, eq = trial, f, trial_eq
            at_hi = state.replace(displacement=trial)
        bisect = hi - lo > 0.5 * width
    return restored(state, at_hi), dataclasses.replace(eq, n_solves=solves, cg_iterations=iterations), hi


def _events(context: PathContext, state, path: LoadPath) -> Iterator[State]:
    d = 0.0
    done = False
    if path.method == "events" and _press_as_contact_problems(context, state):
        # A brush's loading branch as contact problems (`_contact_loading`);
        # from where that cannot be shown to hold, element events.
        outcome = yield from _contact_loading(context, state, path)
        if outcome is None:
            return
        state, d, done = outcome
    # Loading: from first touch (or where the contact problems stopped) to the preload.
    for _ in range(path.max_steps):
        if done:
            break
        outcome = yield from _event_step(context, state, path, d, +1)
        if outcome is None:
            return
        state, d, done = outcome
    else:
        yield _budget_exhausted(context, state, d, True, path)
        return
    # Unloading: until the contact set is empty.
    for _ in range(path.max_steps):
        outcome = yield from _event_step(context, state, path, d, -1)
        if outcome is None:
            return
        state, d, done = outcome
        if done:
            return
    yield _budget_exhausted(context, state, d, False, path)
