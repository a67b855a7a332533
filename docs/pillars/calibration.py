"""The tips' criterion calibrated to Kendall's force (``LoadPath.pillar_tip_calibration``) on the validation families.

The pillar model with every tip's critical stress scaled by F_K / F_R (F_R
the lone tip's pull-off on its raster, `brushbem.pillars.calibration`)
against the model without it and against the exact event path: per 8 x 8
family of ``docs/pillars/validation.py`` and k~, per tip resolution (the
grid's 3.6 elements per radius, 7.2 and, where the exact path on N = 512 is
in ``tips.csv``, 14.4), calibrated or not: F_A, the work of separation, the
CPU time, the lone tip's error on that raster (F_R / F_K - 1), and the
relative errors of F_A and the work against

* the exact path on the grid whose elements are the tips' (N = 128, 256, 512:
  ``validation.jsonl``, ``tips.csv``): the model's own error;
* the exact path on N = 512 (14.4 elements per radius);
* the exact path extrapolated from N = 128, 256 and 512 (first order,
  ``tips_extrapolated.csv``; the work the same way, where it is monotone
  with shrinking steps): none where it is outside its asymptotic range.
  This is the old reference: at k~ = 1e-5 it lies 1.56 % above the
  continuum limit's middle (``continuum_limit.csv``), and the flat,
  hierarchical and concave brushes' F_A against that limit are in
  ``rereferenced.csv`` (``limit.py``).

Rows are written to ``calibration.csv`` atomically at the end (a run takes
about three CPU minutes).

    nice python docs/pillars/calibration.py
"""

from __future__ import annotations

import csv
import json
import math
import os
import sys
import time
from pathlib import Path

import numpy as np

from brushbem.physics.theory.punch import kendall_force
from brushbem.pillars import PillarModel
from brushbem.pillars.calibration import lone_pull_off
from brushbem.pillars.tips import tip_factor
from brushbem.protocol import LoadPath, record_pull_off

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from validation import FAMILIES, STIFFNESSES, problem  # noqa: E402

TABLE = HERE / "calibration.csv"
FIELDS = ("family", "pillars_per_side", "stiffness_ratio", "tip_elements_per_radius", "calibrated", "adhesive_force",
          "work", "cpu_seconds", "lone_tip_error", "own_grid_force_error", "own_grid_work_error", "force_error_512",
          "work_error_512", "force_error_extrapolated", "work_error_extrapolated")
#: Tip resolutions (factors of the grid N = 128: 3.6, 7.2 and 14.4 elements per radius).
FACTORS = (1, 2, 4)


def exact() -> dict[tuple[str, float, int], tuple[float, float]]:
    """(F_A, work) of the exact path per (family, k~, factor of N = 128), 8 x 8 brushes at phi = 0.16."""
    out = {}
    for line in (HERE / "validation.jsonl").read_text().splitlines():
        row = json.loads(line) if line.strip() else {}
        if row and row.get("phi", 0.16) == 0.16 and row["pillars_per_side"] == 8 and row["events_converged"]:
            out[(row["family"], float(row["stiffness_ratio"]), 1)] = (row["events_adhesive_force"],
                                                                      row["events_work_of_separation"])
    with (HERE / "tips.csv").open(newline="") as stream:
        for row in csv.DictReader(stream):
            if row["pillars_per_side"] == "8" and row["events_converged"] == "True":
                out[(row["family"], float(row["stiffness_ratio"]), int(row["tip_factor"]))] = (
                    float(row["events_adhesive_force"]), float(row["events_work"]))
    return out


def extrapolated(values: tuple[float, float, float]) -> float:
    """First-order Richardson value 2 v(512) - v(256) of a sequence over N = 128, 256, 512 in its asymptotic
    range (monotone, steps shrinking), as ``tips.py``'s `extrapolate`; NaN outside it."""
    v1, v2, v4 = values
    ratio = (v1 - v2) / (v2 - v4) if v2 != v4 else math.nan
    return 2 * v4 - v2 if ratio > 1 else math.nan


def lone_tip_error(case, factor: int) -> float:
    """F_R / F_K - 1 of pillar 0's footprint on the tips' raster (a lattice: every pillar's)."""
    model = PillarModel(case, tips=factor)
    size = int(np.count_nonzero(model.full[0]))
    foot = np.stack([model.rows[0][:size], model.cols[0][:size]], axis=1)
    force = lone_pull_off(model.bases, foot, float(model.critical[0, 0]), model.h2)[0]
    radius = float(case.indenter.description.pillar_radius)
    return force / float(kendall_force(radius, contact_modulus=case.contact_modulus,
                                       work_of_adhesion=case.work_of_adhesion)) - 1


def _error(value: float, reference: float | None) -> float:
    return value / reference - 1 if reference else math.nan


def rows() -> list[dict]:
    references = exact()
    out = []
    for stiffness in STIFFNESSES:
        for family in FAMILIES:
            case, preload = problem(family, 8, stiffness)
            per_radius = float(case.indenter.description.pillar_radius) / case.grid.element_size
            levels = [references.get((family, stiffness, f)) for f in FACTORS]
            limit = (extrapolated(tuple(level[0] for level in levels)),
                     extrapolated(tuple(level[1] for level in levels))) if all(levels) else (math.nan, math.nan)
            fine = levels[-1]
            for factor in FACTORS:
                if factor == 4 and fine is None:
                    continue
                tips = None if factor == 1 else factor * per_radius
                lone = lone_tip_error(case, tip_factor(case, tips))
                own = references.get((family, stiffness, factor))
                for calibrated in (False, True):
                    start = time.process_time()
                    summary = record_pull_off(case, LoadPath(
                        method="pillars", preload_force=preload, max_steps=10**7, pillar_tip_resolution=tips,
                        pillar_tip_calibration=calibrated, pillar_tip_peel=False)).summary
                    seconds = time.process_time() - start
                    force, work = summary["adhesive_force"], summary["work_of_separation"]
                    row = {"family": family, "pillars_per_side": 8, "stiffness_ratio": stiffness,
                           "tip_elements_per_radius": round(factor * per_radius, 3), "calibrated": calibrated,
                           "adhesive_force": force, "work": work, "cpu_seconds": round(seconds, 2),
                           "lone_tip_error": lone,
                           "own_grid_force_error": _error(force, own and own[0]),
                           "own_grid_work_error": _error(work, own and own[1]),
                           "force_error_512": _error(force, fine and fine[0]),
                           "work_error_512": _error(work, fine and fine[1]),
                           "force_error_extrapolated": _error(force, limit[0] if math.isfinite(limit[0]) else None),
                           "work_error_extrapolated": _error(work, limit[1] if math.isfinite(limit[1]) else None)}
                    out.append(row)
                    print(", ".join(f"{name}={row[name]}" for name in FIELDS), flush=True)
    return out


def write(table_rows: list[dict], table: Path = TABLE, fields: tuple[str, ...] = FIELDS, digits: int = 6) -> None:
    """``table_rows`` to ``table`` atomically, floats to ``digits`` significant digits (the docs/pillars tables)."""
    temporary = table.with_suffix(".csv.tmp")
    with temporary.open("w", newline="") as stream:
        writer = csv.DictWriter(stream, fieldnames=fields, lineterminator="\n")
        writer.writeheader()
        for row in table_rows:
            writer.writerow({name: (f"{row[name]:.{digits}g}" if isinstance(row[name], float) else row[name])
                             for name in fields})
    os.replace(temporary, table)


def load() -> list[dict]:
    with TABLE.open(newline="") as stream:
        return list(csv.DictReader(stream))


if __name__ == "__main__":
    write(rows())
