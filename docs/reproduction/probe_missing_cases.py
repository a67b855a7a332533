"""Chapter 5: which rows the main preload file's missing cases could change, on the committed cases.

The sampled preload file (``rough_brush.preload.sampled.toml``) is complete for
seed 0 only; seeds 1-9 lack up to 75 points each (curve preloads, and the
stiff brushes at sigma~ >= 0.96; 4.3 CPU-hours a seed at seed 0's times), and
their rows read the sets ``plateau_c``, ``table1_soft``, ``table1_stiff`` and
``rough_plateau`` instead.  Seed 0 has those points, so a row that pools the seeds (c of a
point is the mean over the seeds that have it) reads them on seed 0 alone.
This recomputes every chapter-5 row without seed 0's copies of those points
and prints, per row, whether its number changes: a row that does not change is
the same whether or not seeds 1-9 ever run those points (as long as they behave
there as seed 0 does: the plateau reached at the largest preload, one pillar's
force at the stiff sigma~ >= 0.96).  No computation: seconds.  The rows are written atomically to
``probe_missing_cases.csv`` beside this file (one row a chapter-5 number: its value with and
without seed 0's copies of those points).

    python docs/reproduction/probe_missing_cases.py
"""

from __future__ import annotations

import math
from pathlib import Path

import pandas as pd

from brushbem.io import atomic_path
from brushbem.reproduction import _compute, load_tables
from brushbem.studies import get_study

TABLES = Path(__file__).resolve().parent / "rough_brush"
OUTPUT = Path(__file__).with_suffix(".csv")
POINT = ["indenter.stiffness_ratio", "indenter.roughness.sigma", "protocol.preload_force"]


def main() -> None:
    _, tables = load_tables(TABLES)
    preload = tables["preload"]
    points = preload[POINT].round(10).apply(tuple, axis=1)
    missing = set(points[preload["status"] == "missing"])
    only_seed_0 = points.isin(missing) & (preload["realization"] == 0)
    print(f"{len(missing)} points missing on some seed; seed 0 has {int(only_seed_0.sum())} of them")
    without = {**tables, "preload": preload[~only_seed_0]}
    rows = []
    for number in get_study("rough_brush").numbers:
        (a, _), (b, _) = _compute(number, tables), _compute(number, without)  # n/a as the doc has it
        same = (math.isnan(a) and math.isnan(b)) or math.isclose(a, b, rel_tol=1e-9)
        print(f"{'same   ' if same else 'CHANGES'}  {a:.6g} -> {b:.6g}  {number.quantity}")
        rows.append({"quantity": number.quantity, "with_seed_0_points": a, "without_seed_0_points": b,
                     "same": same, "missing_points": len(missing), "seed_0_has": int(only_seed_0.sum())})
    with atomic_path(OUTPUT) as path:
        pd.DataFrame(rows).to_csv(path, index=False)


if __name__ == "__main__":
    main()
