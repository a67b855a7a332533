"""Is the exact path's extrapolated F_A a reference to 1 %?  Four tip resolutions of a small brush.

``tips_extrapolated.csv`` extrapolates the exact path's F_A of the 8 x 8
brushes at first order from N = 128, 256 and 512 (3.6, 7.2 and 14.4
elements per radius).  Every level carries the lone tip's raster error
e_R = F_R / F_K - 1 (F_R the lone tip's pull-off on that raster,
`brushbem.pillars.calibration.lone_pull_off`), which is not smooth in h: the
extrapolation is only as good as the sequence is asymptotic.  The exact path
on the 8 x 8 brushes at N = 1024 (28.9 elements per radius) would settle it;
from the cost of N = 256 to 512 (29-35 times, 35-470 CPU-s at 512) it would
take about 1000-3000 CPU-s a case.  The 4 x 4 flat brush of the same family
(`validation.problem`: the same pitch of 16 elements, the same radius in
elements, the same footprints on every raster) runs the exact path on
N = 64, 128, 256 and 512, i.e. at 3.6, 7.2, 14.4 and 28.9 elements per
radius, in about a minute a stiffness.

For a brush of flat tips of equal height on linear springs every pressure
is proportional to the displacement, so the exact path's F_A is
proportional to the critical stress: F / (1 + e_R) is exactly the exact
path with every tip calibrated to Kendall's force
(``LoadPath.pillar_tip_calibration``), the lone tip's raster error removed,
and it has the same limit as h -> 0 (e_R -> 0).  Per stiffness and level the
table gives the exact path's F_A and CPU time, e_R, that corrected F_A, and
the pillar model's F_A with the same tips, plain and calibrated.

Rows go to ``reference.csv`` as each completes (atomically; a rerun skips
the rows already there); the verdict is in `docs/pillars/accuracy.md` ("The
reference").

    nice python docs/pillars/reference.py
"""

from __future__ import annotations

import csv
import sys
import time
from pathlib import Path

from brushbem.protocol import LoadPath, record_pull_off

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import calibration  # noqa: E402
from calibration import lone_tip_error  # noqa: E402
from validation import problem  # noqa: E402

TABLE = HERE / "reference.csv"
FIELDS = ("family", "pillars_per_side", "stiffness_ratio", "tip_factor", "tip_elements_per_radius",
          "exact_elements", "events_adhesive_force", "events_cpu_seconds", "lone_tip_error",
          "corrected_adhesive_force", "pillars_adhesive_force", "pillars_calibrated_adhesive_force",
          "pillars_cpu_seconds")
#: (family, pillars per side, k~) and the tips' factors of the grid N = 16 n (3.6 elements per radius).
CASES = (("flat", 4, 10.0), ("flat", 4, 1e-5))
FACTORS = (1, 2, 4, 8)


def _pull_off(case, preload: float, method: str, **extra) -> tuple[float, float]:
    start = time.process_time()
    summary = record_pull_off(case, LoadPath(method=method, preload_force=preload, max_steps=10**7,
                                             pillar_tip_peel=False, **extra)).summary
    if not summary["converged"]:
        raise RuntimeError(f"{method}: {summary['reason']}")
    return summary["adhesive_force"], time.process_time() - start


def row(family: str, per_side: int, stiffness: float, factor: int) -> dict:
    coarse, preload = problem(family, per_side, stiffness)
    fine, _ = problem(family, per_side, stiffness, factor=factor)
    per_radius = factor * float(coarse.indenter.description.pillar_radius) / coarse.grid.element_size
    exact, seconds = _pull_off(fine, preload, "events")
    lone = lone_tip_error(coarse, factor)
    tips = {"pillar_tip_resolution": per_radius if factor > 1 else None}
    model, model_seconds = _pull_off(coarse, preload, "pillars", **tips)
    calibrated, _ = _pull_off(coarse, preload, "pillars", pillar_tip_calibration=True, **tips)
    return {"family": family, "pillars_per_side": per_side, "stiffness_ratio": stiffness, "tip_factor": factor,
            "tip_elements_per_radius": round(per_radius, 3), "exact_elements": fine.grid.elements,
            "events_adhesive_force": exact, "events_cpu_seconds": round(seconds, 2), "lone_tip_error": lone,
            "corrected_adhesive_force": exact / (1 + lone), "pillars_adhesive_force": model,
            "pillars_calibrated_adhesive_force": calibrated, "pillars_cpu_seconds": round(model_seconds, 2)}


def _key(line: dict) -> tuple:
    return (line["family"], int(line["pillars_per_side"]), float(line["stiffness_ratio"]), int(line["tip_factor"]))


def load(table: Path = TABLE) -> list[dict]:
    """The rows of ``table`` (``reference.csv``; ``placement.py`` reads its own with it), [] before any."""
    if not table.exists():
        return []
    with table.open(newline="") as stream:
        return list(csv.DictReader(stream))


def write(rows: list[dict], table: Path = TABLE, fields: tuple[str, ...] = FIELDS) -> None:
    """``rows`` to ``table`` atomically (seven digits)."""
    calibration.write(rows, table, fields, digits=7)


def main() -> None:
    rows = load()
    done = {_key(line) for line in rows}
    for case in CASES:
        for factor in FACTORS:
            if (*case, factor) in done:
                continue
            rows.append(row(*case, factor))
            write(rows)
            print(", ".join(f"{name}={rows[-1][name]}" for name in FIELDS), flush=True)


if __name__ == "__main__":
    main()
