"""Chapter 6 on the clustered layout of Fig. 6-3 (parts ``fig63_*``): one identification, held-out rows.

The rows are read from synthetic tables whose every number is known, so a row that read another
candidate's pillars, grid or stiffness would change value; the committed tables, once present, must
pick the identified N3 by the identification's own score.
"""

from __future__ import annotations

import math
import runpy
from pathlib import Path

import pandas as pd
import pytest

from brushbem.studies import get_study
from brushbem.studies._ch5_7 import FA, FP, SIG, K
from brushbem.studies._ch6_fig63 import TIP
from brushbem.studies._ch6_fig63 import (
    ELEMENTS,
    FIG63_NUMBERS,
    IDENTIFICATION,
    IDENTIFY_GRID,
    IDENTIFY_TIPS,
    K3,
    N3_CANDIDATES,
    N3_IDENTIFIED,
    PILLARS,
    PLATEAUS,
    TIPS_PART,
    TIPS_PARTS,
    discretisation,
    identification,
    plateau,
)
from brushbem.studies.verdicts import STATED_CHOICE, USED_TO_IDENTIFY

ROOT = Path(__file__).resolve().parents[1]


def test_the_identification_rows_say_used_to_identify_and_no_other_row_makes_its_own_choice():
    """The plateaus at sigma~ = 0.04 decide N3: they (and their ratio) are *used to identify*, naming the one
    identification; every other counted chapter-6 row that rests on a choice names that same identification."""
    counted = [n for n in get_study("hierarchy").numbers if not n.outside]
    identifying = [n for n in counted if n.verdict == USED_TO_IDENTIFY]
    assert {n.quantity.split(",")[0] for n in identifying} == {
        "plateau F~_A of one level", "plateau F~_A of two levels", "plateau F~_A of three levels",
        "plateau F~_A"}  # the last: three levels over one, the ratio of two of them
    assert all(n.evidence.startswith(IDENTIFICATION) for n in identifying)
    chosen = [n for n in counted if n.verdict == STATED_CHOICE]
    assert chosen and all(n.evidence.startswith(IDENTIFICATION) for n in chosen), \
        [n.quantity for n in chosen if not n.evidence.startswith(IDENTIFICATION)]
    # every counted row on the clustered layout is a row of the fig63 parts (the exact N = 1024 rows are outside)
    assert all(n in FIG63_NUMBERS for n in counted if "clustered" in n.quantity)


def _tables(values: dict[tuple, float]) -> dict[str, pd.DataFrame]:
    """Tables of the fig63 parts: ``values[(level, n3, elements, k1, k3, sigma~, F~_P)]`` -> F~_A, two seeds
    at value -+ 0.01."""
    rows: dict[str, list[dict]] = {}
    for (level, n3, elements, k1, k3, sigma, preload), value in values.items():
        for realization, shift in ((0, -0.01), (1, 0.01)):
            row = {"status": "finished", "realization": realization, PILLARS: N3_CANDIDATES[n3][0],
                   ELEMENTS: elements, K: k1, SIG: sigma * 1.02, FP: preload * 0.98, FA: value + shift,
                   "normalized.separation_displacement_by_rigid_brush": -value}
            if level == "three":
                row[K3] = k3
            rows.setdefault(f"fig63_{level}", []).append(row)
    return {part: pd.DataFrame(r) for part, r in rows.items()}


def test_a_row_reads_only_the_identified_candidate_at_its_grid_and_stiffness():
    _, grid = N3_CANDIDATES[N3_IDENTIFIED]
    tables = _tables({("three", N3_IDENTIFIED, grid, 1e-3, 2e-2, 0.04, 14.3): 1.8,
                      ("three", N3_IDENTIFIED, 2 * grid, 1e-3, 2e-2, 0.04, 14.3): 1.9,  # the mesh set
                      ("three", N3_IDENTIFIED, grid, 1e-3, 2e-3, 0.04, 14.3): 1.85,  # 0.1 k~3
                      ("three", N3_IDENTIFIED, grid, 5e-2, 1.0, 0.04, 14.3): 1.2,  # k~1 = 5e-2
                      ("three", 16, N3_CANDIDATES[16][1], 1e-3, 2e-2, 0.04, 14.3): 1.95})
    assert plateau("three", 0.04, 14.3)(tables) == pytest.approx(1.8)
    assert plateau("three", 0.04, 14.3, k3=2e-3)(tables) == pytest.approx(1.85)
    assert plateau("three", 0.04, 14.3, k1=5e-2)(tables) == pytest.approx(1.2)
    assert plateau("three", 0.04, 14.3, n3=16)(tables) == pytest.approx(1.95)
    assert plateau("three", 0.04, 14.3, elements=2 * grid)(tables) == pytest.approx(1.9)
    assert math.isnan(plateau("three", 1.6, 1.0)(tables))  # no such point: never read off another


