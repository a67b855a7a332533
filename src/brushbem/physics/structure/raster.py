"""Pillars on the grid: the element labels of the footprints, and the filling factors they give."""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterator

import numpy as np

from brushbem.physics.structure.errors import StructureError
from brushbem.physics.structure.grid import Grid, _check_pillar_radius
from brushbem.physics.structure.layouts import ClusteredLattice

__all__ = ["clustered_filling_factors", "footprint_blocks", "rasterise_pillars"]


def rasterise_pillars(grid: Grid, centres: np.ndarray, radius: float) -> np.ndarray:
    """Label every element whose centre lies inside a pillar's circle (-1 elsewhere).

    Raises StructureError if a pillar is under ``MIN_PILLAR_RADIUS_ELEMENTS`` in
    radius, reaches outside the domain, or shares an element with another.
    """
    _check_pillar_radius(grid, radius)
    half = 0.5 * grid.size
    if np.any(np.abs(centres) + radius > half * (1 + 1e-12)):
        raise StructureError("pillar_radius", radius, "pillars reach outside the domain (Grid.size)")
    n = grid.elements
    labels = np.full((n, n), -1, dtype=np.int64)
    for k, (rows, cols, inside) in enumerate(footprint_blocks(grid, centres, radius)):
        block = labels[rows, cols]
        if np.any(block[inside] >= 0):
            raise StructureError("pillar_radius", radius, "pillars overlap; reduce pillar_radius or increase spacing")
        block[inside] = k
    return labels


def footprint_blocks(grid: Grid, centres: np.ndarray, radius: float) -> Iterator[tuple[slice, slice, np.ndarray]]:
    """For every pillar (in order): the rows and columns of the grid around it and which of those elements'
    centres lie inside its circle (the rule of `rasterise_pillars`, which checks the pillars first)."""
    h = grid.element_size
    half = 0.5 * grid.size
    n = grid.elements
    x = grid.centres()
    reach = math.ceil(radius / h) + 1
    for cy, cx in centres:
        i0 = max(math.floor((cy + half) / h) - reach, 0)
        j0 = max(math.floor((cx + half) / h) - reach, 0)
        rows = slice(i0, min(i0 + 2 * reach + 1, n))
        cols = slice(j0, min(j0 + 2 * reach + 1, n))
        yield rows, cols, (x[rows, None] - cy) ** 2 + (x[None, cols] - cx) ** 2 <= radius * radius


def clustered_filling_factors(grid: Grid, pillar: np.ndarray, lattice: ClusteredLattice) -> tuple[float, ...]:
    """The filling factor of every level of a clustered brush as rasterised, bottom-up (phi1, phi2, ...).

    ``pillar`` is the brush's element labels (`rasterise_pillars`, ``Indenter.pillar``).
    Only the sub-pillars are rasterised: phi1 is the area of their elements
    (count x h^2) over the area (2 r2)^2 of the level-2 squares.  The squares of
    the clusters are no part of the raster (the solver sees the sub-pillars'
    footprints and the cluster each belongs to) and the sub-pillars' centres are
    not snapped to the grid, so the higher factors are the exact area ratios:
    phi_l = the level-l squares over the level-(l+1) squares, the last the top
    level's over the region's area A0.  The product is the rasterised filling
    factor A / A0 of the brush (eq. 6.22 on the raster).

    phi1 converges to its nominal value at first order in h: a disk of radius r
    covers the elements of an area in [pi (r - h / sqrt 2)^2, pi (r + h / sqrt 2)^2]
    (every element whose centre lies inside lies within r + h / sqrt 2 of the
    centre, and every point within r - h / sqrt 2 lies in such an element).
    """
    h2 = grid.element_size**2
    areas = [float(np.count_nonzero(pillar >= 0)) * h2]
    areas += [len(centres) * side * side for centres, side in zip(lattice.square_centres, lattice.sides)]
    areas.append(lattice.region_size**2)
    return tuple(inner / outer for inner, outer in itertools.pairwise(areas))
