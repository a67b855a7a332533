"""The rough brush of independent pillars (theory.rough): closed forms, exactness, and the soft-brush limit.

The independent-pillar brush is the limit the thesis quotes for eq. 5.7 (L922-929):
every pillar a punch on its own spring, no coupling through the half-space.  It
is checked here against eq. 5.7 itself (exponential lengths), against a brute-force
scan of its own force, against the one-dimensional plateau quadrature, and
against the full BEM simulation of a soft rough brush, which must approach it.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.stats import norm

from brushbem.physics import theory
from brushbem.protocol import ContactProblem, LoadPath, record_pull_off
from brushbem.physics.structure import Grid, brush, flat_punch


def _brute_force(heights, preload, stiffness, critical):
    """F(d) on a fine scan of the base displacement, straight from the model's definition."""
    z = np.sort(np.asarray(heights))[::-1] - np.max(heights)
    d = np.linspace(-5.0, 5.0, 400_001)
    pressing = stiffness * np.clip(d[:, None] + z[None, :], 0.0, None).sum(axis=1)
    d0 = np.interp(preload, pressing, d)
    touched = z > -d0
    retract = d[d <= d0][::-1]
    overlap = retract[:, None] + z[None, touched]
    alive = np.minimum.accumulate(overlap >= -critical / stiffness, axis=0)
    force = stiffness * np.where(alive, overlap, 0.0).sum(axis=1)
    tension = np.clip(-force, 0.0, None)
    return tension.max(), np.sum(0.5 * (tension[1:] + tension[:-1]) * np.abs(np.diff(retract)))


def test_pull_off_is_exact_against_a_brute_force_scan():
    rng = np.random.default_rng(4)
    for _ in range(3):
        heights = 0.4 * rng.standard_normal(12)
        exact = theory.independent_pillars_pull_off(heights, 1.5, series_stiffness=2.0, critical_force=0.7)
        force, work = _brute_force(heights, 1.5, 2.0, 0.7)
        # The scan's step is 2.5e-5 in d: F_A to that step times the stiffness of the
        # attached pillars (<= 24 * 2.5e-5 = 6e-4), the trapezoid work to ~1e-4 relative.
        assert exact.adhesive_force == pytest.approx(force, abs=1e-3)
        assert exact.work_of_separation == pytest.approx(work, rel=2e-3)


def test_exponential_lengths_give_eq_5_7():
    """c = Delta_l / sigma - 1 for exponentially distributed lengths ([109], eq. 5.7)."""
    n = 400_000
    for sigma in (0.2, 0.5, 0.8):
        # Deterministic exponential quantiles: the continuum the closed form describes, without sampling noise.
        heights = -sigma * np.log((np.arange(n) + 0.5) / n)
        preload = 4000.0 * sigma  # ~ 4000 pillars touched: c(F_P) is independent of F_P for this law
        result = theory.independent_pillars_pull_off(heights, preload, series_stiffness=1.0, critical_force=1.0)
        # Discreteness of the touched set (~4000 pillars) leaves ~1e-3 of the force.
        assert result.adhesive_force / preload == pytest.approx(1.0 / sigma - 1.0, abs=5e-3)


def test_gaussian_plateau_quadrature_equals_the_exact_sum():
    n = 200_000
    for s in (0.1, 0.5, 2.0):
        heights = s * norm.ppf((np.arange(n) + 0.5) / n)  # Gaussian quantiles, sigma = s Delta_l
        result = theory.independent_pillars_pull_off(heights, 1e3 * n, series_stiffness=1.0, critical_force=1.0)
        assert result.attached == n
        # The quantile sample truncates the tails at ~4.6 sigma: 1e-3 relative is far above that error.
        assert result.adhesive_force / n == pytest.approx(theory.independent_gaussian_plateau(s), rel=1e-3)
    assert theory.independent_gaussian_plateau(0.0) == 1.0


def test_rough_brush_scales_cancel_and_the_floor_is_one_pillar():
    kw = {"pillar_count": 64, "filling_factor": 0.16, "stiffness_ratio": 10.0, "realizations": 3, "seed": 1}
    rough = theory.independent_rough_brush(30.0, 0.01, **kw)
    # Very rough: only the longest pillar touches at a small preload, and F~_A is one pillar's F_K / F_c.
    assert rough.adhesive_force == pytest.approx(rough.single_pillar_force, rel=1e-12, abs=0.0)
    # Rigid pillars: Delta_l is Kendall's critical displacement, d_K / d_c = (phi n)^(-1/4) (eq. 5.4, 2.4).
    rigid = theory.independent_rough_brush(0.1, 1.0, **{**kw, "stiffness_ratio": math.inf})
    assert rigid.critical_elongation == pytest.approx((0.16 * 64) ** -0.25, rel=1e-12)
    by_pillar = theory.independent_rough_brush(0.1 / rigid.critical_elongation, 1.0,
                                               **{**kw, "stiffness_ratio": math.inf}, roughness_scale="pillar")
    assert by_pillar.adhesive_force == pytest.approx(rigid.adhesive_force, rel=1e-12, abs=0.0)


