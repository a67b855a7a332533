"""The load paths: fixed steps, and the event-driven path with a brush's loading as contact problems.

See `brushbem.protocol` for the methods.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np

from ..operator import ContactOperator, Window
from ..solver import Equilibrium, penetration
from .problem import ContactProblem, LoadPath, State
from .tracking import Tracker

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
    tracker = Tracker(problem, path)
    eq = tracker.solve(displacement)
    return _eq_state(tracker, eq, True)


def pull_off(problem: ContactProblem, path: LoadPath) -> Iterator[State]:
    """Yield the states of a press-and-pull-off (module docstring).

    The last state has ``kind == "separated"`` when the indenter came off, or
    ``converged == False`` with the reason when a solve failed or the step
    budget ran out.
    """
    if path.method == "pillars":
        from .pillars import pull_off as pillar_pull_off

        yield from pillar_pull_off(problem, path)
        return
    if problem.indenter.viscoelastic is not None or path.speed is not None:
        path = _time_stepped(problem, path)
    if problem.indenter.pillar_law is not None:
        _check_law_path(problem, path)
    tracker = Tracker(problem, path)
    if path.preload_displacement is not None:
        lowest = problem.indenter.lowest_height
        if path.preload_displacement <= lowest:
            raise ValueError(
                f"protocol.preload_displacement = {path.preload_displacement:g} must be > {lowest:.6g}, "
                "the height of the indenter's lowest element (where it first touches)"
            )
    states = _fixed(tracker, path) if path.method == "fixed" else _events(tracker, path)
    preload = None
    for state in states:
        if state.loading:
            preload = state
        elif preload is not None and preload.converged and preload.contact_area == 0:
            # Pressed to the preload without touching: no pull-off to follow.
            states.close()
            yield dataclasses.replace(preload, converged=False, n_solves=0, cg_iterations=0, reason=(
                f"no contact at the end of the loading branch (d = {preload.displacement:.6g}): the "
                f"penetration there is within the solver's tolerance (solver.tolerance = {path.tolerance:g} "
                "of the path's length scale); raise the preload or lower solver.tolerance"
            ))
            return
        yield state


def _time_stepped(problem: ContactProblem, path: LoadPath) -> LoadPath:
    """The path of viscoelastic pillars: fixed steps to a preload displacement, at a speed; one step size.

    The step is shortened so that the preload is a whole number of steps: the
    time step, and with it the connections' step stiffness, is then the same
    along the whole path (`brushbem.viscoelastic`).
    """
    if problem.indenter.viscoelastic is None:
        raise ValueError(f"protocol.speed = {path.speed:g} only applies to viscoelastic pillars "
                         "(indenter.viscoelastic); remove it")
    if path.speed is None:
        raise ValueError("viscoelastic pillars need protocol.speed, the pulling speed (> 0)")
    if path.method != "fixed":
        raise ValueError(f"protocol.method = {path.method!r}: viscoelastic pillars are stepped in time and need "
                         "method = 'fixed' (its step is the time step times the speed)")
    if path.preload_displacement is None:
        raise ValueError("viscoelastic pillars are pressed to protocol.preload_displacement (a force target "
                         "would need steps of changing length)")
    steps = max(1, math.ceil(path.preload_displacement / path.step - 1e-9))
    return dataclasses.replace(path, step=path.preload_displacement / steps)


def _check_law_path(problem: ContactProblem, path: LoadPath) -> None:
    """A nonlinear pillar law is followed by fixed steps, on elastic connections."""
    if path.method != "fixed":
        raise ValueError(f"protocol.method = {path.method!r}: a nonlinear pillar law (indenter.pillar_law) is "
                         "followed step by step and needs method = 'fixed'")
    if problem.indenter.viscoelastic is not None:
        raise ValueError("indenter.pillar_law and indenter.viscoelastic cannot be combined")
    if path.preload_displacement is None:
        raise ValueError("a nonlinear pillar law is pressed to protocol.preload_displacement (a force target "
                         "would search across the law's pieces)")


def _eq_state(tracker, eq: Equilibrium, loading: bool, kind="equilibrium") -> State:
    trial = tracker.h2 * eq.trial_force_sum
    return tracker.state(eq.displacement, loading, kind, trial, eq.cg_iterations, eq.n_solves, eq.converged, eq.reason)


def _fixed(tracker: Tracker, path: LoadPath) -> Iterator[State]:
    step = path.step
    d = 0.0
    count = 0
    done = False
    if tracker.memory is None and tracker.pieces is None and _press_as_contact_problems(tracker):
        # A brush is pressed as contact problems (`_contact_loading`): the
        # exact loading branch, which adhesive steps approach only slowly (an
        # element that joins overlapping may be held in tension where the
        # exact path never lets it touch).
        outcome = yield from _contact_loading(tracker, path)
        if outcome is None:
            return
        d, done = outcome
    # Loading (from where the contact problems stopped).
    if done:
        pass
    elif path.preload_displacement is not None:
        n_steps = max(1, math.ceil((path.preload_displacement - d) / step - 1e-9))
        start = d
        for k in range(1, min(n_steps, path.max_steps) + 1):
            d = min(start + k * step, path.preload_displacement)
            eq = tracker.step_solve(d)
            state = _eq_state(tracker, eq, True)
            yield state
            if not eq.converged:
                return
            tracker.commit_history()
        if n_steps > path.max_steps:
            yield _budget_exhausted(tracker, d, True, path)
            return
    else:
        target = path.preload_force
        previous = (d, tracker.force())
        while True:
            count += 1
            if count > path.max_steps:
                yield _budget_exhausted(tracker, d, True, path)
                return
            d += step
            saved = (tracker.pressure, tracker.contact)
            eq = tracker.solve(d)
            force = tracker.force()
            if not eq.converged:
                yield _eq_state(tracker, eq, True)
                return
            if force >= target:
                eq, d = _reach_force(tracker, saved, previous, (d, force, eq), target)
                yield _eq_state(tracker, eq, True)
                break
            yield _eq_state(tracker, eq, True)
            previous = (d, force)
    yield from _unload(tracker, path, d)


def _unload(tracker: Tracker, path: LoadPath, d_max: float) -> Iterator[State]:
    """Fixed steps down from ``d_max``, every event inside a step located (`_events_in_step`)."""
    step = path.step
    d = d_max
    for k in range(1, path.max_steps + 1):
        d = d_max - k * step
        before = (d + step, tracker.pressure, tracker.contact, tracker.pieces_state())
        eq = tracker.step_solve(d)
        eq = yield from _events_in_step(tracker, before, eq, d)
        if eq is None:  # separated at an event inside the step
            return
        if not eq.converged:
            yield _eq_state(tracker, eq, False)
            return
        tracker.commit_history()
        if not bool(tracker.xp.any(tracker.contact)):
            yield tracker.state(d, False, "separated", tracker.h2 * eq.trial_force_sum, eq.cg_iterations,
                                eq.n_solves, True, "complete separation")
            return
        yield _eq_state(tracker, eq, False)
    yield _budget_exhausted(tracker, d, False, path)


def _events_in_step(tracker: Tracker, before, eq: Equilibrium, d: float):
    """Every event inside a fixed step, in order; the step's final equilibrium at ``d``, or None if separated.

    The first event is on the step's starting set (`_next_event`); from the
    cascade at its displacement (the step's springs and history held), the
    next is on the set that remains, until none is left before d.  A punch or
    pillar that comes off later in the step keeps its largest force, and a
    pillar law's break lies where the tension reaches the limit.
    """
    for _ in range(MAX_EVENTS_PER_STEP):
        if not eq.converged:
            return eq
        event = _next_event(tracker, before, eq)
        if event is None:
            return eq
        crossing, detach, broken = event
        yield crossing
        tracker.restore_pieces(before[3])
        tracker.contact = crossing.contact
        tracker.set_pressure(crossing.pressure)
        if broken is not None:
            detach = detach | tracker.break_pillars(broken)
        at = tracker.step_solve(crossing.displacement, advance=False, detach=detach)
        if not at.converged:
            return at
        yield _eq_state(tracker, at, False, "event")
        if not bool(tracker.xp.any(tracker.contact)):
            tracker.commit_history()
            yield tracker.state(crossing.displacement, False, "separated", tracker.force(), 0, 0, True,
                                "complete separation")
            return None
        before = (crossing.displacement, tracker.pressure, tracker.contact, tracker.pieces_state())
        eq = tracker.step_solve(d, advance=False)
    return dataclasses.replace(eq, converged=False,
                               reason=f"more than {MAX_EVENTS_PER_STEP} events inside the step to d = {d:.6g}")


#: Events located inside one fixed step before the step is declared not converged (each detaches at
#: least one element or breaks one pillar, so a step holds at most as many as the grid has elements).
MAX_EVENTS_PER_STEP = 100_000


def _first_crossing(tracker: Tracker, before, eq: Equilibrium) -> State | None:
    """The state at which the first element of a fixed step's contact set reached the criterion.

    ``before`` = (d, pressure, contact) is the equilibrium the step started
    from and ``eq`` the step's equilibrium, whose first solve
    (``eq.trial_pressure``) is on the same contact set.  On a fixed set the
    pressure is affine in d, so the first element to reach -Sigma_c (the
    first event of the event path inside the step) and the force there are
    exact: this is where the force extremum of a step lies, which the
    step's end would miss by up to the step times the slope.  None when no
    element left in the step.
    """
    event = _next_event(tracker, before, eq)
    return None if event is None else event[0]


def _next_event(tracker: Tracker, before, eq: Equilibrium):
    """``(state, elements, pillars)`` of the first event between ``before`` and ``eq``, or None.

    The event is the first element of the starting contact set to reach the
    criterion (`_first_crossing`) or, under a pillar law with a tension
    limit, the first intact pillar whose tension reaches the limit: pillar
    forces are affine in d on the step's starting set and pieces too.
    ``elements`` are the contact elements at the criterion there, ``pillars``
    (bool per pillar, or None) the pillars at the limit.
    """
    xp = tracker.xp
    if eq.trial_pressure is None:
        return None
    d0, p0, c0 = before[:3]
    p1 = eq.trial_pressure
    critical = tracker.critical
    # Elements of the old set whose trial pressure is beyond the criterion.
    over = c0 & (p1 < -critical) if critical > 0 else c0 & (p1 < 0)
    tau_elements = 1.0
    fraction = None
    if bool(xp.any(over)):
        drop = xp.where(over, p0 - p1, 1.0)
        fraction = xp.where(over, (p0 + critical) / drop, xp.inf)
        tau_elements = min(max(float(xp.min(fraction)), 0.0), 1.0)
    tau_pillars, breaking = 1.0, None
    limit = tracker.tension_limit
    if limit is not None:
        f0 = tracker._pillar_forces(p0, c0)
        f1 = tracker._pillar_forces(p1, c0)
        intact = ~(before[3][1] if len(before) > 3 and before[3] is not None else tracker.pieces.broken)
        candidates = intact & (f1 < -limit) & (f0 > f1)
        if candidates.any():
            pillar_fraction = np.where(candidates, (f0 + limit) / np.where(candidates, f0 - f1, 1.0), np.inf)
            tau_pillars = min(max(float(pillar_fraction.min()), 0.0), 1.0)
            breaking = candidates & (pillar_fraction <= tau_pillars * (1 + 1e-12) + 1e-15)
    tau = min(tau_elements, tau_pillars)
    if tau >= 1.0:
        return None
    pressure = xp.where(c0, p0 + tau * (p1 - p0), 0.0)
    d = d0 + tau * (eq.displacement - d0)
    if tau_pillars <= tau_elements:
        elements = xp.zeros_like(c0)
        reason = "a pillar's tension reaches pillar_law.tension_limit inside the step (exact on its contact set)"
    else:
        breaking = None
        elements = over & (fraction <= tau * (1 + 1e-12) + 1e-15)
        reason = "a detachment inside the step (exact on the step's contact set)"
    state = tracker.state(d, False, "event", tracker.force(pressure), 0, 0, True, reason,
                          pressure=pressure, contact=c0)
    return state, elements, breaking


def _reach_force(tracker: Tracker, saved, below, above, target: float):
    """The smallest displacement at which the loading force reaches ``target``.

    ``below = (d, F)`` with F < target and ``above = (d, F, eq)`` with F >=
    target bracket it; every trial solves from ``saved``, the contact state at
    ``below``, so the history of the contact set is kept.  False position,
    with a bisection whenever a step fails to halve the bracket, ends when the
    force at the upper end is within 1e-6 of the target, or when the bracket
    has shrunk to rounding: then the force jumps past the target there (an
    adhesive snap-in) and the state just past the jump is the preload.
    Returns (equilibrium at the upper end, with the work of every solve here
    and of ``above``'s, its displacement); the tracker holds that state.
    """
    lo, f_lo = below
    hi, f_hi, eq = above
    at_hi = (tracker.pressure, tracker.contact)  # the tracker holds ``above``'s state on entry
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
        tracker.pressure, tracker.contact = saved
        trial_eq = tracker.solve(trial)
        solves += trial_eq.n_solves
        iterations += trial_eq.cg_iterations
        if not trial_eq.converged:
            return trial_eq, trial
        f = tracker.force()
        if f < target:
            lo, f_lo = trial, f
        else:
            hi, f_hi, eq = trial, f, trial_eq
            at_hi = (tracker.pressure, tracker.contact)
        bisect = hi - lo > 0.5 * width
    tracker.pressure, tracker.contact = at_hi
    return dataclasses.replace(eq, n_solves=solves, cg_iterations=iterations), hi


def _budget_exhausted(tracker, d, loading, path) -> State:
    return tracker.state(d, loading, "equilibrium", tracker.force(), 0, 0, False,
                         f"protocol.max_steps = {path.max_steps} reached before the end of the branch")


def _events(tracker: Tracker, path: LoadPath) -> Iterator[State]:
    d = 0.0
    done = False
    if path.method == "events" and _press_as_contact_problems(tracker):
        # A brush's loading branch as contact problems (`_contact_loading`);
        # from where that cannot be shown to hold, element events.
        outcome = yield from _contact_loading(tracker, path)
        if outcome is None:
            return
        d, done = outcome
    # Loading: from first touch (or where the contact problems stopped) to the preload.
    for _ in range(path.max_steps):
        if done:
            break
        outcome = yield from _event_step(tracker, path, d, +1)
        if outcome is None:
            return
        d, done = outcome
    else:
        yield _budget_exhausted(tracker, d, True, path)
        return
    # Unloading: until the contact set is empty.
    for _ in range(path.max_steps):
        outcome = yield from _event_step(tracker, path, d, -1)
        if outcome is None:
            return
        d, done = outcome
        if done:
            return
    yield _budget_exhausted(tracker, d, False, path)


#: Displacements at which `_contact_loading` samples the loading branch besides
#: those of the search for a preload force (evenly spaced from first touch).
LOADING_SAMPLES = 4

#: An element of an earlier sample that a later one has left counts as
#: released when its gap there exceeds this fraction of the indentation depth
#: (the solver's accuracy: one that just touches has a gap of rounding size).
_RELEASE_GAP = 1e-6


@dataclass
class _Sample:
    """One contact-problem solution on the loading branch (full-grid arrays)."""

    displacement: float
    force: float
    pressure: object
    contact: object
    eq: Equilibrium


def _press_as_contact_problems(tracker: Tracker) -> bool:
    """Whether the loading branch goes by `_contact_loading`: a brush whose tips are not all level.

    A brush of level tips (no roughness, profile or length offsets) touches
    with every footprint element at once, and its element-event loading is
    a single event: the contact problems would only cost more.
    """
    if tracker.n_pillars < 2:
        return False
    heights = np.asarray(tracker.problem.indenter.height)[np.asarray(tracker.problem.indenter.footprint)]
    lowest = float(heights.min())
    return float(heights.max()) - lowest > 1e-12 * max(abs(lowest), 1.0)


def _contact_loading(tracker: Tracker, path: LoadPath):
    """The loading branch of a brush as non-adhesive contact problems.

    While the base presses, an element joins S where the tip touches, at
    zero pressure, and the event path's state at d is the equilibrium on
    every element that has touched so far.  As long as no element of S
    would have turned tensile (its neighbours' compression lifting it off
    again), every pressure of that state is >= 0 and every gap outside >= 0:
    it solves the non-adhesive contact problem at d, whose solution is
    unique (a convex complementarity problem).  So the whole loading branch
    that the event path follows element event by element (one global solve
    per element: ~40 per pillar of 3.6 elements' radius) is given by
    Polonsky-Keer solutions, a few constrained CG solves in all.

    The premise is checked on the samples: every contact set must hold the
    sets of the smaller displacements sampled before it (an element that a
    larger displacement releases - a gap opening by more than
    ``_RELEASE_GAP`` of the indentation depth - would have been held in
    tension by the event path).  Samples: ``LOADING_SAMPLES`` evenly spaced
    displacements up to a preload displacement, or the iterates of the
    search for a preload force (false position on the piecewise linear,
    increasing F(d); exact by interpolation once both ends of the bracket
    have the same contact set).  Where the check fails, the branch goes on
    from the last sample before it by element events (the states up to it
    are the event path's).

    Yields the loading states in increasing d; returns (d, preload reached)
    or None when a solve failed.
    """
    xp = tracker.xp
    problem = tracker.problem
    lowest = problem.indenter.lowest_height
    samples: list[_Sample] = []
    cost = [0, 0]  # solves, iterations of the samples not yet yielded

    def solve_at(d: float, start: _Sample | None) -> _Sample:
        if start is None:
            tracker.pressure = xp.zeros_like(tracker.pressure)
            tracker.contact = xp.zeros_like(tracker.contact)
        else:
            tracker.pressure, tracker.contact = start.pressure, start.contact
        tracker._known_deflection = None
        eq = tracker.solve(d, contact_problem=True)
        cost[0] += eq.n_solves
        cost[1] += eq.cg_iterations
        sample = _Sample(d, tracker.force(), tracker.pressure, tracker.contact, eq)
        if not eq.converged:
            return sample
        samples.append(sample)
        return sample

    final = None
    if path.preload_displacement is not None:
        target = path.preload_displacement
        previous = None
        for j in range(1, LOADING_SAMPLES + 1):
            d = target if j == LOADING_SAMPLES else lowest + (target - lowest) * j / LOADING_SAMPLES
            previous = solve_at(d, previous)
            if not previous.eq.converged:
                yield _eq_state(tracker, previous.eq, True)
                return None
        final = previous
    else:
        final = yield from _contact_preload_force(tracker, path, solve_at, lowest)
        if final is None:
            return None

    # The path ends at the preload: samples beyond it (the search's upper ends) are not on it.
    samples = [sample for sample in samples if sample.displacement < final.displacement] + [final]
    samples.sort(key=lambda sample: sample.displacement)
    accepted = _nested_prefix(tracker, samples, lowest)
    for k, sample in enumerate(accepted):
        tracker.pressure, tracker.contact = sample.pressure, sample.contact
        last = k == len(accepted) - 1
        solves, iterations = (cost[0], cost[1]) if last else (sample.eq.n_solves, sample.eq.cg_iterations)
        if not last:
            cost[0] -= solves
            cost[1] -= iterations
        reason = "contact problem" if len(accepted) == len(samples) or not last else (
            "contact problem; element events from here (a larger displacement releases an element)")
        yield tracker.state(sample.displacement, True, "equilibrium", tracker.force(), iterations, solves,
                            True, reason)
    tracker._known_deflection = None
    tracker.unit = None
    end = accepted[-1]
    if end is final or len(accepted) == len(samples):
        return end.displacement, True
    return end.displacement, False


def _contact_preload_force(tracker: Tracker, path: LoadPath, solve_at, lowest: float):
    """The contact problem at which the loading force reaches ``path.preload_force`` (a `_Sample`).

    F(d) of the non-adhesive problem is continuous, increasing and piecewise
    linear (affine while the contact set stays).  Below the target the secant
    of the last two points is extrapolated (F is convex where the contact
    grows, so it reaches past the target); then the Illinois variant of
    false position, until F is within 1e-9 of the target (the event path's
    test) or both ends of the bracket have the same contact set - then the
    state at the target is their exact interpolation.
    """
    xp = tracker.xp
    problem = tracker.problem
    target = path.preload_force
    indenter = problem.indenter
    area = float(np.count_nonzero(np.asarray(indenter.footprint))) * tracker.h2
    # Displacement of the whole footprint as one punch on its springs in series (a first guess).
    compliance = 1.0 / (2.0 * problem.contact_modulus * math.sqrt(area / math.pi))
    compliance += sum(1.0 / (level.stiffness * level.n_clusters if level.uniform else float(np.sum(level.stiffness)))
                      for level in indenter.elastic_levels)
    lo = hi = None  # samples below and above the target
    lo_points = [(lowest, 0.0)]
    f_lo = f_hi = 0.0  # residuals F - target at the ends, halved by the Illinois rule
    side = 0
    d = lowest + target * compliance
    start = None
    for _ in range(200):
        sample = solve_at(d, start)
        if not sample.eq.converged:
            yield _eq_state(tracker, sample.eq, True)
            return None
        start = sample
        residual = sample.force - target
        if abs(residual) <= 1e-9 * target:
            return sample
        if residual > 0:
            hi, f_hi = sample, residual
            if side > 0:
                f_lo *= 0.5
            side = 1
        else:
            lo, f_lo = sample, residual
            lo_points.append((sample.displacement, sample.force))
            if side < 0:
                f_hi *= 0.5
            side = -1
        if hi is None:
            # Below the target: extrapolate the secant of the last two points.
            (d0, g0), (d1, g1) = lo_points[-2], lo_points[-1]
            step = (target - g1) * (d1 - d0) / (g1 - g0) if g1 > g0 else 2.0 * (d1 - lowest)
            d = d1 + max(step, 1e-3 * (d1 - lowest))
            continue
        if lo is None:
            d = lowest + 0.5 * (hi.displacement - lowest)
            continue
        if bool(xp.all(lo.contact == hi.contact)):
            # One contact set at both ends: F and p are affine in between.
            theta = (target - lo.force) / (hi.force - lo.force)
            d = lo.displacement + theta * (hi.displacement - lo.displacement)
            pressure = lo.pressure + theta * (hi.pressure - lo.pressure)
            tracker.pressure, tracker.contact = pressure, hi.contact
            eq = dataclasses.replace(hi.eq, n_solves=0, cg_iterations=0)
            return _Sample(d, tracker.force(), pressure, hi.contact, eq)
        width = hi.displacement - lo.displacement
        if width <= 4 * np.finfo(float).eps * abs(hi.displacement):
            return hi
        d = lo.displacement - f_lo * width / (f_hi - f_lo)
    yield tracker.state(d, True, "equilibrium", tracker.force(), 0, 0, False,
                        "the search for the preload force did not converge in 200 contact problems")
    return None


def _nested_prefix(tracker: Tracker, samples: list, lowest: float) -> list:
    """The samples (increasing d) up to the first whose contact set does not hold an earlier one's."""
    xp = tracker.xp
    accepted = samples[:1]
    union = samples[0].contact
    for sample in samples[1:]:
        released = union & ~sample.contact
        if bool(xp.any(released)):
            full = ContactOperator(tracker.halfspace, tracker.problem.indenter,
                                   Window.full(tracker.problem.grid.elements))
            gap = -penetration(full, tracker.height, sample.displacement, sample.pressure)
            depth = max(sample.displacement - lowest, 1e-300)
            if bool(xp.any(released & (gap > _RELEASE_GAP * depth))):
                break
        accepted.append(sample)
        union = union | sample.contact
    return accepted


def _event_step(tracker: Tracker, path: LoadPath, d: float, direction: int):
    """Advance to the next event in ``direction`` (+1 press, -1 pull); yield its states.

    Returns (d, branch_finished), or None when the path must stop.

    Why one function: after the prediction (`_events_ahead`) the three endings of a step (a window bound, a
    target, an event and its cascade) all move the tracker from the same predicted state; split, each would
    take the prediction and the tracker and hand back the next d.
    """
    xp = tracker.xp
    loading = direction > 0
    tol = path.tolerance
    if not bool(xp.any(tracker.contact)):
        return (yield from _without_contact(tracker, path, d, loading))
    tracker.ensure_window(tracker.contact)
    if loading and not tracker.covers_footprint and tracker.outside_reach_displacement() <= d:
        # An element outside the window may already be within reach (the
        # bound is conservative): work on the whole footprint from here on.
        tracker.ensure_window(tracker.contact | tracker.footprint)
    sl = tracker.window.slices
    result = tracker.unit_response()
    if not result.converged:
        yield tracker.state(d, loading, "equilibrium", tracker.force(), result.iterations, 1, False,
                            f"unit response: {result.reason}")
        return None
    a = result.solution
    contact = tracker.contact[sl]
    pressure = tracker.pressure[sl]
    s = float(direction)
    ahead = _events_ahead(tracker, path, d, direction, a)
    grows, t_detach, t_det = ahead.grows, ahead.t_detach, ahead.t_detach_min
    closing, t_attach, t_att = ahead.closing, ahead.t_attach, ahead.t_attach_min
    deflection, unit_deflection, candidates = ahead.deflection, ahead.unit_deflection, ahead.candidates
    t = min(c[0] for c in candidates)
    if not math.isfinite(t):
        yield tracker.state(d, loading, "equilibrium", tracker.force(), result.iterations, 1, False,
                            "no event ahead on this branch (the contact neither grows nor shrinks)")
        return None
    t = max(t, 0.0)
    new_d = d + s * t
    new_pressure = xp.zeros_like(tracker.pressure)
    new_pressure[sl] = xp.where(contact, pressure + (s * t) * a, 0.0)
    # Both vanish outside S, so the deflection is affine too (no transform).
    new_deflection = deflection + (s * t) * unit_deflection
    target_hit = any(c[1] == "target" and c[0] <= t for c in candidates)
    tie = 100.0 * tol * (abs(d) + t) + 1e-300
    outside_hit = any(c[1] == "outside" and c[0] <= t for c in candidates)
    if outside_hit and t + tie < min(t_det, t_att):
        # Move to the bound along the exact affine path (a valid equilibrium:
        # nothing detaches or attaches before it), then widen the window to
        # every footprint element the load path may still reach and go on.
        tracker.pressure = new_pressure
        reach = path.preload_displacement if path.preload_displacement is not None else new_d + max(abs(new_d), tracker.problem.grid.element_size)
        before = tracker.window
        tracker.ensure_window(tracker.contact | (tracker.footprint & (tracker.height <= reach)))
        if tracker.window == before or tracker.outside_reach_displacement() <= new_d:
            tracker.ensure_window(tracker.contact | tracker.footprint)
        yield tracker.state(new_d, loading, "equilibrium", tracker.force(new_pressure), result.iterations, 1, True,
                            "window enlarged")
        return new_d, _target_reached(tracker, path, new_d)
    if target_hit and t + tie < min(t_det, t_att):
        tracker.set_pressure(new_pressure, new_deflection)
        state = tracker.state(new_d, loading, "equilibrium", tracker.force(new_pressure), result.iterations, 1,
                              True, "preload reached")
        yield state
        return new_d, True
    # A state on the threshold of the event (still an equilibrium), then the cascade.
    yield tracker.state(new_d, loading, "event", tracker.force(new_pressure), result.iterations, 1, True,
                        "event", pressure=new_pressure)
    n = tracker.problem.grid.elements
    leave = xp.zeros((n, n), dtype=xp.bool)
    join = xp.zeros((n, n), dtype=xp.bool)
    if t_det <= t + tie:
        leave[sl] = grows & (t_detach <= t + tie)
    if t_att <= t + tie:
        join[sl] = closing & (t_attach <= t + tie)
    tracker.set_pressure(new_pressure, new_deflection)
    window = tracker.window
    eq = tracker.solve(new_d, force_detach=leave, force_attach=join)
    if not eq.converged:
        yield _eq_state(tracker, eq, loading)
        return None
    if eq.cg_iterations:
        tracker.record_pressure_change(new_pressure, new_deflection, window)
    if not bool(xp.any(tracker.contact)) and not loading:
        yield tracker.state(new_d, False, "separated", tracker.h2 * eq.trial_force_sum, eq.cg_iterations,
                            eq.n_solves, True, "complete separation")
        return new_d, True
    yield _eq_state(tracker, eq, loading)
    return new_d, loading and _target_reached(tracker, path, new_d)


def _target_reached(tracker, path, d) -> bool:
    if path.preload_displacement is not None:
        return d >= path.preload_displacement * (1 - 1e-12)
    return tracker.force() >= path.preload_force * (1 - 1e-9)


def _without_contact(tracker: Tracker, path: LoadPath, d: float, loading: bool):
    """`_event_step` without contact: separation on the pull-off, the first touch on the loading."""
    if not loading:
        yield tracker.state(d, False, "separated", 0.0, 0, 0, True, "complete separation")
        return d, True
    # First touch: the lowest footprint elements.
    lowest = tracker.problem.indenter.lowest_height
    distance = max(lowest - d, 0.0)
    first = tracker.footprint & (tracker.height <= lowest + 1e-12 * max(abs(lowest), 1.0) + 0.0)
    new_d = d + distance
    eq = tracker.solve(new_d, force_attach=first)
    yield _eq_state(tracker, eq, True)
    if not eq.converged:
        return None
    return new_d, _target_reached(tracker, path, new_d)


@dataclasses.dataclass(frozen=True)
class _Ahead:
    """The events ahead of an affine state p + t s a, on the tracker's window (`_events_ahead`)."""

    grows: object  # elements of S whose tension grows
    t_detach: object  # t at which each reaches -Sigma_c (inf elsewhere)
    t_detach_min: float
    closing: object  # footprint elements off S that approach the surface
    t_attach: object  # t at which each touches (inf elsewhere)
    t_attach_min: float
    deflection: object  # tip deflection of the current pressure
    unit_deflection: object  # tip deflection of a
    candidates: list  # (t, kind, None): detach, attach, and the targets and window bounds ahead


def _events_ahead(tracker: Tracker, path: LoadPath, d: float, direction: int, a) -> _Ahead:
    """Where, along d + t s with the unit response ``a``, each kind of event comes first."""
    xp = tracker.xp
    loading = direction > 0
    sl = tracker.window.slices
    contact = tracker.contact[sl]
    pressure = tracker.pressure[sl]
    s = float(direction)
    candidates: list[tuple[float, str, object]] = []  # (distance along direction, kind, mask)
    if loading and path.preload_displacement is not None:
        candidates.append((path.preload_displacement - d, "target", None))
    # Detachment: p_i + t s a_i = -Sigma_c for t >= 0 (elements whose tension grows).
    rate = s * a
    grows = contact & (rate < 0)
    t_detach = xp.where(grows, (pressure + tracker.critical) / xp.where(grows, -rate, 1.0), xp.inf)
    t_detach = xp.where(t_detach < 0, 0.0, t_detach)
    # Attachment: penetration pen_j + t s slope_j = 0 from below.
    height = tracker.height[sl]
    footprint = tracker.footprint[sl]
    deflection = tracker.deflection()  # known from the last equilibrium's join check
    unit_deflection = tracker.unit_deflection()  # the one transform of a on the window
    reach = d - height - deflection
    slope = 1.0 - unit_deflection
    closing = footprint & ~contact & (s * slope > 0)
    t_attach = xp.where(closing, -reach / xp.where(closing, s * slope, 1.0), xp.inf)
    t_attach = xp.where(t_attach < 0, 0.0, t_attach)
    t_det = float(xp.min(t_detach)) if bool(xp.any(grows)) else math.inf
    t_att = float(xp.min(t_attach)) if bool(xp.any(closing)) else math.inf
    candidates.append((t_det, "detach", None))
    candidates.append((t_att, "attach", None))
    if loading and path.preload_force is not None:
        force_rate = tracker.h2 * float(xp.sum(a))
        if force_rate > 0:
            candidates.append(((path.preload_force - tracker.force()) / force_rate, "target", None))
    if loading and not tracker.covers_footprint:
        # Footprint elements outside the window (other pillars, asperities)
        # are not in the affine prediction: stop where one of them could
        # first touch, enlarge the window there and predict again.
        reach_at = tracker.outside_reach_displacement()
        if reach_at < math.inf:
            candidates.append((max(reach_at - d, 0.0), "outside", None))
    return _Ahead(grows, t_detach, t_det, closing, t_attach, t_att, deflection, unit_deflection, candidates)
