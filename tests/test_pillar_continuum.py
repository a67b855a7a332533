"""The flat brushes' continuum limit (``docs/pillars/continuum.py``) and the peel of one tip in its field
(``docs/pillars/tilted.py``): the spectral solution against closed forms, and the committed tables against what
they claim.
"""

from __future__ import annotations

import math

import numpy as np
import pytest


@pytest.fixture(scope="module")
def continuum():
    from test_pillar_tips import _pillars_script

    return _pillars_script("continuum.py", "pillar_continuum")


@pytest.fixture(scope="module")
def tilted():
    from test_pillar_tips import _pillars_script

    return _pillars_script("tilted.py", "pillar_tilted")


def _rows(name: str) -> list[dict]:
    from test_pillar_tips import _pillars_table

    return _pillars_table(name)


@pytest.mark.parametrize("mode", [(0, 0, 0), (1, 0, 0), (0, 1, 0), (2, 1, 1), (3, 2, 0)])
def test_the_own_disk_operator_is_diagonal_on_the_basis(continuum, mode):
    """int p_mn / |x - x'| dA' over the unit disk is pi l_mn p_mn sqrt(1 - r^2) at an inner point, by direct
    quadrature in polar coordinates about the point (the 1 / rho cancels; the edge's 1 / sqrt is removed by
    rho = rho_max (1 - t^2)): to 1e-9 (the quadrature's own error is about 1e-13)."""
    x, y = 0.3, -0.2
    t, wt = np.polynomial.legendre.leggauss(40)
    t, wt = (t + 1) / 2, wt / 2
    total = 0.0
    for angle in 2 * np.pi * np.arange(200) / 200:
        ex, ey = math.cos(angle), math.sin(angle)
        b = x * ex + y * ey
        reach = -b + math.sqrt(b * b - (x * x + y * y - 1))
        rho = reach * (1 - t**2)
        px, py = x + rho * ex, y + rho * ey
        r = np.hypot(px, py)
        value = continuum.polynomial([mode], np.minimum(r, 1), np.arctan2(py, px))[:, 0] / np.sqrt(1 - r**2)
        total += np.sum(wt * 2 * reach * t * value) * 2 * np.pi / 200
    expected = math.pi * continuum.eigenvalue(*mode[:2]) * continuum.polynomial([mode], [math.hypot(x, y)],
                                                                                 [math.atan2(y, x)])[0, 0]
    assert total == pytest.approx(expected, rel=1e-9)


def test_a_neighbours_uniform_pull_is_the_flat_punchs_closed_form(continuum):
    """The Galerkin block of two tips at the families' pitch (4.43 radii) on the uniform mode is the projection of
    Kendall's punch's outer deflection, int p / |x - x'| = 2 pi c arcsin(a / rho) (to 1e-9 at 12 x 48 points)."""
    pitch = math.sqrt(math.pi / continuum.PHI)
    brush = continuum.Brush(2, pitch, 4, 12, 48)
    r, theta, weights = continuum.quadrature(40, 160)
    field = 2 * math.pi * np.arcsin(1 / np.hypot(r * np.cos(theta) + pitch, r * np.sin(theta)))
    exact = continuum.polynomial(brush.basis, r, theta).T @ (weights * field)
    assert brush.blocks[(1, 0)][:, 0] == pytest.approx(exact, rel=1e-9, abs=1e-12)


def test_a_lone_tip_comes_off_at_kendalls_force(continuum):
    """One tip: F_A = F_K = sqrt(8 pi E* dgamma a^3) (to 1e-12)."""
    row = continuum.run_case(1, 1e-5, 4, 8, 16)
    assert row["force_by_ideal_sharing"] == pytest.approx(1.0, rel=1e-12)


def test_the_reference_is_the_table_and_converged_to_what_it_claims(continuum):
    """``continuum_reference.csv`` is `reference` of ``continuum.csv``; its error column (the change from degree 12
    to 16 plus that from 12 x 48 to 16 x 64 points) is below 1e-7 on every case, and the 4 x 4 brush at degree 8
    runs again to its committed F_A (1e-8)."""
    rows = _rows("continuum.csv")
    computed = continuum.reference(rows)
    committed = _rows("continuum_reference.csv")
    assert len(computed) == len(committed) == 4
    for mine, theirs in zip(computed, committed):
        assert mine["adhesive_force"] == pytest.approx(float(theirs["adhesive_force"]), rel=1e-7)
        assert float(theirs["error"]) < 1e-7
    again = continuum.run_case(4, 1e-5, 8, 12, 48)
    (row,) = [r for r in rows if r["pillars_per_side"] == "4" and r["stiffness_ratio"] == "1e-05"
              and r["degree"] == "8"]
    assert again["adhesive_force"] == pytest.approx(float(row["adhesive_force"]), rel=1e-8)


def test_a_cascade_past_a_quarter_of_the_tip_takes_all_of_it(tilted):
    """The shortcut of `Tip.pull_off_in` changes no F_A on the 7.2-elements rasters (four placements, two
    directions, eps = 0.2)."""
    for placement in tilted.PLACEMENTS:
        tip = tilted.Tip(7.222, placement)
        for direction in tilted.DIRECTIONS:
            assert tip.pull_off(0.2, direction) == tip.pull_off(0.2, direction, gone=1.0)


def test_tips_at_any_centres_are_the_lattice_when_placed_on_it(continuum):
    """`Brush` with ``centres`` (one block per ordered pair, the basis' norms exact) on the 3 x 3 lattice of the
    families' pitch is the lattice construction: the same blocks, coefficients and events to 1e-12 (rounding; at
    degree 4 the lattice's 12 x 48 points hold the norms exactly too)."""
    pitch = math.sqrt(math.pi / continuum.PHI)
    lattice = continuum.Brush(3, pitch, 4, 12, 48)
    anywhere = continuum.Brush(0, 0.0, 4, 12, 48, centres=lattice.centres)
    for i in range(9):
        for j in range(9):
            if i != j:
                expected = lattice.blocks[tuple(lattice.grid[i] - lattice.grid[j])]
                assert np.abs(anywhere.blocks[(i, j)] - expected).max() < 1e-12 * np.abs(expected).max()
    attached = np.ones(9, bool)
    attached[4] = False
    for tips in (np.ones(9, bool), attached):
        c, expected = anywhere.solve(tips, 10.0), lattice.solve(tips, 10.0)
        assert np.abs(c - expected).max() < 1e-12 * np.abs(expected).max()
    mine, theirs = anywhere.pull_off(10.0, last=5), lattice.pull_off(10.0, last=5)
    assert [e[1:] for e in mine] == [e[1:] for e in theirs]
    assert [e[0] for e in mine] == pytest.approx([e[0] for e in theirs], rel=1e-12)
    with pytest.raises(ValueError, match="centres"):
        continuum.Brush(0, 0.0, 4, 12, 48, centres=[[0.0, 0.0], [1.5, 0.0]])
