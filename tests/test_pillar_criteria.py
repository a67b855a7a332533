"""What ``docs/pillars/criteria.csv`` (``docs/pillars/criteria.py``) claims about the tips' criteria at coarse tips.

The pillar model's F_A on the 8 x 8 validation families against the exact path's extrapolated fine-grid value,
with three criteria on the same rasters (the raster's Sigma_c, calibrated to Kendall's force, per element):
the claims are recomputed from the committed table, and one row of each part is run again.
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest

HERE = Path(__file__).resolve().parents[1] / "docs" / "pillars"
TABLE = HERE / "criteria.csv"


def _rows(part: str) -> list[dict]:
    with TABLE.open(newline="") as stream:
        return [line for line in csv.DictReader(stream) if line["part"] == part]


def test_the_per_element_criterion_tends_below_the_reference():
    """On the flat brush at 14.4 elements per radius the per-element criterion lies below the old reference
    (``tips_extrapolated.csv``) on every placement, by more than 0.9 % (k~ = 10: -1.8 .. -2.3 %, 1e-5: -1.0 ..
    -1.8 %), and further below than at 7.2: it takes a tip off where the continuum starts its peel, and the peel
    carries load; its limit is the continuum's first point (on the continuum limit at k~ = 1e-5 these placements
    are -0.2 .. +0.6 %, inside its bounds: ``docs/pillars/rereferenced.csv``, ``tests/test_pillar_limit.py``)."""
    rows = _rows("placement")
    for stiffness in ("10", "1e-05"):
        errors = {q: np.array([float(r["error"]) for r in rows
                               if r["stiffness_ratio"] == stiffness and r["tip_elements_per_radius"] == q])
                  for q in ("7.222", "14.443")}
        assert errors["14.443"].size == 6 and errors["14.443"].max() < -0.009
        assert errors["14.443"].mean() < errors["7.222"].mean() < -0.01


def test_the_per_element_criterion_converges_below_the_reference():
    """At 28.9 elements per radius (the flat brush's own raster) the per-element criterion is still -2.4 / -1.9 %
    (k~ = 10 / 1e-5) off, where the calibrated one (``placement.csv``, the same raster) is +0.6 / +0.7 %: the two
    criteria part by about 2 % at the finest tips, the per-element one below the old reference
    (``tips_extrapolated.csv``)."""
    from test_pillar_tips import _pillars_script

    rows = _rows("finest")
    assert len(rows) == 2
    calibrated = {(r["stiffness_ratio"], r["shift_y"], r["shift_x"]): float(r["calibrated_adhesive_force"])
                  for r in _pillars_script("placement.py", "pillar_placement_table").load()
                  if r["family"] == "flat" and r["tip_factor"] == "8"}
    for row in rows:
        force = float(row["adhesive_force"])
        assert float(row["error"]) < -0.015
        other = calibrated[(row["stiffness_ratio"], "0", "0")]
        assert abs(other / (force / (1 + float(row["error"]))) - 1) < 0.008
        assert other / force - 1 > 0.02


def test_a_canonical_raster_is_no_converged_tip():
    """Every tip on one raster centred on its pillar (an element's centre or corner), at 2.9-4.1 elements per
    radius: the error spreads over more than 10 points with the raster (the raster's Sigma_c and calibrated),
    and about 7 with the per-element criterion, whose error falls with the raster's area over the circle's
    (correlation below -0.8): at 3-4 elements per radius the raster's size, not only its criterion, sets F_A."""
    rows = _rows("canonical")
    assert len(rows) == 5 * 6 * 2 * 3
    for criterion, span in (("plain", 0.10), ("calibrated", 0.10), ("per_element", 0.05)):
        errors = np.array([float(r["error"]) for r in rows if r["criterion"] == criterion])
        assert np.ptp(errors) > span
    chosen = [r for r in rows if r["criterion"] == "per_element"]
    area = np.array([float(r["area_ratio"]) for r in chosen])
    errors = np.array([float(r["error"]) for r in chosen])
    assert np.corrcoef(area, errors)[0, 1] < -0.8
    assert np.abs(errors).max() > 0.04


def test_no_criterion_at_coarse_tips_is_within_one_percent_on_every_family():
    """The six cases with a reference, each on its own raster: at 3.6 and at 7.2 elements per radius every
    criterion misses 1 % on at least one of them (the default, plain at 3.6, +2.8 .. +7.8 %)."""
    rows = _rows("families")
    assert len(rows) == 6 * 2 * 3
    for q in ("3.611", "7.222"):
        for criterion in ("plain", "calibrated", "per_element"):
            errors = [float(r["error"]) for r in rows if r["tip_elements_per_radius"] == q
                      and r["criterion"] == criterion]
            assert len(errors) == 6 and max(abs(e) for e in errors) > 0.01
    default = [float(r["error"]) for r in rows if r["tip_elements_per_radius"] == "3.611" and r["criterion"] == "plain"]
    assert 0.027 < min(default) and max(default) < 0.079


@pytest.mark.parametrize("part", ["placement", "canonical"])
def test_one_row_of_each_part_recomputes(part):
    """One row of each part, run again (the flat brush moved by (0.13, 0.37) elements, per element, k~ = 10;
    the flat brush at a pitch of 15 elements centred on elements, calibrated, k~ = 1e-5): to 1e-6."""
    from test_pillar_tips import _pillars_script

    criteria = _pillars_script("criteria.py", "pillar_criteria_table")
    placement, validation = criteria.placement, criteria.validation
    limits = criteria.references()
    if part == "placement":
        stiffness, criterion, shift = 10.0, "per_element", (0.13, 0.37)
        case = placement.shifted("flat", 8, stiffness, 1, shift)
        row = next(r for r in _rows(part) if r["stiffness_ratio"] == "10" and r["tip_factor"] == "1"
                   and float(r["shift_y"]) == shift[0] and float(r["shift_x"]) == shift[1])
    else:
        stiffness, criterion = 1e-5, "calibrated"
        case = criteria.canonical_case("flat", stiffness, 15, "element")
        row = next(r for r in _rows(part) if r["family"] == "flat" and r["stiffness_ratio"] == "1e-05"
                   and r["pitch_elements"] == "15" and r["centring"] == "element" and r["criterion"] == criterion)
    _, preload = validation.problem("flat", 8, stiffness)
    force, _ = criteria.pull_off(case, preload, criterion)
    assert force == pytest.approx(float(row["adhesive_force"]), rel=1e-6)
    assert force / limits[("flat", stiffness)] - 1 == pytest.approx(float(row["error"]), abs=1e-6)
