"""Locating the events of a load path (an element reaching the criterion or touching, a pillar breaking).

Inside a fixed step (`_events_in_step`, `_next_event`, `_first_crossing`):
on the step's starting contact set the pressure and the pillar forces are
affine in d, so the first element to reach -Sigma_c, or the first pillar to
reach its tension limit, is found exactly, and the step goes on from the
cascade there.  On the event-driven path (`_event_step`, `_events_ahead`):
the state is affine in d along the unit response, and the path jumps to the
next detachment, attachment, target or window bound and follows the cascade
there.  The drivers that call these are in `brushbem.protocol.paths`.  Each
takes the path's state (`brushbem.protocol.values.PathState`) and returns the
next with its outcome, through the steps of `brushbem.protocol.steps` and
`brushbem.protocol.unit_response`.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from brushbem import backend, settings
from brushbem.numerics.solver import Equilibrium
from brushbem.protocol.path_states import _eq_state, _separated, record_state, total_force
from brushbem.protocol.problem import LoadPath, State, detachment_slack, event_tie
from brushbem.protocol.steps import (
    PathContext,
    break_pillars,
    commit_history,
    cover_contact,
    deflection_of,
    pillar_forces,
    restore_pieces,
    solve_from,
    step_from,
    widen_to_reach,
    with_pressure,
)
from brushbem.protocol.unit_response import unit_deflection as unit_deflection_of
from brushbem.protocol.unit_response import unit_response, with_pressure_change


def _events_in_step(context: PathContext, state, before, eq: Equilibrium, d: float):
    """Every event inside a fixed step, in order; the state at ``d`` and its equilibrium (None if separated).

    ``state`` and ``eq`` are the step's end, ``before`` (a saved `PathState`)
    its start.  The first event is on the step's starting set
    (`_next_event`); from the cascade at its displacement (the step's springs
    and history held), the next is on the set that remains, until none is
    left before d.  A punch or pillar that comes off later in the step keeps
    its largest force, and a pillar law's break lies where the tension
    reaches the limit.
    """
    for _ in range(MAX_EVENTS_PER_STEP):
        if not eq.converged:
            return state, eq
        event = _next_event(context, state, before, eq)
        if event is None:
            return state, eq
        crossing, detach, broken = event
        yield crossing
        state = restore_pieces(context, state, before)
        state = state.replace(pressure=crossing.pressure, contact=crossing.contact, deflection=None)
        if broken is not None:
            state, held = break_pillars(context, state, broken)
            detach = detach | held
        state, at = step_from(context, state, crossing.displacement, advance=False, detach=detach)
        if not at.converged:
            return state, at
        yield _eq_state(context, state, at, False, "event")
        if not bool(context.xp.any(state.contact)):
            state = commit_history(context, state)
            yield record_state(context, state, crossing.displacement, False, "separated",
                               total_force(context, state), 0, 0, True, "complete separation")
            return state, None
        before = state.replace(displacement=crossing.displacement)
        state, eq = step_from(context, state, d, advance=False)
    return state, dataclasses.replace(eq, converged=False,
                                      reason=f"more than {MAX_EVENTS_PER_STEP} events inside the step to d = {d:.6g}")


#: Events located inside one fixed step before the step is declared not converged (each detaches at
#: least one element or breaks one pillar, so a step holds at most as many as the grid has elements).
MAX_EVENTS_PER_STEP = 100_000


def _first_crossing(context: PathContext, state, before, eq: Equilibrium) -> State | None:
    """The state at which the first element of a fixed step's contact set reached the criterion.

    ``before`` (a saved `PathState`) is the equilibrium the step started
    from and ``eq`` the step's equilibrium (of ``state``), whose first solve
    (``eq.trial_pressure``) is on the same contact set.  On a fixed set the
    pressure is affine in d, so the first element to reach -Sigma_c (the
    first event of the event path inside the step) and the force there are
    exact: this is where the force extremum of a step lies, which the
    step's end would miss by up to the step times the slope.  None when no
    element left in the step.
    """
    event = _next_event(context, state, before, eq)
    return None if event is None else event[0]


def _next_event(context: PathContext, state, before, eq: Equilibrium):
    """``(state, elements, pillars)`` of the first event between ``before`` and ``eq``, or None.

    The event is the first element of the starting contact set to reach the
    criterion (`_first_crossing`) or, under a pillar law with a tension
    limit, the first intact pillar whose tension reaches the limit: pillar
    forces are affine in d on the step's starting set and pieces too.
    ``elements`` are the contact elements at the criterion there, ``pillars``
    (bool per pillar, or None) the pillars at the limit.
    """
    xp = context.xp
    if eq.trial_pressure is None:
        return None
    d0, p0, c0 = before.displacement, before.pressure, before.contact
    p1 = eq.trial_pressure
    critical = context.critical
    # Elements of the old set whose trial pressure is beyond the criterion.
    over = c0 & (p1 < -critical) if critical > 0 else c0 & (p1 < 0)
    tau_elements = 1.0
    fraction = None
    if bool(xp.any(over)):
        drop = xp.where(over, p0 - p1, 1.0)
        fraction = xp.where(over, (p0 + critical) / drop, xp.inf)
        tau_elements = min(max(float(xp.min(fraction)), 0.0), 1.0)
    tau_pillars, breaking = 1.0, None
    limit = state.connections.tension_limit
    if limit is not None:
        f0 = pillar_forces(context, p0, c0)
        f1 = pillar_forces(context, p1, c0)
        intact = ~before.connections.broken()
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
    crossing = record_state(context, state, d, False, "event", total_force(context, state, pressure), 0, 0, True,
                            reason, pressure=pressure, contact=c0)
    return crossing, elements, breaking


def _event_step(context: PathContext, state, path: LoadPath, d: float, direction: int):
    """Advance from ``state`` to the next event in ``direction`` (+1 press, -1 pull); yield its states.

    Returns (the state there, d, branch_finished), or None when the path must stop.

    Why one function: after the prediction (`_events_ahead`) the three endings of a step (a window bound, a
    target, an event and its cascade) all go on from the same predicted state; split, each would
    take the prediction and the state and hand back the next d.
    """
    xp = context.xp
    loading = direction > 0
    if not bool(xp.any(state.contact)):
        return (yield from _without_contact(context, state, path, d, loading))
    # An element outside the window may already be within reach (the bound is
    # conservative): then the path works on the whole footprint from here on.
    state = cover_contact(state, d, loading)
    sl = state.working.window.slices
    state, result = unit_response(context, state)
    if not result.converged:
        yield record_state(context, state, d, loading, "equilibrium", total_force(context, state), result.iterations,
                           1, False, f"unit response: {result.reason}")
        return None
    a = result.solution
    contact = state.contact[sl]
    pressure = state.pressure[sl]
    s = float(direction)
    state, ahead = _events_ahead(context, state, path, d, direction, a)
    grows, t_detach, t_det = ahead.grows, ahead.t_detach, ahead.t_detach_min
    closing, t_attach, t_att = ahead.closing, ahead.t_attach, ahead.t_attach_min
    deflection, unit_deflection, candidates = ahead.deflection, ahead.unit_deflection, ahead.candidates
    t = min(c[0] for c in candidates)
    if not math.isfinite(t):
        yield record_state(context, state, d, loading, "equilibrium", total_force(context, state), result.iterations,
                           1, False, "no event ahead on this branch (the contact neither grows nor shrinks)")
        return None
    t = max(t, 0.0)
    new_d = d + s * t
    new_pressure = xp.zeros_like(state.pressure)
    new_pressure[sl] = xp.where(contact, pressure + (s * t) * a, 0.0)
    # Both vanish outside S, so the deflection is affine too (no transform).
    new_deflection = deflection + (s * t) * unit_deflection
    target_hit = any(c[1] == "target" and c[0] <= t for c in candidates)
    h = state.working.problem.grid.element_size
    tie = event_tie(path, h)
    outside_hit = any(c[1] == "outside" and c[0] <= t for c in candidates)
    if outside_hit and t + tie < min(t_det, t_att):
        # Move to the bound along the exact affine path (a valid equilibrium:
        # nothing detaches or attaches before it), then widen the window to
        # every footprint element the load path may still reach and go on.
        reach = path.preload_displacement if path.preload_displacement is not None else new_d + max(abs(new_d), h)
        state = widen_to_reach(with_pressure(state, new_pressure), new_d, reach)
        yield record_state(context, state, new_d, loading, "equilibrium", total_force(context, state, new_pressure),
                           result.iterations, 1, True, "window enlarged")
        return state, new_d, _target_reached(context, state, path, new_d)
    if target_hit and t + tie < min(t_det, t_att):
        state = with_pressure(state, new_pressure, new_deflection)
        yield record_state(context, state, new_d, loading, "equilibrium", total_force(context, state, new_pressure),
                           result.iterations, 1, True, "preload reached")
        return state, new_d, True
    # A state on the threshold of the event (still an equilibrium), then the cascade.
    yield record_state(context, state, new_d, loading, "event", total_force(context, state, new_pressure),
                       result.iterations, 1, True, "event", pressure=new_pressure)
    leave = xp.zeros_like(state.contact)
    join = xp.zeros_like(state.contact)
    if t_det <= t + tie:
        leave[sl] = ahead.within(grows, t_detach, t + xp.maximum(tie, ahead.detach_slack))
    if t_att <= t + tie:
        join[sl] = ahead.within(closing, t_attach, t + tie)
    state = with_pressure(state, new_pressure, new_deflection)
    window = state.working.window
    state, eq = solve_from(context, state, new_d, force_detach=leave, force_attach=join)
    if not eq.converged:
        yield _eq_state(context, state, eq, loading)
        return None
    if eq.cg_iterations:
        state = with_pressure_change(state, new_pressure, new_deflection, window)
    if not bool(xp.any(state.contact)) and not loading:
        yield _separated(context, state, new_d, eq)
        return state, new_d, True
    yield _eq_state(context, state, eq, loading)
    return state, new_d, loading and _target_reached(context, state, path, new_d)


def _target_reached(context, state, path, d) -> bool:
    if path.preload_displacement is not None:
        return d >= path.preload_displacement * (1 - 1e-12)
    return total_force(context, state) >= path.preload_force * (1 - 1e-9)


def _without_contact(context: PathContext, state, path: LoadPath, d: float, loading: bool):
    """`_event_step` without contact: separation on the pull-off, the first touch on the loading."""
    if not loading:
        yield record_state(context, state, d, False, "separated", 0.0, 0, 0, True, "complete separation")
        return state, d, True
    # First touch: the lowest footprint elements.
    working = state.working
    lowest = working.problem.indenter.lowest_height
    distance = max(lowest - d, 0.0)
    first = working.footprint & (working.height <= lowest + 1e-12 * max(abs(lowest), 1.0) + 0.0)
    new_d = d + distance
    state, eq = solve_from(context, state, new_d, force_attach=first)
    yield _eq_state(context, state, eq, True)
    if not eq.converged:
        return None
    return state, new_d, _target_reached(context, state, path, new_d)


@dataclasses.dataclass(frozen=True)
class _Ahead:
    """The events ahead of an affine state p + t s a, on the state's window (`_events_ahead`)."""

    grows: object  # elements of S whose tension grows
    t_detach: object  # t at which each reaches -Sigma_c (inf elsewhere)
    t_detach_min: float
    closing: object  # footprint elements off S that approach the surface
    t_attach: object  # t at which each touches (inf elsewhere)
    t_attach_min: float
    deflection: object  # tip deflection of the current pressure
    unit_deflection: object  # tip deflection of a
    candidates: list  # (t, kind, None): detach, attach, and the targets and window bounds ahead
    elements: tuple | None = None  # (rows, cols, window shape) when the arrays above hold these elements only
    # How much further along the path each element of ``grows`` is still within the event window of its
    # detachment: its pressure within event_window x Sigma_c of the criterion (`detachment_slack`).
    detach_slack: object = 0.0

    def within(self, kind, times, bound):
        """The elements of ``kind`` (``grows`` or ``closing``) whose ``times`` are <= ``bound`` (a number or one
        per element), on the window."""
        chosen = kind & (times <= bound)
        if self.elements is None:
            return chosen
        rows, cols, shape = self.elements
        out = np.zeros(shape, dtype=bool)
        out[rows[chosen], cols[chosen]] = True
        return out