@pytest.mark.parametrize(("call", "name"), [
    (lambda: theory.independent_pillars_pull_off([], 1.0, series_stiffness=1.0, critical_force=1.0), "heights"),
    (lambda: theory.independent_pillars_pull_off([0.0, np.nan], 1.0, series_stiffness=1.0, critical_force=1.0),
     "heights"),
    (lambda: theory.independent_pillars_pull_off([0.0], -1.0, series_stiffness=1.0, critical_force=1.0),
     "preload_force"),
    (lambda: theory.independent_rough_brush(0.1, 1.0, pillar_count=0, filling_factor=0.16, stiffness_ratio=1.0),
     "pillar_count"),
    (lambda: theory.independent_rough_brush(0.1, 1.0, pillar_count=4, filling_factor=0.16, stiffness_ratio=1.0,
                                            roughness_scale="grid"), "roughness_scale"),
])
def test_bad_input_names_the_parameter(call, name):
    with pytest.raises(ValueError, match=name):
        call()


def test_soft_rough_brush_approaches_the_independent_limit():
    """k~ = 1e-4: the simulated rough brush is the independent-pillar brush of the same drawn lengths.

    4 x 4 pillars of 3 elements' radius on N = 128 (phi = 0.03).  What the limit
    leaves out is the half-space coupling, of two kinds: (1) the other pillars'
    deflection under a pillar, which the springs dominate by k_c / k ~ 500
    (under 0.3 % of the stretch); (2) the non-uniform deflection the other
    pillars' tension causes across a pillar's tip, which raises one edge's
    stress and detaches it early.  (2) is measured on the same brush without
    roughness, where every pillar is attached: its F_A falls short of 16 single
    pillars by `coupling` (3.4 %).  Roughness attaches fewer pillars, so the
    rough brush must agree with the limit within that shortfall (plus 0.5 % for
    the spring/contact split).  The single pillar's detachment force is the
    simulated one on the same raster, so the mesh's error in Kendall's force
    (13 % at 3 elements) is common to both sides.
    """
    grid = Grid(1.0, 128)
    radius, stiffness = 3 * grid.element_size, 1e-4
    material = {"contact_modulus": 1.0, "work_of_adhesion": 1e-4}

    def pull_off(indenter, preload):
        record = record_pull_off(ContactProblem(grid, indenter, **material),
                                 LoadPath(method="events", preload_force=preload))
        assert record.summary["converged"], record.summary["reason"]
        return record.summary["adhesive_force"]

    single = pull_off(flat_punch(grid, radius, stiffness), 1e-5)
    series = 1.0 / (1.0 / stiffness + 1.0 / (2.0 * radius))
    stretch = single / series

    def pillars(sigma):
        return brush(grid, layout="square", pillars_per_side=4, pillar_radius=radius, stiffness=stiffness,
                     roughness=sigma, seed=3, **material)

    coupling = 1.0 - pull_off(pillars(0.0), 4 * single) / (16 * single)
    assert 0.0 < coupling < 0.05
    for sigma in (0.1, 0.5, 1.5):  # sigma / Delta_l: nearly flat, rough, rougher than one stretch
        indenter = pillars(sigma * stretch)
        limit = theory.independent_pillars_pull_off(-indenter.description["offsets"], 6 * single,
                                                    series_stiffness=series, critical_force=single)
        assert pull_off(indenter, 6 * single) / limit.adhesive_force == pytest.approx(1.0, abs=coupling + 0.005)


def test_the_shipped_table_1_limit_is_what_the_limit_gives():
    """rough_brush.INDEPENDENT_LIMIT (docs/reproduction/identify_table1.py) recomputed for one stiff and one soft k~."""
    from brushbem.studies._ch5_7 import fit_eq58
    from brushbem.studies.rough_brush import INDEPENDENT_LIMIT

    roughnesses = np.array([0.01, 0.03, 0.07, 0.12, 0.2, 0.28, 0.4, 0.5, 0.7, 1.0, 1.4, 2.1, 3.0])
    for k, stiffness in ((0.55, 10.0), (0.001, 0.001)):
        preload, alpha, critical = INDEPENDENT_LIMIT[k]
        c = [theory.independent_rough_brush(s, preload, pillar_count=1024, filling_factor=0.16, stiffness_ratio=stiffness,
                                            realizations=10, seed=1).adhesion_coefficient for s in roughnesses]
        fitted_alpha, beta = fit_eq58(roughnesses, np.array(c))
        assert fitted_alpha == pytest.approx(alpha, rel=5e-3)  # the table keeps three digits
        assert (fitted_alpha / beta if beta > 0 else math.inf) == pytest.approx(critical, rel=5e-3)