def test_the_identification_table_scores_each_candidate_at_both_resolutions_and_the_resolved_tips_decide():
    values = {}
    for n3, (side, grid) in N3_CANDIDATES.items():
        for level, thesis in PLATEAUS.items():
            # on the rows' grid candidate 4 is 10 % off on every plateau, 9 exact, 16 20 % off
            values[(level, n3, grid, 1e-3, 2e-2, 0.04, 14.3)] = thesis * {4: 1.1, 9: 1.0, 16: 0.8}[n3]
    tables = _tables(values)
    # with the tips resolved (set identify_tips): 4 is 2 % off, 9 6 %, 16 not run; and a case of another tips'
    # resolution and one of another global grid, which the scores never read
    point = {"status": "finished", K: 1e-3, K3: 2e-2, SIG: 0.04 * 1.02, FP: 14.3 * 0.98}
    for level, thesis in PLATEAUS.items():
        rows = [{**point, "realization": r, PILLARS: N3_CANDIDATES[n3][0], ELEMENTS: IDENTIFY_GRID,
                 TIP: IDENTIFY_TIPS, FA: thesis * factor + shift}
                for n3, factor in ((4, 1.02), (9, 1.06)) for r, shift in ((0, -0.01), (1, 0.01))]
        rows += [{**point, "realization": r, PILLARS: 40, ELEMENTS: IDENTIFY_GRID, TIP: 13.5, FA: thesis * 1.025}
                 for r in (0, 1)]
        rows += [{**point, "realization": r, PILLARS: 40, ELEMENTS: 1024, TIP: IDENTIFY_TIPS, FA: thesis * 1.015}
                 for r in (0, 1)]
        tables[TIPS_PARTS[level]] = pd.DataFrame(rows)
    text = identification(tables)
    rows = [line for line in text.splitlines() if line[:3].strip("| ").isdigit()]
    coarse = {line[2:].split(" ")[0]: line for line in rows if "the grid's" in line}
    fine = {line[2:].split(" ")[0]: line for line in rows if "own raster" in line}
    # seeds at -+ 0.01: each plateau's standard error 0.01; the score's 0.01 / 3 x sqrt(sum 1 / thesis^2) = 0.3 %
    assert "| 10.0 ± 0.3 % | 2, 2, 2 |" in coarse["4"] and "| 0.0 % | 2, 2, 2 |" in coarse["9"]
    assert "| 20.0 ± 0.3 % | 2, 2, 2 |" in coarse["16"] and "1.760 ± 0.010" in coarse["4"]
    assert "| 2.0 ± 0.3 % | 2, 2, 2 |" in fine["4"] and "| 6.0 ± 0.3 % | 2, 2, 2 |" in fine["9"]
    assert "| not run | not run | not run | — | — | 0, 0, 0 |" in fine["16"]
    assert "decide: there N3 = 4 scores lowest, 4.0 points below N3 = 9's score (± 0.5, the seeds)." in text
    # the tips at 13.5 (+0.5 % over 9: a band of ±0.24 %) and the global grid N = 1024 (-0.49 %) bound a score's
    # move by 0.49 % x 1.06: 0.52 points, a margin of 4.0 exceeds twice that and two standard errors
    assert "within ±0.24 %" in text and "within 0.49 %" in text and "by at most 0.52 points" in text
    assert "the identification holds at this resolution" in text
    # on the rows' grid the tips put +7.6 % (2.09 against 1.943): 8.3 points on a score, more than half of 10.0
    assert "N3 = 9 scores lowest, 10.0 points below N3 = 4" in text and "so that resolution does not decide" in text


def test_the_committed_tables_identify_the_declared_n3():
    """The identified N3 has the smallest score on the committed tables of the identification set."""
    from brushbem.reproduction.tables import load_tables

    folder = ROOT / "docs" / "reproduction" / "hierarchy"
    if not (folder / "fig63_three.csv").is_file():
        pytest.skip("the identification set has not been exported")
    _, tables = load_tables(folder)
    scores = {}
    for line in identification(tables).splitlines():
        cells = [c.strip() for c in line.strip("|").split("|")]
        # the deciding resolution: the tips on rasters of their own
        if cells and cells[0].split(" ")[0].isdigit() and "own raster" in cells[3] and cells[8].endswith("%"):
            floor = cells[8].startswith("≥")  # a candidate not run at every level: its score's floor
            scores[int(cells[0].split(" ")[0])] = (float(cells[8].lstrip("≥ ").split(" ")[0]), floor)
    assert scores and not scores[N3_IDENTIFIED][1], scores  # the identified N3 ran at every level
    assert min(scores, key=lambda n3: scores[n3][0]) == N3_IDENTIFIED, scores


