"""What ``docs/pillars/periodic.csv`` (``docs/pillars/periodic.py``) claims: a tip in an infinite lattice of
identical tips has the lone tip's raster error, not the small brush's.

The proxy's factor on the lattice families (a 4 x 4 brush at 28.9 over 3.6 elements per radius, 0.9348,
``proxy.csv``) against the same factor of a periodic cell of one tip (0.9648) and the lone tip's F_K / F_R
(0.9598).  The coarse rows and the 14.4-elements row are recomputed (0.7 CPU-s; the 28.9 row takes 11).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from brushbem.physics.adhesion import critical_stress
from brushbem.physics.theory.punch import kendall_force
from brushbem.pillars.calibration import lone_pull_off
from brushbem.pillars.modes import MODES, Bases



def _rows(name: str) -> list[dict]:
    from test_pillar_tips import _pillars_table

    return _pillars_table(name)


@pytest.fixture(scope="module")
def script():
    from test_pillar_tips import _pillars_script

    return _pillars_script("periodic.py", "pillar_periodic_table")


def _family(factor: int) -> dict:
    return next(r for r in _rows("periodic.csv") if r["part"] == "family" and r["tip_factor"] == str(factor))


def test_the_lattice_cell_does_not_give_the_small_brushs_correction():
    """On the families' raster (3.6 elements per radius) the periodic cell's factor is 0.9648, the 4 x 4 proxy's
    0.9348 at both stiffnesses: 3.2 % apart, ten times the 0.3 % a lattice calibration would need.  It is the lone
    tip's factor to 0.6 % (0.9598): neighbours that pull alike hardly change a tip's raster error."""
    periodic = float(_family(1)["ratio"])
    lone = float(_family(1)["lone_ratio"])
    proxies = [float(r["proxy_fine_adhesive_force"]) / float(r["proxy_coarse_adhesive_force"])
               for r in _rows("proxy.csv") if r["proxy_pillars_per_side"] == "4" and r["family"] == "flat"]
    assert len(proxies) == 2
    for proxy in proxies:
        assert periodic / proxy - 1 > 0.03
    assert abs(periodic / lone - 1) < 0.006
    # Every canonical raster: the cell's factor follows the lone tip's (to 1.2 %), not what the 8 x 8 brush on that
    # raster needs (F_ref / F_plain, criteria.csv), which it misses by up to 19 %.
    canonical = [r for r in _rows("periodic.csv") if r["part"] == "canonical"]
    assert len(canonical) == 12
    assert max(abs(float(r["ratio"]) / float(r["lone_ratio"]) - 1) for r in canonical) < 0.012
    assert max(abs(float(r["ratio"]) / float(r["brush_needed_ratio"]) - 1) for r in canonical) > 0.15


def test_the_fine_cells_agree():
    """The calibrated cell at 14.4 and 28.9 elements per radius: one F_A per tip to 0.05 % (the limit the factor
    divides by), 2.3 % above Kendall's force of the lone tip."""
    fine, finer = (float(_family(f)["adhesive_force_calibrated"]) for f in (4, 8))
    assert abs(fine / finer - 1) < 5e-4
    kendall = kendall_force(0.125 * math.sqrt(0.16 / math.pi), contact_modulus=1.0, work_of_adhesion=1e-4)
    assert 0.02 < finer / kendall - 1 < 0.026


def _array(factor: int) -> dict:
    return next(r for r in _rows("periodic.csv") if r["part"] == "array" and r["tip_factor"] == str(factor))


def test_a_rigid_two_by_two_array_gives_the_proxys_correction(script):
    """The rigid 2 x 2 array by the exact event path of its elements (no pillar model; every tip at the array's
    edge): at 3.6 elements per radius the 2 x 2 proxy's F_A to 0.3 % (measured +0.13 %; the pillar model's
    validation tolerance), at 14.4 calibrated its 28.9 one to 0.3 % (-0.18 %), and its factor 0.9358 the
    proxy's 0.9387 to 0.5 %, the periodic cell's 0.9648 not (3.0 % apart): the correction is the finite array's,
    which a cell of tips that all pull alike does not hold."""
    proxy = next(r for r in _rows("proxy.csv") if r["family"] == "flat" and r["stiffness_ratio"] == "10"
                 and r["proxy_pillars_per_side"] == "2")
    coarse, fine = _array(1), _array(4)
    assert 4 * float(coarse["adhesive_force_plain"]) == pytest.approx(
        float(proxy["proxy_coarse_adhesive_force"]), rel=3e-3)
    assert 4 * float(fine["adhesive_force_calibrated"]) == pytest.approx(
        float(proxy["proxy_fine_adhesive_force"]), rel=3e-3)
    ratio = float(coarse["ratio"])
    assert ratio == pytest.approx(float(coarse["proxy_ratio"]), rel=5e-3)
    assert float(_family(1)["ratio"]) / ratio - 1 > 0.025
    now = script.array(16)
    assert now["adhesive_force_plain"] == pytest.approx(float(coarse["adhesive_force_plain"]), rel=1e-5)


