"""The rough family: tips at their continuum capacity against the raster's sequence towards the limit.

The rough 8 x 8 brush of ``docs/pillars/validation.py`` (Gaussian lengths of
sigma~ = 1, phi = 0.16, 3.6 elements per radius on N = 128, seed 3) at
k~ = 10, 1, 0.1, 0.01 and 1e-5, pressed to the rigid flat lattice's F_c and
pulled off.  No continuum limit of a rough brush is known (its tips press at
different depths, some in part contact), so the limit is approached from the
two sides the flat brush was decided by (``docs/pillars/accuracy.md``):

* ``raster``: ``pillar_tip_peel = false``, every tip peeling by its elements'
  criterion, with the tips f = 1, 2, 4, 8 times finer than the grid's
  (3.6 .. 28.9 elements per radius; f = 16 at k~ = 10 ran 58 CPU-min without
  finishing: the peeled rasters' bases at 57.8 per radius, and was stopped).  With tips f times finer
  it is the exact path on the grid f N to 0.1 % on this family
  (``tips.csv``: -0.09 % at f = 4, k~ = 10; +0.03 % at f = 2, k~ = 0.01), so
  this is the exact path's sequence, at a fraction of its cost.  On the flat
  brush a raster's peel holds more than the continuum's (its gains fall
  towards the limit from above: +1.4 % at 28.9 per radius).
* ``peel``: ``LoadPath.pillar_tip_peel`` (whole tips leave at their
  first-order continuum capacity, tips beyond the gain's table peel by their
  elements) at f = 1, 2, 4, 8.  Its first-order gains are lower ends where a
  tip's K varies much along its edge.
* ``clamped``: the same with the table's edge gain for those tips beyond
  the table (the criterion before they peeled by their elements), f = 1, 2.

Each row holds F_A, the work of separation, the CPU time, and for the runs
with whole tips leaving, the relative n = 1 amplitudes of K along their edges
as they left (``tilt_*``: median, 90th percentile, largest, and how many
beyond `brushbem.pillars.domain.PEEL_TILT`).

Rows are written to ``rough.csv`` as each run completes (atomically; a rerun
skips those there; about 6 CPU-min in all).

From them, ``src/brushbem/data/rough_error.csv`` (`error_rows`), the error a
run on a rough brush reports beside the flat brush's (`brushbem.config.advice`):
per tip resolution and criterion, the range of F_A over the five stiffnesses
between the two ends of the limit: below, the option's tips at 28.9
elements per radius; above, the raster's finest (28.9).

    nice python docs/pillars/rough.py             # every run, resuming
    nice python docs/pillars/rough.py --limit 600 # start no run after 600 s
    python docs/pillars/rough.py --errors         # only rewrite rough_error.csv
"""

from __future__ import annotations

import argparse
import csv
import math
import os
import sys
import time
from pathlib import Path

import numpy as np

from brushbem.pillars import peel as peel_model
from brushbem.pillars import state as pillar_state
from brushbem.pillars.domain import PEEL_TILT
from brushbem.protocol import LoadPath, record_pull_off

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import calibration  # noqa: E402
import reference  # noqa: E402
import validation  # noqa: E402

TABLE = HERE / "rough.csv"
ERROR_TABLE = HERE.parents[1] / "src" / "brushbem" / "data" / "rough_error.csv"
ERROR_HEADER = ("# the rough 8 x 8 brush (sigma~ = 1, phi = 0.16) at k~ = 10, 1, 0.1, 0.01 and 1e-5: F_A's range over "
                "the stiffnesses, each against the ends of its limit (below: pillar_tip_peel's tips at 28.9 elements per "
                "radius; above: the raster's finest tips, 28.9 per radius), for the tips on their rasters "
                "(protocol.pillar_tip_peel = false: raster) and at their continuum capacity (the default: peel); "
                "docs/pillars/rough.py")
STIFFNESSES = (10.0, 1.0, 0.1, 0.01, 1e-5)
FIELDS = ("stiffness_ratio", "criterion", "tip_factor", "tip_elements_per_radius", "adhesive_force",
          "work_of_separation", "tips_left_whole", "tilt_median", "tilt_90", "tilt_largest", "tilts_beyond",
          "cpu_seconds")


def runs() -> list[tuple[float, str, int]]:
    """(k~, criterion, f): the cheap ones first."""
    out = [(k, c, f) for k in STIFFNESSES for f in (1, 2, 4, 8) for c in ("raster", "peel")]
    out += [(k, "clamped", f) for k in STIFFNESSES for f in (1, 2)]
    return out


def _clamped_strength(original):
    """`peel.strength` with the table's edge gain beyond the table (no tip handed to its elements)."""
    limits = np.array([peel_model.TABLE_LIMITS["tilt"], peel_model.TABLE_LIMITS["bend"], math.inf])

    def strength(intensity, load, control, kendall, angles=peel_model.TABLE_ANGLES, parameters=None):
        shape = peel_model.shape_parameters(intensity) if parameters is None else parameters
        return original(intensity, load, control, kendall, angles, parameters=np.minimum(shape, limits))
    return strength


