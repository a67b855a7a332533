"""Chapter 7's one identification: the rule that picks (p_c, pillar count, grid N) from the stiff optimum.

The thesis states for chapter 7 neither the reference stress p_c of h~ (eq. 7.3), nor the pillar
count, nor the grid (L1263-1363; the 512 x 512 of L736 is chapter 4's).  The rule, declared in
``docs/reproduction/probe_concave_count.py`` before the candidates at other grids were run and
before any held-out row was read at them:

* score = |h~ at the largest F~_A / 0.04 - 1| on the identification row only (k~ = 10, phi = 0.06,
  the circle; Fig. 7-6 a's 0.04), h~ in the candidate's unit of p_c;
* its error: a range of scores (below);
* the best score wins; a candidate whose score range overlaps the best's ties with it, and of the
  tied the cheapest wins (the least mean time a case at k~ = 10).

The candidates are the grids declared with the rule (`CANDIDATE_GRIDS`, and the part's 16 x 16 on
N = 512).  Grids run later, within `NEIGHBOURS_WITHIN` of a candidate's N, measure its discretisation
scatter and are not candidates: the score moves by more between neighbouring grids than its
reading error (24 x 24: 4.1, 0.1, 8.9, 9.4, 6.8 % on N = 464, 488, 512, 536, 560), so the best of
them would be picked for its noise.

Two error definitions (`choose`'s ``scatter``), both reported in the document:

* strict (the rule as first declared, and the one the identification uses): the reading alone, half the
  sampled h~ step on each side of the maximum, on the premise that the runs are deterministic.  It picks
  24 x 24 on N = 512 (8.9 %, 8.1-9.7 %) with no tie;
* with scatter (a sensitivity only: it was widened after the strict reading was known): the envelope of the
  reading intervals of h~ at the maximum over the candidate's grid and its neighbours (`with_scatter`; the
  part's 16 x 16 on N = 512 takes the probe's 16 x 16 on N = 464 to 560); a candidate with no neighbour run
  keeps its reading.  It ties 16 x 16 on N = 288, 320, 352 with 24 x 24 on N = 512 and picks the cheapest,
  16 x 16 on N = 320; 16 x 16 on N = 512 scores 19.1 % (13.8-23.3 %), 12 x 12 32.2 % (28.2-34.6 %), 8 x 8
  46.5 % (42.3-49.9 %), none tied.  The discretisation scatter stated beside it is the spread (largest -
  smallest) of h~ at the maximum over those grids, over 0.04.

The scatter is measured: a grid 5 to 10 % finer or coarser moves the score by 10 to 30 times the reading
error (16 x 16: 18.2, 10.6, 13.3 % on N = 288, 320, 352 at steps of 0.001), and the strict pick moves with the
h~ step (16 x 16 on N = 320, tied with 24 x 24 and cheaper, at steps of 0.002; 24 x 24 on N = 512 alone at
0.001).  The rule is kept as declared, not widened after the fact; the widened pick is the chapter's grid and
count sensitivity (its rows on 16 x 16, N = 320, outside the counts).
`identification_table` prints both picks.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
import pandas as pd

from brushbem.physics.theory import concave_reference_stress
from brushbem.studies._ch5_7 import RADIUS, H, has

__all__ = ["PC_CANDIDATES", "PC_IDENTIFIED", "in_unit", "CANDIDATE_GRIDS", "NEIGHBOURS_WITHIN", "THESIS_H", "Candidate",
           "choose", "identification_table",
           "interpolated", "neighbours", "probe_candidates", "probe_curve", "read_maximum", "score_interval",
           "with_scatter"]

#: The thesis's stiff optimum (Fig. 7-6 a, text), the identification row.
THESIS_H = 0.04
#: Pillars per side -> the grids N of the probe that are candidates (declared with the rule).
CANDIDATE_GRIDS = {8: (512,), 12: (512,), 16: (288, 320, 352), 24: (512,)}
#: A grid within this share of a candidate's N (same pillars) is its neighbour (16 x 16 on N = 320:
#: 288 to 352).
NEIGHBOURS_WITHIN = 0.1


#: The units of the shipped concave sweeps (their base): E* = 1, dgamma = 1e-4.
CONTACT_MODULUS, WORK_OF_ADHESION = 1.0, 1e-4
#: The candidates for the reference stress p_c of h~ (eq. 7.3; the thesis states none): name -> p_c of
#: a table's rows.  The runs use the first (the code's default); h~ in another unit is h~ p_c_run / p_c,
#: since the profile S_p = h~ S_c is linear in p_c.
PC_CANDIDATES = {
    "F_K / (pi r^2), one pillar's Kendall stress (the runs' unit)":
        lambda frame: concave_reference_stress(frame[RADIUS].to_numpy(float), contact_modulus=CONTACT_MODULUS,
                                               work_of_adhesion=WORK_OF_ADHESION),
    "Sigma_c, the BEM's critical stress (Fig. 7-4's unit)": lambda frame: frame["critical_stress"].to_numpy(float),
}
#: The identified candidate: chapter 7's one identification.
PC_IDENTIFIED = "Sigma_c, the BEM's critical stress (Fig. 7-4's unit)"


def in_unit(frame: pd.DataFrame, candidate: str = PC_IDENTIFIED) -> pd.DataFrame:
    """``frame`` with h~ in the unit of ``candidate`` (`PC_CANDIDATES`)."""
    if not has(frame, H, RADIUS, "critical_stress"):
        return frame.iloc[0:0]
    run = PC_CANDIDATES[next(iter(PC_CANDIDATES))](frame)
    return frame.assign(**{H: frame[H].to_numpy(float) * run / PC_CANDIDATES[candidate](frame)})


def score_interval(low: float, high: float) -> tuple[float, float]:
    """The scores over an interval [low, high] of h~ at the maximum."""
    ends = [abs(h / THESIS_H - 1) for h in (low, high)]
    return (0.0 if low <= THESIS_H <= high else min(ends)), max(ends)


def neighbours(elements: int, grids) -> list[int]:
    """The grids of ``grids`` within `NEIGHBOURS_WITHIN` of ``elements`` (itself included)."""
    return sorted(int(g) for g in grids if abs(g / elements - 1) <= NEIGHBOURS_WITHIN * (1 + 1e-12))


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
    #: The score range with scatter (the envelope over `neighbours`; NaNs: no neighbour run) and the
    #: spread of h~ at the maximum over those grids, over 0.04; the grids.
    scattered: tuple[float, float] = (math.nan, math.nan)
    spread: float = math.nan
    grids: tuple[int, ...] = ()
    #: ``cost_s`` is wall time (a part's cases record no CPU time), not CPU-s.
    wall: bool = False

    @property
    def score(self) -> float:
        return abs(self.h_at_max / THESIS_H - 1)

    @property
    def score_range(self) -> tuple[float, float]:
        """The scores over the reading interval [low, high] of h~ at the maximum."""
        return score_interval(self.low, self.high)

    def error_range(self, scatter: bool) -> tuple[float, float]:
        """The score range strict (the reading) or, with ``scatter``, over the neighbouring grids too."""
        return self.scattered if scatter and math.isfinite(self.scattered[0]) else self.score_range

    @property
    def name(self) -> str:
        return f"{self.side} x {self.side} on N = {self.elements}"

    @property
    def cost(self) -> str:
        """``cost_s`` with its kind: "0.77 CPU-s" or "5.22 s wall time"."""
        return f"{self.cost_s:.2f} " + ("s wall time" if self.wall else "CPU-s")


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


def choose(candidates: list[Candidate], scatter: bool = False) -> tuple[Candidate | None, list[Candidate]]:
    """The candidate the rule (module docstring) picks and the candidates that tie with the best: the
    error strict (the reading) or, with ``scatter``, widened by the discretisation scatter."""
    scored = [c for c in candidates if math.isfinite(c.score)]
    if not scored:
        return None, []
    best = min(scored, key=lambda c: c.score)
    low, high = best.error_range(scatter)
    tied = [c for c in scored if c.error_range(scatter)[0] <= high and low <= c.error_range(scatter)[1]]
    return min(tied, key=lambda c: (c.cost_s, c.score)), tied


def _converged(probe: pd.DataFrame, recorded_grid: int) -> pd.DataFrame:
    """The probe's converged cases with the grid N of every row (``recorded_grid`` where it has none)."""
    if not len(probe) or "force_by_ideal_sharing" not in probe.columns:
        return probe.iloc[0:0]
    grid = probe["elements"].fillna(recorded_grid) if "elements" in probe.columns else recorded_grid
    return probe.assign(elements=grid)[probe["converged"].astype(bool)]


