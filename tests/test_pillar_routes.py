"""What ``docs/pillars/routes.csv`` (``docs/pillars/routes.py``) claims: no small-brush correction holds 1 % on every raster.

The 8 x 8 flat brush on the twelve canonical rasters of ``criteria.py`` at k~ = 10 and 1e-5 (24 cases), corrected
by the routes of ``routes.py``, against `routes.references` (the continuum limit at k~ = 1e-5, the exact path's
extrapolated value at 10).  The claims are recomputed from the committed table; one coarse row is run again (the
fine ones take 15-118 CPU-s).
"""

from __future__ import annotations

import pytest

ROUTES = ("proxy", "own", "own_debiased", "inv_2_4", "inv_3_4", "edge_3_4")


def _rows(name: str) -> list[dict]:
    from test_pillar_tips import _pillars_table

    return _pillars_table(name)


@pytest.fixture(scope="module")
def script():
    from test_pillar_tips import _pillars_script

    return _pillars_script("routes.py", "pillar_routes_table")


def test_the_summary_is_the_tables(script):
    """``routes_summary.csv`` is ``summary`` of ``routes.csv`` (four digits written: 1e-3 relative, 1e-6 absolute
    on errors of a few per cent)."""
    computed = script.summary(_rows("routes.csv"))
    committed = _rows("routes_summary.csv")
    assert len(computed) == len(committed) == 24
    for mine, theirs in zip(computed, committed):
        for name in script.SUMMARY_FIELDS[3:]:
            if theirs[name] == "":
                assert mine[name] == ""
            else:
                assert mine[name] == pytest.approx(float(theirs[name]), rel=1e-3, abs=1e-6)


def test_no_route_holds_one_percent_on_every_raster():
    """Every route misses 1 % somewhere; the best, the proxy's fine side on each raster's own tips divided by its
    bias on the families, is -1.10 .. +1.72 % (17 of 24, 8 of the 12 at k~ = 1e-5), and the proxy itself is within
    1 % on 10 (against ``continuum_limit.csv``'s middle at 1e-5, the neighbours' field of the right sign)."""
    lines = _rows("routes_summary.csv")
    within = {name: sum(abs(float(line[name])) < 0.01 for line in lines) for name in ROUTES}
    assert all(count < 24 for count in within.values())
    assert within["proxy"] == 10 and within["own_debiased"] == 17
    assert max(within.values()) == within["own_debiased"]
    soft = [line for line in lines if line["stiffness_ratio"] == "1e-05"]
    assert max(sum(abs(float(line[name])) < 0.01 for line in soft) for name in ROUTES) == 8
    debiased = [float(line["own_debiased"]) for line in lines]
    assert min(debiased) == pytest.approx(-0.0110, abs=5e-5) and max(debiased) == pytest.approx(0.01715, abs=5e-5)


def test_no_route_holds_one_percent_on_the_families_own_raster(script):
    """On the families' own raster (``proxy.csv``): the default +2.8 .. +8.4 %, the proxy +1.3 % on the lattices at
    k~ = 1e-5, and the debiased proxy (its bias fitted on those lattices) -0.4 .. +0.2 % there but -1.5 % on the
    random brush: every route misses 1 % on some family."""
    lines = script.families()
    assert len(lines) == 6
    for name in ("plain", "proxy", "own_debiased"):
        assert max(abs(line[name]) for line in lines) > 0.01
    plain = [line["plain"] for line in lines]
    assert min(plain) == pytest.approx(0.0283, abs=5e-4) and max(plain) == pytest.approx(0.0837, abs=5e-4)
    debiased = {(line["family"], line["stiffness_ratio"]): line["own_debiased"] for line in lines}
    assert debiased[("random", 1e-5)] == pytest.approx(-0.0154, abs=5e-4)
    assert all(abs(value) < 0.01 for key, value in debiased.items() if key[0] != "random")


