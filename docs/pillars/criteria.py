"""Which part of a coarse tip's error a criterion can remove: the tips' rasters and their criteria against the reference.

Every F_A here is the pillar model's on an 8 x 8 brush of ``docs/pillars/validation.py``,
and every error is against the exact path's extrapolated fine-grid value
(``tips_extrapolated.csv``; at k~ = 1e-5 it is 1.6 % above the continuum limit,
``continuum_limit.csv``).  Three
criteria on the same rasters:

* ``plain``: the raster's Sigma_c (the default);
* ``calibrated``: Sigma_c F_K / F_R per footprint (``LoadPath.pillar_tip_calibration``);
* ``per_element``: every element its own critical stress, in proportion to
  its pressure under the lone tip's uniform pull, so that the lone tip comes
  off at F_K with every element at its criterion at once
  (`brushbem.pillars.calibration.calibrated_criteria`): the element where
  the stress intensity is largest goes first, as in the continuum.

Four parts:

* ``placement``: the flat brush (k~ = 10 and 1e-5) moved by the fractions of
  the tips' element of ``placement.SHIFTS`` at 3.6, 7.2 and 14.4 elements per
  radius (tips' factors 1, 2, 4), ``per_element`` (the calibrated rows are
  ``placement.csv``'s): does the per-element criterion remove the placement
  spread and the brush's error?
* ``canonical``: every tip on the same raster, its circle centred on an
  element's centre (``element``) or corner (``corner``), on grids of a pitch
  of 13 to 18 elements (3.0 to 4.1 elements per radius; the grid's own tips,
  the brush and its preload unchanged), the three criteria, on the families
  with a reference (flat and hierarchy at k~ = 10; flat, hierarchy and
  concave at 1e-5).  A tip on a raster of its own centred on the pillar (the
  global grid only placing the pillars) is this: on a lattice whose pitch is
  a whole number of elements every pillar's raster is the same one, and the
  near field between two is the global grid's.
* ``finest``: the flat brush on its own raster at 28.9 elements per radius
  (the tips' factor 8), per element: where its limit lies (the calibrated
  rows are ``placement.csv``'s).
* ``families``: every family with a reference (``FAMILIES``), on its own
  raster, the tips at 3.6 and 7.2 elements per radius, the three criteria:
  the default (``plain`` at 3.6) and what each criterion makes of it.

Rows go to ``criteria.csv`` as each part completes (atomically; a rerun skips
the parts already there).  About 40 CPU-s, and the finest part 10 more.

    nice python docs/pillars/criteria.py
"""

from __future__ import annotations

import csv
import sys
import time
from pathlib import Path
from unittest import mock

import numpy as np

from brushbem.physics.structure import builders
from brushbem.pillars import calibration
from brushbem.protocol import LoadPath, record_pull_off

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import placement  # noqa: E402
import reference  # noqa: E402
import validation  # noqa: E402

TABLE = HERE / "criteria.csv"
#: `calibration.tip_criteria` itself (`pull_off` puts a variant in its place).
_TIP_CRITERIA = calibration.tip_criteria
FIELDS = ("part", "family", "stiffness_ratio", "criterion", "tip_factor", "pitch_elements", "tip_elements_per_radius",
          "centring", "shift_y", "shift_x", "footprint_elements", "area_ratio", "adhesive_force", "error", "cpu_seconds")
CRITERIA = ("plain", "calibrated", "per_element")
#: The cases with a reference (``tips_extrapolated.csv``): the canonical part's.
CANONICAL = (("flat", 10.0), ("hierarchy", 10.0), ("flat", 1e-5), ("hierarchy", 1e-5), ("concave", 1e-5))
PITCHES = (13, 14, 15, 16, 17, 18)
#: The families' part: every case of ``tips_extrapolated.csv`` with an extrapolated value.
FAMILIES = (("flat", 10.0), ("hierarchy", 10.0), ("flat", 1e-5), ("random", 1e-5), ("hierarchy", 1e-5),
            ("concave", 1e-5))
CENTRINGS = ("element", "corner")


def references() -> dict[tuple[str, float], float]:
    with (HERE / "tips_extrapolated.csv").open(newline="") as stream:
        return {(line["family"], float(line["stiffness_ratio"])): float(line["extrapolated_adhesive_force"])
                for line in csv.DictReader(stream)}


def pull_off(case, preload: float, criterion: str, factor: int = 1) -> tuple[float, float]:
    """(F_A, CPU s) of the pillar model on ``case`` with the tips ``factor`` times finer and ``criterion``."""
    per_radius = factor * float(case.indenter.description.pillar_radius) / case.grid.element_size
    path = LoadPath(method="pillars", preload_force=preload, max_steps=10**7,
                    pillar_tip_resolution=per_radius if factor > 1 else None,
                    pillar_tip_calibration=criterion != "plain", pillar_tip_peel=False)

    def criteria(model, problem, critical, calibrate):
        return _TIP_CRITERIA(model, problem, critical, calibrate, per_element=criterion == "per_element")

    start = time.process_time()
    with mock.patch.object(calibration, "tip_criteria", criteria):
        summary = record_pull_off(case, path).summary
    if not summary["converged"]:
        raise RuntimeError(summary["reason"])
    return summary["adhesive_force"], time.process_time() - start


