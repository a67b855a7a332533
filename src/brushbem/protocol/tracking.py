"""The state of one pull-off (`Tracker`): pressure and contact on the full grid, the solves and the records.

The `Tracker` composes the parts of that state that have their own modules:
the working window and its operator (``working``, a
`brushbem.protocol.window.WorkingWindow`) and the connections' state
(``connections``, a `brushbem.protocol.connections.ConnectionState`: the
viscoelastic memory and the pillar law's pieces).  It holds the pressure and
the contact set, the solves (`Tracker.solve`, `Tracker.step_solve`, the unit
response of the event path), the deflections known without another
transform, and the `State` records.  The load paths
(`brushbem.protocol.paths`, `brushbem.protocol.events`,
`brushbem.protocol.contact_loading`) use only its public members.

Cached deflections: the deflection of the pressure and of the unit response
are kept with the array and the window they were computed on, and are used
only while both are the current ones.  They are computed with the window's
operator, so when the connections change the pillars' springs (a piece of a
nonlinear law moves) every one of them, the unit response and the cascade's
pressure change are dropped (`Tracker._apply`, the one place where the
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
from brushbem.numerics.operator import ContactOperator, Window
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
from brushbem.protocol.problem import ContactProblem, LoadPath, State
from brushbem.protocol.values import Known, PathPoint
from brushbem.protocol.window import WorkingWindow

__all__ = ["Tracker"]


class Tracker:
    """The state of one pull-off: pressure and contact, the window (``working``) and the connections.

    ``pressure`` and ``contact`` (full grid) are the current equilibrium's;
    the paths read them and replace them through `set_state`,
    `set_pressure` and `restore`.
    """

    def __init__(self, problem: ContactProblem, path: LoadPath):
        self.path = path
        self.connections, problem = ConnectionState.begin(problem, path)
        self.settings = Settings(tolerance=path.tolerance, max_iterations=path.max_iterations, cascade=path.cascade)
        xp = problem.xp
        self.xp = xp
        self.working = WorkingWindow(problem, path)
        grid = problem.grid
        n = grid.elements
        self.h2 = grid.element_size**2
        indenter = problem.indenter
        self.pillar = xp.asarray(indenter.pillar)
        self.n_pillars = indenter.n_pillars
        self.critical = problem.critical_stress
        self.pressure = xp.zeros((n, n), dtype=xp.float64)
        self.contact = xp.zeros((n, n), dtype=xp.bool)
        self.unit = None  # a = A_S^-1 1, full grid (warm start for the next one, kept across windows)
        # Deflections known without another transform (`Known`: of an array on a
        # window): of self.pressure, and of self.unit (module docstring: when they
        # are dropped).
        self._known_deflection: Known | None = None
        self._unit_deflection: Known | None = None
        # Of the contact array on the window: (dp, K dp), how the last cascade changed
        # the pressure beyond the affine prediction, for the next unit response.
        self._pressure_change: Known | None = None
        # The error that single-precision products left in the kept deflections of the equilibria and
        # of the unit responses (`brushbem.numerics.solver.cg.ProductLedger`).
        self._ledgers = (ProductLedger(), ProductLedger())
        self.length_scale = 0.0  # the largest |d| reached: the path's length scale
        self._footprint_elements: tuple | None = None  # (window, footprint, rows, cols): `footprint_elements`

    # -- what the window holds ------------------------------------------------
    @property
    def problem(self) -> ContactProblem:
        """The problem the solves see: the pillars' springs of the connections' current state."""
        return self.working.problem

    @property
    def window(self) -> Window | None:
        """The current working window (None before the first solve)."""
        return self.working.window

    @property
    def operator(self) -> ContactOperator | None:
        """The contact operator on the current window."""
        return self.working.operator

    @property
    def height(self):
        """Tip heights on the full grid (inf off the footprint), the connections' offsets included."""
        return self.working.height

    @property
    def footprint(self):
        """The indenter's footprint on the full grid (bool)."""
        return self.working.footprint

    @property
    def covers_footprint(self) -> bool:
        """Whether the window holds the whole footprint."""
        return self.working.covers_footprint

    def footprint_elements(self):
        """Row and column (host arrays) of every footprint element of the window, row-major (cached)."""
        cached = self._footprint_elements
        if cached is None or cached[0] != self.window or cached[1] is not self.footprint:
            rows, cols = np.nonzero(np.asarray(backend.to_numpy(self.footprint[self.window.slices])))
            cached = self._footprint_elements = (self.window, self.footprint, rows, cols)
        return cached[2], cached[3]

    @property
    def has_contact(self) -> bool:
        """Whether any element is in contact."""
        return bool(self.xp.any(self.contact))

    def cover_contact(self, displacement: float, loading: bool) -> None:
        """A window that holds the contact; the whole footprint when pressing and one outside may reach.

        The bound of `outside_reach_displacement` is conservative: when it
        cannot exclude a touch outside the window at ``displacement`` on the
        loading branch, the path works on the whole footprint from here on.
        """
        self.working.ensure(self.contact)
        if loading and not self.covers_footprint and self.outside_reach_displacement() <= displacement:
            self.working.ensure(self.contact | self.footprint)

    def widen_to_reach(self, displacement: float, reach: float) -> None:
        """A window enlarged to every footprint element whose tip is at most ``reach`` high.

        The whole footprint when that leaves the window as it was, or when
        the bound still cannot exclude a touch outside it at ``displacement``.
        """
        before = self.window
        self.working.ensure(self.contact | (self.footprint & (self.height <= reach)))
        if self.window == before or self.outside_reach_displacement() <= displacement:
            self.working.ensure(self.contact | self.footprint)

    def outside_reach_displacement(self) -> float:
        """The smallest base displacement at which an element outside the window could touch (a bound)."""
        return self.working.outside_reach_displacement(self.pressure, self.contact)

    def full_penetration(self, displacement: float, pressure):
        """Penetration of every element of the grid at ``displacement`` under ``pressure`` (full grid)."""
        return self.working.full_penetration(displacement, pressure)

    # -- connections with a state: viscoelastic (in time) or nonlinear (pieces) --
    @property
    def has_connection_state(self) -> bool:
        """Whether the connections carry a state (viscoelastic history or a nonlinear pillar law)."""
        return self.connections.has_state

    def _apply(self, change: SpringChange | None) -> None:
        """Apply a change of the connections: new springs (a new operator) and raised tips.

        New springs make every cached deflection stale: they are dropped here,
        the one place where the operator's springs change.
        """
        if change is None:
            return
        if change.problem is not None:
            self.working.use_problem(change.problem)
            self.forget_deflections()
        self.working.raise_tips(change.offsets, change.lifted)

    def pillar_forces(self, pressure=None, contact=None) -> np.ndarray:
        """Force of every pillar in the current state, or of the given one (compressive positive)."""
        contact = np.asarray(backend.to_numpy(self.contact if contact is None else contact))
        pressure = np.asarray(backend.to_numpy(self.pressure if pressure is None else pressure))
        pillar = self.working.pillar_host
        return self.h2 * np.bincount(pillar[contact], weights=pressure[contact], minlength=self.n_pillars)

    def _held_by(self, pillars: np.ndarray):
        """The contact elements of ``pillars`` (bool, one per pillar), a full-grid mask."""
        return self.contact & self.xp.asarray(np.isin(self.working.pillar_host, np.flatnonzero(pillars)))

    @property
    def tension_limit(self) -> float | None:
        """The pillar law's tension limit, or None."""
        return self.connections.tension_limit

    def point(self, displacement: float | None = None) -> PathPoint:
        """The current state as a value to return to: pressure, contact and the pillar law's pieces (a copy)."""
        return PathPoint(displacement, self.pressure, self.contact, self.connections.saved())

    def broken_pillars(self, pieces=None) -> np.ndarray:
        """The broken pillars (bool per pillar) now, or in ``pieces`` (a `PathPoint`'s) when given."""
        return self.connections.broken(pieces)

    def restore_pieces(self, point: PathPoint) -> None:
        """Back to the pieces and breaks of ``point``: the springs and the tips with them."""
        self._apply(self.connections.restore(point.pieces, self.problem))

    def break_pillars(self, pillars: np.ndarray):
        """Mark ``pillars`` (bool, one per pillar) broken and lift them; the elements they held (a mask)."""
        self._apply(self.connections.break_pillars(pillars))
        return self._held_by(pillars)

    def advance_history(self) -> None:
        """Before a time step: every pillar's tip raised by its connection's history offset b."""
        self._apply(self.connections.advance())

    def commit_history(self) -> None:
        """After a time step's equilibrium: the connections' compression and arm forces from the pillar forces."""
        if self.connections.memory is not None:
            self.connections.commit(self.pillar_forces())

    def step_solve(self, displacement: float, *, advance: bool = True, detach=None) -> Equilibrium:
        """One step of a fixed-step path: the equilibrium at d with the connections' state.

        Viscoelastic connections: their history offsets first (``advance``;
        False inside a step, where the step's springs and offsets hold).  A
        nonlinear pillar law: the piece iteration of `brushbem.physics.pillar_laws`,
        then the breaks, each break solved again at the same d.  ``detach``:
        elements that leave the contact first (an event located in the step).
        """
        if advance:
            self.advance_history()
        if self.connections.pieces is None:
            return self.solve(displacement, force_detach=detach)
        from brushbem.physics.pillar_laws import MAX_PIECE_ROUNDS

        iterations = solves = detached = 0
        first = None
        moved = np.zeros(self.n_pillars, dtype=bool)

        def settled(eq: Equilibrium, **changes) -> Equilibrium:
            # The first round's trial solve is on the step's starting set and pieces: the one
            # on which the pressure is affine in d (`events._first_crossing`).
            return dataclasses.replace(eq, cg_iterations=iterations, n_solves=solves, detached=detached,
                                       trial_force_sum=first.trial_force_sum, trial_pressure=first.trial_pressure,
                                       **changes)

        for _ in range(MAX_PIECE_ROUNDS):
            eq = self.solve(displacement, force_detach=detach)
            first = eq if first is None else first
            iterations += eq.cg_iterations
            solves += eq.n_solves
            detached += eq.detached
            detach = None
            if not eq.converged:
                return settled(eq)
            moved, broken, change = self.connections.update(self.pillar_forces(), self.problem)
            if change is None:
                return settled(eq)
            if broken is not None:
                detach = self._held_by(broken)
            self._apply(change)
        return settled(
            eq, converged=False,
            reason=f"the pillar law's pieces did not settle in {MAX_PIECE_ROUNDS} rounds at d = {displacement:.6g} "
                   f"(pillars still changing: {np.flatnonzero(moved)[:10].tolist()})",
        )

    # -- solves -------------------------------------------------------------
    def solve(self, displacement: float, force_detach=None, force_attach=None,
              contact_problem: bool = False) -> Equilibrium:
        """Equilibrium at d from the current state; enlarges the window as needed.

        ``contact_problem``: the non-adhesive contact problem at d instead
        (Polonsky-Keer from the current pressure), whatever the adhesion.
        """
        xp = self.xp
        needed = self.contact
        margin = None
        if contact_problem or self.critical == 0.0 or not bool(xp.any(self.contact)):
            # A cold or non-adhesive start attaches every overlapping element
            # first; the contact then only shrinks, so a thin margin suffices.
            needed = needed | (self.footprint & (self.height < displacement))
            margin = 0.02
        if force_attach is not None:
            needed = needed | force_attach
        self.working.ensure(needed, margin)
        iterations = solves = 0
        trial = trial_pressure = None
        enlarged = False
        while True:
            sl = self.window.slices
            height = self.height[sl]
            if contact_problem or (self.critical == 0.0 and force_detach is None and force_attach is None
                                   and solves == 0):
                eq = polonsky_keer(
                    self.operator, height, displacement, self.pressure[sl],
                    self.path.tolerance, self.path.max_iterations,
                )
            else:
                start = Start(
                    contact=self.contact[sl], pressure=self.pressure[sl], deflection=self.known_deflection(),
                    detach=None if force_detach is None else force_detach[sl],
                    attach=None if force_attach is None else force_attach[sl],
                )
                eq = equilibrium(self.operator, height, displacement, start, critical=self.critical,
                                 settings=self.settings, length_scale=self.length_scale, ledger=self._ledgers[0],
                                 cache=self.working.cache)
            iterations += eq.cg_iterations
            solves += eq.n_solves
            if trial is None:
                trial = eq.trial_force_sum
                if eq.trial_pressure is not None:
                    trial_pressure = xp.zeros_like(self.pressure)
                    trial_pressure[sl] = eq.trial_pressure
            force_detach = force_attach = None
            self.pressure = xp.zeros_like(self.pressure)
            self.pressure[sl] = eq.pressure
            self.contact = xp.zeros_like(self.contact)
            self.contact[sl] = eq.contact
            self._known_deflection = None if eq.deflection is None else Known(self.pressure, self.window, eq.deflection)
            if not eq.converged:
                break
            if self.covers_footprint or self.working.outside_safe(displacement, self.pressure, self.contact):
                break
            if not enlarged and bool(xp.any(self.contact)):
                # The contact has grown close to the window's edge, where the
                # bound cannot exclude penetration.  A window rebuilt around
                # the contact with the usual margin usually restores the
                # bound; the equilibrium is then re-checked on it (a warm
                # start at the solution: one residual and one penetration on
                # the window), far cheaper than the full-grid penetration.
                enlarged = True
                candidate = self.working.outside_safe_around(displacement, self.pressure, self.contact)
                if candidate is not None:
                    self.working.install(candidate)
                    continue
            # Penetration outside the window: the contact grew beyond it.
            outside = self.working.outside_penetration(displacement, self.pressure, self.contact)
            if not bool(xp.any(outside)):
                break
            self.working.ensure(self.contact | outside)
            force_attach = outside
        return Equilibrium(
            displacement=displacement, pressure=self.pressure, contact=self.contact, converged=eq.converged,
            reason=eq.reason, cg_iterations=iterations, n_solves=solves, trial_force_sum=trial,
            detached=eq.detached, attached=eq.attached, deflection=eq.deflection,
            trial_pressure=trial_pressure,
        )

    # -- the state and its deflection (module docstring: when cached deflections are dropped) --
    def set_state(self, pressure, contact) -> None:
        """A new pressure and contact set (full grid); no deflection of the pressure known."""
        self.contact = contact
        self.set_pressure(pressure)

    def restore(self, point: PathPoint) -> None:
        """Back to the pressure and contact of ``point``; a deflection still cached of that pressure is kept."""
        self.pressure, self.contact = point.pressure, point.contact

    def forget_deflections(self) -> None:
        """Drop every cached deflection and the unit response (the next ones are computed afresh)."""
        self._known_deflection = self._unit_deflection = self._pressure_change = None
        self.unit = None
        self._ledgers = (ProductLedger(), ProductLedger())

    def known_deflection(self):
        """Tip deflection of the current pressure on the window if known, else None."""
        known = self._known_deflection
        return None if known is None else known.of(self.pressure, self.window)

    def deflection(self):
        """Tip deflection (half-space + springs) of the current pressure on the window."""
        deflection = self.known_deflection()
        if deflection is None:
            deflection = tip_deflection(self.operator, self.pressure[self.window.slices], self.working.cache)
            self._known_deflection = Known(self.pressure, self.window, deflection)
        return deflection

    def set_pressure(self, pressure, deflection=None) -> None:
        """Replace the pressure (full grid), with its tip deflection on the window if known."""
        self.pressure = pressure
        self._known_deflection = None if deflection is None else Known(pressure, self.window, deflection)

    # -- the unit response of the event path ---------------------------------------
    def unit_deflection(self):
        """Tip deflection of the unit response on the window (transformed once per response)."""
        known = None if self._unit_deflection is None else self._unit_deflection.of(self.unit, self.window)
        if known is not None:
            return known
        deflection = tip_deflection(self.operator, self.unit[self.window.slices], self.working.cache)
        self._unit_deflection = Known(self.unit, self.window, deflection)
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
        self._pressure_change = None
        deflection = self.known_deflection()
        if deflection is None or window != self.window:
            return
        sl = window.slices
        record = cascade_record(self.operator, self.contact[sl], predicted[sl], self.pressure[sl], deflection,
                                predicted_deflection)
        if record is not None:
            self._pressure_change = Known(self.contact, window, record)

    def unit_response(self):
        """a = A_S^-1 1 on the window (dp/dd for the fixed contact set)."""
        xp = self.xp
        sl = self.window.slices
        contact = self.contact[sl]
        block, operator = self.working.cache.sub_operator(self.operator, contact)
        block_contact = contact[block]
        ones = xp.astype(block_contact, xp.float64)
        initial, product = self._unit_guess(contact)
        result = solve_on_set(
            operator, block_contact, ones,
            initial=None if initial is None else initial[block],
            initial_product=None if product is None else product[block],
            tolerance=self.path.tolerance, max_iterations=self.path.max_iterations, ledger=self._ledgers[1],
            cache=self.working.cache,
        )
        solution = xp.zeros(contact.shape, dtype=ones.dtype)
        solution[block] = result.solution
        result = dataclasses.replace(result, solution=solution)
        if result.converged:
            self.unit = xp.zeros_like(self.pressure)
            self.unit[sl] = solution
        else:
            self.unit = None
        return result

    def _unit_guess(self, contact):
        """Starting guess for A_S^-1 1 on the window and its deflection (None where unknown).

        The previous response restricted to S, its deflection kept in step by
        dropping the elements that left (no transform for a few of them).
        After a cascade the guess is the Galerkin (energy-optimal) combination
        of that and the cascade's pressure change dp (``record_pressure_change``),
        exact for a single element leaving (`brushbem.protocol.unit_guess`).
        """
        if self.unit is None:
            return None, None
        previous = self.unit[self.window.slices]
        known = None if self._unit_deflection is None else self._unit_deflection.of(self.unit, self.window)
        if known is None:
            return self.xp.where(contact, previous, 0.0), None
        change = None if self._pressure_change is None else self._pressure_change.of(self.contact, self.window)
        return unit_guess(self.operator, contact, previous, known, change)

    # -- records ------------------------------------------------------------
    def _on_window(self, array):
        """``array`` (full grid) restricted to the window, where every pressure
        and contact set of the path lies (the window always holds the contact)."""
        return array if self.window is None else array[self.window.slices]

    def force(self, pressure=None) -> float:
        """The total force of the current pressure, or of ``pressure`` (full grid; compressive positive)."""
        p = self.pressure if pressure is None else pressure
        return self.h2 * float(self.xp.sum(self._on_window(p)))

    def attached_pillars(self, contact=None) -> int:
        """How many pillars touch in the current contact set, or in ``contact`` (full grid)."""
        c = self.contact if contact is None else contact
        if self.n_pillars == 1:
            return int(bool(self.xp.any(self._on_window(c))))
        labels = self.pillar[c]
        if labels.shape[0] == 0:
            return 0
        return int(self.xp.unique_values(labels).shape[0])

    def state(self, displacement, loading, kind, trial_force, iterations, solves, converged, reason,
              pressure=None, contact=None) -> State:
        """The `State` at ``displacement`` of the given pressure and contact (default: the tracker's).

        Why these parameters: one per field of `State` that the caller knows (the rest are computed here).
        """
        p = self.pressure if pressure is None else pressure
        c = self.contact if contact is None else contact
        self.length_scale = max(self.length_scale, abs(float(displacement)))
        return State(
            displacement=float(displacement),
            force=self.force(p),
            contact_area=self.h2 * int(self.xp.count_nonzero(self._on_window(c))),
            attached_pillars=self.attached_pillars(c),
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
