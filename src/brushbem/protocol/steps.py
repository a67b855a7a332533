"""The steps of one pull-off: each takes the path's state and gives the next (`solve_from`, `step_from`, ...).

The path's state is one frozen value (`brushbem.protocol.values.PathState`:
the pressure and the contact set, the working window with its operator and
tip heights, a `brushbem.protocol.window.WorkingWindow`, the connections'
state, a `brushbem.protocol.connections.ConnectionState`, the deflections
known of them without another transform and the last unit response).  The
steps here take a state and return the next, leaving the one they took as it
was and sharing every array that did not change: `solve_from` (the
equilibrium at d, on a window enlarged as the contact needs), `step_from` (a
fixed step: the connections' history, a law's pieces and breaks),
`with_change` (a change of the connections: new springs give the window a new
operator, raised tips new heights), `cover_contact` and `widen_to_reach` (the
window the event path predicts on), `with_pressure`, `restored` and
`without_deflections` (a pressure put in by the paths, a return to a saved
state, the known deflections dropped), `deflection_of` (the tip deflection
of the pressure, computed once), and for the connections `pillar_forces`,
`break_pillars`, `restore_pieces` and `commit_history`.  The event path's
unit response is stepped the same way (`brushbem.protocol.unit_response`).

A saved state is a state kept (with its ``displacement``); going back to it
(`restored`) takes its pressure and contact on the current window with what
is known now: a window is a choice of where to compute, and the path keeps
the one it has.  The load paths (`brushbem.protocol.paths`,
`brushbem.protocol.events`, `brushbem.protocol.contact_loading`) hand their
state from step to step and make the `State` records of it
(`brushbem.protocol.path_states`).

What the steps share besides the state is a `PathContext`, made once per path:
the problem's constants, the solver's settings, the ledgers of
single-precision products (the solver's, kept beside the state: a solve adds
to them) and the path's length scale (the largest |d| a record reached);
``PathContext.state`` is the state the path starts from, never written back.

Cached deflections: the deflection of the pressure and of the unit response
are kept with the array and the window they were computed on, and are used
only while both are the current ones (`Known.of`).  They are computed with
the window's operator, so when the connections change the pillars' springs
(a piece of a nonlinear law moves) every one of them, the unit response and
the cascade's pressure change are dropped (`with_change`, the one place
where the operator's springs change).  Raised tips (history offsets, breaks)
change the heights, not the operator: the cached deflections stay valid.  A
pressure put in by the paths comes without a known deflection
(`with_pressure`) unless they give it; `without_deflections` drops all of
them.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from brushbem import backend
from brushbem.numerics.operator import Window
from brushbem.numerics.solver import (
    Equilibrium,
    ProductLedger,
    Settings,
    Start,
    equilibrium,
    polonsky_keer,
    tip_deflection,
)
from brushbem.protocol.connections import ConnectionState, SpringChange
from brushbem.protocol.problem import ContactProblem, LoadPath
from brushbem.protocol.values import Known, PathState
from brushbem.protocol.window import WorkingWindow

__all__ = [
    "PathContext",
    "break_pillars",
    "commit_history",
    "cover_contact",
    "deflection_of",
    "pillar_forces",
    "restore_pieces",
    "restored",
    "solve_from",
    "step_from",
    "widen_to_reach",
    "with_change",
    "with_pressure",
    "without_deflections",
]


class PathContext:
    """What the steps of one pull-off share besides its state (module docstring), and the state it starts from.

    ``state`` is the first `PathState` (no contact, the indenter's own
    tips); the load paths hand the state on from step to step and never
    write it back.  ``ledgers`` are the errors that single-precision
    products left in the kept deflections of the equilibria and of the unit
    responses (`brushbem.numerics.solver.cg.ProductLedger`), new with new
    springs; ``length_scale`` the largest |d| reached.
    """

    def __init__(self, problem: ContactProblem, path: LoadPath):
        self.path = path
        connections, problem = ConnectionState.begin(problem, path)
        self.settings = Settings(tolerance=path.tolerance, max_iterations=path.max_iterations, cascade=path.cascade)
        xp = problem.xp
        self.xp = xp
        grid = problem.grid
        n = grid.elements
        self.h2 = grid.element_size**2
        indenter = problem.indenter
        self.pillar = xp.asarray(indenter.pillar)
        self.pillar_host = np.asarray(indenter.pillar)
        self.n_pillars = indenter.n_pillars
        self.critical = problem.critical_stress
        self.state = PathState(pressure=xp.zeros((n, n), dtype=xp.float64), contact=xp.zeros((n, n), dtype=xp.bool),
                               working=WorkingWindow.begin(problem, path), connections=connections)
        self.ledgers = (ProductLedger(), ProductLedger())
        self.length_scale = 0.0


# -- a pressure put in, a saved state returned to, what is known of the pressure -------------
def with_pressure(state: PathState, pressure, deflection=None) -> PathState:
    """``state`` with ``pressure`` (full grid), with its tip deflection on the state's window if known."""
    return state.replace(pressure=pressure, deflection=(
        None if deflection is None else Known(pressure, state.working.window, deflection)))


