"""Chapter 5, Table 1: how the fit of eq. 5.8 depends on its weighting, on the committed cases.

The thesis fits c = alpha / sigma~ - beta to its c(sigma~) (Fig. 5-5, drawn in
linear and in double-logarithmic coordinates) without saying how.  c spans four
decades over sigma~ = 0.01 to 3, so the weighting decides what beta is.  This
reads the committed chapter-5 table (``docs/reproduction/rough_brush``), takes
the c of every (k~, sigma~) with c > 0 as ``brushbem.studies.rough_brush.table_1``
does (the seeds' mean), and prints, per k~, alpha, beta and sigma~_c = alpha/beta of

* ``relative``: least squares of (alpha/sigma~ - beta)/c - 1 (the shipped fit);
* ``absolute``: least squares of alpha/sigma~ - beta - c;

and, for each, the largest relative miss max |fit/c - 1| over the points; then
the thesis's Table 1.  No computation: a second.  The table is written atomically to
``probe_fit_weighting.csv`` beside this file (one row a k~ and weighting).

    python docs/reproduction/probe_fit_weighting.py
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd

from brushbem.io import atomic_path
from brushbem.reproduction import load_tables
from brushbem.studies._ch5_7 import K, SIGMA, adhesion_coefficients, finished, fit_eq58
from brushbem.studies.rough_brush import FIT_POINTS, FIT_SPAN, TABLE_1

TABLES = Path(__file__).resolve().parent / "rough_brush"
OUTPUT = Path(__file__).with_suffix(".csv")


def main() -> None:
    _, results = load_tables(TABLES)
    coeff = adhesion_coefficients(finished(results, "preload"), [K, SIGMA])
    print(f"{'k~':>6} {'points':>6} | {'relative: alpha':>15} {'beta':>7} {'sigma~_c':>8} {'miss':>5} | "
          f"{'absolute: alpha':>15} {'beta':>7} {'sigma~_c':>8} {'miss':>5} | thesis alpha, sigma~_c")
    rows = []
    for k, group in coeff.groupby(K):
        usable = group[np.isfinite(group["c"]) & (group["c"] > 0) & (group["sigma"] > 0)]
        sigma, c = usable["sigma"].to_numpy(), usable["c"].to_numpy()
        enough = len(usable) >= FIT_POINTS and sigma.max() >= FIT_SPAN * sigma.min()
        cells = []
        thesis = TABLE_1.get(k, TABLE_1[0.55] if k >= 0.55 else (math.nan, math.nan))
        for weighting in ("relative", "absolute"):
            alpha, beta = fit_eq58(sigma, c, weighting=weighting)
            critical = alpha / beta if beta > 0 else math.nan
            miss = np.max(np.abs((alpha / sigma - beta) / c - 1.0))
            cells.append(f"{alpha:15.3f} {beta:7.3f} {critical:8.3g} {miss:5.2f}")
            rows.append({"stiffness_ratio": k, "weighting": weighting, "points": len(usable), "enough": enough,
                         "alpha": alpha, "beta": beta, "critical_roughness": critical, "largest_miss": miss,
                         "thesis_alpha": thesis[0], "thesis_critical_roughness": thesis[1]})
        print(f"{k:6g} {len(usable):6d} | {cells[0]} | {cells[1]} | {thesis[0]:g}, {thesis[1]:g}"
              + ("" if enough else "  (too few points for a row)"))
    with atomic_path(OUTPUT) as path:
        pd.DataFrame(rows).to_csv(path, index=False)


if __name__ == "__main__":
    main()
