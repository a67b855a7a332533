"""Indenters rasterised on the grid: footprints, tip heights, pillars and springs.

An indenter is a set of rigid pillars n = 0..M-1 held by springs to a rigid
base.  On the grid it is described by

* ``height[i, j]``: the height of the tip surface above its lowest point when
  the base is at d = 0 (tip profile z plus the pillar's length offset g);
  ``inf`` where there is no material (outside every footprint).  An element
  penetrates the half-space when ``d - height - (spring deflection) - u > 0``.
* ``pillar[i, j]``: the index of the pillar an element belongs to, -1 outside.
* ``levels``: the springs, bottom-up.  Level l has a stiffness k_l (inf: rigid)
  and a map ``cluster[n]`` from pillars to the clusters of that level (level 0:
  every pillar its own cluster).

A compact punch or a sphere is a structure with one pillar.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

__all__ = ["Grid", "SpringLevel", "Indenter", "flat_punch", "sphere", "height_map"]


@dataclass(frozen=True)
class Grid:
    """Square domain L x L of N x N square elements, centred on the origin.

    Parameters
    ----------
    size : float
        Side L of the domain, in units of length.
    elements : int
        N, elements per side.
    """

    size: float
    elements: int

    def __post_init__(self):
        if not (math.isfinite(self.size) and self.size > 0):
            raise ValueError(f"grid.size = {self.size} must be finite and > 0")
        if int(self.elements) != self.elements or self.elements < 2:
            raise ValueError(f"grid.elements = {self.elements} must be an integer >= 2")

    @property
    def element_size(self) -> float:
        """h = L / N, in units of length."""
        return self.size / self.elements

    def centres(self) -> np.ndarray:
        """Coordinates of the element centres along one axis, shape (N,)."""
        return (np.arange(self.elements) + 0.5) * self.element_size - 0.5 * self.size

    def radius_squared(self) -> np.ndarray:
        """Squared distance of every element centre from the domain centre, shape (N, N)."""
        x = self.centres()
        return x[:, None] ** 2 + x[None, :] ** 2


@dataclass(frozen=True)
class SpringLevel:
    """One level of springs.

    Attributes
    ----------
    stiffness : float
        k_l of every spring of the level, in units of force / length; inf = rigid.
    cluster : ndarray of int, shape (M,)
        Cluster of the level that each pillar belongs to, in [0, n_clusters).
    """

    stiffness: float
    cluster: np.ndarray

    @property
    def n_clusters(self) -> int:
        return int(self.cluster.max()) + 1 if self.cluster.size else 0

    @property
    def rigid(self) -> bool:
        return math.isinf(self.stiffness)


@dataclass(frozen=True)
class Indenter:
    """A rasterised indenter (see the module docstring).

    Attributes
    ----------
    height : ndarray, shape (N, N)
        Tip height above the lowest tip point at d = 0, in units of length;
        inf outside the footprints.
    pillar : ndarray of int, shape (N, N)
        Pillar index of every element, -1 outside the footprints.
    levels : tuple of SpringLevel
        Springs, bottom-up (empty or all rigid: a rigid indenter).
    description : dict
        Geometry parameters for the record (shape, radius, ...).
    """

    height: np.ndarray
    pillar: np.ndarray
    levels: tuple[SpringLevel, ...] = ()
    description: dict = field(default_factory=dict)

    def __post_init__(self):
        if self.height.shape != self.pillar.shape or self.height.ndim != 2:
            raise ValueError("height and pillar must be 2-D arrays of the same shape")
        footprint = np.isfinite(self.height)
        if not np.array_equal(footprint, self.pillar >= 0):
            raise ValueError("pillar labels must cover exactly the finite heights")
        if not footprint.any():
            raise ValueError("the indenter has no element on the grid")
        for level in self.levels:
            if level.cluster.shape != (self.n_pillars,):
                raise ValueError("every spring level needs one cluster index per pillar")
            if not (level.stiffness > 0):
                raise ValueError(f"stiffness = {level.stiffness} must be > 0 (inf = rigid)")

    @property
    def footprint(self) -> np.ndarray:
        """Elements that belong to some pillar, bool (N, N)."""
        return self.pillar >= 0

    @property
    def n_pillars(self) -> int:
        return int(self.pillar.max()) + 1

    @property
    def elastic_levels(self) -> tuple[SpringLevel, ...]:
        """The levels with finite stiffness (the rigid ones add nothing to the operator)."""
        return tuple(level for level in self.levels if not level.rigid)

    def element_clusters(self, level: SpringLevel) -> np.ndarray:
        """Cluster index of every element for ``level``, -1 outside the footprints."""
        return np.where(self.pillar >= 0, level.cluster[np.maximum(self.pillar, 0)], -1)


def _single_spring(stiffness: float) -> tuple[SpringLevel, ...]:
    if math.isinf(stiffness):
        return ()
    if not (stiffness > 0 and math.isfinite(stiffness)):
        raise ValueError(f"indenter.stiffness = {stiffness} must be > 0 (inf = rigid)")
    return (SpringLevel(stiffness=float(stiffness), cluster=np.zeros(1, dtype=np.int64)),)


def flat_punch(grid: Grid, radius: float, stiffness: float = math.inf) -> Indenter:
    """Flat-ended cylindrical punch of ``radius`` centred on the domain.

    The footprint is the set of elements whose centre lies inside the circle.
    """
    h = grid.element_size
    if not (math.isfinite(radius) and radius >= 2 * h):
        raise ValueError(f"indenter.radius = {radius} must be >= 2 elements (2h = {2 * h})")
    if 2 * radius > grid.size:
        raise ValueError(f"indenter.radius = {radius} is larger than the domain (L/2 = {grid.size / 2})")
    inside = grid.radius_squared() <= radius**2
    height = np.where(inside, 0.0, np.inf)
    pillar = np.where(inside, 0, -1)
    area = inside.sum() * h * h
    return Indenter(
        height=height,
        pillar=pillar,
        levels=_single_spring(stiffness),
        description={"shape": "flat_punch", "radius": radius, "rasterised_area": float(area)},
    )


def sphere(grid: Grid, radius: float, stiffness: float = math.inf) -> Indenter:
    """Paraboloid tip r^2 / (2R) of curvature radius ``radius``, centred on the domain."""
    if not (math.isfinite(radius) and radius > 0):
        raise ValueError(f"indenter.radius = {radius} must be finite and > 0")
    height = grid.radius_squared() / (2.0 * radius)
    pillar = np.zeros(height.shape, dtype=np.int64)
    return Indenter(
        height=height,
        pillar=pillar,
        levels=_single_spring(stiffness),
        description={"shape": "sphere", "radius": radius},
    )


def height_map(grid: Grid, heights: np.ndarray, stiffness: float = math.inf) -> Indenter:
    """Arbitrary tip heights (N x N, units of length) on one spring; shifted so min = 0."""
    heights = np.asarray(heights, dtype=np.float64)
    if heights.shape != (grid.elements, grid.elements):
        raise ValueError(f"indenter.file holds shape {heights.shape}, expected {(grid.elements, grid.elements)}")
    if not np.all(np.isfinite(heights)):
        raise ValueError("indenter.file holds non-finite heights")
    height = heights - heights.min()
    pillar = np.zeros(height.shape, dtype=np.int64)
    return Indenter(
        height=height,
        pillar=pillar,
        levels=_single_spring(stiffness),
        description={"shape": "height_map"},
    )
