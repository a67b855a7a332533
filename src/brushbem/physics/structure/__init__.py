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

The package's modules, each re-exported here:

* `errors`: `StructureError`.
* `grid`: the `Grid` of elements and the smallest pillar it resolves.
* `records`: `SpringLevel`, `Indenter` and the `Geometry` records.
* `tips`: the length `Profile`, tip shapes (`Tip`), the base's `Tilt`, graded springs (`Grading`).
* `layouts`: the square and clustered lattices and random packing of the pillars' centres.
* `raster`: the pillars' footprints on the grid (`rasterise_pillars`) and the filling factors they give.
* `hierarchy`: the levels of springs above the pillars (`Level`, `hierarchy_clusters`).
* `builders`: `flat_punch`, `sphere`, `height_map` and the `brush` of pillars.
"""

from __future__ import annotations

from brushbem.physics.structure.builders import brush, flat_punch, height_map, sphere
from brushbem.physics.structure.errors import StructureError
from brushbem.physics.structure.grid import MIN_PILLAR_RADIUS_ELEMENTS, Grid
from brushbem.physics.structure.hierarchy import Level, hierarchy_clusters
from brushbem.physics.structure.layouts import (
    HEXAGONAL_PACKING_DENSITY,
    MAX_RANDOM_DRAWS,
    ClusteredLattice,
    clustered_lattice,
    random_positions,
    square_lattice,
)
from brushbem.physics.structure.raster import clustered_filling_factors, rasterise_pillars
from brushbem.physics.structure.records import (
    BrushGeometry,
    Geometry,
    HeightMapGeometry,
    Indenter,
    PunchGeometry,
    SphereGeometry,
    SpringLevel,
    elastic_connection_problems,
)
from brushbem.physics.structure.tips import GRADING_RULES, TIP_SHAPES, Grading, Profile, Tilt, Tip, graded_stiffness

__all__ = [
    "GRADING_RULES",
    "HEXAGONAL_PACKING_DENSITY",
    "MAX_RANDOM_DRAWS",
    "MIN_PILLAR_RADIUS_ELEMENTS",
    "TIP_SHAPES",
    "BrushGeometry",
    "ClusteredLattice",
    "Geometry",
    "Grading",
    "Grid",
    "HeightMapGeometry",
    "Indenter",
    "Level",
    "Profile",
    "PunchGeometry",
    "SphereGeometry",
    "SpringLevel",
    "StructureError",
    "Tilt",
    "Tip",
    "brush",
    "clustered_filling_factors",
    "clustered_lattice",
    "elastic_connection_problems",
    "flat_punch",
    "graded_stiffness",
    "height_map",
    "hierarchy_clusters",
    "random_positions",
    "rasterise_pillars",
    "sphere",
    "square_lattice",
]
