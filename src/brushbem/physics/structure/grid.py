"""The grid of square elements (`Grid`) and the smallest pillar it resolves (`MIN_PILLAR_RADIUS_ELEMENTS`)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from brushbem.errors import ParameterError
from brushbem.physics.structure.errors import StructureError

__all__ = ["MIN_PILLAR_RADIUS_ELEMENTS", "Grid"]


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
            raise ParameterError("Grid", "size", f"Grid.size = {self.size} must be finite and > 0")
        if int(self.elements) != self.elements or self.elements < 2:
            raise ParameterError("Grid", "elements", f"Grid.elements = {self.elements} must be an integer >= 2")

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


# A pillar narrower than this (in elements, radius) is a handful of elements
# whose rasterised area and edge stress no longer approximate a cylinder; the
# same bound as for the compact punch.
MIN_PILLAR_RADIUS_ELEMENTS = 2.0


def _check_pillar_radius(grid: Grid, radius: float, key: str = "pillar_radius", value: object = None,
                         origin: str = "") -> None:
    """StructureError if a pillar of ``radius`` is under `MIN_PILLAR_RADIUS_ELEMENTS` elements.

    A derived radius names the key it comes from (``key``, ``value``) and
    says how it follows from it (``origin``).
    """
    h = grid.element_size
    if not radius >= MIN_PILLAR_RADIUS_ELEMENTS * h:
        raise StructureError(
            key, radius if value is None else value,
            f"{origin}is under {MIN_PILLAR_RADIUS_ELEMENTS:g} elements (h = Grid.size / Grid.elements = {h:g}); a "
            f"pillar needs at least {MIN_PILLAR_RADIUS_ELEMENTS:g} elements in radius (refine Grid.elements)",
        )
