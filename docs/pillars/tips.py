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

``tips_extrapolated.csv`` (`extrapolate`, written at the end of every run
and by ``--extrapolate`` alone) holds, per 8 x 8 case with both f = 2 and
f = 4, the exact path's F_A on N = 128 (from ``validation.jsonl``), 256 and
512 (3.6, 7.2 and 14.4 elements per radius), its observed order, the
first-order Richardson extrapolation 2 F(512) - F(256) (the order of a lone
punch's F_A, ``data/resolution_error.csv``; the difference from the
extrapolation at the observed order is its error estimate; none where F_A is
not monotone over the three grids or its steps do not shrink, outside the
asymptotic range), and the pillar
model's F_A with the grid's tips (the default) and with tips at 7.2 and 14.4
elements per radius, relative to that extrapolated value.

    nice python docs/pillars/tips.py                 # every case, resuming
    nice python docs/pillars/tips.py --limit 600     # stop starting cases after 600 s
    python docs/pillars/tips.py --extrapolate        # only rewrite tips_extrapolated.csv
"""

from __future__ import annotations

import argparse
import csv
import json
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
EXTRAPOLATED = HERE / "tips_extrapolated.csv"
EXTRAPOLATED_FIELDS = ("family", "pillars_per_side", "stiffness_ratio", "events_adhesive_force_128",
                       "events_adhesive_force_256", "events_adhesive_force_512", "observed_order",
                       "extrapolated_adhesive_force", "extrapolation_error", "grid_tips_error", "tips_7_error",
                       "tips_14_error")
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
                                             pillar_tip_peel=False, **extra)).summary
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


def write(rows: list[dict], table: Path = TABLE, fields: tuple[str, ...] = FIELDS) -> None:
    if table == TABLE:
        order = {case: i for i, case in enumerate(cases())}
        rows = sorted(rows, key=lambda row: order.get(_key(row), len(order)))
    temporary = table.with_suffix(".csv.tmp")
    with temporary.open("w", newline="") as stream:
        writer = csv.DictWriter(stream, fieldnames=fields, lineterminator="\n")
        writer.writeheader()
        for row in rows:
            writer.writerow({name: (f"{row[name]:.6g}" if isinstance(row[name], float) else row[name])
                             for name in fields})
    os.replace(temporary, table)


def extrapolate(rows: list[dict]) -> list[dict]:
    """The rows of ``tips_extrapolated.csv`` (module docstring) from ``tips.csv``'s ``rows``."""
    coarse = {}
    for line in (HERE / "validation.jsonl").read_text().splitlines():
        if line.strip():
            row = json.loads(line)
            if row.get("phi", 0.16) == 0.16 and row["pillars_per_side"] == 8:
                coarse[(row["family"], 8, float(row["stiffness_ratio"]))] = row
    table = {_key(row): row for row in rows}
    out = []
    for family, per_side, stiffness, factor in cases():
        two, four = table.get((family, per_side, stiffness, 2)), table.get((family, per_side, stiffness, 4))
        first = coarse.get((family, per_side, stiffness))
        if factor != 4 or two is None or four is None or first is None:
            continue
        f1, f2, f4 = first["events_adhesive_force"], float(two["events_adhesive_force"]), \
            float(four["events_adhesive_force"])
        ratio = (f1 - f2) / (f2 - f4) if f2 != f4 else math.nan
        order = math.log2(ratio) if ratio > 0 else math.nan
        # Outside the asymptotic range (F_A not monotone in h, or its steps not shrinking: ratio <= 1) there is
        # no extrapolated value.
        extrapolated = 2 * f4 - f2 if ratio > 1 else math.nan
        at_order = f4 + (f4 - f2) / (ratio - 1) if ratio > 1 else math.nan
        out.append({
            "family": family, "pillars_per_side": per_side, "stiffness_ratio": stiffness,
            "events_adhesive_force_128": f1, "events_adhesive_force_256": f2, "events_adhesive_force_512": f4,
            "observed_order": order, "extrapolated_adhesive_force": extrapolated,
            "extrapolation_error": abs(at_order / extrapolated - 1) if math.isfinite(at_order) else math.nan,
            "grid_tips_error": (1 + float(two["grid_tips_adhesive_force_error"])) * f2 / extrapolated - 1,
            "tips_7_error": float(two["pillars_adhesive_force"]) / extrapolated - 1,
            "tips_14_error": float(four["pillars_adhesive_force"]) / extrapolated - 1,
        })
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--limit", type=float, default=math.inf, help="start no case after this many seconds")
    parser.add_argument("--extrapolate", action="store_true", help="only rewrite tips_extrapolated.csv")
    args = parser.parse_args()
    rows = load()
    if args.extrapolate:
        write(extrapolate(rows), EXTRAPOLATED, EXTRAPOLATED_FIELDS)
        return
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
    write(extrapolate(rows), EXTRAPOLATED, EXTRAPOLATED_FIELDS)


if __name__ == "__main__":
    main()
