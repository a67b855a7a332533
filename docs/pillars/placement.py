"""How much of a brush's F_A is where its circles fall on the raster: the lattice moved by a fraction of an element.

A brush translated by less than an element is the same problem on a
different raster of its circles: on a half-space that is not periodic only
the staircase of the footprints changes.  Per 8 x 8 brush of
``docs/pillars/validation.py`` (flat at k~ = 10 and 1e-5, rough at 10),
per tip resolution (3.6, 7.2 and 14.4 elements per radius: the tips' raster
the grid N = 128 subdivided 1, 2 and 4 times; and 28.9 (8 times), for four
placements of the flat ones) and per shift of ``SHIFTS`` and, for the rough
one, ``MORE_SHIFTS`` (fractions of the tips' element, y and x; (0, 0) is
the family's own raster): the pillar model's F_A with its tips
calibrated to Kendall's force (``LoadPath.pillar_tip_calibration``: the
lone tip's raster error removed) and the lone tip's raster error e_R of
that placement.  The spread over the shifts at one resolution is the part
of the brush's error that an extrapolation over one raster's h carries
along; the family's own raster is one draw of it.  The preload is the unshifted brush's F_c.

``--exact`` runs the placements of ``CHECKS`` by the exact path on the
grid whose elements are the tips' and by the pillar model beside it
(``placement_exact.csv``): the model follows the exact path on moved
rasters as on the families' own.

Rows go to ``placement.csv`` as each completes (atomically; a rerun skips
the rows already there).  The summary is in `docs/pillars/accuracy.md` ("The
reference").

    nice python docs/pillars/placement.py
    nice python docs/pillars/placement.py --exact    # the moved placements of CHECKS by the exact path
    nice python docs/pillars/placement.py --finer    # the flat brush at k~ = 1e-5 at 39.7 per radius (FINER)
"""

from __future__ import annotations

import sys
import time
from pathlib import Path
from unittest import mock

import numpy as np

from brushbem.physics.structure import builders
from brushbem.protocol import LoadPath, record_pull_off

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import reference  # noqa: E402
from calibration import lone_tip_error  # noqa: E402
from validation import problem  # noqa: E402

TABLE = HERE / "placement.csv"
EXACT = HERE / "placement_exact.csv"
EXACT_FIELDS = ("stiffness_ratio", "tip_factor", "shift_y", "shift_x", "events_adhesive_force", "events_cpu_seconds",
                "pillars_adhesive_force", "adhesive_force_error")
#: The moved placements checked against the exact path (k~, factor, shift): ``--exact``.
CHECKS = ((10.0, 1, (0.29, 0.71)), (10.0, 2, (0.13, 0.37)), (1e-5, 2, (0.41, 0.09)), (10.0, 4, (0.13, 0.37)))
FIELDS = ("family", "pillars_per_side", "stiffness_ratio", "tip_factor", "tip_elements_per_radius", "shift_y",
          "shift_x", "lone_tip_error", "calibrated_adhesive_force", "cpu_seconds")
#: Shifts of the lattice (y, x) in the tips' elements: (0, 0) and five off the grid's symmetry lines.
SHIFTS = ((0.0, 0.0), (0.13, 0.37), (0.29, 0.71), (0.41, 0.09), (0.67, 0.53), (0.83, 0.21))
#: Six more, for the rough brush at k~ = 10: its F_A (a few pillars in partial contact, a small difference) spreads
#: over the placements by about 20 % at every resolution, so its means need twelve placements.
MORE_SHIFTS = ((0.07, 0.61), (0.23, 0.89), (0.37, 0.47), (0.53, 0.19), (0.61, 0.79), (0.97, 0.43))
CASES = (("flat", 8, 10.0), ("flat", 8, 1e-5), ("rough", 8, 10.0))
FACTORS = (1, 2, 4)
#: 28.9 elements per radius (the tips' factor 8; 90-110 CPU-s a flat pull-off, 30 s a rough one): the flat
#: brushes' first four placements.
FINEST = (8, SHIFTS[:4])
#: 39.7 elements per radius (the tips' factor 11; ``--finer``): the flat brush at k~ = 1e-5, where the continuum
#: reference is pinned (``continuum_limit.csv``), on the first four placements.
FINER = (11, SHIFTS[:4], ("flat", 8, 1e-5))


def placements(family: str, factor: int) -> tuple[tuple[float, float], ...]:
    """The shifts of ``family`` at the tips' ``factor``: the flat brushes' ``SHIFTS`` (``FINEST`` at 28.9 per
    radius), the rough brush's ``SHIFTS`` and ``MORE_SHIFTS`` at every resolution."""
    if family == "flat":
        return FINEST[1] if factor == FINEST[0] else SHIFTS
    return SHIFTS + MORE_SHIFTS


