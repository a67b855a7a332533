"""Load paths as generators: press, then pull off until complete separation.

``pull_off(problem, path)`` yields one ``State`` per recorded equilibrium::

    for state in pull_off(problem, path):
        print(state.displacement, state.force)

Three methods:

* ``"fixed"`` - the thesis's displacement steps: press to the preload (by
  displacement, or by force with a final secant refinement), then retract by
  ``step`` until the contact set is empty.  Each step is an equilibrium with
  the detachment/attachment loop, warm-started from the previous one.  The
  first solve of a step is on the previous contact set, so the first
  element to reach the criterion inside the step, and the force there, are
  located exactly (a state of kind "event"), and the work of separation
  takes the cascade there (`_fixed_unloading_path`).  A brush whose tips are
  not level is pressed as contact problems, as by ``"events"``.
* ``"events"`` - exact event-driven path.  A brush of two or more pillars
  whose tips are not all level (rough, concave, length offsets) is pressed
  as non-adhesive contact problems (`_contact_loading`: the same branch,
  checked on its samples, in a few constrained CG solves instead of one
  global solve per element that joins); single bodies, level brushes (one
  loading event) and the unloading of every structure go event by event.
* ``"element_events"`` - the event-driven path with every element event on
  the loading branch too: the reference that ``"events"`` is tested against.

The event-driven path: for a fixed contact set S the solution is affine in
d, p(d) = p(d0) + (d - d0) a with a = A_S^-1 1, and the penetration outside
S is affine too; the path jumps to the displacement at which the next
element reaches the critical stress or touches, records that state (an
equilibrium on the threshold), lets the element leave or join and follows
the cascade at the same d.  There is no step-size error: the force
  extremum is found exactly up to the solver tolerance.  Elements whose event
  displacements agree within the solver's accuracy are treated together.

Both work on a window of the grid that holds the contact set with a margin
(the half-space convolution is translation invariant).  After every
equilibrium a bound proves that nothing outside the window penetrates; when it
cannot, the window is rebuilt around the contact and, if the bound still fails,
the penetration is checked on the whole grid and the window enlarged to take in
what touches.  The CG solves run on the block of the window around the contact
set (``ContactOperator.sub_operator``).  The event path also keeps the
deflections of the pressure and of A_S^-1 1 on the window in step (both are
affine between events), so that an event transforms only the new A_S^-1 1.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field

import numpy as np

from . import backend
from .halfspace import HalfSpace
from .operator import ContactOperator, Window, fast_size
from .results import Curve, Snapshot
from .solver import (
    Equilibrium,
    critical_stress,
    equilibrium,
    penetration,
    polonsky_keer,
    solve_on_set,
    tip_deflection,
)
from .structure import Grid, Indenter

__all__ = ["ContactProblem", "LoadPath", "NotConvergedError", "PullOffRecord", "State", "indent", "pull_off", "record_pull_off"]


class NotConvergedError(RuntimeError):
    """A solve did not converge; the path stops and the record says why."""


@dataclass(frozen=True)
class ContactProblem:
    """An indenter on springs against an elastic half-space.

    Parameters
    ----------
    grid : Grid
    indenter : Indenter
    contact_modulus : float
        E*, in units of stress.
    work_of_adhesion : float
        dgamma, energy per unit area (0: no adhesion).
    coupling : {"segments", "discriminant"}
        How the spring sums are evaluated (see ``brushbem.operator``).
    """

    grid: Grid
    indenter: Indenter
    contact_modulus: float
    work_of_adhesion: float
    coupling: str = "segments"
    xp: object = np

    def __post_init__(self):
        if not (math.isfinite(self.contact_modulus) and self.contact_modulus > 0):
            raise ValueError(f"contact_modulus = {self.contact_modulus} must be finite and > 0")
        if not (math.isfinite(self.work_of_adhesion) and self.work_of_adhesion >= 0):
            raise ValueError(f"work_of_adhesion = {self.work_of_adhesion} must be finite and >= 0")

    @property
    def critical_stress(self) -> float:
        """Sigma_c of the mesh (eq. 2.14); 0 without adhesion."""
        return critical_stress(self.contact_modulus, self.work_of_adhesion, self.grid.element_size)


@dataclass(frozen=True)
class LoadPath:
    """How the indenter is pressed and pulled off.

    Parameters
    ----------
    method : {"events", "element_events", "fixed"}
    preload_displacement, preload_force : float or None
        Exactly one: press to this base displacement, or until this force.
    step : float
        Displacement step of the "fixed" method, in units of length.
    max_steps : int
        Bound on the recorded states of each branch (a path that needs more is
        reported as not converged).
    tolerance : float
        Relative residual of every CG solve.
    max_iterations : int
        Bound on the iterations of one CG solve.
    window_margin : float
        Margin of the working window around the contact, as a fraction of its
        size (at least 4 elements).
    cascade : {"local", "global"}
        How the detachment rounds of a brush run (``solver.equilibrium``).
    """

    method: str = "events"
    preload_displacement: float | None = None
    preload_force: float | None = None
    step: float = 1e-4
    max_steps: int = 200000
    tolerance: float = 1e-8
    max_iterations: int = 20000
    window_margin: float = 0.25
    cascade: str = "local"

    def __post_init__(self):
        if self.method not in ("events", "element_events", "fixed"):
            raise ValueError(f"protocol.method = {self.method!r} must be 'events', 'element_events' or 'fixed'")
        if self.cascade not in ("local", "global"):
            raise ValueError(f"solver.cascade = {self.cascade!r} must be 'local' or 'global'")
        if (self.preload_displacement is None) == (self.preload_force is None):
            raise ValueError("exactly one of protocol.preload_displacement and protocol.preload_force is required")
        for name in ("preload_displacement", "preload_force"):
            value = getattr(self, name)
            if value is not None and not (math.isfinite(value) and value > 0):
                raise ValueError(f"protocol.{name} = {value} must be finite and > 0")
        if not (math.isfinite(self.step) and self.step > 0):
            raise ValueError(f"protocol.step = {self.step} must be finite and > 0")


@dataclass(frozen=True)
class State:
    """One recorded equilibrium of the load path.

    Attributes
    ----------
    displacement : float
        Base displacement d.
    force : float
        F = h^2 sum p, compressive positive.
    contact_area : float
        h^2 times the number of contact elements.
    attached_pillars : int
    loading : bool
        True while pressing, False while pulling off.
    kind : str
        "equilibrium" (after any cascade), "event" (a state on the threshold
        of the next event, before elements leave or join) or "separated".
    trial_force : float
        Force of the fixed-set solution at this d before the cascade (equal to
        ``force`` when nothing changed); the path passes through it.
    cg_iterations, n_solves : int
        Spent to reach this state.
    converged : bool
    reason : str
    pressure : ndarray, shape (N, N)
    contact : ndarray of bool, shape (N, N)
    """

    displacement: float
    force: float
    contact_area: float
    attached_pillars: int
    loading: bool
    kind: str
    trial_force: float
    cg_iterations: int
    n_solves: int
    converged: bool
    reason: str
    pressure: object
    contact: object


#: A window this many times wider (+ 8 elements) than a fresh one around the
#: contact is rebuilt.  The JKR benchmark's unloading windows: 1.15 -> 6 % less
#: area than the former "2 x the contact + 16" rule, at 1 more rebuild (a few
#: transforms and a cached spectrum each).
_OVERSIZED = 1.15


class _Tracker:
    """Full-grid state, the working window and its operator."""

    def __init__(self, problem: ContactProblem, path: LoadPath):
        self.problem = problem
        self.path = path
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

    # -- window -------------------------------------------------------------
    def _box_of(self, mask) -> tuple[int, int, int, int]:
        """Bounding box of a non-empty full-grid mask (any namespace)."""
        return backend.bounding_box(backend.namespace(mask), mask)

    def ensure_window(self, needed, margin_fraction: float | None = None) -> None:
        """Make the working window cover ``needed`` (full-grid bool) with a margin.

        The window is rebuilt when ``needed`` comes within 2 elements of its
        edge (attachments there must be predicted inside the window) and when
        it is more than ``_OVERSIZED`` times as wide as a fresh window would be
        (after the contact shrank), so the window transforms stay as small as
        the contact allows.
        """
        n = self.problem.grid.elements
        box = backend.bounding_box(backend.namespace(needed), needed)
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
                eq = equilibrium(
                    self.operator, height, displacement, self.contact[sl], self.pressure[sl], self.critical,
                    tolerance=self.path.tolerance, max_iterations=self.path.max_iterations,
                    force_detach=None if force_detach is None else force_detach[sl],
                    force_attach=None if force_attach is None else force_attach[sl],
                    deflection=self.known_deflection(),
                    cascade=self.path.cascade,
                    length_scale=self.length_scale,
                )
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
            if not enlarged:
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
            displacement, self.pressure, self.contact, eq.converged, eq.reason, iterations, solves,
            trial, eq.detached, eq.attached, eq.deflection, trial_pressure,
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
        stretch = sum(tension / level.stiffness for level in self.problem.indenter.elastic_levels)
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
        stretch = sum(tension / level.stiffness for level in self.problem.indenter.elastic_levels)
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


def indent(problem: ContactProblem, displacement: float, tolerance: float = 1e-8,
           max_iterations: int = 20000) -> State:
    """Equilibrium at one base displacement, pressed from no contact in one step.

    The thesis's way of applying a preload ("pressed by a general
    displacement d"); without adhesion it is the unique solution of the
    contact problem (Polonsky-Keer).
    """
    path = LoadPath(method="fixed", preload_displacement=max(displacement, 1e-300), tolerance=tolerance,
                    max_iterations=max_iterations)
    tracker = _Tracker(problem, path)
    eq = tracker.solve(displacement)
    return _eq_state(tracker, eq, True)


def pull_off(problem: ContactProblem, path: LoadPath) -> Iterator[State]:
    """Yield the states of a press-and-pull-off (module docstring).

    The last state has ``kind == "separated"`` when the indenter came off, or
    ``converged == False`` with the reason when a solve failed or the step
    budget ran out.
    """
    tracker = _Tracker(problem, path)
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


def _eq_state(tracker, eq: Equilibrium, loading: bool, kind="equilibrium") -> State:
    trial = tracker.h2 * eq.trial_force_sum
    return tracker.state(eq.displacement, loading, kind, trial, eq.cg_iterations, eq.n_solves, eq.converged, eq.reason)


def _fixed(tracker: _Tracker, path: LoadPath) -> Iterator[State]:
    step = path.step
    d = 0.0
    count = 0
    done = False
    if _press_as_contact_problems(tracker):
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
            eq = tracker.solve(d)
            state = _eq_state(tracker, eq, True)
            yield state
            if not eq.converged:
                return
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
    # Unloading.
    d_max = d
    for k in range(1, path.max_steps + 1):
        d = d_max - k * step
        before = (d + step, tracker.pressure, tracker.contact)
        eq = tracker.solve(d)
        if not eq.converged:
            yield _eq_state(tracker, eq, False)
            return
        crossing = _first_crossing(tracker, before, eq)
        if crossing is not None:
            yield crossing
        if not bool(tracker.xp.any(tracker.contact)):
            yield tracker.state(d, False, "separated", tracker.h2 * eq.trial_force_sum, eq.cg_iterations,
                                eq.n_solves, True, "complete separation")
            return
        yield _eq_state(tracker, eq, False)
    yield _budget_exhausted(tracker, d, False, path)


def _first_crossing(tracker: _Tracker, before, eq: Equilibrium) -> State | None:
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
    xp = tracker.xp
    if eq.detached == 0 or eq.trial_pressure is None:
        return None
    d0, p0, c0 = before
    p1 = eq.trial_pressure
    critical = tracker.critical
    # Elements of the old set whose trial pressure is beyond the criterion.
    over = c0 & (p1 < -critical) if critical > 0 else c0 & (p1 < 0)
    if not bool(xp.any(over)):
        return None
    drop = xp.where(over, p0 - p1, 1.0)
    fraction = xp.where(over, (p0 + critical) / drop, xp.inf)
    tau = min(max(float(xp.min(fraction)), 0.0), 1.0)
    if tau >= 1.0:
        return None
    pressure = xp.where(c0, p0 + tau * (p1 - p0), 0.0)
    d = d0 + tau * (eq.displacement - d0)
    return tracker.state(d, False, "event", tracker.force(pressure), 0, 0, True,
                         "first detachment inside the step (exact on the step's contact set)",
                         pressure=pressure, contact=c0)


def _reach_force(tracker: _Tracker, saved, below, above, target: float):
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


def _events(tracker: _Tracker, path: LoadPath) -> Iterator[State]:
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


def _press_as_contact_problems(tracker: _Tracker) -> bool:
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


def _contact_loading(tracker: _Tracker, path: LoadPath):
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


def _contact_preload_force(tracker: _Tracker, path: LoadPath, solve_at, lowest: float):
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
    compliance += sum(1.0 / (level.stiffness * level.n_clusters) for level in indenter.elastic_levels)
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


def _nested_prefix(tracker: _Tracker, samples: list, lowest: float) -> list:
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


def _event_step(tracker: _Tracker, path: LoadPath, d: float, direction: int):
    """Advance to the next event in ``direction`` (+1 press, -1 pull); yield its states.

    Returns (d, branch_finished), or None when the path must stop.
    """
    xp = tracker.xp
    loading = direction > 0
    critical = tracker.critical
    tol = path.tolerance
    has_contact = bool(xp.any(tracker.contact))
    candidates: list[tuple[float, str, object]] = []  # (distance along direction, kind, mask)
    if loading and path.preload_displacement is not None:
        candidates.append((path.preload_displacement - d, "target", None))
    if not has_contact:
        if not loading:
            yield tracker.state(d, False, "separated", 0.0, 0, 0, True, "complete separation")
            return d, True
        # First touch: the lowest footprint elements.
        lowest = tracker.problem.indenter.lowest_height
        distance = max(lowest - d, 0.0)
        first = tracker.footprint & (tracker.height <= lowest + 1e-12 * max(abs(lowest), 1.0) + 0.0)
        new_d = d + distance
        eq = tracker.solve(new_d, force_attach=first)
        state = _eq_state(tracker, eq, True)
        yield state
        if not eq.converged:
            return None
        return new_d, _target_reached(tracker, path, new_d)
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
    # Detachment: p_i + t s a_i = -Sigma_c for t >= 0 (elements whose tension grows).
    rate = s * a
    grows = contact & (rate < 0)
    t_detach = xp.where(grows, (pressure + critical) / xp.where(grows, -rate, 1.0), xp.inf)
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


# -- recording ------------------------------------------------------------------


@dataclass(frozen=True)
class PullOffRecord:
    """The curve, the snapshots and the summary numbers of one pull-off."""

    curve: Curve
    snapshots: tuple[Snapshot, ...]
    summary: dict
    pillars: dict = field(default_factory=dict)


def record_pull_off(
    problem: ContactProblem,
    path: LoadPath,
    progress: Callable[[float, str], None] | None = None,
    stop: Callable[[], bool] | None = None,
) -> PullOffRecord:
    """Run ``pull_off`` and collect the curve, snapshots and summary.

    Summary fields: adhesive_force (-min F on the pull-off, >= 0),
    pull_off_displacement, separation_displacement (last d with contact),
    work_of_separation (work against the tensile force from the zero-force
    crossing of the unloading branch to separation, along the path, cascades
    vertical), preload_force, max_displacement, converged, reason,
    interrupted, n_solves, n_cg_iterations, n_states, wall_time_s.

    ``stop`` is polled after every state: when it returns True the path
    ends there, and the record holds what was computed, with
    ``interrupted = True`` and ``converged = False`` (a partial pull-off is
    not a result).  A summary number that comes out non-finite (an overflow
    of extreme inputs) makes the run not converged, with the reason.
    """
    from .backend import to_numpy

    start = time.perf_counter()
    labels = np.asarray(to_numpy(problem.indenter.pillar)).ravel()
    n_pillars = problem.indenter.n_pillars
    h2 = problem.grid.element_size**2
    last_attached_d = np.full(n_pillars, np.nan)
    max_tension = np.zeros(n_pillars)

    def pillar_forces(state: State) -> tuple[np.ndarray, np.ndarray]:
        contact = np.flatnonzero(np.asarray(to_numpy(state.contact)).ravel())
        pressure = np.asarray(to_numpy(state.pressure)).ravel()[contact]
        force = h2 * np.bincount(labels[contact], weights=pressure, minlength=n_pillars)
        attached = np.bincount(labels[contact], minlength=n_pillars) > 0
        return force, attached

    attached_at_preload = 0
    half_taken = False
    zero_taken = False
    # The states without their arrays: keeping every State would keep two
    # full-grid arrays per state alive (1.4 GB for the N = 256 JKR benchmark,
    # and a page fault for every fresh page of every new array).
    rows: list[State] = []
    path_points: list[tuple[float, float, bool]] = []  # (d, F, loading) along the path, cascades included
    snapshots: dict[str, Snapshot] = {}
    last_contact_state: State | None = None
    last_loading_state: State | None = None
    best: State | None = None
    converged = True
    reason = "complete separation"
    n_solves = n_iterations = 0
    max_area = 0.0
    separated = False
    interrupted = False
    for state in pull_off(problem, path):
        n_solves += state.n_solves
        n_iterations += state.cg_iterations
        if not state.converged:
            converged = False
            reason = state.reason
        if state.kind == "separated":
            separated = True
            path_points.append((state.displacement, state.trial_force, False))
            path_points.append((state.displacement, 0.0, False))
            rows.append(dataclasses.replace(state, pressure=None, contact=None))
            break
        if state.trial_force != state.force:
            path_points.append((state.displacement, state.trial_force, state.loading))
        path_points.append((state.displacement, state.force, state.loading))
        rows.append(dataclasses.replace(state, pressure=None, contact=None))
        if state.loading:
            last_loading_state = state
            attached_at_preload = state.attached_pillars
        elif state.contact_area > 0:
            last_contact_state = state
            forces, attached = pillar_forces(state)
            last_attached_d[attached] = state.displacement
            np.maximum(max_tension, -forces, out=max_tension)
            if best is None or state.force < best.force:
                best = state
            if not zero_taken and state.force <= 0:
                snapshots["zero_force"] = _snapshot("zero_force", state, to_numpy, pillar_forces)
                zero_taken = True
            if not half_taken and n_pillars > 1 and 2 * state.attached_pillars <= attached_at_preload:
                snapshots["half_detached"] = _snapshot("half_detached", state, to_numpy, pillar_forces)
                half_taken = True
        max_area = max(max_area, state.contact_area)
        if progress is not None:
            if state.loading:
                target = path.preload_displacement
                fraction = 0.3 * (state.displacement / target if target else min(state.force / path.preload_force, 1))
            else:
                fraction = 0.3 + 0.7 * (1.0 - state.contact_area / max_area if max_area else 1.0)
            progress(min(max(fraction, 0.0), 1.0), f"d = {state.displacement:.4g}, F = {state.force:.4g}")
        if not state.converged:
            break
        if stop is not None and stop():
            interrupted = True
            converged = False
            reason = f"interrupted at d = {state.displacement:.6g} after {len(rows)} states"
            break
    if not separated and converged:
        converged = False
        reason = "the path ended before complete separation"
    if last_contact_state is None and last_loading_state is not None and last_loading_state.contact_area > 0:
        # The first unloading step already separated: the unloading branch
        # starts at the preload, which is its last state with contact and the
        # least compressive one.
        last_contact_state = best = last_loading_state
        _, attached = pillar_forces(last_loading_state)
        last_attached_d[attached] = last_loading_state.displacement
    if last_loading_state is not None:
        snapshots["max_preload"] = _snapshot("max_preload", last_loading_state, to_numpy, pillar_forces)
    if best is not None:
        snapshots["adhesive_force"] = _snapshot("adhesive_force", best, to_numpy, pillar_forces)
    if last_contact_state is not None:
        snapshots["before_separation"] = _snapshot("before_separation", last_contact_state, to_numpy, pillar_forces)
    order = ("max_preload", "zero_force", "adhesive_force", "half_detached", "before_separation")
    snapshots = {name: snapshots[name] for name in order if name in snapshots}
    curve = Curve(
        displacement=np.array([s.displacement for s in rows]),
        force=np.array([s.force if s.kind != "separated" else 0.0 for s in rows]),
        contact_area=np.array([s.contact_area for s in rows]),
        cg_iterations=np.array([s.cg_iterations for s in rows], dtype=np.int64),
        converged=np.array([s.converged for s in rows], dtype=bool),
        loading=np.array([s.loading for s in rows], dtype=bool),
        attached_pillars=np.array([s.attached_pillars for s in rows], dtype=np.int64),
    )
    loading_states = [s for s in rows if s.loading]
    # The unloading path starts at the end of the loading branch.
    start_point = [(loading_states[-1].displacement, loading_states[-1].force)] if loading_states else []
    if path.method == "fixed":
        unloading = start_point + _fixed_unloading_path([s for s in rows if not s.loading])
    else:
        unloading = start_point + [(d, f) for d, f, load in path_points if not load]
    summary = {
        "adhesive_force": max(0.0, -best.force) if best is not None else 0.0,
        "pull_off_displacement": best.displacement if best is not None else None,
        "separation_displacement": last_contact_state.displacement if last_contact_state is not None else None,
        "work_of_separation": work_of_separation(unloading),
        "preload_force": loading_states[-1].force if loading_states else 0.0,
        "max_displacement": loading_states[-1].displacement if loading_states else 0.0,
        "converged": bool(converged),
        "reason": reason,
        "interrupted": interrupted,
        "n_solves": int(n_solves),
        "n_cg_iterations": int(n_iterations),
        "mean_cg_iterations_per_solve": n_iterations / n_solves if n_solves else 0.0,
        "attached_pillars_at_pull_off": best.attached_pillars if best is not None else 0,
        "n_states": len(rows),
        "wall_time_s": time.perf_counter() - start,
    }
    overflowed = [key for key in _FINITE_SUMMARY if summary[key] is not None and not math.isfinite(summary[key])]
    if overflowed and summary["converged"]:
        summary["converged"] = False
        summary["reason"] = (
            f"non-finite {', '.join(overflowed)}: the inputs' scales overflow double precision "
            "(e.g. work_of_adhesion or the preload far from contact_modulus x grid.size)"
        )
    pillars = {"separation_displacement": last_attached_d, "max_tension": max_tension}
    return PullOffRecord(curve=curve, snapshots=tuple(snapshots.values()), summary=summary, pillars=pillars)


#: Summary numbers that a converged run reports finite.
_FINITE_SUMMARY = ("adhesive_force", "pull_off_displacement", "separation_displacement", "work_of_separation",
                   "preload_force", "max_displacement")


def _snapshot(name: str, state: State, to_numpy, pillar_forces) -> Snapshot:
    return Snapshot(
        name=name,
        displacement=state.displacement,
        force=state.force,
        pressure=np.array(to_numpy(state.pressure)),
        contact=np.array(to_numpy(state.contact)),
        pillar_force=pillar_forces(state)[0],
    )


def _fixed_unloading_path(rows: list[State]) -> list[tuple[float, float]]:
    """The unloading path (d, F) of fixed steps, cascades placed where they start.

    A step whose first detachment was located (a ``kind == "event"`` state
    from `_first_crossing`) follows its contact set's line exactly to that
    point; the cascade is then taken there, as the event path does, down to
    the line of the contact set the step ended with, which passes through the
    step's equilibrium with the slope of the next step's first solve (the
    same contact set: exact where nothing else happened in the step).  A
    step that ends in separation drops to zero at its crossing.  Elsewhere
    the path goes through every state, cascades vertical at the step's end.
    """
    points: list[tuple[float, float]] = []
    crossing: State | None = None
    for i, state in enumerate(rows):
        if state.kind == "event":
            crossing = state
            points.append((state.displacement, state.force))
            continue
        force = 0.0 if state.kind == "separated" else state.force
        if crossing is not None:
            after = force
            following = rows[i + 1] if i + 1 < len(rows) else None
            if state.kind != "separated" and following is not None and following.displacement != state.displacement:
                # The next step's first solve is on this step's contact set.
                reached = following.force if following.kind == "event" else following.trial_force
                slope = (reached - force) / (following.displacement - state.displacement)
                after = force + slope * (crossing.displacement - state.displacement)
            points.append((crossing.displacement, after))
            crossing = None
        elif state.trial_force != force:
            points.append((state.displacement, state.trial_force))
        points.append((state.displacement, force))
    return points


def work_of_separation(points: list[tuple[float, float]]) -> float:
    """Work against the tensile force along an unloading path (d decreasing).

    ``points`` is the path (d, F) in order, cascades as vertical segments; each
    segment is linear (exact for the event-driven path).  The work is the area
    of the tensile part of the curve, -F dd where F < 0: it starts at the
    first zero crossing of F and ends at separation.  Where F turns
    compressive again on the way (a cascade that leaves compressed contacts
    behind, as on a rough brush), that stretch is pushed by the half-space,
    not pulled against its adhesion, and adds nothing - so the work is never
    negative.
    """
    work = 0.0
    for (d0, f0), (d1, f1) in itertools.pairwise(points):
        run = d0 - d1  # >= 0 along the unloading
        if run == 0.0 or (f0 >= 0.0 and f1 >= 0.0):
            continue
        if f0 <= 0.0 and f1 <= 0.0:
            work += 0.5 * (-f0 - f1) * run
        else:  # F changes sign inside the segment: the tensile triangle
            tension = -min(f0, f1)
            work += 0.5 * tension * run * tension / (abs(f0) + abs(f1))
    return float(work)