def run(stiffness: float, criterion: str, factor: int) -> dict:
    case, preload = validation.problem("rough", 8, stiffness)
    per_radius = factor * float(case.indenter.description.pillar_radius) / case.grid.element_size
    path = LoadPath(method="pillars", preload_force=preload, max_steps=10**7,
                    pillar_tip_resolution=per_radius if factor > 1 else None,
                    pillar_tip_peel=criterion != "raster")
    tilts: list[float] = []
    original_peeled, original_strength = pillar_state.peeled, peel_model.strength

    def peeled(cache, state, p, leave, frozen, x, d):
        # The tip's K as it leaves whole (the criterion's own test, `state.peeled`).
        whole = np.array_equal(state.raster[p], cache.model.full[p])
        if cache.model.continuum_peel and whole and np.isfinite(pillar_state.tip_strengths(cache, state, d)[p]):
            tilts.append(float(pillar_state.tip_tilts(cache, state, d)[p]))
        return original_peeled(cache, state, p, leave, frozen, x, d)

    pillar_state.peeled = peeled
    if criterion == "clamped":
        peel_model.strength = _clamped_strength(original_strength)
    try:
        start = time.process_time()
        summary = record_pull_off(case, path).summary
        seconds = time.process_time() - start
    finally:
        pillar_state.peeled, peel_model.strength = original_peeled, original_strength
    if not summary["converged"]:
        raise RuntimeError(summary["reason"])
    t = np.array(tilts)
    return {"stiffness_ratio": stiffness, "criterion": criterion, "tip_factor": factor,
            "tip_elements_per_radius": round(per_radius, 3), "adhesive_force": float(summary["adhesive_force"]),
            "work_of_separation": float(summary["work_of_separation"]), "tips_left_whole": t.size,
            "tilt_median": float(np.median(t)) if t.size else "", "tilt_90": float(np.quantile(t, 0.9)) if t.size else "",
            "tilt_largest": float(t.max()) if t.size else "", "tilts_beyond": int((t > PEEL_TILT).sum()) if t.size else "",
            "cpu_seconds": round(seconds, 2)}


def _key(row: dict) -> tuple:
    return float(row["stiffness_ratio"]), row["criterion"], int(row["tip_factor"])


def load() -> list[dict]:
    return reference.load(TABLE)


def write(rows: list[dict]) -> None:
    order = {case: i for i, case in enumerate(runs())}
    calibration.write(sorted(rows, key=lambda row: order.get(_key(row), len(order))), TABLE, FIELDS, digits=7)


def error_rows(rows: list[dict]) -> list[dict]:
    """``rough_error.csv``'s rows (module docstring): per tips' resolution below the ends' own, each criterion's
    least F_A / upper - 1 and largest F_A / lower - 1 over the stiffnesses."""
    value = {_key(row): float(row["adhesive_force"]) for row in rows}
    ends = {}
    for k in STIFFNESSES:
        finest = max(f for (s, c, f) in value if s == k and c == "raster")
        ends[k] = value[(k, "peel", 8)], value[(k, "raster", finest)]
    out = []
    for factor in (1, 2, 4):
        row = {"elements_per_radius": next(float(r["tip_elements_per_radius"]) for r in rows
                                           if int(r["tip_factor"]) == factor)}
        for criterion in ("raster", "peel"):
            forces = {k: value[(k, criterion, factor)] for k in STIFFNESSES}
            row[f"{criterion}_force_error_min"] = min(forces[k] / ends[k][1] - 1 for k in STIFFNESSES)
            row[f"{criterion}_force_error_max"] = max(forces[k] / ends[k][0] - 1 for k in STIFFNESSES)
        out.append(row)
    return out


def write_errors(rows: list[dict]) -> None:
    fields = ("elements_per_radius", "raster_force_error_min", "raster_force_error_max", "peel_force_error_min",
              "peel_force_error_max")
    temporary = ERROR_TABLE.with_suffix(".csv.tmp")
    with temporary.open("w", newline="") as stream:
        stream.write(ERROR_HEADER + "\n")
        writer = csv.DictWriter(stream, fieldnames=fields, lineterminator="\n")
        writer.writeheader()
        for row in error_rows(rows):
            writer.writerow({name: f"{row[name]:.5g}" for name in fields})
    os.replace(temporary, ERROR_TABLE)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--limit", type=float, default=math.inf, help="start no run after this many seconds")
    parser.add_argument("--errors", action="store_true", help="only rewrite src/brushbem/data/rough_error.csv")
    args = parser.parse_args()
    rows = load()
    if args.errors:
        write_errors(rows)
        return
    done = {_key(row) for row in rows}
    start = time.monotonic()
    for case in runs():
        if case in done:
            continue
        if time.monotonic() - start > args.limit:
            print(f"stopped after {time.monotonic() - start:.0f} s; rerun to continue", flush=True)
            break
        rows.append(run(*case))
        write(rows)
        print(", ".join(f"{name}={rows[-1][name]}" for name in FIELDS), flush=True)
    write_errors(load())


if __name__ == "__main__":
    main()
