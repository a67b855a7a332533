"""The pillar model's tips on a raster of their own against the exact event path on the grid that resolves them.

``LoadPath.pillar_tip_resolution`` puts every tip of the pillar model on the
global grid subdivided f times (`brushbem.pillars.tips`); the brush is then
the brush of the grid f N, which the exact path (``method = "events"``) runs
element by element.  Per case and f this table gives both on that problem
(pressed to the rigid flat lattice's force F_c of the grid N, pulled off to
separation): F_A, the work of separation, their relative differences
(targets 1 % and 3 %), and the CPU time of each; and the pillar model with
the grid's own tips (f = 1, the default) against the same exact path, which
is the default's discretisation error measured against the grid f N.

The families are those of ``docs/pillars/validation.py`` (flat, rough,
random, hierarchy, concave; phi = 0.16, 3.61 elements per radius on the grid
N = 16 n, seed 3), with the centres, lengths and preload of the grid N on
every finer grid.  Rows are written to ``tips.csv`` as each case completes
(atomically; a rerun skips the rows already there), in the order of
`cases`: the cheap grids first.

    nice python docs/pillars/tips.py                 # every case, resuming
    nice python docs/pillars/tips.py --limit 600     # stop starting cases after 600 s
"""

from __future__ import annotations

import argparse
import csv
import math
import os
import sys
import time
from pathlib import Path

from brushbem.protocol import LoadPath, record_pull_off

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from validation import FAMILIES, STIFFNESSES, problem  # noqa: E402

TABLE = HERE / "tips.csv"
FIELDS = ("family", "pillars_per_side", "pillars", "elements", "stiffness_ratio", "tip_factor",
          "tip_elements_per_radius", "exact_elements", "events_adhesive_force", "events_work",
          "events_cpu_seconds", "events_converged", "pillars_adhesive_force", "pillars_work",
          "pillars_cpu_seconds", "adhesive_force_error", "work_error", "grid_tips_adhesive_force_error",
          "grid_tips_work_error")


def cases() -> list[tuple[str, int, float, int]]:
    """(family, pillars per side, k~, f): 8 x 8 at f = 2 and 4 (7.2 and 14.4 elements per radius; at f = 4
    k~ = 10 and 1e-5 first), then 16 x 16 at f = 4 (the exact path on N = 1024), then one 8 x 8 at f = 8
    (28.9 per radius)."""
    out = [(family, 8, k, 2) for k in STIFFNESSES for family in FAMILIES]
    out += [(family, 8, k, 4) for k in (10.0, 1e-5, 1e-2) for family in FAMILIES]
    out += [(family, 16, k, 4) for k in (1e-2, 10.0, 1e-5) for family in FAMILIES]
    out += [("flat", 8, 1e-2, 8)]
    return out


def _pull_off(case, method: str, preload: float, tips: float | None = None) -> tuple[float, dict]:
    extra = {} if tips is None else {"pillar_tip_resolution": tips}
    start = time.process_time()
    summary = record_pull_off(case, LoadPath(method=method, preload_force=preload, max_steps=10**7,
                                             **extra)).summary
    return time.process_time() - start, summary


def _error(value: float, reference: float) -> float:
    return value / reference - 1 if reference else math.nan


def run_case(family: str, per_side: int, stiffness: float, factor: int, grid_tips: dict) -> dict:
    """One row; ``grid_tips`` caches the pillar model with the grid's own tips per (family, n, k~)."""
    coarse, preload = problem(family, per_side, stiffness)
    fine, _ = problem(family, per_side, stiffness, factor=factor)
    per_radius = float(coarse.indenter.description.pillar_radius) / coarse.grid.element_size
    key = (family, per_side, stiffness)
    if key not in grid_tips:
        grid_tips[key] = _pull_off(coarse, "pillars", preload)[1]
    seconds, model = _pull_off(coarse, "pillars", preload, factor * per_radius)
    events_seconds, exact = _pull_off(fine, "events", preload)
    default = grid_tips[key]
    force, work = exact["adhesive_force"], exact["work_of_separation"]
    return {
        "family": family, "pillars_per_side": per_side, "pillars": coarse.indenter.n_pillars,
        "elements": coarse.grid.elements, "stiffness_ratio": stiffness, "tip_factor": factor,
        "tip_elements_per_radius": round(factor * per_radius, 3), "exact_elements": fine.grid.elements,
        "events_adhesive_force": force, "events_work": work, "events_cpu_seconds": round(events_seconds, 2),
        "events_converged": bool(exact["converged"]), "pillars_adhesive_force": model["adhesive_force"],
        "pillars_work": model["work_of_separation"], "pillars_cpu_seconds": round(seconds, 2),
        "adhesive_force_error": _error(model["adhesive_force"], force),
        "work_error": _error(model["work_of_separation"], work),
        "grid_tips_adhesive_force_error": _error(default["adhesive_force"], force),
        "grid_tips_work_error": _error(default["work_of_separation"], work),
    }


def _key(row: dict) -> tuple:
    return (row["family"], int(row["pillars_per_side"]), float(row["stiffness_ratio"]), int(row["tip_factor"]))


def load() -> list[dict]:
    if not TABLE.exists():
        return []
    with TABLE.open(newline="") as stream:
        return list(csv.DictReader(stream))


def write(rows: list[dict]) -> None:
    order = {case: i for i, case in enumerate(cases())}
    rows = sorted(rows, key=lambda row: order.get(_key(row), len(order)))
    temporary = TABLE.with_suffix(".csv.tmp")
    with temporary.open("w", newline="") as stream:
        writer = csv.DictWriter(stream, fieldnames=FIELDS, lineterminator="\n")
        writer.writeheader()
        for row in rows:
            writer.writerow({name: (f"{row[name]:.6g}" if isinstance(row[name], float) else row[name])
                             for name in FIELDS})
    os.replace(temporary, TABLE)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--limit", type=float, default=math.inf, help="start no case after this many seconds")
    args = parser.parse_args()
    rows = load()
    done = {_key(row) for row in rows}
    grid_tips: dict = {}
    start = time.monotonic()
    for case in cases():
        if case in done:
            continue
        if time.monotonic() - start > args.limit:
            print(f"stopped after {time.monotonic() - start:.0f} s; rerun to continue", flush=True)
            break
        row = run_case(*case, grid_tips)
        rows.append(row)
        write(rows)
        print(", ".join(f"{name}={row[name]}" for name in FIELDS), flush=True)


if __name__ == "__main__":
    main()
