"""The tips' own raster in the pillar model: `TipRaster`, `tip_factor` (``LoadPath.pillar_tip_resolution``).

The element paths hold a tip on the global grid, so a tip resolved by q
elements per radius needs a global grid that fine everywhere.  The pillar
model keeps a few numbers per pillar (`brushbem.pillars`): only its bases,
its near-field blocks, the criterion and the touch test look at a tip's
elements.  Here every tip is rasterised on a grid of its own, the global grid
subdivided ``factor`` times along each side: the same circle (centre and
radius of `brushbem.physics.structure.BrushGeometry`) labelled by the same
rule as `brushbem.physics.structure.raster.rasterise_pillars`, element by
element of the fine grid, without the fine grid's arrays.  A brush on a grid
of N elements with tips ``factor`` times finer therefore holds exactly the
footprints of the same brush on a grid of N x ``factor`` elements: the global
grid only places the pillars (``tests/test_pillar_tips.py`` checks the two
give the same pull-off).  The far field depends on a tip's force and low
moments only (`brushbem.pillars.lattice`); the criterion
Sigma_c = sqrt(E* dgamma / (0.473201 h)) is the fine element's.

The states carry the pressure on the global grid: the fine elements'
pressures summed over each global element's ``factor``^2 sub-elements over
``factor``^2 (the same force), an element in contact where any of them is;
force and contact area are the fine raster's.

A lone flat tip's F_A at q elements per radius (``data/resolution_error.csv``,
Kendall's punch by the exact path, which the pillar model equals for a lone
tip): +2.7 % at q = 4, +3.4 % at 8, +2.1 % at 16, +1.0 % at 32.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from brushbem.errors import ParameterError
from brushbem.physics.adhesion import critical_stress
from brushbem.physics.structure import Grid
from brushbem.physics.structure.raster import footprint_blocks
from brushbem.protocol.problem import ContactProblem, PressedElements

__all__ = ["TipRaster", "tip_factor"]


def tip_factor(problem: ContactProblem, resolution: float | None) -> int:
    """The subdivision of the global grid that gives the tips at least ``resolution`` elements per radius.

    None: 1 (the global grid's own).  The factor is the smallest integer with
    factor x (pillar radius / h) >= ``resolution`` (the tips' elements per
    radius are then that product, `TipRaster.per_radius`).
    """
    if resolution is None:
        return 1
    if not (math.isfinite(resolution) and resolution > 0):
        raise ParameterError("LoadPath", "pillar_tip_resolution", f"LoadPath.pillar_tip_resolution = {resolution} "
                             "must be finite and > 0 (elements per pillar radius)")
    per_radius = float(problem.indenter.description.pillar_radius) / problem.grid.element_size
    return max(1, math.ceil(resolution / per_radius * (1 - 1e-12)))


@dataclass(frozen=True)
class TipRaster:
    """Every tip's footprint on the global grid subdivided ``factor`` times.

    ``flat`` : the fine grid's flat indices (row-major, ``elements`` per side)
    of every footprint element, pillar by pillar, each pillar's row-major;
    ``owner`` : the pillar of each; ``heights`` (M,) : every tip's height
    (its elements' on the global grid: the tips are flat).
    """

    factor: int
    grid_elements: int
    elements: int
    element_size: float
    critical_stress: float
    flat: np.ndarray
    owner: np.ndarray
    heights: np.ndarray
    per_radius: float
    #: The global element that each of ``flat`` reports to (`pressed`), sorted by ``flat``: (fine, coarse).
    coarse: tuple[np.ndarray, np.ndarray] | None = None

    @classmethod
    def build(cls, problem: ContactProblem, factor: int = 1) -> TipRaster:
        """The tips of ``problem``'s brush ``factor`` times finer than its grid (1: the grid's own footprints)."""
        grid, indenter = problem.grid, problem.indenter
        labels = np.asarray(indenter.pillar).ravel()
        flat = np.flatnonzero(labels >= 0)
        owner = labels[flat]
        order = np.argsort(owner, kind="stable")
        flat, owner = flat[order], owner[order]
        first = np.searchsorted(owner, np.arange(indenter.n_pillars))
        heights = np.asarray(indenter.height).ravel()[flat[first]].astype(np.float64)
        radius = float(indenter.description.pillar_radius)
        per_radius = factor * radius / grid.element_size
        if factor == 1:
            return cls(1, grid.elements, grid.elements, grid.element_size, problem.critical_stress, flat, owner,
                       heights, per_radius)
        fine = Grid(grid.size, grid.elements * factor)
        flat, owner = _rasterise(fine, np.asarray(indenter.description.centres, dtype=np.float64), radius)
        if np.unique(flat).size != flat.size:
            raise ParameterError("LoadPath", "pillar_tip_resolution", f"the tips at {per_radius:.3g} elements per "
                                 "radius share elements (the footprints touch): use a coarser "
                                 "pillar_tip_resolution or the global grid's (None)")
        h = fine.element_size
        return cls(factor, grid.elements, fine.elements, h,
                   critical_stress(problem.contact_modulus, problem.work_of_adhesion, h), flat, owner, heights,
                   per_radius, _coarse_elements(labels.reshape(grid.elements, grid.elements), flat, owner, factor))

    def reporting(self, slots: np.ndarray) -> np.ndarray:
        """The global element (flat) that each of the fine elements ``slots`` reports to (`pressed`).

        A fine element reports to the global element it lies in, or, where that
        one is not its pillar's (a fine element inside the circle whose global
        element's centre is outside), to the nearest of its pillar's global
        elements: every pillar's force and contact stay on its own footprint.
        """
        if self.factor == 1:
            return slots
        fine, to = self.coarse
        return to[np.searchsorted(fine, slots)]

    def pressed(self, elements: np.ndarray, values: np.ndarray) -> PressedElements:
        """The contact on the global grid (n x n) of the fine elements that report to the global ``elements``
        (`reporting`, each pillar's ascending) and carry ``values``: each global element's pressure is the sum of
        its fine elements' over ``factor``^2 (the same force), in contact where any of them is."""
        if self.factor == 1:  # the global grid's own footprints: one element each, every pillar's ascending
            return PressedElements(self.grid_elements, elements, values)
        coarse, where = np.unique(elements, return_inverse=True)
        pressure = np.zeros(coarse.size)
        np.add.at(pressure, where, values)  # in the order of ``values``, as a full grid would sum them
        pressure /= self.factor**2
        return PressedElements(self.grid_elements, coarse, pressure)


def _rasterise(grid: Grid, centres: np.ndarray, radius: float) -> tuple[np.ndarray, np.ndarray]:
    """(flat indices, owners) of every element of ``grid`` whose centre lies inside a pillar's circle, pillar by
    pillar, row-major: `rasterise_pillars`'s rule, without the grid's label array."""
    n = grid.elements
    flats, owners = [], []
    for k, (rows, cols, inside) in enumerate(footprint_blocks(grid, centres, radius)):
        i, j = np.nonzero(inside)
        flats.append((i + rows.start) * n + (j + cols.start))
        owners.append(np.full(i.size, k, dtype=np.int64))
    return np.concatenate(flats).astype(np.int64), np.concatenate(owners)


def _coarse_elements(labels: np.ndarray, flat: np.ndarray, owner: np.ndarray,
                     factor: int) -> tuple[np.ndarray, np.ndarray]:
    """(fine flat indices sorted, the global element each reports to): its own, or its pillar's nearest."""
    n = labels.shape[0]
    rows, cols = np.divmod(flat, n * factor)
    coarse = (rows // factor) * n + cols // factor
    stray = np.flatnonzero(labels.ravel()[coarse] != owner)
    if stray.size:
        mine = np.flatnonzero(labels.ravel() >= 0)
        mine = mine[np.argsort(labels.ravel()[mine], kind="stable")]
        bounds = np.searchsorted(labels.ravel()[mine], np.arange(int(owner.max()) + 2))
        for k in stray:
            own = mine[bounds[owner[k]]:bounds[owner[k] + 1]]
            ci, cj = np.divmod(own, n)
            # Distances between element centres, in fine elements.
            dy = (ci + 0.5) * factor - (rows[k] + 0.5)
            dx = (cj + 0.5) * factor - (cols[k] + 0.5)
            coarse[k] = own[np.argmin(dy * dy + dx * dx)]
    order = np.argsort(flat)
    return flat[order], coarse[order]
