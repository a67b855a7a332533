"""The working window of a pull-off (`WorkingWindow`): the part of the grid the solves run on, as a value.

The half-space convolution is translation invariant, so the solves run on a
window of the grid that holds the contact set with a margin.  A
`WorkingWindow` is a frozen value that the path's state carries
(`brushbem.protocol.values.PathState.working`): the window and its
`ContactOperator`, the problem whose springs the operator sees, the tip
heights (the indenter's, raised by the connections' offsets), and the checks
that nothing outside the window can touch: the cheap bound
(`WorkingWindow.outside_safe`, `WorkingWindow.outside_reach_displacement`)
and the full-grid penetration (`WorkingWindow.outside_penetration`).  Every
change gives a new value (`covering`, `on`, `with_tips`, `with_problem`)
that shares what did not change; the steps of
`brushbem.protocol.steps` take a state with its window and return the
next.  The pressure and the contact set are the state's; the methods here
take them as arguments.

The value refers to the `SolverCache` the solves on its window are passed
(owned by the path, not by the operator): a memo of what depends only on the
operator and the arrays a solve is given, so that two values sharing it
compute the same numbers as two that do not (`brushbem.numerics.solver.cache`).
"""

from __future__ import annotations

import dataclasses
import functools
import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from brushbem import backend
from brushbem.physics.halfspace import HalfSpace
from brushbem.numerics.operator import ContactOperator, Window, fast_size
from brushbem.numerics.solver import penetration
from brushbem.numerics.solver.cache import SolverCache
from brushbem.protocol.problem import ContactProblem, LoadPath

__all__ = ["WorkingWindow"]


#: A window this many times wider (+ 8 elements) than a fresh one around the
#: contact is rebuilt.  The JKR benchmark's unloading windows: 1.15 -> 6 % less
#: area than the former "2 x the contact + 16" rule, at 1 more rebuild (a few
#: transforms and a cached spectrum each).
_OVERSIZED = 1.15