def restored(state: PathState, point: PathState) -> PathState:
    """``state`` back at the pressure and contact of ``point`` (a saved state; its pieces: `restore_pieces`).

    The window and what is known (the deflections, the unit response) stay ``state``'s: each is used only
    while it is of the restored arrays on the current window (`Known.of`).
    """
    return state.replace(pressure=point.pressure, contact=point.contact)


def without_deflections(context: PathContext, state: PathState) -> PathState:
    """``state`` without its known deflections and unit response (the next ones are computed afresh)."""
    context.ledgers = (ProductLedger(), ProductLedger())
    return state.replace(deflection=None, unit=None, unit_deflection=None, pressure_change=None)


def deflection_of(state: PathState) -> tuple[PathState, object]:
    """The tip deflection (half-space + springs) of the state's pressure on its window, and the state that knows it."""
    deflection = state.known_deflection()
    if deflection is None:
        working, pressure = state.working, state.pressure
        deflection = tip_deflection(working.operator, pressure[working.window.slices], working.cache)
        state = state.replace(deflection=Known(pressure, working.window, deflection))
    return state, deflection


# -- the steps: a state in, the next state out ---------------------------------------
def with_change(context: PathContext, state: PathState, change: SpringChange | None) -> PathState:
    """``state`` after a change of the connections: new springs (a new operator) and raised tips.

    New springs make every deflection known of ``state`` stale: the new state
    has none (the one place where the operator's springs change), and its
    window (`WorkingWindow.with_problem`) the new operator; raised tips give
    the window new heights (`WorkingWindow.with_tips`).
    """
    if change is None:
        return state
    working = state.working
    if change.problem is not None:
        working = working.with_problem(change.problem)
        state = without_deflections(context, state)
    return state.replace(working=working.with_tips(change.offsets, change.lifted))


