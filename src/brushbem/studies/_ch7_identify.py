"""Chapter 7's one identification: the rule that picks (p_c, pillar count, grid N) from the stiff optimum.

The thesis states for chapter 7 neither the reference stress p_c of h~ (eq. 7.3), nor the pillar
count, nor the grid (L1263-1363; the 512 x 512 of L736 is chapter 4's).  The rule, declared in
``docs/reproduction/probe_concave_count.py`` before the candidates at other grids were run and
before any held-out row was read at them:

* score = |h~ at the largest F~_A / 0.04 - 1| on the identification row only (k~ = 10, phi = 0.06,
  the circle; Fig. 7-6 a's 0.04), h~ in the candidate's unit of p_c;
* its error is the reading: half the sampled h~ step on each side of the maximum (the runs are
  deterministic, one layout), so a score is a range;
* the best score wins; a candidate whose score range overlaps the best's ties with it, and of the
  tied the cheapest wins (the least mean time a case at k~ = 10).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd

__all__ = ["THESIS_H", "Candidate", "choose", "read_maximum"]

#: The thesis's stiff optimum (Fig. 7-6 a, text), the identification row.
THESIS_H = 0.04


@dataclass(frozen=True)
class Candidate:
    """One candidate (p_c, pillars per side, grid N) and its reading of the identification row."""

    unit: str
    side: int
    elements: int
    pillars: int
    per_radius: float
    h_at_max: float
    low: float
    high: float
    cost_s: float
    wide: float = math.nan

    @property
    def score(self) -> float:
        return abs(self.h_at_max / THESIS_H - 1)

    @property
    def score_range(self) -> tuple[float, float]:
        """The scores over the reading interval [low, high] of h~ at the maximum."""
        ends = [abs(h / THESIS_H - 1) for h in (self.low, self.high)]
        return (0.0 if self.low <= THESIS_H <= self.high else min(ends)), max(ends)


def read_maximum(forces: pd.Series) -> tuple[float, float, float]:
    """h~ of the largest F~_A of ``forces`` (F~_A by h~) and half the sampled step on each side: (h, low, high);
    NaNs where nothing was sampled."""
    forces = forces.dropna().sort_index()
    if not len(forces):
        return math.nan, math.nan, math.nan
    h = forces.index.to_numpy(float)
    i = int(np.argmax(forces.to_numpy(float)))
    low = h[i] - (h[i] - h[i - 1]) / 2 if i > 0 else h[i]
    high = h[i] + (h[i + 1] - h[i]) / 2 if i + 1 < len(h) else h[i]
    return float(h[i]), float(low), float(high)


def choose(candidates: list[Candidate]) -> tuple[Candidate | None, list[Candidate]]:
    """The identified candidate by the rule (module docstring) and the candidates that tie with the best."""
    scored = [c for c in candidates if math.isfinite(c.score)]
    if not scored:
        return None, []
    best = min(scored, key=lambda c: c.score)
    low, high = best.score_range
    tied = [c for c in scored if c.score_range[0] <= high and low <= c.score_range[1]]
    return min(tied, key=lambda c: (c.cost_s, c.score)), tied
