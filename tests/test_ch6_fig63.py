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
from brushbem.studies._ch6_fig63 import (
    ELEMENTS,
    FIG63_NUMBERS,
    IDENTIFICATION,
    K3,
    N3_CANDIDATES,
    N3_IDENTIFIED,
    PILLARS,
    PLATEAUS,
    TIPS_PART,
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


def test_the_identification_table_scores_each_candidate_on_the_three_plateaus():
    values = {}
    for n3, (side, grid) in N3_CANDIDATES.items():
        for level, thesis in PLATEAUS.items():
            # candidate 4 is 10 % off on every plateau, 9 exact, 16 20 % off
            values[(level, n3, grid, 1e-3, 2e-2, 0.04, 14.3)] = thesis * {4: 1.1, 9: 1.0, 16: 0.8}[n3]
    text = identification(_tables(values))
    lines = {line.split(" |")[0].lstrip("| ").split(" ")[0]: line for line in text.splitlines() if line.startswith("| ")}
    assert "| 10.0 % | 2 |" in lines["4"] and "| 0.0 % | 2 |" in lines["9"] and "| 20.0 % | 2 |" in lines["16"]
    assert "1.760 ± 0.010" in lines["4"]  # one level: 1.6 x 1.1, seeds at -+ 0.01


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
        if cells and cells[0].split(" ")[0].isdigit() and cells[7].endswith("%"):
            scores[int(cells[0].split(" ")[0])] = float(cells[7].rstrip(" %"))
    assert scores and min(scores, key=scores.get) == N3_IDENTIFIED, scores


def test_the_sweep_files_are_those_the_generator_writes():
    """``docs/reproduction/make_fig63.py`` and the committed sweeps agree (a set's case: its full sweep's)."""
    make = runpy.run_path(str(ROOT / "docs" / "reproduction" / "make_fig63.py"))
    sweeps = ROOT / "src" / "brushbem" / "studies" / "sweeps"
    assert make["N3"] == N3_IDENTIFIED
    for level in make["LEVELS"]:
        for name, points in make["sets"](level).items():
            expected = make["text"](level, points, f"Named set {name!r} of hierarchy.fig63_{level}.toml")
            assert (sweeps / f"hierarchy.fig63_{level}.{name}.sampled.toml").read_text(encoding="utf-8") == expected
    assert (sweeps / "hierarchy.fig63_tips.toml").read_text(encoding="utf-8") == make["tips_text"]()


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