def step_from(context: PathContext, state: PathState, displacement: float, *, advance: bool = True,
              detach=None) -> tuple[PathState, Equilibrium]:
    """One step of a fixed-step path from ``state``: the state at its end and its equilibrium at d.

    Viscoelastic connections: their history offsets first (``advance``;
    False inside a step, where the step's springs and offsets hold).  A
    nonlinear pillar law: the piece iteration of `brushbem.physics.pillar_laws`,
    then the breaks, each break solved again at the same d.  ``detach``:
    elements that leave the contact first (an event located in the step).
    """
    if advance:
        connections, change = state.connections.advance()
        state = with_change(context, state.replace(connections=connections), change)
    if state.connections.pieces is None:
        return solve_from(context, state, displacement, force_detach=detach)
    from brushbem.physics.pillar_laws import MAX_PIECE_ROUNDS

    iterations = solves = detached = 0
    first = None
    moved = np.zeros(context.n_pillars, dtype=bool)

    def settled(eq: Equilibrium, **changes) -> Equilibrium:
        # The first round's trial solve is on the step's starting set and pieces: the one
        # on which the pressure is affine in d (`events._first_crossing`).
        return dataclasses.replace(eq, cg_iterations=iterations, n_solves=solves, detached=detached,
                                   trial_force_sum=first.trial_force_sum, trial_pressure=first.trial_pressure,
                                   **changes)

    for _ in range(MAX_PIECE_ROUNDS):
        state, eq = solve_from(context, state, displacement, force_detach=detach)
        first = eq if first is None else first
        iterations += eq.cg_iterations
        solves += eq.n_solves
        detached += eq.detached
        detach = None
        if not eq.converged:
            return state, settled(eq)
        connections, moved, broken, change = state.connections.update(
            pillar_forces(context, state.pressure, state.contact), state.working.problem)
        state = state.replace(connections=connections)
        if change is None:
            return state, settled(eq)
        if broken is not None:
            detach = _held_by(context, broken, state.contact)
        state = with_change(context, state, change)
    return state, settled(
        eq, converged=False,
        reason=f"the pillar law's pieces did not settle in {MAX_PIECE_ROUNDS} rounds at d = {displacement:.6g} "
               f"(pillars still changing: {np.flatnonzero(moved)[:10].tolist()})",
    )


def solve_from(context: PathContext, state: PathState, displacement: float, force_detach=None, force_attach=None,
               contact_problem: bool = False) -> tuple[PathState, Equilibrium]:
    """The equilibrium at d from ``state``, and the state it gives, on a window enlarged as needed.

    ``contact_problem``: the non-adhesive contact problem at d instead
    (Polonsky-Keer from the state's pressure), whatever the adhesion.
    """
    xp, working = context.xp, state.working
    needed = state.contact
    margin = None
    if contact_problem or context.critical == 0.0 or not bool(xp.any(needed)):
        # A cold or non-adhesive start attaches every overlapping element
        # first; the contact then only shrinks, so a thin margin suffices.
        needed = needed | (working.footprint & (working.height < displacement))
        margin = 0.02
    if force_attach is not None:
        needed = needed | force_attach
    working = working.covering(needed, margin)
    iterations = solves = 0
    trial = trial_pressure = None
    enlarged = False
    while True:
        sl = working.window.slices
        height = working.height[sl]
        if contact_problem or (context.critical == 0.0 and force_detach is None and force_attach is None
                               and solves == 0):
            eq = polonsky_keer(
                working.operator, height, displacement, state.pressure[sl],
                context.path.tolerance, context.path.max_iterations,
            )
        else:
            start = Start(
                contact=state.contact[sl], pressure=state.pressure[sl],
                deflection=_known(state.deflection, state.pressure, working.window),
                detach=None if force_detach is None else force_detach[sl],
                attach=None if force_attach is None else force_attach[sl],
            )
            eq = equilibrium(working.operator, height, displacement, start, critical=context.critical,
                             settings=context.settings, length_scale=context.length_scale, ledger=context.ledgers[0],
                             cache=working.cache)
        iterations += eq.cg_iterations
        solves += eq.n_solves
        if trial is None:
            trial = eq.trial_force_sum
            if eq.trial_pressure is not None:
                trial_pressure = xp.zeros_like(state.pressure)
                trial_pressure[sl] = eq.trial_pressure
        force_detach = force_attach = None
        pressure = xp.zeros_like(state.pressure)
        pressure[sl] = eq.pressure
        contact = xp.zeros_like(state.contact)
        contact[sl] = eq.contact
        state = state.replace(pressure=pressure, contact=contact, working=working, deflection=(
            None if eq.deflection is None else Known(pressure, working.window, eq.deflection)))
        if not eq.converged:
            break
        if working.covers_footprint or working.outside_safe(displacement, pressure, contact):
            break
        if not enlarged and bool(xp.any(contact)):
            # The contact has grown close to the window's edge, where the
            # bound cannot exclude penetration.  A window rebuilt around
            # the contact with the usual margin usually restores the
            # bound; the equilibrium is then re-checked on it (a warm
            # start at the solution: one residual and one penetration on
            # the window), far cheaper than the full-grid penetration.
            enlarged = True
            candidate = working.outside_safe_around(displacement, pressure, contact)
            if candidate is not None:
                working = working.on(candidate)
                continue
        # Penetration outside the window: the contact grew beyond it.
        outside = working.outside_penetration(displacement, pressure, contact)
        if not bool(xp.any(outside)):
            break
        working = working.covering(contact | outside)
        force_attach = outside
    return state, Equilibrium(
        displacement=displacement, pressure=state.pressure, contact=state.contact, converged=eq.converged,
        reason=eq.reason, cg_iterations=iterations, n_solves=solves, trial_force_sum=trial,
        detached=eq.detached, attached=eq.attached, deflection=eq.deflection,
        trial_pressure=trial_pressure,
    )


