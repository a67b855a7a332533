"""The sub-pillars' rasters of chapter 6's clustered brush (Fig. 6-3, 40 x 40 sub-pillars, N3 = 4) on each grid.

The three-level plateau of parts ``fig63_*`` moves by +4.1 % and then -3.8 % from N = 1024 to 2048 to 4096
(2.25, 4.5, 9 elements a radius).  This probe measures what the grid changes in the brush itself: the
rasterised area of every sub-pillar against pi r^2 (mean, smallest, largest), the number of distinct
footprints (element patterns), and the mean of (area ratio)^(3/4), the change of Kendall's force
F_K ~ a^(3/2) that the area alone would make.  Geometry only (no pull-off): seconds.  Output:
``probe_fig63_raster.json`` beside this file.

    python docs/reproduction/probe_fig63_raster.py
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from brushbem.physics.structure import Grid
from brushbem.physics.structure.layouts import clustered_lattice
from brushbem.physics.structure.raster import footprint_blocks

HERE = Path(__file__).resolve().parent
#: The global grids of set mesh and the rows (1024, 2048, 4096) and the tips' rasters of part fig63_tips on
#: N = 2048 (factors 3 and 4: 6144, 8192 elements a side).
GRIDS = (1024, 2048, 4096, 6144, 8192)


def main() -> None:
    lattice = clustered_lattice(40, [5, 4], [0.12, 0.45, 0.45], 1.0)
    radius = lattice.pillar_radius
    rows = []
    for n in GRIDS:
        grid = Grid(1.0, n)
        h = grid.element_size
        counts, shapes = [], set()
        for rows_, cols, inside in footprint_blocks(grid, np.asarray(lattice.centres), radius):
            i, j = np.nonzero(inside)
            counts.append(i.size)
            shapes.add(tuple(sorted(zip((i - i.min()).tolist(), (j - j.min()).tolist()))))
        ratio = np.asarray(counts) * h * h / (math.pi * radius**2)
        rows.append({"elements": n, "elements_per_radius": radius / h, "area_ratio_mean": float(ratio.mean()),
                     "area_ratio_min": float(ratio.min()), "area_ratio_max": float(ratio.max()),
                     "distinct_footprints": len(shapes), "kendall_from_area": float((ratio**0.75).mean())})
        print(rows[-1])
    (HERE / "probe_fig63_raster.json").write_text(json.dumps(rows, indent=1) + "\n", encoding="utf-8")


if __name__ == "__main__":
    main()
