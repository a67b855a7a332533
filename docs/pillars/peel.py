"""Tips that leave at their continuum capacity (``LoadPath.pillar_tip_peel``) against the brush's limit.

Every F_A here is the pillar model's with ``pillar_tip_peel = true`` on the
8 x 8 brushes of ``docs/pillars/validation.py``.  Two parts:

* ``families``: every family with a reference (``criteria.FAMILIES``: the
  exact path's extrapolated fine-grid value, ``tips_extrapolated.csv``) on
  its own raster, the tips at 3.6 and 7.2 elements per radius (the tips'
  factors 1 and 2): the error against that reference, and for the flat
  brush against the decided limit (``limit.py::interval``: the lower end
  at k~ = 10, the middle of 0.0120385 .. 0.0121588 at 1e-5).
* ``placement``: the flat brush (k~ = 10 and 1e-5) moved by the fractions of
  the tips' element of ``placement.SHIFTS`` at 3.6, 7.2 and 14.4 elements per
  radius: how much of the answer is where the circles fall on the raster,
  and whether the placements' mean converges to the limit.

Beside each F_A the work of separation, the CPU time and, for the families,
the default's F_A on the same raster (the tips peeling on their rasters).

Rows go to ``peel.csv`` (atomically, when all are done; about 15 CPU-s), and the placement part at
k~ = 1e-5 to ``src/brushbem/data/brush_peel_error.csv``, the error a run with the option reports
(`brushbem.config.advice`): F_A against the limit (the mean against its middle, the range every placement
between its bounds), the work against the placements' mean at 14.4 elements per radius (no limit of the
work is known).
The summary is in `docs/pillars/accuracy.md` ("Tips at their continuum
capacity").

    nice python docs/pillars/peel.py
    python docs/pillars/peel.py --errors   # brush_peel_error.csv again from peel.csv
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

from brushbem.protocol import LoadPath, record_pull_off

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import calibration  # noqa: E402
import criteria  # noqa: E402
import limit  # noqa: E402
import placement  # noqa: E402
import validation  # noqa: E402

TABLE = HERE / "peel.csv"
#: The error a run with ``pillar_tip_peel`` reports (`brushbem.config.advice`): the placement part at k~ = 1e-5.
ERROR_TABLE = HERE.parents[1] / "src" / "brushbem" / "data" / "brush_peel_error.csv"
ERROR_FIELDS = ("elements_per_radius", "placements", "force_error_mean", "force_error_min", "force_error_max",
                "work_error_mean", "work_error_min", "work_error_max")
FIELDS = ("part", "family", "stiffness_ratio", "tip_factor", "tip_elements_per_radius", "shift_y", "shift_x",
          "adhesive_force", "work_of_separation", "reference", "error", "default_adhesive_force", "cpu_seconds")


def pull_off(case, preload: float, factor: int, peel: bool = True) -> tuple[dict, float]:
    """(summary, CPU s) of the pillar model on ``case`` with the tips ``factor`` times finer."""
    per_radius = factor * float(case.indenter.description.pillar_radius) / case.grid.element_size
    path = LoadPath(method="pillars", preload_force=preload, max_steps=10**7,
                    pillar_tip_resolution=per_radius if factor > 1 else None, pillar_tip_peel=peel)
    start = time.process_time()
    summary = record_pull_off(case, path).summary
    if not summary["converged"]:
        raise RuntimeError(summary["reason"])
    return summary, time.process_time() - start


def _row(part, family, stiffness, factor, case, shift, summary, seconds, reference, default) -> dict:
    per_radius = factor * float(case.indenter.description.pillar_radius) / case.grid.element_size
    force = float(summary["adhesive_force"])
    return {"part": part, "family": family, "stiffness_ratio": stiffness, "tip_factor": factor,
            "tip_elements_per_radius": round(per_radius, 3), "shift_y": shift[0], "shift_x": shift[1],
            "adhesive_force": force, "work_of_separation": float(summary["work_of_separation"]),
            "reference": reference, "error": force / reference - 1, "default_adhesive_force": default,
            "cpu_seconds": round(seconds, 2)}


def _load() -> list[dict]:
    """``peel.csv``'s rows, numbers as numbers."""
    import csv

    with TABLE.open(newline="") as stream:
        rows = list(csv.DictReader(stream))
    numeric = ("stiffness_ratio", "tip_factor", "tip_elements_per_radius", "adhesive_force", "work_of_separation",
               "error")
    return [{**r, **{name: (int(float(r[name])) if name == "tip_factor" else float(r[name])) for name in numeric}}
            for r in rows]