def probe_curve(probe: pd.DataFrame, side: int, elements: int, k: float, phi: float, column: str,
                recorded_grid: int = 512) -> pd.Series:
    """F~_A by h~ (``column``: the runs' unit ``amplification`` or ``amplification_sigma_c``) of the probe's
    circle, ``side`` pillars a side on N = ``elements`` at (k~, phi); empty where not run."""
    frame = _converged(probe, recorded_grid)
    if not len(frame):
        return pd.Series(dtype=float)
    frame = frame[np.isclose(frame["phi"], phi) & (frame["pillars_per_side"] == side)
                  & (frame["elements"] == elements) & np.isclose(frame["stiffness_ratio"], k)]
    return frame.groupby(column)["force_by_ideal_sharing"].mean().sort_index()


def probe_candidates(probe: pd.DataFrame, unit: str, column: str, recorded_grid: int = 512) -> list[Candidate]:
    """The candidates (`CANDIDATE_GRIDS`) of the probe's converged cases at k~ = 10, phi = 0.06 (phi = 0.15
    beside), h~ in ``column`` (the unit ``unit``), with their scatter over the neighbouring grids run;
    cost: the mean CPU-s a case at k~ = 10, phi = 0.06."""
    frame = _converged(probe, recorded_grid)
    if not len(frame):
        return []
    stiff = frame[np.isclose(frame["stiffness_ratio"], 10.0) & np.isclose(frame["phi"], 0.06)]
    found = []
    for side, elements in sorted({(int(s), int(e)) for s, e in zip(stiff["pillars_per_side"], stiff["elements"])}):
        if elements not in CANDIDATE_GRIDS.get(side, ()):
            continue
        g = stiff[(stiff["pillars_per_side"] == side) & (stiff["elements"] == elements)]
        h, low, high = read_maximum(g.groupby(column)["force_by_ideal_sharing"].mean())
        wide = read_maximum(probe_curve(frame, side, elements, 10.0, 0.15, column))[0]
        found.append(with_scatter(Candidate(unit, side, elements, int(g["pillars"].iloc[0]),
                                            float(g["elements_per_radius"].iloc[0]), h, low, high,
                                            float(g["cpu_s"].mean()), wide), frame, column))
    return found


