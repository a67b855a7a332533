"""The state of one pull-off (`Tracker`): pressure and contact on the full grid, the solves and the records.

The `Tracker` holds the path's state as one frozen value, ``state`` (a
`brushbem.protocol.values.PathState`: the pressure and the contact set, the
working window with its operator and tip heights (a
`brushbem.protocol.window.WorkingWindow`), the connections' state (a
`brushbem.protocol.connections.ConnectionState`: the viscoelastic memory and
the pillar law's pieces), the deflections known of them without another
transform, the last unit response), which it replaces and never writes into,
sharing every array that did not change; a saved state (`Tracker.point`) is
that value, its window included, and `Tracker.restore` returns to its
pressure and contact (on the current window: a window is a choice of where
to compute, and the path keeps the one it has).

The steps take a state and give the next one: `solve_from` (the equilibrium
at d, on a window enlarged as the contact needs), `step_from` (a fixed step:
the connections' history, a law's pieces and breaks), `with_change` (a
change of the connections: new springs give the window a new operator,
raised tips new heights), `cover_contact` and `widen_to_reach` (the window
the event path predicts on).  What they keep besides is the solver's: the
`SolverCache` each window refers to and the ledgers of single-precision
products.  `Tracker.solve` and `Tracker.step_solve` take the tracker's state
through them.  The load paths (`brushbem.protocol.paths`,
`brushbem.protocol.events`, `brushbem.protocol.contact_loading`) use the
tracker's public members and its state's directly
(``tracker.state.working.window``, ``tracker.state.connections.tension_limit``);
what they do with the connections through the tracker's state are the
module's functions (`pillar_forces`, `break_pillars`, `restore_pieces`,
`commit_history`).  The `State` records are made in
`brushbem.protocol.path_states`.

Cached deflections: the deflection of the pressure and of the unit response
are kept with the array and the window they were computed on, and are used
only while both are the current ones.  They are computed with the window's
operator, so when the connections change the pillars' springs (a piece of a
nonlinear law moves) every one of them, the unit response and the cascade's
pressure change are dropped (`with_change`, the one place where the
operator's springs change).  Raised tips (history offsets, breaks) change the
heights, not the operator: the cached deflections stay valid.  A pressure
put in by the paths comes without a known deflection (`Tracker.set_state`,
`Tracker.set_pressure`) unless they give it; `Tracker.forget_deflections`
drops all of them.
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
    solve_on_set,
    tip_deflection,
)
from brushbem.protocol.unit_guess import cascade_record, unit_guess
from brushbem.protocol.connections import ConnectionState, SpringChange
from brushbem.protocol.problem import ContactProblem, LoadPath
from brushbem.protocol.values import Known, PathState
from brushbem.protocol.window import WorkingWindow

__all__ = [
    "Tracker",
    "break_pillars",
    "commit_history",
    "cover_contact",
    "pillar_forces",
    "restore_pieces",
    "solve_from",
    "step_from",
    "widen_to_reach",
    "with_change",
]


class Tracker:
    """The state of one pull-off: pressure and contact, the window and the connections (``state``).

    ``pressure`` and ``contact`` (full grid) are the current equilibrium's;
    the paths read them and replace them through `set_state`,
    `set_pressure` and `restore`.
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
        self.n_pillars = indenter.n_pillars
        self.critical = problem.critical_stress
        #: The path's state as one value (`PathState`): pressure, contact and what is known of them (the
        #: deflections: module docstring, when they are dropped).  Replaced, never written into.
        self.state = PathState(pressure=xp.zeros((n, n), dtype=xp.float64), contact=xp.zeros((n, n), dtype=xp.bool),
                               working=WorkingWindow.begin(problem, path), connections=connections)
        # The error that single-precision products left in the kept deflections of the equilibria and
        # of the unit responses (`brushbem.numerics.solver.cg.ProductLedger`).
        self._ledgers = (ProductLedger(), ProductLedger())
        self.length_scale = 0.0  # the largest |d| reached: the path's length scale

    def apply_change(self, change: SpringChange | None) -> None:
        """Apply a change of the connections: new springs (a new operator) and raised tips (`with_change`)."""
        self.state = with_change(self, self.state, change)

    def point(self, displacement: float | None = None) -> PathState:
        """The current state as a value to return to (`restore`, `restore_pieces`), with its ``displacement``."""
        return self.state.replace(displacement=displacement)

    def step_solve(self, displacement: float, *, advance: bool = True, detach=None) -> Equilibrium:
        """One step of a fixed-step path from the current state (`step_from`); the state becomes its end."""
        self.state, eq = step_from(self, self.state, displacement, advance=advance, detach=detach)
        return eq

    # -- solves -------------------------------------------------------------
    def solve(self, displacement: float, force_detach=None, force_attach=None,
              contact_problem: bool = False) -> Equilibrium:
        """Equilibrium at d from the current state (`solve_from`); the state becomes the equilibrium's."""
        self.state, eq = solve_from(self, self.state, displacement, force_detach, force_attach, contact_problem)
        return eq

    # -- the state and its deflection (module docstring: when cached deflections are dropped) --
    def set_state(self, pressure, contact) -> None:
        """A new pressure and contact set (full grid); no deflection of the pressure known."""
        self.state = self.state.replace(pressure=pressure, contact=contact, deflection=None)

    def restore(self, point: PathState) -> None:
        """Back to the pressure and contact of ``point`` (a saved state, `point`; its pieces: `restore_pieces`).

        What is known (the deflections, the unit response) stays the current state's: each is used only
        while it is of the restored arrays on the current window (`Known.of`).
        """
        self.state = self.state.replace(pressure=point.pressure, contact=point.contact)

    def forget_deflections(self) -> None:
        """Drop every cached deflection and the unit response (the next ones are computed afresh; `with_change`)."""
        self.state = self.state.replace(deflection=None, unit=None, unit_deflection=None, pressure_change=None)
        self._ledgers = (ProductLedger(), ProductLedger())

    def known_deflection(self):
        """Tip deflection of the current pressure on the window if known, else None."""
        return _known(self.state.deflection, self.state.pressure, self.state.working.window)

    def deflection(self):
        """Tip deflection (half-space + springs) of the current pressure on the window."""
        deflection = self.known_deflection()
        if deflection is None:
            working, pressure = self.state.working, self.state.pressure
            deflection = tip_deflection(working.operator, pressure[working.window.slices], working.cache)
            self.state = self.state.replace(deflection=Known(pressure, working.window, deflection))
        return deflection

    def set_pressure(self, pressure, deflection=None) -> None:
        """Replace the pressure (full grid), with its tip deflection on the window if known."""
        self.state = self.state.replace(pressure=pressure, deflection=(
            None if deflection is None else Known(pressure, self.state.working.window, deflection)))

    # -- the unit response of the event path ---------------------------------------
    def unit_deflection(self):
        """Tip deflection of the unit response on the window (transformed once per response)."""
        state = self.state
        working = state.working
        window = working.window
        known = None if state.unit_deflection is None else state.unit_deflection.of(state.unit, window)
        if known is not None:
            return known
        deflection = tip_deflection(working.operator, state.unit[window.slices], working.cache)
        self.state = state.replace(unit_deflection=Known(state.unit, window, deflection))
        return deflection

    def record_pressure_change(self, predicted, predicted_deflection, window: Window) -> None:
        """Remember dp = p - predicted on the contact and what its product needs, after a cascade at fixed d.

        ``predicted`` is the affine prediction the cascade started from (full
        grid) and ``predicted_deflection`` its tip deflection on ``window``.
        For a single element k leaving S the new unit response is exactly
        a|S' + (a_k / p_k) dp (both corrections are A_S'^-1 A_S'k times a
        scalar), so dp is the natural second direction of the next unit
        response's starting guess (``unit_response``, `brushbem.protocol.unit_guess`).
        What is kept of it: `brushbem.protocol.unit_guess.cascade_record`.
        """
        self.state = self.state.replace(pressure_change=None)
        deflection = self.known_deflection()
        if deflection is None or window != self.state.working.window:
            return
        sl = window.slices
        state = self.state
        record = cascade_record(state.working.operator, state.contact[sl], predicted[sl], state.pressure[sl],
                                deflection, predicted_deflection)
        if record is not None:
            self.state = state.replace(pressure_change=Known(state.contact, window, record))

    def unit_response(self):
        """a = A_S^-1 1 on the window (dp/dd for the fixed contact set)."""
        xp = self.xp
        working = self.state.working
        sl = working.window.slices
        contact = self.state.contact[sl]
        block, operator = working.cache.sub_operator(working.operator, contact)
        block_contact = contact[block]
        ones = xp.astype(block_contact, xp.float64)
        initial, product = self._unit_guess(contact)
        result = solve_on_set(
            operator, block_contact, ones,
            initial=None if initial is None else initial[block],
            initial_product=None if product is None else product[block],
            tolerance=self.path.tolerance, max_iterations=self.path.max_iterations, ledger=self._ledgers[1],
            cache=working.cache,
        )
        solution = xp.zeros(contact.shape, dtype=ones.dtype)
        solution[block] = result.solution
        result = dataclasses.replace(result, solution=solution)
        unit = None
        if result.converged:
            unit = xp.zeros_like(self.state.pressure)
            unit[sl] = solution
        self.state = self.state.replace(unit=unit)
        return result

    def _unit_guess(self, contact):
        """Starting guess for A_S^-1 1 on the window and its deflection (None where unknown).

        The previous response restricted to S, its deflection kept in step by
        dropping the elements that left (no transform for a few of them).
        After a cascade the guess is the Galerkin (energy-optimal) combination
        of that and the cascade's pressure change dp (``record_pressure_change``),
        exact for a single element leaving (`brushbem.protocol.unit_guess`).
        """
        state = self.state
        window = state.working.window
        if state.unit is None:
            return None, None
        previous = state.unit[window.slices]
        known = None if state.unit_deflection is None else state.unit_deflection.of(state.unit, window)
        if known is None:
            return self.xp.where(contact, previous, 0.0), None
        change = None if state.pressure_change is None else state.pressure_change.of(state.contact, window)
        return unit_guess(state.working.operator, contact, previous, known, change)


