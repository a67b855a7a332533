"""The pillar springs on a window: S p = sum_l (h^2 / k_l) P_l^T P_l p (DESIGN.md sec. 2).

Every elastic level l of an indenter (`brushbem.physics.structure.SpringLevel`) groups
the pillars into clusters; the springs' deflection above an element is, summed
over the levels, the compliance h^2 / k_l times the pressure summed over the
element's cluster (thesis eq. 3.11, 6.12, 6.17).  `PillarSprings` is that
operator on one window of the grid, by segment sums over the element-to-cluster
incidence: exact for any layout, O(n), in the namespace of the half-space.
`ContactOperator` adds it to the half-space's deflection; `PillarSprings.on_set`
gives the same sums on the elements of a contact set, for the solvers that
work on the values of S.  The compliance of a level is one number per
cluster (h^2 / k_c: a graded or per-pillar stiffness), applied to the cluster
sums before they are read back through the labels, ``(compliance *
sums)[labels]``; a uniform level gives the same products, bit for bit, as one
number would.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from array_api_compat import is_numpy_namespace

from brushbem import backend
from brushbem.physics.structure import Indenter, SpringLevel

__all__ = ["LevelLabels", "PillarSprings", "SetSprings"]


@dataclass(frozen=True)
class LevelLabels:
    """One elastic level on a window: its compliance and every window element's cluster.

    Attributes
    ----------
    compliance : ndarray, shape (n_clusters,)
        h^2 / k_c of every cluster's spring, in units of length per stress
        (host array).
    labels : array, flat over the window
        Cluster of every element; off-footprint elements carry the dummy
        cluster ``n_clusters`` (its sum is never read back on the footprint).
    n_clusters : int
    level : SpringLevel
    padded : array, shape (n_clusters + 1,)
        ``compliance`` with 0 for the dummy cluster, in the namespace of the
        half-space.
    """

    compliance: np.ndarray
    labels: object
    n_clusters: int
    level: SpringLevel
    padded: object


class PillarSprings:
    """The springs of an indenter's elastic levels on a window (module docstring).

    Parameters
    ----------
    indenter : Indenter
    element_size : float
        h; the compliance of a level is h^2 / k.
    slices : tuple of slice
        The window's block of the grid.
    xp : namespace
        The array namespace of the half-space (NumPy, CuPy, ...).
    """

    def __init__(self, indenter: Indenter, element_size: float, slices: tuple[slice, slice], xp):
        self.xp = xp
        h2 = element_size**2
        self.levels: list[LevelLabels] = []
        for level in indenter.elastic_levels:
            window_labels = indenter.element_clusters(level)[slices]
            n = level.n_clusters
            flat = np.where(window_labels >= 0, window_labels, n).ravel()
            compliance = h2 / level.stiffnesses
            padded = xp.asarray(np.append(compliance, 0.0))
            self.levels.append(LevelLabels(compliance, xp.asarray(flat), n, level, padded))
        # The spring sums only ever see pressure on the footprints: gather
        # those elements once (far fewer than the window's for a sparse brush).
        footprint = np.flatnonzero(indenter.pillar[slices].ravel() >= 0)
        self._footprint_index = xp.asarray(footprint)
        self._footprint_levels = [
            (lv.padded[:-1], xp.asarray(np.asarray(backend.to_numpy(lv.labels))[footprint]), lv.n_clusters)
            for lv in self.levels
        ]
        self.element_size = element_size

    def __bool__(self) -> bool:
        """Whether there is any elastic level (a rigid indenter has none)."""
        return bool(self.levels)

    def cluster_forces(self, pressure):
        """Force carried by every cluster of every elastic level: list of arrays h^2 sum p."""
        xp = self.xp
        h2 = self.element_size**2
        values = xp.reshape(pressure, (-1,))[self._footprint_index]
        return [h2 * backend.segment_sum(xp, labels, values, n) for _, labels, n in self._footprint_levels]

    def apply(self, pressure):
        """Total spring deflection above every element of the window, in units of length.

        Zero outside the footprints; pressure outside the footprints is ignored
        (it is zero in every state of the solver).
        """
        xp = self.xp
        if not is_numpy_namespace(xp):
            # Gathers only (the array API standard has no scatter): sums per
            # cluster over the window, the off-footprint dummy cluster n set
            # to zero, read back through the labels.
            values = xp.reshape(pressure, (-1,))
            total = xp.zeros(values.shape, dtype=pressure.dtype)
            for lv in self.levels:
                n = lv.n_clusters
                sums = backend.segment_sum(xp, lv.labels, values, n + 1)
                total = total + xp.take(lv.padded * sums, lv.labels)
            return xp.reshape(total, pressure.shape)
        values = xp.reshape(pressure, (-1,))[self._footprint_index]
        on_footprint = xp.zeros(values.shape, dtype=pressure.dtype)
        for compliance, labels, n in self._footprint_levels:
            on_footprint = on_footprint + (compliance * backend.segment_sum(xp, labels, values, n))[labels]
        total = xp.zeros(pressure.size, dtype=pressure.dtype)
        total[self._footprint_index] = on_footprint
        return xp.reshape(total, pressure.shape)

    def on_set(self, index) -> SetSprings:
        """The springs on the elements ``index`` (flat window indices) of a contact set."""
        return SetSprings([(lv.padded, lv.labels[index], lv.n_clusters) for lv in self.levels], self.xp)


class SetSprings:
    """The springs' part of A_S on the |S| values of a contact set S."""

    def __init__(self, levels: list[tuple[object, object, int]], xp):
        """``levels``: per elastic level, (compliance of every cluster and 0 for the dummy one, the
        cluster of every element of S, n_clusters)."""
        self.levels = levels
        self.xp = xp

    def __bool__(self) -> bool:
        return bool(self.levels)

    def apply(self, values, out=None):
        """The deflection of every level above each element of S, for the pressure ``values`` on S.

        ``out`` (a deflection on S) is added to, level by level, in that order.
        """
        xp = self.xp
        if out is None:
            out = xp.zeros_like(values)
        for compliance, labels, n in self.levels:
            out = out + (compliance * backend.segment_sum(xp, labels, values, n + 1))[labels]
        return out