def with_scatter(candidate: Candidate, probe: pd.DataFrame, column: str, recorded_grid: int = 512) -> Candidate:
    """``candidate`` with its scatter over the probe's grids of its pillars within `NEIGHBOURS_WITHIN` of its N
    (k~ = 10, phi = 0.06, h~ in ``column``): the envelope of the readings, its own included, and their spread.
    A candidate outside the probe (the part's 16 x 16 on N = 512) takes its neighbours from the probe too."""
    frame = _converged(probe, recorded_grid)
    stiff = frame[np.isclose(frame["stiffness_ratio"], 10.0) & np.isclose(frame["phi"], 0.06)] if len(frame) else frame
    run = set(stiff.loc[stiff["pillars_per_side"] == candidate.side, "elements"]) if len(stiff) else set()
    grids = neighbours(candidate.elements, run | {candidate.elements})
    if len(grids) < 2:
        return candidate
    reads = [(candidate.h_at_max, candidate.low, candidate.high)] + [
        read_maximum(probe_curve(frame, candidate.side, n, 10.0, 0.06, column)) for n in grids if n != candidate.elements]
    return dataclasses.replace(candidate, scattered=score_interval(min(r[1] for r in reads), max(r[2] for r in reads)),
                               spread=(max(r[0] for r in reads) - min(r[0] for r in reads)) / THESIS_H,
                               grids=tuple(grids))


def interpolated(curve: pd.Series, h: float) -> float:
    """``curve`` (F~_A by h~) at ``h``, linear between its sampled h~; NaN outside them or where empty."""
    if not len(curve) or not curve.index.min() <= h <= curve.index.max():
        return math.nan
    return float(np.interp(h, curve.index.to_numpy(float), curve.to_numpy(float)))


def _range(pair: tuple[float, float]) -> str:
    return f"{100 * pair[0]:.1f}-{100 * pair[1]:.1f} %" if math.isfinite(pair[0]) else "—"