def plan() -> list[tuple[tuple, int, tuple[float, float]]]:
    """(case, factor, shift) of every row, in order: every case at ``FACTORS``, then at ``FINEST``'s factor."""
    out = [(case, factor, shift) for case in CASES for factor in FACTORS for shift in placements(case[0], factor)]
    return out + [(case, FINEST[0], shift) for case in CASES for shift in placements(case[0], FINEST[0])]


def shifted(family: str, per_side: int, stiffness: float, factor: int, shift: tuple[float, float],
            grid_factor: int = 1):
    """The family's brush (`validation.problem`) with its lattice moved by ``shift`` tips' elements (y, x), on
    its grid (``grid_factor`` 1) or on the grid ``grid_factor`` times finer (the exact path's, `exact_row`)."""
    coarse, _ = problem(family, per_side, stiffness)
    step = coarse.grid.element_size / factor
    original = builders.square_lattice

    def moved(pillars_per_side: int, spacing: float) -> tuple[np.ndarray, np.ndarray]:
        centres, index = original(pillars_per_side, spacing)
        return centres + step * np.asarray(shift), index

    with mock.patch.object(builders, "square_lattice", moved):
        case, _ = problem(family, per_side, stiffness, factor=grid_factor)
    return case


def exact_row(stiffness: float, factor: int, shift: tuple[float, float]) -> dict:
    """A moved placement by the exact path on the grid ``factor`` N and by the pillar model (uncalibrated, tips
    ``factor`` times the grid's): does the model follow the exact path on a moved raster?"""
    _, preload = problem("flat", 8, stiffness)
    fine, coarse = (shifted("flat", 8, stiffness, factor, shift, f) for f in (factor, 1))
    per_radius = factor * float(coarse.indenter.description.pillar_radius) / coarse.grid.element_size
    start = time.process_time()
    exact = record_pull_off(fine, LoadPath(method="events", preload_force=preload, max_steps=10**7)).summary
    seconds = time.process_time() - start
    model = record_pull_off(coarse, LoadPath(method="pillars", preload_force=preload, max_steps=10**7,
                                             pillar_tip_resolution=per_radius if factor > 1 else None,
                                             pillar_tip_peel=False)).summary
    return {"stiffness_ratio": stiffness, "tip_factor": factor, "shift_y": shift[0], "shift_x": shift[1],
            "events_adhesive_force": exact["adhesive_force"], "events_cpu_seconds": round(seconds, 2),
            "pillars_adhesive_force": model["adhesive_force"],
            "adhesive_force_error": model["adhesive_force"] / exact["adhesive_force"] - 1}


def row(family: str, per_side: int, stiffness: float, factor: int, shift: tuple[float, float]) -> dict:
    _, preload = problem(family, per_side, stiffness)
    case = shifted(family, per_side, stiffness, factor, shift)
    per_radius = factor * float(case.indenter.description.pillar_radius) / case.grid.element_size
    start = time.process_time()
    summary = record_pull_off(case, LoadPath(method="pillars", preload_force=preload, max_steps=10**7,
                                             pillar_tip_resolution=per_radius if factor > 1 else None,
                                             pillar_tip_calibration=True)).summary
    seconds = time.process_time() - start
    if not summary["converged"]:
        raise RuntimeError(summary["reason"])
    return {"family": family, "pillars_per_side": per_side, "stiffness_ratio": stiffness, "tip_factor": factor,
            "tip_elements_per_radius": round(per_radius, 3), "shift_y": shift[0], "shift_x": shift[1],
            "lone_tip_error": lone_tip_error(case, factor), "calibrated_adhesive_force": summary["adhesive_force"],
            "cpu_seconds": round(seconds, 2)}


def _key(line: dict) -> tuple:
    return (line["family"], int(line["pillars_per_side"]), float(line["stiffness_ratio"]), int(line["tip_factor"]),
            float(line["shift_y"]), float(line["shift_x"]))


def load() -> list[dict]:
    return reference.load(TABLE)


def write(rows: list[dict]) -> None:
    reference.write(rows, TABLE, FIELDS)


def main() -> None:
    if "--exact" in sys.argv[1:]:
        checks = reference.load(EXACT)
        done = {(float(line["stiffness_ratio"]), int(line["tip_factor"]), float(line["shift_y"]),
                 float(line["shift_x"])) for line in checks}
        for stiffness, factor, shift in CHECKS:
            if (stiffness, factor, *shift) not in done:
                checks.append(exact_row(stiffness, factor, shift))
                reference.write(checks, EXACT, EXACT_FIELDS)
                print(checks[-1], flush=True)
        return
    rows = load()
    done = {_key(line) for line in rows}
    todo = plan()
    if "--finer" in sys.argv[1:]:
        todo = [(FINER[2], FINER[0], shift) for shift in FINER[1]]
    for case, factor, shift in todo:
        if (*case, factor, *shift) in done:
            continue
        rows.append(row(*case, factor, shift))
        write(rows)
        print(", ".join(f"{name}={rows[-1][name]}" for name in FIELDS), flush=True)


if __name__ == "__main__":
    main()
