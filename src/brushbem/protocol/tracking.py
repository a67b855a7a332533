"""The state of a pull-off on the full grid, its working window and the window's operator (`Tracker`)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from .. import backend
from ..halfspace import HalfSpace
from ..operator import ContactOperator, Window, fast_size
from ..solver import (
    Equilibrium,
    Settings,
    Start,
    equilibrium,
    penetration,
    polonsky_keer,
    solve_on_set,
    tip_deflection,
)
from ..structure import SpringLevel
from .problem import ContactProblem, LoadPath, State

__all__ = ["Tracker"]


#: A window this many times wider (+ 8 elements) than a fresh one around the
#: contact is rebuilt.  The JKR benchmark's unloading windows: 1.15 -> 6 % less
#: area than the former "2 x the contact + 16" rule, at 1 more rebuild (a few
#: transforms and a cached spectrum each).
_OVERSIZED = 1.15


class Tracker:
    """Full-grid state, the working window and its operator."""

    def __init__(self, problem: ContactProblem, path: LoadPath):
        self.path = path
        #: The viscoelastic connections' history along a time-stepped path (`brushbem.viscoelastic`), else None.
        self.memory = None
        if problem.indenter.viscoelastic is not None:
            from ..viscoelastic import Memory

            self.memory = Memory(problem.indenter, path.step, path.speed)
            # The solves see the pillar springs of the step's stiffness k_eff.
            problem = dataclasses.replace(problem, indenter=self.memory.stepped)
        #: The pieces of a nonlinear pillar law and the broken pillars (`brushbem.pillar_laws`), else None.
        self.pieces = None
        if problem.indenter.pillar_law is not None:
            from ..pillar_laws import PieceState

            self.pieces = PieceState(problem.indenter.pillar_law, problem.indenter.levels[0].stiffnesses)
            # The springs of the piece that holds F = 0 (its offset is 0).
            level = problem.indenter.levels[0]
            levels = (SpringLevel(self.pieces.springs()[0], level.cluster), *problem.indenter.levels[1:])
            problem = dataclasses.replace(problem, indenter=dataclasses.replace(problem.indenter, levels=levels))
        self.problem = problem
        self.settings = Settings(tolerance=path.tolerance, max_iterations=path.max_iterations, cascade=path.cascade)
        xp = problem.xp
        self.xp = xp
        grid = problem.grid
        n = grid.elements
        self.h2 = grid.element_size**2
        self.halfspace = HalfSpace(n, grid.element_size, problem.contact_modulus, xp=xp)
        indenter = problem.indenter
        self.height = xp.asarray(indenter.height)
        self.footprint = xp.isfinite(self.height)
        self.pillar = xp.asarray(indenter.pillar)
        self.n_pillars = indenter.n_pillars
        self.critical = problem.critical_stress
        self.pressure = xp.zeros((n, n), dtype=xp.float64)
        self.contact = xp.zeros((n, n), dtype=xp.bool)
        self.unit = None  # a = A_S^-1 1, full grid (warm start for the next one, kept across windows)
        # Deflections known without another transform, each as (array, window,
        # tip deflection of the array on that window): of self.pressure, and of
        # self.unit.
        self._known_deflection: tuple | None = None
        self._unit_deflection: tuple | None = None
        # (contact array, window, dp, K dp): how the last cascade changed the
        # pressure beyond the affine prediction, for the next unit response.
        self._pressure_change: tuple | None = None
        self.window: Window | None = None
        self.length_scale = 0.0  # the largest |d| reached: the path's length scale
        self.operator: ContactOperator | None = None
        # The geometry on the host (the indenter's own arrays): windows and
        # bounds are computed from these, without copies of device arrays.
        self._height_host = np.asarray(indenter.height)
        self._footprint_host = np.isfinite(self._height_host)
        self.footprint_box = backend.bounding_box(np, self._footprint_host)
        self._base_height_host = self._height_host
        self._pillar_host = np.asarray(indenter.pillar)

    # -- connections with a state: viscoelastic (in time) or nonlinear (pieces) --
    def _raise_tips(self, offsets: np.ndarray, lifted: np.ndarray | None = None) -> None:
        """Every pillar's tip raised by ``offsets`` (one per pillar); the ``lifted`` pillars out of reach."""
        if lifted is not None and lifted.any():
            offsets = np.where(lifted, 1e3 * self.problem.grid.size, offsets)
        host = np.where(self._footprint_host, self._base_height_host + offsets[np.maximum(self._pillar_host, 0)],
                        np.inf)
        self._height_host = host
        self.height = self.xp.asarray(host)
        if self.window is not None:
            self._outside_lowest = self._lowest_outside(self.window)

    def _pillar_forces(self, pressure=None, contact=None) -> np.ndarray:
        """Force of every pillar in the current state, or of the given one (compressive positive)."""
        contact = np.asarray(backend.to_numpy(self.contact if contact is None else contact))
        pressure = np.asarray(backend.to_numpy(self.pressure if pressure is None else pressure))
        return self.h2 * np.bincount(self._pillar_host[contact], weights=pressure[contact], minlength=self.n_pillars)

    @property
    def tension_limit(self) -> float | None:
        """The pillar law's tension limit, or None."""
        return None if self.pieces is None else self.pieces.law.tension_limit

    def pieces_state(self):
        """The pillar law's pieces and breaks (a copy), or None: what `restore_pieces` returns to."""
        return None if self.pieces is None else (self.pieces.pieces.copy(), self.pieces.broken.copy())

    def restore_pieces(self, saved) -> None:
        """Back to the pieces and breaks of `pieces_state`: the springs and the tips with them."""
        if saved is None:
            return
        pieces, broken = saved
        if np.array_equal(pieces, self.pieces.pieces) and np.array_equal(broken, self.pieces.broken):
            return
        moved = not np.array_equal(pieces, self.pieces.pieces)
        self.pieces.pieces, self.pieces.broken = pieces.copy(), broken.copy()
        stiffness, offsets = self.pieces.springs()
        if moved:
            self._set_pillar_stiffness(stiffness)
        self._raise_tips(offsets, self.pieces.broken)

    def break_pillars(self, pillars: np.ndarray):
        """Mark ``pillars`` (bool, one per pillar) broken and lift them; the elements they held (a mask)."""
        self.pieces.broken |= pillars
        _, offsets = self.pieces.springs()
        self._raise_tips(offsets, self.pieces.broken)
        return self.contact & self.xp.asarray(np.isin(self._pillar_host, np.flatnonzero(pillars)))

    def _set_pillar_stiffness(self, stiffness: np.ndarray) -> None:
        """The pillars' own springs (level 1) get ``stiffness``: a new operator, nothing cached of the old."""
        indenter = self.problem.indenter
        level = indenter.levels[0]
        levels = (SpringLevel(np.array(stiffness, dtype=np.float64), level.cluster), *indenter.levels[1:])
        self.problem = dataclasses.replace(self.problem, indenter=dataclasses.replace(indenter, levels=levels))
        self.operator = None
        self._known_deflection = self._unit_deflection = self._pressure_change = None
        self.unit = None
        if self.window is not None:
            self._install_window(self.window)

    def advance_history(self) -> None:
        """Before a time step: every pillar's tip raised by its connection's history offset b."""
        if self.memory is not None:
            self._raise_tips(self.memory.advance())

    def commit_history(self) -> None:
        """After a time step's equilibrium: the connections' compression and arm forces from the pillar forces."""
        if self.memory is not None:
            self.memory.commit(self._pillar_forces())

    def step_solve(self, displacement: float, *, advance: bool = True, detach=None) -> Equilibrium:
        """One step of a fixed-step path: the equilibrium at d with the connections' state.

        Viscoelastic connections: their history offsets first (``advance``;
        False inside a step, where the step's springs and offsets hold).  A
        nonlinear pillar law: the piece iteration of `brushbem.pillar_laws`,
        then the breaks, each break solved again at the same d.  ``detach``:
        elements that leave the contact first (an event located in the step).
        """
        if advance:
            self.advance_history()
        if self.pieces is None:
            return self.solve(displacement, force_detach=detach)
        from ..pillar_laws import MAX_PIECE_ROUNDS

        iterations = solves = detached = 0
        first = None
        moved = np.zeros(self.n_pillars, dtype=bool)

        def settled(eq: Equilibrium, **changes) -> Equilibrium:
            # The first round's trial solve is on the step's starting set and pieces: the one
            # on which the pressure is affine in d (`paths._first_crossing`).
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
            forces = self._pillar_forces()
            moved = self.pieces.update(forces)
            if not moved.any():
                broken = self.pieces.breaking(forces)
                if not broken.any():
                    return settled(eq)
                detach = self.contact & self.xp.asarray(np.isin(self._pillar_host, np.flatnonzero(broken)))
            stiffness, offsets = self.pieces.springs()
            if moved.any():
                self._set_pillar_stiffness(stiffness)
            self._raise_tips(offsets, self.pieces.broken)
        return settled(
            eq, converged=False,
            reason=f"the pillar law's pieces did not settle in {MAX_PIECE_ROUNDS} rounds at d = {displacement:.6g} "
                   f"(pillars still changing: {np.flatnonzero(moved)[:10].tolist()})",
        )

    # -- window -------------------------------------------------------------
    def _box_of(self, mask) -> tuple[int, int, int, int]:
        """Bounding box of a non-empty full-grid mask (any namespace)."""
        return backend.bounding_box(self.xp, mask)

    def ensure_window(self, needed, margin_fraction: float | None = None) -> None:
        """Make the working window cover ``needed`` (full-grid bool) with a margin.

        The window is rebuilt when ``needed`` comes within 2 elements of its
        edge (attachments there must be predicted inside the window) and when
        it is more than ``_OVERSIZED`` times as wide as a fresh window would be
        (after the contact shrank), so the window transforms stay as small as
        the contact allows.
        """
        n = self.problem.grid.elements
        box = backend.bounding_box(self.xp, needed)
        r0, r1, c0, c1 = self.footprint_box if box is None else box
        fr0, fr1, fc0, fc1 = self.footprint_box
        if self.window is not None:
            w = self.window
            inside = (
                (w.r0 <= max(r0 - 2, fr0, 0)) and (w.r1 >= min(r1 + 2, fr1, n))
                and (w.c0 <= max(c0 - 2, fc0, 0)) and (w.c1 >= min(c1 + 2, fc1, n))
            )
            if inside:
                rows, cols = self._window_for_box((r0, r1, c0, c1), margin_fraction).shape
                oversized = (w.r1 - w.r0) > _OVERSIZED * rows + 8 or (w.c1 - w.c0) > _OVERSIZED * cols + 8
                if not oversized:
                    return

        self._install_window(self._window_for_box((r0, r1, c0, c1), margin_fraction))

    def _window_around(self, needed, margin_fraction: float | None = None) -> Window:
        """The window that holds ``needed`` (full-grid bool, not empty) with the margin, in fast sizes."""
        return self._window_for_box(self._box_of(needed), margin_fraction)

    def _window_for_box(self, box, margin_fraction: float | None = None) -> Window:
        """The window around the box (r0, r1, c0, c1) with the margin, in fast sizes."""
        n = self.problem.grid.elements
        r0, r1, c0, c1 = box
        fr0, fr1, fc0, fc1 = self.footprint_box

        def widen(lo, hi, flo, fhi):
            size = hi - lo
            fraction = self.path.window_margin if margin_fraction is None else margin_fraction
            margin = max(4, math.ceil(fraction * size))
            lo, hi = max(lo - margin, flo, 0), min(hi + margin, fhi, n)
            target = min(fast_size(hi - lo), n)
            while hi - lo < target:
                if hi < n:
                    hi += 1
                if hi - lo < target and lo > 0:
                    lo -= 1
            return lo, hi

        r0, r1 = widen(r0, r1, fr0, fr1)
        c0, c1 = widen(c0, c1, fc0, fc1)
        return Window(int(r0), int(r1), int(c0), int(c1))

    def _lowest_outside(self, window: Window) -> float:
        """Lowest tip height on the footprint outside ``window`` (inf if none)."""
        outside = self._footprint_host.copy()
        outside[window.slices] = False
        heights = self._height_host[outside]
        return float(heights.min()) if heights.size else math.inf

    def _install_window(self, window: Window) -> None:
        self.window = window
        if self.operator is None:
            self.operator = ContactOperator(self.halfspace, self.problem.indenter, window, self.problem.coupling)
        else:
            self.operator = self.operator.for_window(window)
        self._outside_lowest = self._lowest_outside(window)

    @property
    def covers_footprint(self) -> bool:
        fr0, fr1, fc0, fc1 = self.footprint_box
        w = self.window
        return w.r0 <= fr0 and w.r1 >= fr1 and w.c0 <= fc0 and w.c1 >= fc1

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
        self.ensure_window(needed, margin)
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
                                 settings=self.settings, length_scale=self.length_scale)
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
            self._known_deflection = None if eq.deflection is None else (self.pressure, self.window, eq.deflection)
            if not eq.converged:
                break
            if self.covers_footprint or self._outside_safe(displacement):
                break
            if not enlarged and bool(xp.any(self.contact)):
                # The contact has grown close to the window's edge, where the
                # bound cannot exclude penetration.  A window rebuilt around
                # the contact with the usual margin usually restores the
                # bound; the equilibrium is then re-checked on it (a warm
                # start at the solution: one residual and one penetration on
                # the window), far cheaper than the full-grid penetration.
                enlarged = True
                candidate = self._window_around(self.contact)
                if candidate != self.window and self._outside_safe(
                    displacement, candidate, self._lowest_outside(candidate)
                ):
                    self._install_window(candidate)
                    continue
            # Penetration outside the window: the contact grew beyond it.
            outside = self._outside_penetration(displacement)
            if not bool(xp.any(outside)):
                break
            self.ensure_window(self.contact | outside)
            force_attach = outside
        return Equilibrium(
            displacement=displacement, pressure=self.pressure, contact=self.contact, converged=eq.converged,
            reason=eq.reason, cg_iterations=iterations, n_solves=solves, trial_force_sum=trial,
            detached=eq.detached, attached=eq.attached, deflection=eq.deflection,
            trial_pressure=trial_pressure,
        )

    def known_deflection(self):
        """Tip deflection of the current pressure on the window if known, else None."""
        known = self._known_deflection
        if known is not None and known[0] is self.pressure and known[1] == self.window:
            return known[2]
        return None

    def deflection(self):
        """Tip deflection (half-space + springs) of the current pressure on the window."""
        deflection = self.known_deflection()
        if deflection is None:
            deflection = tip_deflection(self.operator, self.pressure[self.window.slices])
            self._known_deflection = (self.pressure, self.window, deflection)
        return deflection

    def set_pressure(self, pressure, deflection=None) -> None:
        """Replace the pressure (full grid), with its tip deflection on the window if known."""
        self.pressure = pressure
        self._known_deflection = None if deflection is None else (pressure, self.window, deflection)

    def unit_deflection(self):
        """Tip deflection of the unit response on the window (transformed once per response)."""
        known = self._unit_deflection
        if known is not None and known[0] is self.unit and known[1] == self.window:
            return known[2]
        deflection = tip_deflection(self.operator, self.unit[self.window.slices])
        self._unit_deflection = (self.unit, self.window, deflection)
        return deflection

    def record_pressure_change(self, predicted, predicted_deflection, window: Window) -> None:
        """Remember dp = p - predicted on the contact and K dp, after a cascade at fixed d.

        ``predicted`` is the affine prediction the cascade started from (full
        grid) and ``predicted_deflection`` its tip deflection on ``window``.
        For a single element k leaving S the new unit response is exactly
        a|S' + (a_k / p_k) dp (both corrections are A_S'^-1 A_S'k times a
        scalar), so dp is the natural second direction of the next unit
        response's starting guess (``unit_response``).
        """
        self._pressure_change = None
        deflection = self.known_deflection()
        if deflection is None or window != self.window:
            return
        sl = window.slices
        contact = self.contact[sl]
        before = predicted[sl]
        change = self.pressure[sl] - self.xp.where(contact, before, 0.0)
        if not bool(self.xp.any(change != 0)):
            return
        dropped = self.operator.element_deflection(before, ~contact)
        self._pressure_change = (self.contact, window, change, deflection - predicted_deflection + dropped)

    def _outside_safe(self, displacement: float, window: Window | None = None, lowest: float | None = None) -> bool:
        """A cheap proof that no element outside the window can penetrate.

        Outside the window the tip is at least ``_outside_lowest`` high.  The
        half-space surface there is lifted by tension inside the window by at
        most T / (pi E* r), T the total tensile force and r the distance to the
        window (the point-load bound of the kernel), and a spring in tension
        lowers the tip by at most |F|/k.  ``window`` and ``lowest`` evaluate
        the bound for another window (holding the contact) instead.
        """
        xp = self.xp
        w = self.window if window is None else window
        lowest = self._outside_lowest if lowest is None else lowest
        if lowest == math.inf:
            return True
        # The pressure and the contact vanish outside the current window.
        current = self.window.slices
        pressure = self.pressure[current]
        tension = -self.h2 * float(xp.sum(xp.where(pressure < 0, pressure, 0.0)))
        lift = 0.0
        if tension > 0:
            # Distance from the contact's bounding box to the nearest element outside the window.
            r0, r1, c0, c1 = self._box_of(self.contact[current])
            r0, r1 = r0 + self.window.r0, r1 + self.window.r0
            c0, c1 = c0 + self.window.c0, c1 + self.window.c0
            gap = min(r0 - w.r0, w.r1 - r1, c0 - w.c0, w.c1 - c1) + 0.5
            lift = tension / (math.pi * self.problem.contact_modulus * max(gap, 0.5) * self.problem.grid.element_size)
        stretch = sum(tension / level.softest for level in self.problem.indenter.elastic_levels)
        return lowest > displacement + lift + stretch

    def outside_reach_displacement(self) -> float:
        """The smallest base displacement at which an element outside the window could touch.

        The same bound as `_outside_safe`, solved for d at the current
        tension: outside the window the tip is at least ``_outside_lowest``
        high, the surface there is lifted by at most T / (pi E* r) and a spring
        in tension lowers the tip by at most T / k.
        """
        xp = self.xp
        if self._outside_lowest == math.inf:
            return math.inf
        tension = -self.h2 * float(xp.sum(xp.where(self.pressure < 0, self.pressure, 0.0)))
        lift = 0.0
        if tension > 0:
            r0, r1, c0, c1 = self._box_of(self.contact)
            w = self.window
            gap = min(r0 - w.r0, w.r1 - r1, c0 - w.c0, w.c1 - c1) + 0.5
            lift = tension / (math.pi * self.problem.contact_modulus * max(gap, 0.5) * self.problem.grid.element_size)
        stretch = sum(tension / level.softest for level in self.problem.indenter.elastic_levels)
        return self._outside_lowest - lift - stretch

    def _outside_penetration(self, displacement: float):
        xp = self.xp
        full = ContactOperator(self.halfspace, self.problem.indenter, Window.full(self.problem.grid.elements))
        reach = penetration(full, self.height, displacement, self.pressure)
        inside = xp.zeros_like(self.contact)
        inside[self.window.slices] = True
        slack = 10.0 * self.path.tolerance * max(abs(displacement), 1e-300)
        return self.footprint & ~self.contact & ~inside & (reach > slack)

    def unit_response(self):
        """a = A_S^-1 1 on the window (dp/dd for the fixed contact set)."""
        xp = self.xp
        sl = self.window.slices
        contact = self.contact[sl]
        block, operator = self.operator.sub_operator(contact)
        block_contact = contact[block]
        ones = xp.astype(block_contact, xp.float64)
        initial, product = self._unit_guess(contact)
        result = solve_on_set(
            operator, block_contact, ones,
            initial=None if initial is None else initial[block],
            initial_product=None if product is None else product[block],
            tolerance=self.path.tolerance, max_iterations=self.path.max_iterations,
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
        exact for a single element leaving; the 2 x 2 system uses the known
        deflections only.
        """
        if self.unit is None:
            return None, None
        sl = self.window.slices
        previous = self.unit[sl]
        guess = self.xp.where(contact, previous, 0.0)
        known = self._unit_deflection
        if known is None or known[0] is not self.unit or known[1] != self.window:
            return guess, None
        product = known[2] - self.operator.element_deflection(previous, ~contact)
        change = self._pressure_change
        if change is None or change[0] is not self.contact or change[1] != self.window:
            return guess, product
        xp = self.xp
        dp, dp_product = change[2], change[3]

        def inner(a, b) -> float:  # both vanish outside S, so this is the inner product on S
            return float(xp.sum(a * b))

        g11 = inner(guess, product)
        g12 = 0.5 * (inner(guess, dp_product) + inner(dp, product))
        g22 = inner(dp, dp_product)
        f1 = float(xp.sum(guess))
        f2 = float(xp.sum(dp))
        determinant = g11 * g22 - g12 * g12
        if not (g11 > 0 and g22 > 0 and determinant > 1e-12 * g11 * g22):
            return guess, product
        c1 = (f1 * g22 - f2 * g12) / determinant
        c2 = (g11 * f2 - g12 * f1) / determinant
        return c1 * guess + c2 * dp, c1 * product + c2 * dp_product

    # -- records ------------------------------------------------------------
    def _on_window(self, array):
        """``array`` (full grid) restricted to the window, where every pressure
        and contact set of the path lies (the window always holds the contact)."""
        return array if self.window is None else array[self.window.slices]

    def force(self, pressure=None) -> float:
        p = self.pressure if pressure is None else pressure
        return self.h2 * float(self.xp.sum(self._on_window(p)))

    def attached_pillars(self, contact=None) -> int:
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