@dataclass(frozen=True, eq=False)
class WorkingWindow:
    """The window of the grid that holds the contact, its operator and the tip heights (module docstring).

    Make the first with `begin` (no window yet: ``window`` and ``operator``
    None until the first `covering`).  ``problem`` is the problem whose
    springs the operator sees (`with_problem`: a nonlinear pillar law's new
    pieces).  ``window`` and ``operator`` change together (`on`), and with
    them ``cache``, the `SolverCache` the solves on the window are passed
    (its pillar entries kept across windows, new with new springs).
    ``height`` and ``footprint`` are the full-grid tip heights (inf off the
    footprint) and the footprint, in the problem's array namespace
    (`with_tips` moves the heights); ``height_host``, ``footprint_host`` and
    ``pillar_host`` (the pillar of every element, negative off the
    footprint) their host copies, ``footprint_box`` the footprint's bounding
    box (r0, r1, c0, c1).  Windows and bounds are computed from host copies
    of the geometry (the indenter's own arrays), without copies of device
    arrays.  ``outside_lowest`` is the lowest tip outside the window.
    """

    problem: ContactProblem
    path: LoadPath
    halfspace: HalfSpace
    height: Any
    footprint: Any
    height_host: np.ndarray
    base_height_host: np.ndarray
    footprint_host: np.ndarray
    footprint_box: tuple
    pillar_host: np.ndarray
    window: Window | None = None
    operator: ContactOperator | None = None
    cache: SolverCache = field(default_factory=SolverCache)
    outside_lowest: float = math.inf

    @classmethod
    def begin(cls, problem: ContactProblem, path: LoadPath) -> WorkingWindow:
        """The first value of a path on ``problem``: the indenter's own tips, no window yet."""
        xp = problem.xp
        grid = problem.grid
        indenter = problem.indenter
        height = xp.asarray(indenter.height)
        host = np.asarray(indenter.height)
        footprint_host = np.isfinite(host)
        return cls(
            problem=problem, path=path,
            halfspace=HalfSpace(grid.elements, grid.element_size, problem.contact_modulus, xp=xp),
            height=height, footprint=xp.isfinite(height), height_host=host, base_height_host=host,
            footprint_host=footprint_host, footprint_box=backend.bounding_box(np, footprint_host),
            pillar_host=np.asarray(indenter.pillar),
        )

    # -- the geometry ---------------------------------------------------------
    def with_tips(self, offsets: np.ndarray, lifted: np.ndarray | None = None) -> WorkingWindow:
        """Every pillar's tip raised by ``offsets`` (one per pillar) from the indenter's; the ``lifted`` out of reach.

        The operator does not depend on the heights: deflections computed
        with it stay valid.
        """
        if lifted is not None and lifted.any():
            offsets = np.where(lifted, 1e3 * self.problem.grid.size, offsets)
        host = np.where(self.footprint_host, self.base_height_host + offsets[np.maximum(self.pillar_host, 0)],
                        np.inf)
        lowest = self.outside_lowest if self.window is None else _lowest_outside(self.footprint_host, host,
                                                                                   self.window)
        return dataclasses.replace(self, height_host=host, height=self.problem.xp.asarray(host),
                                   outside_lowest=lowest)

    def with_problem(self, problem: ContactProblem) -> WorkingWindow:
        """Solve ``problem`` (the same grid and geometry, new pillar springs): a new operator on the window.

        Every deflection computed with the old operator is stale; the caller
        (`brushbem.protocol.steps.with_change`) drops those its state keeps.
        """
        fresh = dataclasses.replace(self, problem=problem, operator=None, cache=SolverCache())
        return fresh if self.window is None else fresh.on(self.window)

    # -- the window -------------------------------------------------------------
    def covering(self, needed, margin_fraction: float | None = None) -> WorkingWindow:
        """The window that covers ``needed`` (full-grid bool) with a margin: this one, or a new one.

        A new window when ``needed`` comes within 2 elements of the edge
        (attachments there must be predicted inside the window) and when the
        window is more than ``_OVERSIZED`` times as wide as a fresh window
        would be (after the contact shrank), so the window transforms stay
        as small as the contact allows.
        """
        n = self.problem.grid.elements
        box = backend.bounding_box(self.problem.xp, needed)
        r0, r1, c0, c1 = self.footprint_box if box is None else box
        fr0, fr1, fc0, fc1 = self.footprint_box
        if self.window is not None:
            w = self.window
            inside = (
                (w.r0 <= max(r0 - 2, fr0, 0)) and (w.r1 >= min(r1 + 2, fr1, n))
                and (w.c0 <= max(c0 - 2, fc0, 0)) and (w.c1 >= min(c1 + 2, fc1, n))
            )
            if inside:
                rows, cols = self._for_box((r0, r1, c0, c1), margin_fraction).shape
                oversized = (w.r1 - w.r0) > _OVERSIZED * rows + 8 or (w.c1 - w.c0) > _OVERSIZED * cols + 8
                if not oversized:
                    return self

        return self.on(self._for_box((r0, r1, c0, c1), margin_fraction))

    def _for_box(self, box, margin_fraction: float | None = None) -> Window:
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

    def on(self, window: Window) -> WorkingWindow:
        """This value on ``window``: its operator (from the current one's cached spectra) and its outside bound."""
        if self.operator is None:
            operator = ContactOperator(self.halfspace, self.problem.indenter, window, self.problem.coupling)
        else:
            operator = self.operator.for_window(window)
        return dataclasses.replace(self, window=window, operator=operator, cache=self.cache.on_new_window(),
                                   outside_lowest=_lowest_outside(self.footprint_host, self.height_host, window))

    @property
    def covers_footprint(self) -> bool:
        """Whether the window holds the whole footprint (nothing outside it can touch)."""
        fr0, fr1, fc0, fc1 = self.footprint_box
        w = self.window
        return w.r0 <= fr0 and w.r1 >= fr1 and w.c0 <= fc0 and w.c1 >= fc1

    @functools.cached_property
    def footprint_elements(self):
        """Row and column (host arrays) of every footprint element of the window, row-major (kept with the value)."""
        return np.nonzero(np.asarray(backend.to_numpy(self.footprint[self.window.slices])))

    # -- nothing outside the window touches ---------------------------------------
    def outside_safe(self, displacement: float, pressure, contact, window: Window | None = None,
                     lowest: float | None = None) -> bool:
        """A cheap proof that no element outside the window can penetrate at ``displacement``.

        ``pressure`` and ``contact`` (full grid) vanish outside the current
        window.  Outside the window the tip is at least ``outside_lowest``
        high.  The half-space surface there is lifted by tension inside the
        window by at most T / (pi E* r), T the total tensile force and r the
        distance to the window (the point-load bound of the kernel), and a
        spring in tension lowers the tip by at most |F|/k.  ``window`` and
        ``lowest`` evaluate the bound for another window (holding the
        contact) instead.
        """
        xp = self.problem.xp
        w = self.window if window is None else window
        lowest = self.outside_lowest if lowest is None else lowest
        if lowest == math.inf:
            return True
        # The pressure and the contact vanish outside the current window.
        current = self.window.slices
        pressure = pressure[current]
        tension = -self.problem.grid.element_size**2 * float(xp.sum(xp.where(pressure < 0, pressure, 0.0)))
        lift = 0.0
        if tension > 0:
            # Distance from the contact's bounding box to the nearest element outside the window.
            r0, r1, c0, c1 = backend.bounding_box(xp, contact[current])
            r0, r1 = r0 + self.window.r0, r1 + self.window.r0
            c0, c1 = c0 + self.window.c0, c1 + self.window.c0
            gap = min(r0 - w.r0, w.r1 - r1, c0 - w.c0, w.c1 - c1) + 0.5
            lift = tension / (math.pi * self.problem.contact_modulus * max(gap, 0.5) * self.problem.grid.element_size)
        stretch = sum(tension / level.softest for level in self.problem.indenter.elastic_levels)
        return lowest > displacement + lift + stretch

    def outside_safe_around(self, displacement: float, pressure, contact) -> Window | None:
        """A window rebuilt around ``contact`` (with the usual margin) on which `outside_safe` holds, or None.

        None also when that window is the current one.
        """
        candidate = self._for_box(backend.bounding_box(self.problem.xp, contact))
        if candidate != self.window and self.outside_safe(
            displacement, pressure, contact, candidate, _lowest_outside(self.footprint_host, self.height_host, candidate)
        ):
            return candidate
        return None

    def outside_reach_displacement(self, pressure, contact) -> float:
        """The smallest base displacement at which an element outside the window could touch.

        The same bound as `outside_safe`, solved for d at the tension of
        ``pressure`` (full grid, on ``contact``): outside the window the tip
        is at least ``outside_lowest`` high, the surface there is lifted by
        at most T / (pi E* r) and a spring in tension lowers the tip by at
        most T / k.
        """
        xp = self.problem.xp
        if self.outside_lowest == math.inf:
            return math.inf
        tension = -self.problem.grid.element_size**2 * float(xp.sum(xp.where(pressure < 0, pressure, 0.0)))
        lift = 0.0
        if tension > 0:
            r0, r1, c0, c1 = backend.bounding_box(xp, contact)
            w = self.window
            gap = min(r0 - w.r0, w.r1 - r1, c0 - w.c0, w.c1 - c1) + 0.5
            lift = tension / (math.pi * self.problem.contact_modulus * max(gap, 0.5) * self.problem.grid.element_size)
        stretch = sum(tension / level.softest for level in self.problem.indenter.elastic_levels)
        return self.outside_lowest - lift - stretch

    def full_penetration(self, displacement: float, pressure):
        """Penetration of every element of the grid at ``displacement`` under ``pressure`` (one full-grid solve)."""
        full = ContactOperator(self.halfspace, self.problem.indenter, Window.full(self.problem.grid.elements))
        return penetration(full, self.height, displacement, pressure)

    def outside_penetration(self, displacement: float, pressure, contact):
        """Footprint elements outside the window and off ``contact`` that penetrate at ``displacement``.

        Penetration counts beyond the solver's accuracy (10 x the tolerance
        of |d|).
        """
        xp = self.problem.xp
        reach = self.full_penetration(displacement, pressure)
        inside = xp.zeros_like(contact)
        inside[self.window.slices] = True
        slack = 10.0 * self.path.tolerance * max(abs(displacement), 1e-300)
        return self.footprint & ~contact & ~inside & (reach > slack)


def _lowest_outside(footprint_host: np.ndarray, height_host: np.ndarray, window: Window) -> float:
    """Lowest tip height on the footprint outside ``window`` (inf if none)."""
    outside = footprint_host.copy()
    outside[window.slices] = False
    heights = height_host[outside]
    return float(heights.min()) if heights.size else math.inf