def _known(known: Known | None, array, window: Window | None):
    """``known``'s value if it is of ``array`` on ``window`` (`Known.of`), else None."""
    return None if known is None else known.of(array, window)


# -- the window: the contact covered, and widened to what may touch next --------------
def cover_contact(state: PathState, displacement: float, loading: bool) -> PathState:
    """``state`` on a window that holds the contact; the whole footprint when pressing and one outside may reach.

    The bound of `WorkingWindow.outside_reach_displacement` is conservative:
    when it cannot exclude a touch outside the window at ``displacement`` on
    the loading branch, the path works on the whole footprint from here on.
    """
    contact = state.contact
    working = state.working.covering(contact)
    if (loading and not working.covers_footprint
            and working.outside_reach_displacement(state.pressure, contact) <= displacement):
        working = working.covering(contact | working.footprint)
    return state.replace(working=working)


def widen_to_reach(state: PathState, displacement: float, reach: float) -> PathState:
    """``state`` on a window enlarged to every footprint element whose tip is at most ``reach`` high.

    The whole footprint when that leaves the window as it was, or when
    the bound still cannot exclude a touch outside it at ``displacement``.
    """
    contact, before = state.contact, state.working
    working = before.covering(contact | (before.footprint & (before.height <= reach)))
    if working.window == before.window or working.outside_reach_displacement(state.pressure, contact) <= displacement:
        working = working.covering(contact | working.footprint)
    return state.replace(working=working)


# -- connections with a state: viscoelastic (in time) or nonlinear (pieces) --------
def pillar_forces(context: PathContext, pressure, contact) -> np.ndarray:
    """Force of every pillar under ``pressure`` on ``contact`` (full grid; compressive positive)."""
    contact = np.asarray(backend.to_numpy(contact))
    pressure = np.asarray(backend.to_numpy(pressure))
    pillar = context.pillar_host
    return context.h2 * np.bincount(pillar[contact], weights=pressure[contact], minlength=context.n_pillars)


def _held_by(context: PathContext, pillars: np.ndarray, contact):
    """The elements of ``contact`` on ``pillars`` (bool, one per pillar), a full-grid mask."""
    return contact & context.xp.asarray(np.isin(context.pillar_host, np.flatnonzero(pillars)))


def restore_pieces(context: PathContext, state: PathState, point: PathState) -> PathState:
    """``state`` back at the pieces and breaks of ``point``: the springs and the tips with them."""
    connections, change = state.connections.restore(point.connections, state.working.problem)
    return with_change(context, state.replace(connections=connections), change)


def break_pillars(context: PathContext, state: PathState, pillars: np.ndarray):
    """``state`` with ``pillars`` (bool, one per pillar) broken and lifted, and the elements they held (a mask)."""
    connections, change = state.connections.break_pillars(pillars)
    return with_change(context, state.replace(connections=connections), change), _held_by(context, pillars,
                                                                                          state.contact)


def commit_history(context: PathContext, state: PathState) -> PathState:
    """After a time step's equilibrium: the connections' compression and arm forces from the pillar forces."""
    connections = state.connections
    if connections.memory is None:
        return state
    return state.replace(connections=connections.commit(pillar_forces(context, state.pressure, state.contact)))
