"""Chapter 6 on the clustered layout of Fig. 6-3 by the pillar-level model: parts ``fig63_one``, ``fig63_two``, ``fig63_three``.

The sweeps (written by ``docs/reproduction/make_fig63.py``) run the brushes of Fig. 6-3 (phi1 = 0.12,
phi2 = phi3 = 0.45, L1163; clusters of 5 x 5 sub-pillars and 4 x 4 of those, N1 = 25, N2 = 16, so that eq.
6.28 gives 4.21e-5 against the thesis's 0.4e-4) with ``method = "pillars"`` at 4.5 elements a pillar radius.

Chapter 6's one identification: N3, the number of level-3 clusters (the thesis states N1, N2, N3 nowhere;
eq. 6.28 fixes N1 N2 only), among 4, 9 and 16 (40 x 40, 60 x 60, 80 x 80 sub-pillars), scored on the three
plateau numbers at sigma~ = 0.04 (L1197), the rows *used to identify*, at two resolutions: the rows' 4.5
elements a radius and the tips on rasters of their own at 9 (parts ``fig63_tips_one``, ``fig63_tips_two``,
``fig63_tips``, set ``identify_tips``), which decides (`identification`: there the tips' discretisation error
bounds a score's move below the margin).  Every other row of these parts reads the identified N3 at
N = `ELEMENTS[N3_IDENTIFIED]` and declares no choice of its own: the small preload F~_P = 1 of Fig. 6-4 a, c,
e is the chapter's one (ours: the thesis states none), one for all three panels.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping

import numpy as np
import pandas as pd

from brushbem.studies._ch5_7 import FA, FP, PRELOAD, SIG, SIGMA, K, finished, has
from brushbem.studies.base import ThesisNumber
from brushbem.studies.verdicts import RESOLUTIONS, STATED_CHOICE, USED_TO_IDENTIFY

__all__ = ["BY_SYMMETRY", "FIG63_LEVELS", "FIG63_NUMBERS", "IDENTIFICATION", "IDENTIFY_GRID", "IDENTIFY_TIPS",
           "LEVEL_2", "LEVEL_TIE", "N3_CANDIDATES", "N3_IDENTIFIED", "TIPS_PART", "TIPS_PARTS", "discretisation",
           "identification", "part_difference", "tie_table", "part_plateau", "part_ratio", "plateau",
           "plateau_difference", "plateau_ratio"]

FIG63_LEVELS = {"one": "fig63_one", "two": "fig63_two", "three": "fig63_three"}
#: Candidate N3 -> (sub-pillars per side, elements per side): 4.5 elements a pillar radius each.
N3_CANDIDATES = {4: (40, 2048), 9: (60, 3072), 16: (80, 4096)}
#: Chapter 6's identified N3 (`identification`: the smallest score on the rows used to identify).
N3_IDENTIFIED = 4
PILLARS = "indenter.pillars_per_side"
ELEMENTS = "grid.elements"
K2 = "indenter.levels.0.stiffness_ratio"
K3 = "indenter.levels.1.stiffness_ratio"
#: The thesis's plateaus at sigma~ = 0.04, F~_P = 14.3 (L1197): the rows used to identify N3.
PLATEAUS = {"one": 1.6, "two": 1.65, "three": 1.9}
#: Fig. 6-4's small preload (a, c, e): ours, the thesis states none; one value for every row.
SMALL_PRELOAD = 1.0
#: The resolution of a ratio of two brushes' F~_A (`ThesisNumber.tie`) and the mesh error a decided ratio must clear
#: too (`ThesisNumber.mesh`): chapter 6's `RESOLUTIONS`, measured and sourced there.
LEVEL_TIE, _LEVEL = RESOLUTIONS[6].relative, {"tie": RESOLUTIONS[6].relative, "mesh": RESOLUTIONS[6].mesh}
TIED = RESOLUTIONS[6].stated
IDENTIFICATION = (f"chapter 6's identification: N3 = {N3_IDENTIFIED} level-3 clusters ({N3_CANDIDATES[N3_IDENTIFIED][0]} x "
                  f"{N3_CANDIDATES[N3_IDENTIFIED][0]} sub-pillars; N1 = 25, N2 = 16, ours: the thesis states none) "
                  "from the three plateaus at sigma~ = 0.04 among N3 = 4, 9, 16, decided with the tips at 9 elements a "
                  "radius (table after the rows); clustered layout of Fig. 6-3, pillar-level model, 4.5 elements a "
                  "radius (its discretisation error: the table of the tips' refinement after the rows)")


def _select(frame: pd.DataFrame, n3: int = N3_IDENTIFIED, elements: int | None = None, k1: float = 1e-3,
            k3: float | None = None) -> pd.DataFrame:
    """The rows of ``frame`` at candidate ``n3`` (its grid unless ``elements``), bottom stiffness ``k1`` and,
    for three levels, top stiffness ``k3`` (default 20 k1, eq. 6.26's scaling)."""
    if not has(frame, PILLARS, ELEMENTS):
        return frame.iloc[0:0]
    side, grid = N3_CANDIDATES[n3]
    mask = (frame[PILLARS] == side) & (frame[ELEMENTS] == (elements or grid))
    if K in frame.columns:
        mask &= np.isclose(frame[K], k1, rtol=1e-6)
    if K3 in frame.columns:
        mask &= np.isclose(frame[K3], 20 * k1 if k3 is None else k3, rtol=1e-3)
    return frame[mask]


def plateau(level: str, sigma_tilde: float, preload: float, column: str = FA, **where) -> Callable:
    """F~_A (or ``column``), mean over the seeds, of ``level`` at sigma~ and F~_P (each within 10 % of the
    rasterised brush's value), at the identified N3 unless ``where`` (`_select`) says otherwise; nan where
    the tables have no such point."""
    def compute(results: Mapping[str, pd.DataFrame]) -> float:
        frame = _select(finished(results, FIG63_LEVELS[level]), **where)
        if not has(frame, column, SIG, FP):
            return math.nan
        frame = frame[np.isclose(frame[SIG], sigma_tilde, rtol=0.1) & np.isclose(frame[FP], preload, rtol=0.1)]
        return float(frame[column].mean()) if len(frame) else math.nan
    return compute


def plateau_ratio(top: Callable, bottom: Callable) -> Callable:
    """``top`` over ``bottom`` (magnitudes), each a `plateau`."""
    def compute(results):
        b = bottom(results)
        return abs(top(results)) / abs(b) if math.isfinite(b) and b != 0 else math.nan
    return compute


def plateau_difference(top: Callable, bottom: Callable) -> Callable:
    return lambda results: top(results) - bottom(results)  # ``top`` less ``bottom``, each a `plateau`


# The readers of the chapter's other parts (one sweep table per part: uniform lattice, exact clustered).
#: The grid of the exact clustered parts' rows (clustered_*; their set mesh adds N = 1536, read only by `tie_table`).
CLUSTERED_GRID = 1024


def _with_grid(frame: pd.DataFrame) -> pd.DataFrame:
    """``frame`` with its global N in `ELEMENTS`: a case recorded before its part swept the grid has none there,
    and ran the sweep's base grid, `CLUSTERED_GRID` (the clustered parts' only grid until set mesh)."""
    return frame.assign(**{ELEMENTS: frame[ELEMENTS].fillna(CLUSTERED_GRID) if ELEMENTS in frame.columns
                            else CLUSTERED_GRID})


def part_plateau(part: str, sigma_tilde: float, preload: float | None = None, column: str = FA):
    """F~_A (mean over realisations) of ``part`` at sigma~ (and F~_P): the plateau (largest mean over
    the preloads) when ``preload`` is None.  A part whose table sweeps the grid is read at `CLUSTERED_GRID`.

    The sweeps' sigma~ and F~_P are normalised by the rasterised brush's d_c and F_c, a few per cent
    from the nominal values the thesis quotes: a point within 10 % counts, and where the tables have
    none the number is not computable (nan), never read off another point.
    """
    def compute(results):
        frame = finished(results, part)  # on `CLUSTERED_GRID` (all of a part that does not sweep the grid)
        frame = frame[_with_grid(frame)[ELEMENTS] == CLUSTERED_GRID]
        if not has(frame, FA, SIG, PRELOAD):
            return math.nan
        nearest = frame.iloc[np.argmin(np.abs(frame[SIG] - sigma_tilde))]
        if abs(nearest[SIG] - sigma_tilde) > 0.1 * sigma_tilde:
            return math.nan
        frame = frame[np.isclose(frame[SIGMA], nearest[SIGMA])]
        means = frame.groupby(PRELOAD).agg(fa=(column, "mean"), fp=(FP, "mean"))
        if preload is None:
            return float(means["fa"].max())
        row = means.iloc[np.argmin(np.abs(means["fp"] - preload))]
        return float(row["fa"]) if abs(row["fp"] - preload) <= 0.1 * preload else math.nan
    return compute


def part_ratio(part: str, over: str, sigma_tilde: float, preload: float | None = None, column: str = FA):
    """F~_A (or ``column``) of ``part`` over that of ``over`` at sigma~ (and F~_P), each as `part_plateau` reads it."""
    top, bottom = part_plateau(part, sigma_tilde, preload, column), part_plateau(over, sigma_tilde, preload, column)

    def compute(results):
        b = bottom(results)  # magnitudes: a separation displacement is signed (negative: pulled away)
        return abs(top(results)) / abs(b) if math.isfinite(b) and b != 0 else math.nan
    return compute


def part_difference(part: str, less: str, sigma_tilde: float, preload: float | None = None):
    """F~_A of ``part`` less that of ``less`` at sigma~ (and F~_P), each as `part_plateau` reads it."""
    top, bottom = part_plateau(part, sigma_tilde, preload), part_plateau(less, sigma_tilde, preload)
    return lambda results: top(results) - bottom(results)


def _most_of_the_others(sigma_tilde: float, preload: float) -> Callable:
    """Three levels over the larger of one and two levels at sigma~, F~_P ("the three-level structure attains
    the largest adhesive force, compared with other two structures", L1183)."""
    three, one, two = (plateau(level, sigma_tilde, preload) for level in ("three", "one", "two"))

    def compute(results):
        other = max(one(results), two(results))
        return three(results) / other if math.isfinite(other) and other > 0 else math.nan
    return compute


#: Part fig63_tips: the three-level plateau on the rows' grid with the tips on rasters of their own.
TIPS_PART = "fig63_tips"
TIP = "protocol.pillar_tip_resolution"


def _discretisation_points(results: Mapping[str, pd.DataFrame]) -> list[tuple[str, int, float, float, int]]:
    """(how, global N, tips' elements a radius, F~_A, seeds) of the three-level plateau at sigma~ = 0.04,
    F~_P = 14.3, the identified N3, on the seeds that part fig63_tips has (none: those of the rows' grid)."""
    _, grid = N3_CANDIDATES[N3_IDENTIFIED]
    per_radius = 4.5 / grid  # elements a radius per element of the side (4.5 at the rows' grid)
    level = finished(results, FIG63_LEVELS["three"])
    tips = finished(results, TIPS_PART)
    seed = "seed" if "seed" in level.columns else "realization"

    def plateau_at(frame):
        if not has(frame, SIG, FP, FA, seed):
            return frame.iloc[0:0]
        return frame[np.isclose(frame[SIG], 0.04, rtol=0.1) & np.isclose(frame[FP], 14.3, rtol=0.1)]

    tips = plateau_at(_select(tips)) if has(tips, PILLARS, ELEMENTS, TIP) else tips.iloc[0:0]
    # The seeds that have every tips' resolution (a sweep stopped inside a seed leaves it out).
    counts = tips.groupby(seed)[TIP].nunique() if len(tips) else pd.Series(dtype=int)
    seeds = set(counts[counts == counts.max()].index) if len(counts) else set()
    tips = tips[tips[seed].isin(seeds)] if seeds else tips
    points = []
    for n in (grid // 2, grid, 2 * grid):
        frame = plateau_at(_select(level, elements=n))
        if TIP in frame.columns:
            frame = frame[frame[TIP].isna()]
        if seeds:
            frame = frame[frame[seed].isin(seeds)]
        if len(frame):
            points.append(("global grid", n, per_radius * n, float(frame[FA].mean()), frame[seed].nunique()))
    for tip, group in (tips.groupby(TIP) if len(tips) else ()):
        points.append(("tips' own raster", grid, float(tip), float(group[FA].mean()), group[seed].nunique()))
    return points


def discretisation(results: Mapping[str, pd.DataFrame]) -> list[str]:
    """The Markdown of the three-level plateau's discretisation: the global grid refined (set mesh) and, at the
    rows' grid, the tips alone (part fig63_tips); the plateau at the finest tips with the spread of the tips'
    refinements as its error, and the rows' grid's distance from it (empty where neither has run)."""
    points = _discretisation_points(results)
    if len(points) < 2:
        return []
    lines = ["", "Discretisation of the three-level plateau at sigma~ = 0.04, F~_P = 14.3 (N3 = 4; seeds: those of "
             "part fig63_tips): the global grid refined (set mesh) and, on the rows' grid N = 2048, the tips alone "
             "on rasters of their own (part fig63_tips, `protocol.pillar_tip_resolution`; 9 elements a radius "
             "there holds the footprints of N = 4096).", "",
             "| refined | N | tips, elements a radius | F~_A | seeds |", "| --- | --- | --- | --- | --- |"]
    lines += [f"| {how} | {n} | {tip:.3g} | {fa:.4f} | {seeds} |" for how, n, tip, fa, seeds in points]
    tips = sorted((tip, fa) for how, _, tip, fa, _ in points if how != "global grid")
    rows_grid = [fa for how, n, _, fa, _ in points if how == "global grid" and n == N3_CANDIDATES[N3_IDENTIFIED][1]]
    if len(tips) >= 2 and rows_grid:
        values = [fa for _, fa in tips]
        # The tips' refinement need not be monotone (a rasterised circle's pull-off moves with its staircase,
        # data/resolution_error.csv), so no extrapolation: the band of the refined tips, its middle and half width.
        middle, half = (max(values) + min(values)) / 2, (max(values) - min(values)) / 2
        lines += ["", f"The plateau with its tips resolved: {middle:.4f} ± {half:.4f}, the band of the tips at "
                  f"{', '.join(f'{t:.3g}' for t, _ in tips)} elements a radius (its middle and half width: the "
                  "refinement need not be monotone, so it is not extrapolated).  The rows' grid (4.5 elements a "
                  f"radius, {rows_grid[0]:.4f}) lies {100 * (rows_grid[0] / middle - 1):+.1f} % from it: the "
                  "discretisation error of every row of these parts."]
    refined = _refinement(results)
    if refined:
        lines += ["", "The global grid refined from 4.5 to 9 elements a radius (N = 2048 to 4096, set mesh, the seeds "
                  "with both) for each level: " + ", ".join(
                      f"{level} {fa2:.4f} to {fa4:.4f} ({100 * (fa4 / fa2 - 1):+.1f} %, {n} seed{'s' * (n > 1)})"
                      for level, (fa2, fa4, n) in refined.items()) + "."]
    return lines


def _refinement(results: Mapping[str, pd.DataFrame]) -> dict[str, tuple[float, float, int]]:
    """Level -> (plateau at the rows' grid, at twice its elements, seeds) on the seeds that have both."""
    _, grid = N3_CANDIDATES[N3_IDENTIFIED]
    found = {}
    for level, part in FIG63_LEVELS.items():
        frame = finished(results, part)
        seed = "seed" if "seed" in frame.columns else "realization"
        if not has(frame, PILLARS, ELEMENTS, SIG, FP, FA, seed):
            continue
        at = {n: _select(frame, elements=n) for n in (grid, 2 * grid)}
        at = {n: f[np.isclose(f[SIG], 0.04, rtol=0.1) & np.isclose(f[FP], 14.3, rtol=0.1)] for n, f in at.items()}
        seeds = set(at[grid][seed]) & set(at[2 * grid][seed])
        if seeds:
            found[level] = (float(at[grid][at[grid][seed].isin(seeds)][FA].mean()),
                            float(at[2 * grid][at[2 * grid][seed].isin(seeds)][FA].mean()), len(seeds))
    return found


#: The tips' parts per level (part fig63_tips: three levels) and set identify_tips's tips and global grid: the
#: plateau point for every candidate N3 on N = 2048 with the tips at 9 elements a radius (factors 2, 3, 4).
TIPS_PARTS = {"one": "fig63_tips_one", "two": "fig63_tips_two", "three": TIPS_PART}
IDENTIFY_TIPS, IDENTIFY_GRID = 9.0, 2048


def _candidate(results: Mapping[str, pd.DataFrame], n3: int, resolved: bool) -> dict[str, tuple[float, float, int]]:
    """Level -> (mean plateau F~_A over the seeds, its standard error, seeds) of candidate ``n3`` at sigma~ = 0.04,
    F~_P = 14.3: on its grid of 4.5 elements a radius (parts fig63_*), or with the tips at `IDENTIFY_TIPS` on
    N = `IDENTIFY_GRID` (``resolved``, the tips' parts, set identify_tips)."""
    values = {}
    for level in PLATEAUS:
        if resolved:
            frame = finished(results, TIPS_PARTS[level])
            frame = (_select(frame, n3=n3, elements=IDENTIFY_GRID) if has(frame, TIP) else frame.iloc[0:0])
            frame = frame[np.isclose(frame[TIP], IDENTIFY_TIPS)] if len(frame) else frame
        else:
            frame = _select(finished(results, FIG63_LEVELS[level]), n3=n3)
            if TIP in frame.columns:
                frame = frame[frame[TIP].isna()]
        at = (frame[np.isclose(frame[SIG], 0.04, rtol=0.1) & np.isclose(frame[FP], 14.3, rtol=0.1)]
              if has(frame, SIG, FP, FA) else frame.iloc[0:0])
        per_seed = at.groupby("realization")[FA].mean() if len(at) else pd.Series(dtype=float)
        error = per_seed.std() / math.sqrt(len(per_seed)) if len(per_seed) > 1 else math.nan
        values[level] = (float(per_seed.mean()) if len(per_seed) else math.nan, error, len(per_seed))
    return values


def _score(values: Mapping[str, tuple[float, float, int]]) -> tuple[float, float, bool]:
    """The root mean square of F~_A / thesis - 1 over the three plateaus, its standard error over the seeds
    (propagated from each plateau's; nan where a plateau has one seed) and whether every plateau ran.  Where
    some did not, the root mean square with the missing ones at 0: a floor under the score whatever they give."""
    relative = {lv: values[lv][0] / PLATEAUS[lv] - 1 for lv in PLATEAUS if math.isfinite(values[lv][0])}
    if not relative:
        return math.nan, math.nan, False
    score = math.sqrt(sum(r ** 2 for r in relative.values()) / 3)
    if not score > 0:
        return score, math.nan, len(relative) == 3
    # d score / d F_l = r_l / (3 score thesis_l)
    error = math.sqrt(sum((r / (3 * score * PLATEAUS[lv]) * values[lv][1]) ** 2 for lv, r in relative.items()))
    return score, error, len(relative) == 3


Score = tuple[float, float, bool]  #: a candidate's score: value, standard error, every plateau ran (else a floor)


def _identification_rows(results: Mapping[str, pd.DataFrame],
                         resolved: bool) -> tuple[list[str], dict[int, Score], float]:
    """The candidates' table rows at one resolution, their scores (`_score`; those with a plateau) and the
    largest plateau over its thesis value (nan where none ran)."""
    lines, scores, largest = [], {}, math.nan
    for n3, (side, grid) in N3_CANDIDATES.items():
        values = _candidate(results, n3, resolved)
        score, error, complete = _score(values)
        if math.isfinite(score):
            scores[n3] = (score, error, complete)
            largest = np.nanmax([largest, *(v[0] / PLATEAUS[lv] for lv, v in values.items())])
        shown = [f"{m:.3f} ± {e:.3f}" if math.isfinite(e) else (f"{m:.3f}" if math.isfinite(m) else "not run")
                 for m, e, _ in values.values()]
        ratio = values["three"][0] / values["one"][0]
        grid_text = f"{IDENTIFY_GRID}" if resolved else f"{grid}"
        tips = f"{IDENTIFY_TIPS:g} (own raster)" if resolved else "4.5 (the grid's)"
        scored = ("—" if not math.isfinite(score) else ("" if complete else "≥ ") + f"{100 * score:.1f}"
                  + (f" ± {100 * error:.1f}" if math.isfinite(error) else "") + " %")
        label = f"{n3} (identified)" if resolved and n3 == N3_IDENTIFIED else f"{n3}"
        lines.append(f"| {label} | {side} x {side} | {grid_text} | {tips} | {' | '.join(shown)} | "
                     f"{f'{ratio:.3f}' if math.isfinite(ratio) else '—'} | {scored} | "
                     f"{', '.join(str(v[2]) for v in values.values())} |")
    return lines, scores, float(largest)


def _global_grid_at_fixed_tips(results: Mapping[str, pd.DataFrame]) -> dict[int, tuple[float, int]]:
    """Global N -> (three-level plateau of the identified N3 with the tips at `IDENTIFY_TIPS`, seeds), on the
    seeds that have N = 1024 and 2048 (set tips); N = 4096 is the grid's own 9 elements a radius (set mesh)."""
    tips = finished(results, TIPS_PART)
    level = finished(results, FIG63_LEVELS["three"])
    if not has(tips, PILLARS, ELEMENTS, TIP, SIG, FP, FA, "realization"):
        return {}
    side, grid = N3_CANDIDATES[N3_IDENTIFIED]
    point = (tips[PILLARS] == side) & np.isclose(tips[TIP], IDENTIFY_TIPS) & np.isclose(tips[SIG], 0.04, rtol=0.1) \
        & np.isclose(tips[FP], 14.3, rtol=0.1)
    at = {n: tips[point & (tips[ELEMENTS] == n)] for n in (grid // 2, grid)}
    seeds = set(at[grid // 2]["realization"]) & set(at[grid]["realization"])
    if not seeds:
        return {}
    found = {n: (float(f[f["realization"].isin(seeds)][FA].mean()), len(seeds)) for n, f in at.items()}
    fine = _select(level, elements=2 * grid)
    if has(fine, SIG, FP, FA, "realization"):
        fine = fine[np.isclose(fine[SIG], 0.04, rtol=0.1) & np.isclose(fine[FP], 14.3, rtol=0.1)
                    & fine["realization"].isin(seeds)]
        if len(fine):
            found[2 * grid] = (float(fine[FA].mean()), fine["realization"].nunique())
    return found


def _tie_points(results: Mapping[str, pd.DataFrame]) -> dict[int, dict[str, dict[int, tuple[float, float]]]]:
    """Global N -> level -> seed -> (the pillar-level model's plateau, the exact path's) at sigma~ = 0.04,
    F~_P = 14.3, N3 = 4, for the seeds both ran at that N (parts fig63_* set mesh against clustered_*)."""
    found: dict[int, dict[str, dict[int, tuple[float, float]]]] = {}
    for level, part in FIG63_LEVELS.items():
        model, exact = finished(results, part), finished(results, f"clustered_{level}")
        if not (has(model, PILLARS, ELEMENTS, SIG, FP, FA, "realization") and has(exact, SIG, FP, FA, "realization")):
            continue
        exact = _with_grid(exact)
        for n in sorted(set(exact[ELEMENTS])):
            m = _select(model, elements=n)
            m = m[np.isclose(m[SIG], 0.04, rtol=0.1) & np.isclose(m[FP], 14.3, rtol=0.1)]
            e = exact[(exact[ELEMENTS] == n) & np.isclose(exact[SIG], 0.04, rtol=0.1)
                      & np.isclose(exact[FP], 14.3, rtol=0.1)]
            m, e = m.groupby("realization")[FA].mean(), e.groupby("realization")[FA].mean()
            pairs = {int(r): (float(m[r]), float(e[r])) for r in set(m.index) & set(e.index)}
            if pairs:
                found.setdefault(int(n), {})[level] = pairs
    return found


def tie_table(results: Mapping[str, pd.DataFrame]) -> list[str]:
    """The Markdown of `LEVEL_TIE`'s measurement: the pillar-level model against the exact path on the same clustered
    brush at each grid both ran, per level and for the ratios of levels (each on the seeds it has; empty where none)."""
    found = _tie_points(results)
    if not found:
        return []
    lines = ["", "The resolution of the level comparisons (`LEVEL_TIE`, 1.5 %): the pillar-level model against the exact "
             "path on the same clustered brush (N3 = 4, sigma~ = 0.04, F~_P = 14.3; parts fig63_* set mesh against "
             "clustered_*; N = 1536: sets mesh1536 of fig63_* and mesh of clustered_*, `brushbem study hierarchy "
             "--sampled-set mesh1536 --parts fig63_two,fig63_three --out out/fig63-mesh1536` and `brushbem study "
             "hierarchy --sampled-set mesh --parts clustered_two,clustered_three --out out/clustered-mesh`); a level "
             "on the seeds both "
             "methods ran, a ratio on the seeds both levels have.", "",
             "| N | elements a radius | level | model | exact path | model / exact - 1 | seeds |",
             "| --- | --- | --- | --- | --- | --- | --- |"]
    for n, levels in sorted(found.items()):
        per_radius = f"{4.5 * n / N3_CANDIDATES[N3_IDENTIFIED][1]:.4g}"
        for level, pairs in levels.items():
            m, e = (float(np.mean([v[i] for v in pairs.values()])) for i in (0, 1))
            lines.append(f"| {n} | {per_radius} | {level} | {m:.4f} | {e:.4f} | {100 * (m / e - 1):+.2f} % | "
                         f"{len(pairs)} |")
        for top, bottom in (("three", "two"), ("three", "one"), ("two", "one")):
            seeds = sorted(set(levels.get(top, {})) & set(levels.get(bottom, {})))
            if seeds:
                m = float(np.mean([levels[top][r][0] / levels[bottom][r][0] for r in seeds]))
                e = float(np.mean([levels[top][r][1] / levels[bottom][r][1] for r in seeds]))
                lines.append(f"| {n} | {per_radius} | {top} over {bottom} | {m:.4f} | {e:.4f} | "
                             f"{100 * (m / e - 1):+.2f} % | {len(seeds)} |")
    return lines


def identification(results: Mapping[str, pd.DataFrame]) -> str:
    """The Markdown of chapter 6's identification: each N3's plateaus and score on the rows used to identify, on
    the rows' grid and with the tips resolved; the resolved tips decide (`N3_IDENTIFIED`)."""
    lines = ["Chapter 6's identification (the rows *used to identify*): N3, the number of level-3 clusters, on the "
             "clustered layout of Fig. 6-3 (N1 = 25, N2 = 16: eq. 6.28 gives 4.21e-5 for every N3), pillar-level "
             "model; score = root mean square of F~_A / thesis - 1 over the three plateaus at sigma~ = 0.04, "
             "F~_P = 14.3 (1.6, 1.65, 1.9; L1197), smaller wins (± its standard error over the seeds where every "
             "plateau has two).  Each candidate at two resolutions: the rows' 4.5 elements a pillar radius (tips "
             "on the global grid; parts fig63_*, sets identify and identify16) and the tips on rasters of their "
             f"own at {IDENTIFY_TIPS:g} elements a radius on N = {IDENTIFY_GRID} (parts fig63_tips_one, "
             "fig63_tips_two, fig63_tips, set identify_tips: `brushbem study hierarchy --sampled-set identify_tips "
             "--parts fig63_tips_one,fig63_tips_two,fig63_tips --out out/fig63-identify_tips`).", "",
             "| N3 | sub-pillars | N | tips, elements a radius | one level | two levels | three levels | three over "
             "one | score | seeds (one, two, three) |",
             "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    coarse, coarse_scores, coarse_largest = _identification_rows(results, resolved=False)
    fine, fine_scores, fine_largest = _identification_rows(results, resolved=True)
    lines += [row for pair in zip(coarse, fine) for row in pair]
    lines += _deciding(results, coarse_scores, fine_scores, {False: coarse_largest, True: fine_largest})
    return "\n".join(lines + discretisation(results) + tie_table(results))


def _margin(scores: Mapping[int, Score]) -> tuple[int | None, int | None, float, float]:
    """The candidate with the smallest complete score, the next candidate (complete score or floor), the
    margin between them and the standard error of that margin (nan where it has none)."""
    complete = {n3: sc for n3, sc in scores.items() if sc[2]}
    best = min(complete, key=lambda n3: complete[n3][0]) if complete else None
    others = {n3: sc for n3, sc in scores.items() if n3 != best}
    if best is None or not others:
        return best, None, math.nan, math.nan
    runner = min(others, key=lambda n3: others[n3][0])
    error = math.hypot(scores[best][1], others[runner][1])
    return best, runner, others[runner][0] - scores[best][0], error


def _decided(margin: float, bound: float, error: float) -> bool:
    """A margin decides where it exceeds the discretisation's bound on both scores (2 ``bound``: they may move
    apart) and two standard errors of the margin (where it has one)."""
    return margin > 2 * bound + (2 * error if math.isfinite(error) else 0.0)


def _deciding(results, coarse: Mapping[int, Score], fine: Mapping[int, Score], largest: Mapping[bool, float]) -> list[str]:
    """Which resolution decides and why: each resolution's winner and margin against the bound its discretisation
    error puts on a score.  Relative shifts of at most e on the plateaus move a score (a root mean square of
    F~_A / thesis - 1, or its floor) by at most e times the largest F~_A / thesis."""
    best, runner, margin, margin_error = _margin(fine)
    if best is None:
        return []
    points = _discretisation_points(results)
    tips = [fa for how, _, _, fa, _ in points if how != "global grid"]
    _, grid = N3_CANDIDATES[N3_IDENTIFIED]
    band = (max(tips) - min(tips)) / (max(tips) + min(tips)) if len(tips) >= 2 else math.nan
    rows_grid = [fa for how, n, _, fa, _ in points if how == "global grid" and n == grid]
    coarse_error = rows_grid[0] / ((max(tips) + min(tips)) / 2) - 1 if len(tips) >= 2 and rows_grid else math.nan
    grids = _global_grid_at_fixed_tips(results)
    spread = max(abs(fa / grids[grid][0] - 1) for fa, _ in grids.values()) if grid in grids else math.nan
    found = [e for e in (band, spread) if math.isfinite(e)]
    error = max(found) if found else math.nan
    floor = runner is not None and not fine[runner][2]
    other = f"N3 = {runner}'s {'floor' if floor else 'score'}"
    seeds = f" (± {100 * margin_error:.1f}, the seeds)" if math.isfinite(margin_error) else ""
    text = f"The tips at {IDENTIFY_TIPS:g} elements a radius decide: "
    if runner is None:  # (a lone candidate: nothing to decide)
        return ["", text + f"there only N3 = {best} has a score."]
    if margin > 0:
        text += f"there N3 = {best} scores lowest, {100 * margin:.1f} points below {other}{seeds}."
    else:
        text += (f"there N3 = {best} has the lowest complete score, but {other} lies {100 * -margin:.1f} points "
                 f"below it{seeds}: undecided until N3 = {runner} runs every level.")
    if math.isfinite(band):
        text += (f"  Refining the tips from 9 to 18 elements a radius moves the three-level plateau within "
                 f"±{100 * band:.2f} % (part fig63_tips, the table below)")
    if grids:
        text += ("; the global grid at fixed tips (9 elements a radius) within "
                 f"{100 * spread:.2f} % (" + ", ".join(f"N = {n}: {fa:.4f}" for n, (fa, _) in sorted(grids.items()))
                 + f", {min(s for _, s in grids.values())} seed(s); N = 1024 has N3 = 16's 2.25 elements a radius on "
                 "the global grid, N = 4096 the grid's own tips at 9)")
    text += "." if math.isfinite(band) or grids else ""
    if math.isfinite(error) and runner is not None and margin > 0:
        bound = error * largest[True]
        text += (f"  Shifts of at most {100 * error:.2f} % on the plateaus move a score by at most "
                 f"{100 * bound:.2f} points (times {largest[True]:.3f}, the largest F~_A / thesis); the margin "
                 + ("exceeds twice that (both scores may move, apart) and two of its standard errors: the "
                    "identification holds at this resolution." if _decided(margin, bound, margin_error) else
                    "does not exceed twice that and two of its standard errors: the identification is undecided."))
    coarse_best, coarse_runner, coarse_margin, coarse_margin_error = _margin(coarse)
    if coarse_best is not None and coarse_runner is not None and math.isfinite(coarse_error):
        bound = abs(coarse_error) * largest[False]
        text += (f"  On the rows' grid (4.5 elements a radius, tips on the global grid) N3 = {coarse_best} scores "
                 f"lowest, {100 * coarse_margin:.1f} points below N3 = {coarse_runner}; there the tips alone put "
                 f"{100 * coarse_error:+.1f} % on the three-level plateau (the table below), {100 * bound:.1f} points "
                 "on a score: "
                 + ("the margin exceeds twice that, so that resolution decides too." if
                    _decided(coarse_margin, bound, coarse_margin_error) else
                    "the margin does not exceed twice that, so that resolution does not decide."))
    return ["", text]


def _held_out(text: str = "") -> str:
    return IDENTIFICATION + (f"; {text}" if text else "")


def _by(*names: str) -> str:
    """The sets whose cases a row reads, and the command that runs them."""
    return "; ".join(f"set {name}: `brushbem study hierarchy --sampled-set {name} --parts fig63_one,fig63_two,"
                     f"fig63_three --out out/fig63-{name}`" for name in names)


_WHERE = f"clustered (Fig. 6-3), N3 = {N3_IDENTIFIED}"
#: Why N3 = 4 decides a level-3 row at sigma~ = 0.04 (`ThesisNumber.untested`), and three against one levels there.
BY_SYMMETRY = (f"N3 = {N3_IDENTIFIED} decides it by symmetry: at sigma~ = 0.04 the 2 x 2 level-3 clusters are alike, "
               "their springs shift them alike, and level 3 changes nothing (three levels equal two within 0.1 % "
               "here; 1.729 both on the exact path, N = 1024): the row tests the symmetry, not the claim; no other "
               "N3 was run here")
LEVEL_2 = f"three levels equal two here (N3 = {N3_IDENTIFIED}: level 3 inert by symmetry): the difference is level 2's"
FIG63_NUMBERS = (
    ThesisNumber(f"plateau F~_A of one level, sigma~ = 0.04, F~_P = 14.3, {_WHERE}", "Fig. 6-5, text (L1197)", 1.6,
                 plateau("one", 0.04, 14.3), USED_TO_IDENTIFY, IDENTIFICATION),
    ThesisNumber(f"plateau F~_A of two levels, sigma~ = 0.04, F~_P = 14.3, {_WHERE}", "Fig. 6-5, text (L1197)",
                 1.65, plateau("two", 0.04, 14.3), USED_TO_IDENTIFY, IDENTIFICATION),
    ThesisNumber(f"plateau F~_A of three levels, sigma~ = 0.04, F~_P = 14.3, {_WHERE}", "Fig. 6-5, text (L1197)",
                 1.9, plateau("three", 0.04, 14.3), USED_TO_IDENTIFY, IDENTIFICATION),
    ThesisNumber(f"plateau F~_A, three levels over one level, sigma~ = 0.04 (1.9 / 1.6), {_WHERE}",
                 "Fig. 6-5, text (L1197)", 1.9 / 1.6,
                 plateau_ratio(plateau("three", 0.04, 14.3), plateau("one", 0.04, 14.3)), USED_TO_IDENTIFY,
                 IDENTIFICATION + " (the ratio of two rows used to identify)", inputs=(
                     f"plateau F~_A of three levels, sigma~ = 0.04, F~_P = 14.3, {_WHERE}",
                     f"plateau F~_A of one level, sigma~ = 0.04, F~_P = 14.3, {_WHERE}")),
    ThesisNumber(f"separation displacement, three levels over one level, sigma~ = 0.04, F~_P = 14.3 ('a larger "
                 f"critical displacement appears in the case of the structure with more levels'), {_WHERE}",
                 "Fig. 6-4 b, text (L1185)", 1.0,
                 plateau_ratio(plateau("three", 0.04, 14.3, "normalized.separation_displacement_by_rigid_brush"),
                               plateau("one", 0.04, 14.3, "normalized.separation_displacement_by_rigid_brush")),
                 evidence=_by("identify"), claim=">"),
    *(ThesisNumber(f"F~_A at small preload F~_P = 1, sigma~ = {s:g}, three levels over the larger of one and two "
                   f"('the three-level structure attains the largest adhesive force'), {_WHERE}",
                   f"Fig. 6-4 {panel}, text (L1183)", 1.0, _most_of_the_others(s, SMALL_PRELOAD),
                   evidence=f"{TIED}; {_by('rows')}", claim=">", **_LEVEL, untested=BY_SYMMETRY if s == 0.04 else "")
      for s, panel in ((0.04, "a"), (0.8, "c"), (1.6, "e"))),
    ThesisNumber(f"three-level F~_A at sigma~ = 1.6, small preload (F~_P = 1), {_WHERE}", "Fig. 6-4 e, text (L1185)",
                 0.4, plateau("three", 1.6, SMALL_PRELOAD), STATED_CHOICE,
                 _held_out("the small preload F~_P = 1 (ours, one for Fig. 6-4 a, c, e; the thesis states none); "
                           + _by("rows"))),
    ThesisNumber(f"one-level F~_A at sigma~ = 1.6, small preload (F~_P = 1; 'tend to zero'), {_WHERE}",
                 "Fig. 6-4 e, text (L1185)", 0.0, plateau("one", 1.6, SMALL_PRELOAD), evidence=_by("rows")),
    ThesisNumber(f"two-level F~_A at sigma~ = 1.6, small preload (F~_P = 1; 'tend to zero'), {_WHERE}",
                 "Fig. 6-4 e, text (L1185)", 0.0, plateau("two", 1.6, SMALL_PRELOAD), evidence=_by("rows")),
    ThesisNumber(f"F~_A at sigma~ = 1.6, F~_P = 1, three levels over two levels (more levels stronger: two levels "
                 f"do not beat three), {_WHERE}", "Fig. 6-4 e, text (L1183)", 1.0,
                 plateau_ratio(plateau("three", 1.6, SMALL_PRELOAD), plateau("two", 1.6, SMALL_PRELOAD)),
                 evidence=f"{TIED}; {_by('rows')}", claim=">", **_LEVEL, outside="a duplicate: two levels beat one at "
                 "sigma~ = 1.6, so it equals the row three levels over the larger of one and two there (Fig. 6-4 e)"),
    ThesisNumber(f"c = F~_A / F~_P at sigma~ = 1.6, F~_P = 1, three levels over one level ('the structure with more "
                 f"levels determines a relatively larger adhesion coefficient'), {_WHERE}", "Fig. 6-6 a, text (L1199)",
                 1.0, plateau_ratio(plateau("three", 1.6, SMALL_PRELOAD), plateau("one", 1.6, SMALL_PRELOAD)),
                 evidence=f"{TIED}; {_by('rows')}", claim=">", **_LEVEL),
    ThesisNumber(f"three-level c = F~_A / F~_P at F~_P = 1, sigma~ = 0.04 over sigma~ = 1.6 ('for small roughness "
                 f"... the adhesive force increases rapidly with preload'), {_WHERE}", "Fig. 6-5, text (L1195)", 1.0,
                 plateau_ratio(plateau("three", 0.04, SMALL_PRELOAD), plateau("three", 1.6, SMALL_PRELOAD)),
                 evidence=_by("rows"), claim=">"),
    ThesisNumber(f"three-level F~_A at sigma~ = 0.04, F~_P = 14.3 over F~_P = 1 ('a plateau region where the maximum "
                 f"adhesive force is obtained and independent of the preload'; below F~_P = 1 not sampled), {_WHERE}",
                 "Fig. 6-5, text (L1187)", 1.0, plateau_ratio(plateau("three", 0.04, 14.3), plateau(
                     "three", 0.04, SMALL_PRELOAD)), evidence=_by("identify", "rows")),
    ThesisNumber(f"three-level F~_A at the large preload, sigma~ = 0.04 (F~_P = 14.3) less sigma~ = 2.5 (F~_P = 20) "
                 f"('the maximum adhesive force at the plateau is higher' for small roughness), {_WHERE}",
                 "Fig. 6-5, text (L1195)", 0.0, plateau_difference(plateau("three", 0.04, 14.3), plateau(
                     "three", 2.5, 20.0)), evidence=_by("identify", "rows"), claim=">"),
    ThesisNumber(f"F~_A at sigma~ = 2.5, F~_P = 20, three levels less one level ('all curves go close to each "
                 f"other' for sigma~ > 2), {_WHERE}", "Fig. 6-6 b, text (L1201)", 0.0,
                 plateau_difference(plateau("three", 2.5, 20.0), plateau("one", 2.5, 20.0)), evidence=_by("rows")),
    ThesisNumber(f"F~_A at sigma~ = 2.5, F~_P = 20, three levels less two levels ('all curves go close to each "
                 f"other' for sigma~ > 2), {_WHERE}", "Fig. 6-6 b, text (L1201)", 0.0,
                 plateau_difference(plateau("three", 2.5, 20.0), plateau("two", 2.5, 20.0)), evidence=_by("rows")),
    ThesisNumber(f"three levels less one level: sigma~ = 0.04 (F~_P = 14.3) less sigma~ = 2.5 (F~_P = 20) ('the "
                 f"difference of adhesive force among the three structures becomes smaller as roughness "
                 f"increases'), {_WHERE}", "Fig. 6-5, text (L1197)", 0.0,
                 plateau_difference(
                     plateau_difference(plateau("three", 0.04, 14.3), plateau("one", 0.04, 14.3)),
                     plateau_difference(plateau("three", 2.5, 20.0), plateau("one", 2.5, 20.0))),
                 evidence=_by("identify", "rows"), claim=">"),
    ThesisNumber(f"F~_A at sigma~ = 2.5, F~_P = 20, three levels over one level (k~1' < k~1: 'hierarchy results in "
                 f"smaller effective stiffness than stiffness k1'; one level's F~_A falls with k~1), {_WHERE}",
                 "Fig. 6-7 b, text (L1234)", 1.0, plateau_ratio(plateau("three", 2.5, 20.0), plateau("one", 2.5, 20.0)),
                 evidence=f"{TIED}; {_by('rows')}", claim=">", **_LEVEL),
    ThesisNumber(f"F~_A at k~1 = 5e-4 (k~2 = 9 k~1, k~3 = 20 k~1), sigma~ = 0.04, F~_P = 14.3, three levels over one "
                 f"('a very limited enhancement ... when stiffness is small'), {_WHERE}", "Fig. 6-8 a, text (L1240)",
                 1.0, plateau_ratio(plateau("three", 0.04, 14.3, k1=5e-4), plateau("one", 0.04, 14.3, k1=5e-4)),
                 evidence=f"{LEVEL_2}; {TIED}; {_by('stiffness')}", claim=">", **_LEVEL),
    ThesisNumber(f"F~_A at k~1 = 5e-2 (k~2 = 9 k~1, k~3 = 20 k~1), sigma~ = 0.04, F~_P = 14.3, three levels less one "
                 f"('this enhancement even disappears when stiffness is large'), {_WHERE}", "Fig. 6-8 a, text (L1240)",
                 0.0, plateau_difference(plateau("three", 0.04, 14.3, k1=5e-2), plateau("one", 0.04, 14.3, k1=5e-2)),
                 evidence=f"{LEVEL_2}; {_by('stiffness')}"),
    ThesisNumber(f"three-level F~_A at sigma~ = 0.04, F~_P = 14.3, k~3 = 2e-3 (0.1 k~3) over k~3 = 2e-2 ('a minor "
                 f"improvement for the structure with small k3'), {_WHERE}", "Fig. 6-8 b, text (L1249)", 1.0,
                 plateau_ratio(plateau("three", 0.04, 14.3, k3=2e-3), plateau("three", 0.04, 14.3)),
                 evidence=f"{TIED}; {_by('identify', 'stiffness')}", claim=">", **_LEVEL, untested=BY_SYMMETRY),
    ThesisNumber(f"three-level F~_A at k~3 = 2e-3 (0.1 k~3), sigma~ = 0.2 over sigma~ = 0.04, F~_P = 14.3 "
                 f"('roughness has little effect ... when sigma~ < 0.3'), {_WHERE}", "Fig. 6-8 b, text (L1249)", 1.0,
                 plateau_ratio(plateau("three", 0.2, 14.3, k3=2e-3), plateau("three", 0.04, 14.3, k3=2e-3)),
                 STATED_CHOICE, _held_out(_by("stiffness"))),
)