def identification_table(found: list[Candidate], at_rows: bool) -> str:
    """The Markdown of chapter 7's identification: each candidate's stiff optimum, its score with the reading
    error (strict, the rule) and with the discretisation scatter (a sensitivity), its cost, and each definition's
    pick.  ``at_rows``: the rows are computed on the strict pick, the identification's."""
    pick, tied = choose(found)
    wide, wide_tied = choose(found, scatter=True)
    lines = ["Chapter 7's identification (the row *used to identify*): the reference stress p_c of h~ (eq. 7.3), "
             "the pillar count and the grid N (the thesis states none of them for chapter 7), from the stiff "
             "optimum, k~ = 10, phi = 0.06, the circle.  Score = |h~ at the maximum / 0.04 - 1|.  Rule (declared "
             "before the grids other than 512 were run): the best score wins; a candidate whose score range "
             "overlaps the best's ties with it, and the cheapest of the tied wins.  The range is the rule's as "
             "declared, *strict*: the reading, half the sampled h~ step on each side of the maximum.  Beside it, a "
             "sensitivity only (widened after the strict reading was known): *with scatter*, the envelope of the "
             "readings over the candidate's grid and its neighbours within "
             f"{100 * NEIGHBOURS_WITHIN:.0f} % of its N (grids run to measure the scatter, not candidates).  The "
             "scatter column is the spread of h~ at the maximum over those grids, over 0.04: 10 to 30 times the "
             "reading error.  The 16 x 16 on N = 512 from the part `stiffness` "
             "(cost: wall time a case), the others from `probe_concave_count.csv` (`python "
             "docs/reproduction/probe_concave_count.py`; cost: CPU-s a case at k~ = 10).", "",
             "| candidate p_c | pillars | N (elements a radius) | h~ at max F~_A, k~ = 10, phi = 0.06 (thesis 0.04) "
             "| h~ at max, k~ = 10, phi = 0.15 | score | strict range | scatter (grids) | range with scatter "
             "| s a case (CPU-s; wall time where marked) |", "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for c in found:
        w = f"{c.wide:.4g}" if math.isfinite(c.wide) else "—"
        marks = [m for m, on in (("**identified**", c is pick), ("ties", c in tied and c is not pick),
                                 ("pick with scatter", c is wide),
                                 ("ties with scatter", c in wide_tied and c is not wide)) if on]
        scatter = (f"{100 * c.spread:.1f} % ({', '.join(map(str, c.grids))})" if math.isfinite(c.spread)
                   else "not measured")
        lines.append(f"| {c.unit} | {c.side} x {c.side} ({c.pillars} in the circle) | {c.elements} "
                     f"({c.per_radius:.2f}) | {c.h_at_max:.4g} | {w} | {100 * c.score:.1f} %"
                     f"{' ' + ', '.join(marks) if marks else ''} | {_range(c.score_range)} | {scatter} | "
                     f"{_range(c.error_range(True))} | {c.cost_s:.2f}{' wall time' if c.wall else ''} |")
    if pick is None or wide is None:
        return "\n".join(lines)

    def said(chosen: Candidate, among: list[Candidate]) -> str:
        best = min(among, key=lambda c: c.score)
        others = ", ".join(c.name for c in among if c is not chosen)
        return (f"{chosen.name} ({100 * chosen.score:.1f} %, {chosen.cost} a case"
                + ("" if best is chosen else f"; the best is {best.name} at {100 * best.score:.1f} %")
                + (f"; tied: {others}" if others else "; no tie") + ")")

    lines += ["", f"Identified (strict, the rule as declared): p_c = {pick.unit.split(',')[0]} with {said(pick, tied)}.  "
              f"With scatter (a sensitivity, widened after the strict reading was known): {said(wide, wide_tied)}"
              + (" — the same pick." if wide is pick else " — a different pick: the chapter's grid and count "
                 "sensitivity (its rows outside the counts).")
              + (f"  Every counted row above is computed on the identified candidate (the parts' points on "
                 f"{pick.side} x {pick.side} pillars, N = {pick.elements}, set `n{pick.elements}x{pick.side}`)."
                 if at_rows else "  The rows above are NOT computed on it.")
              + ("" if len(tied) < 2 else "  The strict rule ties candidates here, and the parts run only the pick: "
                 "no row above is checked at the others, so none of its reproduced rows decides the thesis's number.")]
    return "\n".join(lines)