def test_neither_layout_is_a_raster_independent_calibration():
    """On the twelve canonical rasters (2.9 to 4.1 elements per radius) the 2 x 2 array's factor misses what the
    8 x 8 brush needs by -0.7 .. +10 % (the cell's by up to 19 %); only on the families' raster (+0.85 %) and two
    others is it within 1 %."""
    rows = [r for r in _rows("periodic.csv") if r["part"] == "array_canonical"]
    assert len(rows) == 12
    misses = [float(r["ratio"]) / float(r["brush_needed_ratio"]) - 1 for r in rows]
    assert max(misses) > 0.09 and min(misses) < 0
    within = [(r["pitch_elements"], r["centring"]) for r, miss in zip(rows, misses) if abs(miss) < 0.01]
    assert ("16", "corner") in within and len(within) <= 5


def test_the_four_by_four_proxy_transfers_across_rasters_within_two_and_a_half_percent(script):
    """The layout that transfers is a brush: the 4 x 4 proxy on every canonical raster (k~ = 10 and 1e-5), against
    its one 28.9-elements F_A, gives the 8 x 8 brush's need to -0.6 .. +2.3 % (within 1 % on 11 of 24), where the
    cell misses by up to 19 % and the 2 x 2 array by up to 10 %."""
    rows = [r for r in _rows("periodic.csv") if r["part"] == "proxy_canonical"]
    assert len(rows) == 24
    misses = [float(r["ratio"]) / float(r["brush_needed_ratio"]) - 1 for r in rows]
    assert -0.01 < min(misses) and max(misses) < 0.025
    assert 0.02 < max(misses)  # not within 1 % on every raster
    row = next(r for r in rows if r["stiffness_ratio"] == "10" and r["pitch_elements"] == "14"
               and r["centring"] == "element")
    fine = float(row["ratio"]) * 16 * float(row["adhesive_force_plain"])
    now = script.proxy_canonical(10.0, 14, "element", fine)
    assert now["adhesive_force_plain"] == pytest.approx(float(row["adhesive_force_plain"]), rel=1e-6)


def test_rows_recompute(script):
    """The families' raster and its tips at 14.4 elements per radius, to 1e-6."""
    for factor in (1, 4):
        row = _family(factor)
        now = script.raster(16 * factor, "corner")
        for name in ("lone_error", "adhesive_force_plain", "adhesive_force_calibrated"):
            assert now[name] == pytest.approx(float(row[name]), rel=1e-5, abs=1e-9), name
        assert now["footprint_elements"] == int(row["footprint_elements"])


def test_images_converged(script):
    """Twice the images (a 65 x 65 lattice and its tail) moves the coarse cell's F_A by under 1e-6: the tail's
    second-order term leaves the fourth (measured 1.5e-6 between 17 x 17 and 33 x 33)."""
    once = script.raster(16, "corner")["adhesive_force_plain"]
    twice = script.raster(16, "corner", images=2 * script.IMAGES)["adhesive_force_plain"]
    assert twice == pytest.approx(once, rel=1e-6)


def test_a_sparse_lattice_is_the_lone_tip(script):
    """Independent of the image sums' constant and of the control: with the pitch 100 times the families' the
    cell's pull-off is the lone tip's event path (`lone_pull_off`, displacement control) to 1e-5 (the neighbours'
    curvature across a tip scales as (r / p)^3, 1e-8 here)."""
    offsets = script.footprint(16, "corner")
    h = script.PITCH / 16
    span = int(offsets.max()) + 1
    critical = critical_stress(1.0, script.DGAMMA, h)
    lattice = script.lattice_pull_off(Bases(script.periodic_table(span, h, 1600, images=2), MODES["uniform"]),
                                      offsets, critical, h * h)[0]
    lone = lone_pull_off(Bases(script.lone_table(span, h), MODES["uniform"]), offsets, critical, h * h)[0]
    assert lattice == pytest.approx(lone, rel=1e-5)
    assert np.isfinite(lattice) and lattice > 0