def test_the_sweep_files_are_those_the_generator_writes():
    """``docs/reproduction/make_fig63.py`` and the committed sweeps agree (a set's case: its full sweep's)."""
    make = runpy.run_path(str(ROOT / "docs" / "reproduction" / "make_fig63.py"))
    sweeps = ROOT / "src" / "brushbem" / "studies" / "sweeps"
    assert make["N3"] == N3_IDENTIFIED
    for level in make["LEVELS"]:
        for name, points in make["sets"](level).items():
            expected = make["text"](level, points, f"Named set {name!r} of hierarchy.fig63_{level}.toml",
                                     make["REALIZATIONS"].get(level, 10))
            assert (sweeps / f"hierarchy.fig63_{level}.{name}.sampled.toml").read_text(encoding="utf-8") == expected
    for level, part in make["TIPS_PARTS"].items():
        named = make["tip_sets"](level)
        for name, points in named.items():
            expected = make["tips_text"](level, points, f"Named set {name!r} of hierarchy.{part}.toml")
            assert (sweeps / f"hierarchy.{part}.{name}.sampled.toml").read_text(encoding="utf-8") == expected
        every = [p for i, p in enumerate(sum(named.values(), [])) if p not in sum(named.values(), [])[:i]]
        assert (sweeps / f"hierarchy.{part}.toml").read_text(encoding="utf-8") == make["tips_text"](
            level, every, "Every point of the named sets of the tips' part")


def test_the_named_sets_carry_every_row_and_the_identification_set_its_rows():
    """Tables with one finished row per case of the fig63 set files (sigma~ and F~_P from the nominal d_c and
    F_c of the headers, made-up forces) give every fig63 row a value; the identification set alone gives
    exactly the rows that read only the plateaus at sigma~ = 0.04 (never another point)."""
    import tomllib

    f_c, d_c = 0.00331177, 0.00293498
    sweeps = ROOT / "src" / "brushbem" / "studies" / "sweeps"
    factor = {"one": 1.0, "two": 1.5, "three": 2.0}

    def tables(*names: str) -> dict[str, pd.DataFrame]:
        found = {}
        for level in factor:
            rows = []
            for name in names:
                path = sweeps / f"hierarchy.fig63_{level}.{name}.sampled.toml"
                if not path.is_file():
                    continue
                spec = tomllib.loads(path.read_text(encoding="utf-8"))
                for realization in range(spec["realizations"]):
                    for values in zip(*spec["sweep"].values()):
                        point = dict(zip(spec["sweep"], values))
                        rows.append({"status": "finished", "realization": realization, **point,
                                     SIG: point["indenter.roughness.sigma"] / d_c,
                                     FP: point["protocol.preload_force"] / f_c,
                                     FA: factor[level] * (1 + realization) / (1 + point["indenter.roughness.sigma"]),
                                     "normalized.separation_displacement_by_rigid_brush": -factor[level]})
            found[f"fig63_{level}"] = pd.DataFrame(rows)
        return found

    every = tables("identify", "identify16", "mesh", "rows", "stiffness")
    assert all(math.isfinite(n.compute(every)) for n in FIG63_NUMBERS), \
        [n.quantity for n in FIG63_NUMBERS if not math.isfinite(n.compute(every))]
    alone = tables("identify")
    plateau_only = {n.quantity for n in FIG63_NUMBERS if math.isfinite(n.compute(alone))}
    assert plateau_only == {n.quantity for n in FIG63_NUMBERS
                            if n.verdict == USED_TO_IDENTIFY or n.quantity.startswith("separation displacement")}