def test_the_reference_at_soft_springs_is_the_continuum_limit_within_its_stated_error(script):
    """At k~ = 1e-5 the routes are judged against ``continuum_limit.csv``: `tilted.limit` of ``tilted_brush.csv``
    (to its seven digits), between the continuum's first point (``continuum_reference.csv``) and the weakest tip's
    capacity at 40 elements per radius (the middle of an edge, 0-3, in the neighbours' field of the right sign);
    its error column is the half-width, 1.6 %, and the exact path's first-order extrapolation lies inside."""
    from test_pillar_tips import _pillars_script

    tilted = _pillars_script("tilted.py", "pillar_routes_tilted")
    (mine,) = tilted.limit(_rows("tilted_brush.csv"))
    (theirs,) = _rows("continuum_limit.csv")
    for name in ("first_point_adhesive_force", "tip_adhesive_force", "adhesive_force", "error"):
        assert mine[name] == pytest.approx(float(theirs[name]), rel=1e-6)
    lower, upper = float(theirs["first_point_adhesive_force"]), float(theirs["tip_adhesive_force"])
    (first,) = [r for r in _rows("continuum_reference.csv") if r["pillars_per_side"] == "8"
                and r["stiffness_ratio"] == "1e-05"]
    assert lower == pytest.approx(float(first["adhesive_force"]), rel=1e-7) and lower < upper
    middle = float(theirs["adhesive_force"])
    assert middle == pytest.approx((lower + upper) / 2, rel=1e-6)  # seven digits written
    assert float(theirs["error"]) == pytest.approx((upper - lower) / 2 / middle, abs=1e-6)  # of written bounds
    assert float(theirs["error"]) == pytest.approx(0.0159, abs=2e-4)
    assert lower < float(theirs["extrapolated_exact"]) < upper
    assert script.references()[("flat", 1e-5)] == pytest.approx(middle, rel=1e-12)


def test_the_miss_has_two_parts_of_about_one_percent():
    """Apart from the reference: the coarse F(8 x 8) / F(4 x 4) moves with the raster by more than 2 % at each k~,
    the coarse 8 x 8 error over the proxy's (each against its own fine tips) is off 1 by 0.8 .. 1.1 % on all four
    rasters measured; the proxy's fine F_A on its own fine rasters spreads by more than 1.5 % at each k~; the 8 x 8
    brush at about 29 per radius is above the reference by up to 1.7 % and is not monotone between 14 and 29."""
    lines = _rows("routes_summary.csv")
    for stiffness in ("10", "1e-05"):
        sizes = [float(line["size_ratio_8_4"]) for line in lines if line["stiffness_ratio"] == stiffness]
        assert max(sizes) / min(sizes) - 1 > 0.02
        fine = [float(r["adhesive_force"]) for r in _rows("routes.csv")
                if r["part"] == "own_fine" and r["stiffness_ratio"] == stiffness]
        assert len(fine) == 12 and max(fine) / min(fine) - 1 > 0.015
    measured = [line for line in lines if line["transfer"] != ""]
    assert len(measured) == 4
    assert all(0.007 < abs(float(line["transfer"]) - 1) < 0.012 for line in measured)
    errors = [float(line["fine_error"]) for line in measured]
    assert max(errors) > 0.015 and min(errors) > 0
    assert any((float(line["mid_error"]) - float(line["fine_error"])) * (float(line["plain"]) - float(line["mid_error"]))
               < 0 for line in measured)


def test_rasters_that_are_one_raster_give_one_fine_answer():
    """Pitches 14 x 9 and 18 x 7 elements are one fine raster (126 a pitch) on the same centring: the proxy's fine
    F_A is the same to the digits written (a check that the fine side is the raster's subdivision)."""
    fine = {(r["stiffness_ratio"], r["pitch_elements"], r["centring"]): float(r["adhesive_force"])
            for r in _rows("routes.csv") if r["part"] == "own_fine"}
    for stiffness in ("10", "1e-05"):
        for centring in ("element", "corner"):
            assert fine[(stiffness, "14", centring)] == pytest.approx(fine[(stiffness, "18", centring)], rel=1e-6)


def test_one_coarse_row_recomputes(script):
    """The flat 8 x 8 brush at k~ = 10 on the families' raster (pitch 16, corner): the table's F_A and
    ``proxy.csv``'s default, to 1e-6."""
    row = script.measure("sizes", 10.0, 16, "corner", 8, 0.0)
    committed = next(r for r in _rows("routes.csv") if r["part"] == "sizes" and r["stiffness_ratio"] == "10"
                     and r["pitch_elements"] == "16" and r["centring"] == "corner" and r["pillars_per_side"] == "8")
    assert row["adhesive_force"] == pytest.approx(float(committed["adhesive_force"]), rel=1e-6)
    proxy = next(r for r in _rows("proxy.csv") if r["family"] == "flat" and r["stiffness_ratio"] == "10"
                 and r["proxy_pillars_per_side"] == "4")
    assert row["adhesive_force"] == pytest.approx(float(proxy["brush_adhesive_force"]), rel=1e-6)