def canonical_case(family: str, stiffness: float, pitch: int, centring: str, per_side: int = 8):
    """The family's ``per_side`` x ``per_side`` brush on the grid of ``pitch`` elements between pillars, every
    centre moved onto the nearest element centre (``element``) or corner (``corner``): every tip on the same
    raster."""
    elements = per_side * pitch
    h = 1.0 / elements
    original, grid = builders.square_lattice, validation.Grid

    def snapped(pillars_per_side: int, spacing: float) -> tuple[np.ndarray, np.ndarray]:
        centres, index = original(pillars_per_side, spacing)
        corners = (centres + 0.5) / h
        moved = np.floor(corners) + 0.5 if centring == "element" else np.round(corners)
        return moved * h - 0.5, index

    with mock.patch.object(builders, "square_lattice", snapped), \
            mock.patch.object(validation, "Grid", lambda size, _elements: grid(size, elements)):
        case, _ = validation.problem(family, per_side, stiffness)
    return case


def placement_rows(limits: dict) -> list[dict]:
    out = []
    for stiffness in (10.0, 1e-5):
        _, preload = validation.problem("flat", 8, stiffness)
        for factor in placement.FACTORS:
            for shift in placement.SHIFTS:
                case = placement.shifted("flat", 8, stiffness, factor, shift)
                force, seconds = pull_off(case, preload, "per_element", factor)
                out.append(_row("placement", "flat", stiffness, "per_element", factor, 16, case, "lattice", shift,
                                force, limits, seconds))
                print(_line(out[-1]), flush=True)
    return out


def canonical_rows(limits: dict) -> list[dict]:
    out = []
    for family, stiffness in CANONICAL:
        _, preload = validation.problem(family, 8, stiffness)
        for pitch in PITCHES:
            for centring in CENTRINGS:
                case = canonical_case(family, stiffness, pitch, centring)
                for criterion in CRITERIA:
                    force, seconds = pull_off(case, preload, criterion)
                    out.append(_row("canonical", family, stiffness, criterion, 1, pitch, case, centring, (0.0, 0.0),
                                    force, limits, seconds))
                    print(_line(out[-1]), flush=True)
    return out


def finest_rows(limits: dict) -> list[dict]:
    out = []
    for stiffness in (10.0, 1e-5):
        case, preload = validation.problem("flat", 8, stiffness)
        force, seconds = pull_off(case, preload, "per_element", placement.FINEST[0])
        out.append(_row("finest", "flat", stiffness, "per_element", placement.FINEST[0], 16, case, "lattice",
                        (0.0, 0.0), force, limits, seconds))
        print(_line(out[-1]), flush=True)
    return out


def family_rows(limits: dict) -> list[dict]:
    out = []
    for family, stiffness in FAMILIES:
        case, preload = validation.problem(family, 8, stiffness)
        for factor in (1, 2):
            for criterion in CRITERIA:
                force, seconds = pull_off(case, preload, criterion, factor)
                out.append(_row("families", family, stiffness, criterion, factor, 16, case, "own", (0.0, 0.0), force,
                                limits, seconds))
                print(_line(out[-1]), flush=True)
    return out


def _row(part, family, stiffness, criterion, factor, pitch, case, centring, shift, force, limits, seconds) -> dict:
    labels = np.asarray(case.indenter.pillar)
    sizes = np.bincount(labels[labels >= 0])
    per_radius = float(case.indenter.description.pillar_radius) / case.grid.element_size
    return {"part": part, "family": family, "stiffness_ratio": stiffness, "criterion": criterion,
            "tip_factor": factor, "pitch_elements": pitch * factor,
            "tip_elements_per_radius": round(factor * float(case.indenter.description.pillar_radius)
                                             / case.grid.element_size, 3),
            "centring": centring, "shift_y": shift[0], "shift_x": shift[1],
            "footprint_elements": int(sizes.max()) if factor == 1 else "",
            "area_ratio": round(float(sizes.mean()) / (np.pi * per_radius**2), 4) if factor == 1 else "",
            "adhesive_force": force, "error": force / limits[(family, stiffness)] - 1, "cpu_seconds": round(seconds, 2)}


def _line(row: dict) -> str:
    return ", ".join(f"{name}={row[name]}" for name in FIELDS)


def main() -> None:
    rows = reference.load(TABLE)
    done = {line["part"] for line in rows}
    limits = references()
    for part, make in (("placement", placement_rows), ("canonical", canonical_rows), ("families", family_rows),
                       ("finest", finest_rows)):
        if part not in done:
            rows += make(limits)
            reference.write(rows, TABLE, FIELDS)


if __name__ == "__main__":
    main()