def family_rows() -> list[dict]:
    references = criteria.references()
    out = []
    for family, stiffness in criteria.FAMILIES:
        case, preload = validation.problem(family, 8, stiffness)
        for factor in (1, 2):
            summary, seconds = pull_off(case, preload, factor)
            default = float(pull_off(case, preload, factor, peel=False)[0]["adhesive_force"])
            out.append(_row("families", family, stiffness, factor, case, (0.0, 0.0), summary, seconds,
                            references[(family, stiffness)], default))
            print(out[-1], flush=True)
    return out


def placement_rows() -> list[dict]:
    out = []
    for stiffness in (10.0, 1e-5):
        _, preload = validation.problem("flat", 8, stiffness)
        reference = limit.interval(stiffness)[0 if stiffness == 10.0 else 2]
        for factor in placement.FACTORS:
            for shift in placement.SHIFTS:
                case = placement.shifted("flat", 8, stiffness, factor, shift)
                summary, seconds = pull_off(case, preload, factor)
                out.append(_row("placement", "flat", stiffness, factor, case, shift, summary, seconds, reference, ""))
                print(out[-1], flush=True)
    return out


def error_rows(rows: list[dict]) -> list[dict]:
    """``brush_peel_error.csv``: per tip resolution, the flat brush's placements at k~ = 1e-5 (module docstring)."""
    lower, upper, middle = limit.interval(1e-5)
    placed = [r for r in rows if r["part"] == "placement" and r["stiffness_ratio"] == 1e-5]
    finest = max(r["tip_factor"] for r in placed)
    work_reference = float(np.mean([r["work_of_separation"] for r in placed if r["tip_factor"] == finest]))
    out = []
    for factor in sorted({r["tip_factor"] for r in placed}):
        forces = np.array([r["adhesive_force"] for r in placed if r["tip_factor"] == factor])
        works = np.array([r["work_of_separation"] for r in placed if r["tip_factor"] == factor]) / work_reference - 1
        out.append({"elements_per_radius": next(r["tip_elements_per_radius"] for r in placed
                                                if r["tip_factor"] == factor),
                    "placements": forces.size, "force_error_mean": float(forces.mean() / middle - 1),
                    "force_error_min": float(forces.min() / upper - 1), "force_error_max": float(forces.max() / lower - 1),
                    "work_error_mean": float(works.mean()), "work_error_min": float(works.min()),
                    "work_error_max": float(works.max())})
    return out


def main() -> None:
    if "--errors" in sys.argv:  # the error table again from peel.csv
        rows = _load()
    else:
        rows = family_rows() + placement_rows()
        calibration.write(rows, TABLE, FIELDS, digits=7)
    calibration.write(error_rows(rows), ERROR_TABLE, ERROR_FIELDS, digits=5)
    header = ("# the flat 8 x 8 brush at k~ = 1e-5 (phi = 0.16), tips leaving at their continuum capacity "
              "(protocol.pillar_tip_peel): F_A's mean over placements of the lattice on the tips' raster against the "
              "continuum limit's middle, its range every placement between the limit's bounds; the work against "
              "the placements' mean at the finest tips; docs/pillars/peel.py\n")
    ERROR_TABLE.write_text(header + ERROR_TABLE.read_text())
    for stiffness in (10.0, 1e-5):
        for factor in placement.FACTORS:
            errors = np.array([r["error"] for r in rows if r["part"] == "placement"
                               and r["stiffness_ratio"] == stiffness and r["tip_factor"] == factor])
            print(f"k~ = {stiffness:g}, tips x{factor}: placements {errors.min():+.4f} .. {errors.max():+.4f}, "
                  f"mean {errors.mean():+.4f} (s.e. {errors.std(ddof=1) / np.sqrt(errors.size):.4f})")


if __name__ == "__main__":
    main()