def _events_ahead(context: PathContext, state, path: LoadPath, d: float, direction: int, a):
    """Where, along d + t s with the unit response ``a``, each kind of event comes first (an `_Ahead`).

    Returns the state that knows the deflections of its pressure and of ``a`` (`_Ahead.deflection`,
    `_Ahead.unit_deflection`) and the `_Ahead`.
    """
    xp = context.xp
    loading = direction > 0
    working = state.working
    sl = working.window.slices
    contact = state.contact[sl]
    pressure = state.pressure[sl]
    height = working.height[sl]
    footprint = working.footprint[sl]
    a_all = a
    state, deflection = deflection_of(state)  # known from the last equilibrium's join check
    state, unit_deflection = unit_deflection_of(state)  # the one transform of a on the window
    elements = None
    known_deflection, known_unit_deflection = deflection, unit_deflection
    if settings.switches().compact_event_search and backend.is_numpy_namespace(xp):
        rows, cols = working.footprint_elements
        elements = (rows, cols, contact.shape)
        contact, pressure, height, a = contact[rows, cols], pressure[rows, cols], height[rows, cols], a[rows, cols]
        deflection, unit_deflection = deflection[rows, cols], unit_deflection[rows, cols]
        footprint = True
    s = float(direction)
    candidates: list[tuple[float, str, object]] = []  # (distance along direction, kind, mask)
    if loading and path.preload_displacement is not None:
        candidates.append((path.preload_displacement - d, "target", None))
    # Detachment: p_i + t s a_i = -Sigma_c for t >= 0 (elements whose tension grows).
    rate = s * a
    grows = contact & (rate < 0)
    t_detach = xp.where(grows, (pressure + context.critical) / xp.where(grows, -rate, 1.0), xp.inf)
    t_detach = xp.where(t_detach < 0, 0.0, t_detach)
    # Attachment: penetration pen_j + t s slope_j = 0 from below.
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
        force_rate = context.h2 * float(xp.sum(a_all))
        if force_rate > 0:
            candidates.append(((path.preload_force - total_force(context, state)) / force_rate, "target", None))
    if loading and not working.covers_footprint:
        # Footprint elements outside the window (other pillars, asperities)
        # are not in the affine prediction: stop where one of them could
        # first touch, enlarge the window there and predict again.
        reach_at = working.outside_reach_displacement(state.pressure, state.contact)
        if reach_at < math.inf:
            candidates.append((max(reach_at - d, 0.0), "outside", None))
    return state, _Ahead(grows, t_detach, t_det, closing, t_attach, t_att, known_deflection, known_unit_deflection,
                         candidates, elements, detachment_slack(path, context.critical, grows, rate, xp))