# -- the steps: a state in, the next state out ---------------------------------------
def with_change(tracker: Tracker, state: PathState, change: SpringChange | None) -> PathState:
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
        state = state.replace(deflection=None, unit=None, unit_deflection=None, pressure_change=None)
        tracker._ledgers = (ProductLedger(), ProductLedger())
    return state.replace(working=working.with_tips(change.offsets, change.lifted))


def step_from(tracker: Tracker, state: PathState, displacement: float, *, advance: bool = True,
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
        state = with_change(tracker, state.replace(connections=connections), change)
    if state.connections.pieces is None:
        return solve_from(tracker, state, displacement, force_detach=detach)
    from brushbem.physics.pillar_laws import MAX_PIECE_ROUNDS

    iterations = solves = detached = 0
    first = None
    moved = np.zeros(tracker.n_pillars, dtype=bool)

    def settled(eq: Equilibrium, **changes) -> Equilibrium:
        # The first round's trial solve is on the step's starting set and pieces: the one
        # on which the pressure is affine in d (`events._first_crossing`).
        return dataclasses.replace(eq, cg_iterations=iterations, n_solves=solves, detached=detached,
                                   trial_force_sum=first.trial_force_sum, trial_pressure=first.trial_pressure,
                                   **changes)

    for _ in range(MAX_PIECE_ROUNDS):
        state, eq = solve_from(tracker, state, displacement, force_detach=detach)
        first = eq if first is None else first
        iterations += eq.cg_iterations
        solves += eq.n_solves
        detached += eq.detached
        detach = None
        if not eq.converged:
            return state, settled(eq)
        connections, moved, broken, change = state.connections.update(
            pillar_forces(tracker, state.pressure, state.contact), state.working.problem)
        state = state.replace(connections=connections)
        if change is None:
            return state, settled(eq)
        if broken is not None:
            detach = _held_by(tracker, broken, state.contact)
        state = with_change(tracker, state, change)
    return state, settled(
        eq, converged=False,
        reason=f"the pillar law's pieces did not settle in {MAX_PIECE_ROUNDS} rounds at d = {displacement:.6g} "
               f"(pillars still changing: {np.flatnonzero(moved)[:10].tolist()})",
    )


def solve_from(tracker: Tracker, state: PathState, displacement: float, force_detach=None, force_attach=None,
               contact_problem: bool = False) -> tuple[PathState, Equilibrium]:
    """The equilibrium at d from ``state``, and the state it gives, on a window enlarged as needed.

    ``contact_problem``: the non-adhesive contact problem at d instead
    (Polonsky-Keer from the state's pressure), whatever the adhesion.
    """
    xp, working = tracker.xp, state.working
    needed = state.contact
    margin = None
    if contact_problem or tracker.critical == 0.0 or not bool(xp.any(needed)):
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
        if contact_problem or (tracker.critical == 0.0 and force_detach is None and force_attach is None
                               and solves == 0):
            eq = polonsky_keer(
                working.operator, height, displacement, state.pressure[sl],
                tracker.path.tolerance, tracker.path.max_iterations,
            )
        else:
            start = Start(
                contact=state.contact[sl], pressure=state.pressure[sl],
                deflection=_known(state.deflection, state.pressure, working.window),
                detach=None if force_detach is None else force_detach[sl],
                attach=None if force_attach is None else force_attach[sl],
            )
            eq = equilibrium(working.operator, height, displacement, start, critical=tracker.critical,
                             settings=tracker.settings, length_scale=tracker.length_scale, ledger=tracker._ledgers[0],
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
def pillar_forces(tracker: Tracker, pressure=None, contact=None) -> np.ndarray:
    """Force of every pillar in the tracker's state, or of the given one (compressive positive)."""
    contact = np.asarray(backend.to_numpy(tracker.state.contact if contact is None else contact))
    pressure = np.asarray(backend.to_numpy(tracker.state.pressure if pressure is None else pressure))
    pillar = tracker.state.working.pillar_host
    return tracker.h2 * np.bincount(pillar[contact], weights=pressure[contact], minlength=tracker.n_pillars)


def _held_by(tracker: Tracker, pillars: np.ndarray, contact=None):
    """The contact elements of ``pillars`` (bool, one per pillar) in ``contact`` (default: the tracker's), a full-grid
    mask."""
    contact = tracker.state.contact if contact is None else contact
    return contact & tracker.xp.asarray(np.isin(tracker.state.working.pillar_host, np.flatnonzero(pillars)))


def restore_pieces(tracker: Tracker, point: PathState) -> None:
    """Back to the pieces and breaks of ``point``: the springs and the tips with them."""
    connections, change = tracker.state.connections.restore(point.connections, tracker.state.working.problem)
    tracker.state = tracker.state.replace(connections=connections)
    tracker.apply_change(change)


def break_pillars(tracker: Tracker, pillars: np.ndarray):
    """Mark ``pillars`` (bool, one per pillar) broken and lift them; the elements they held (a mask)."""
    connections, change = tracker.state.connections.break_pillars(pillars)
    tracker.state = tracker.state.replace(connections=connections)
    tracker.apply_change(change)
    return _held_by(tracker, pillars)


def commit_history(tracker: Tracker) -> None:
    """After a time step's equilibrium: the connections' compression and arm forces from the pillar forces."""
    connections = tracker.state.connections
    if connections.memory is not None:
        tracker.state = tracker.state.replace(connections=connections.commit(pillar_forces(tracker)))