def test_the_discretisation_table_reads_the_tips_refinement_at_the_rows_grid_on_the_tips_seeds():
    """The three-level plateau on the global grids of set mesh and, on the rows' grid, with the tips on rasters of
    their own (part fig63_tips): the finest tips' value with half the tips' spread, the rows' grid's distance from
    it; only the seeds the tips ran are read, and the other candidates' and points' rows never."""
    point = {SIG: 0.04, FP: 14.3, PILLARS: 40, K: 1e-3, K3: 2e-2, "status": "finished"}
    three = pd.DataFrame([{**point, ELEMENTS: n, FA: fa, "seed": seed}
                          for n, fa, seed in ((1024, 1.70, 7), (2048, 1.80, 7), (2048, 1.90, 8), (4096, 1.74, 7),
                                              (3072, 9.0, 7))]
                         + [{**point, ELEMENTS: 2048, PILLARS: 60, FA: 9.0, "seed": 7},
                            {**point, ELEMENTS: 2048, FP: 1.0, SIG: 1.6, FA: 9.0, "seed": 7}])
    tips = pd.DataFrame([{**point, ELEMENTS: 2048, "protocol.pillar_tip_resolution": t, FA: fa, "seed": 7}
                         for t, fa in ((9.0, 1.74), (13.5, 1.72), (18.0, 1.73))])
    assert discretisation({"fig63_three": three}) != []  # the global grids alone: their table, no estimate
    text = "\n".join(discretisation({"fig63_three": three, TIPS_PART: tips}))
    assert "| global grid | 2048 | 4.5 | 1.8000 | 1 |" in text  # seed 8 (no tips) left out
    assert "| tips' own raster | 2048 | 18 | 1.7300 | 1 |" in text and "9.0000" not in text
    # The band of 1.74, 1.72, 1.73: 1.73 +- 0.01; 1.80 / 1.73 - 1 = +4.0 %.
    assert "1.7300 ± 0.0100" in text and "1.8000) lies +4.0 % from it" in text
    # A seed without every resolution (stopped inside it) is left out: its 9 elements a radius alone is not read.
    partial = pd.concat([tips, tips.iloc[:1].assign(seed=8, **{FA: 9.0})])
    assert "9.0000" not in "\n".join(discretisation({"fig63_three": three, TIPS_PART: partial}))


def test_the_tie_table_compares_the_model_and_the_exact_path_on_the_same_seeds_and_grid():
    """Each level on the seeds both methods ran at that N, each ratio of levels on the seeds both levels have;
    the exact parts' rows (`part_plateau`) read their grid N = 1024 only, never the set mesh's N = 1536."""
    from brushbem.studies._ch5_7 import PRELOAD, SIGMA
    from brushbem.studies._ch6_fig63 import CLUSTERED_GRID, part_plateau, tie_table

    point = {SIG: 0.04, FP: 14.3, SIGMA: 1.2e-4, PRELOAD: 0.047, K: 1e-3, K3: 2e-2, "status": "finished"}
    model = {"two": [(1024, 0, 1.70), (1024, 1, 1.72), (1536, 0, 1.75)], "three": [(1024, 0, 1.734), (1536, 0, 1.80)]}
    # seed 1's N unrecorded (a case from before the part swept the grid): the base grid, 1024
    exact = {"two": [(1024, 0, 1.7356), (math.nan, 1, 1.7254), (1536, 0, 1.76)],
             "three": [(1024, 0, 1.7354), (1024, 2, 9.0), (1536, 0, 1.78)]}
    tables = {f"fig63_{level}": pd.DataFrame([{**point, PILLARS: 40, ELEMENTS: n, "realization": r, FA: fa}
                                              for n, r, fa in rows]) for level, rows in model.items()}
    tables |= {f"clustered_{level}": pd.DataFrame([{**point, ELEMENTS: n, "realization": r, FA: fa}
                                                   for n, r, fa in rows]) for level, rows in exact.items()}
    text = "\n".join(tie_table(tables))
    # two levels at N = 1024 on seeds 0 and 1: 1.71 against 1.7305; three on seed 0 only (seed 2 has no model case)
    assert "| 1024 | 2.25 | two | 1.7100 | 1.7305 | -1.18 % | 2 |" in text
    assert "| 1024 | 2.25 | three | 1.7340 | 1.7354 | -0.08 % | 1 |" in text
    # three over two on seed 0 alone: (1.734 / 1.70) / (1.7354 / 1.7356) - 1 = +2.01 %
    assert "| 1024 | 2.25 | three over two | 1.0200 | 0.9999 | +2.01 % | 1 |" in text
    assert "| 1536 | 3.375 | two | 1.7500 | 1.7600 | -0.57 % | 1 |" in text
    assert CLUSTERED_GRID == 1024
    # the exact row's mean over its seeds at N = 1024 (1.7356, 1.7254), never N = 1536's 1.76
    assert part_plateau("clustered_two", 0.04)(tables) == pytest.approx((1.7356 + 1.7254) / 2)
