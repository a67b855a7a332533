"""The springs above the pillars: hierarchy `Level`s, the clusters of each, and every level's stiffness."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from brushbem.physics.structure.errors import StructureError
from brushbem.physics.structure.records import SpringLevel
from brushbem.physics.structure.tips import Grading

__all__ = ["Level", "hierarchy_clusters"]


@dataclass(frozen=True)
class Level:
    """One hierarchy level above the pillars: ``cluster`` x ``cluster`` units of the level below.

    ``stiffness``: k of every spring of the level, or an array of one per
    cluster (in the order of `hierarchy_clusters`: row-major over the
    clusters' lattice).
    """

    cluster: int
    stiffness: float | np.ndarray
    grading: Grading | None = None


def hierarchy_clusters(index: np.ndarray, pillars_per_side: int, clusters: tuple[int, ...]) -> list[np.ndarray]:
    """Cluster maps of the levels above the pillars for a square lattice.

    Level l groups ``clusters[l] x clusters[l]`` units of level l-1 (level 0:
    the pillars).  ``index`` holds the lattice (row, column) of every pillar.
    The product of the cluster sizes must divide ``pillars_per_side`` so that
    the clusters tile the lattice.
    """
    block = 1
    maps = []
    for level, size in enumerate(clusters, start=2):
        block *= int(size)
        if pillars_per_side % block:
            raise StructureError(
                "levels", list(clusters),
                f"level {level} groups {block} x {block} pillars, which does not tile the "
                f"{pillars_per_side} x {pillars_per_side} lattice (pillars_per_side must be a multiple of "
                f"the product of the cluster sizes)",
            )
        per_side = pillars_per_side // block
        key = (index[:, 0] // block) * per_side + index[:, 1] // block
        maps.append(np.unique(key, return_inverse=True)[1].astype(np.int64))
    return maps


def _level_stiffness(stiffness, n_springs: int, key: str) -> float | np.ndarray:
    """One level's stiffness as given: a number for every spring, or n_springs values (StructureError names ``key``)."""
    if np.ndim(stiffness) == 0:
        value = float(stiffness)
        if not value > 0:
            raise StructureError(key, value, "must be > 0 (inf = rigid)")
        return value
    values = np.asarray(stiffness, dtype=np.float64).ravel()
    if values.shape != (n_springs,):
        raise StructureError(key, f"{values.size} values", f"must hold one stiffness per spring ({n_springs})")
    if not np.all(values > 0):
        raise StructureError(key, float(values.min()), "every spring's stiffness must be > 0 (inf = rigid)")
    infinite = np.isinf(values)
    if infinite.any() and not infinite.all():
        raise StructureError(key, "inf and finite values", "a level is rigid (all inf) or elastic (all finite)")
    return float(values[0]) if infinite.all() else values


def _spring_levels(stiffness, grading: Grading | None, centres: np.ndarray, index: np.ndarray | None,
                   pillars_per_side: int | None, levels: tuple[Level, ...]) -> list[SpringLevel]:
    """The brush step "springs": the pillars' own springs (graded by ``grading``), then every `Level`'s, bottom-up."""
    n_pillars = len(centres)
    if grading is not None:
        stiffness = grading.apply(_level_stiffness(stiffness, n_pillars, "stiffness"), centres, "grading")
    spring_levels = [SpringLevel(_level_stiffness(stiffness, n_pillars, "stiffness"),
                                 np.arange(n_pillars, dtype=np.int64))]
    if levels:
        maps = hierarchy_clusters(index, int(pillars_per_side), tuple(lv.cluster for lv in levels))
        for i, (lv, cluster) in enumerate(zip(levels, maps)):
            n_clusters = int(cluster.max()) + 1
            k = lv.stiffness
            if lv.grading is not None:
                counts_c = np.bincount(cluster, minlength=n_clusters)
                cluster_centres = np.stack([np.bincount(cluster, weights=centres[:, axis], minlength=n_clusters)
                                            for axis in (0, 1)], axis=1) / counts_c[:, None]
                k = lv.grading.apply(_level_stiffness(k, n_clusters, f"levels.{i}.stiffness"), cluster_centres,
                                     f"levels.{i}.grading")
            spring_levels.append(SpringLevel(_level_stiffness(k, n_clusters, f"levels.{i}.stiffness"), cluster))
    return spring_levels
