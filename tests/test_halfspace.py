"""Rung 1 of the validation ladder (DESIGN.md sec. 5): identities of the half-space operator.

``brushbem.physics.halfspace`` maps the element pressures to the deflections at the element
centres with the Love coefficients of a uniformly loaded square (thesis eq. 3.5),
convolved non-periodically by zero-padded FFTs.  Every test here compares the code
with something computed independently of it:

* the padded FFT product with the dense matrix product (the same coefficients,
  a completely different summation);
* the closed-form coefficients with numerical quadrature of the Boussinesq
  integral ``1 / (pi E* r)`` over the element (adaptive ``dblquad`` near the
  element, tensor Gauss-Legendre far from it);
* the far field with the point load ``h^2 / (pi E* r)`` and its multipole
  correction;
* the centre value with its closed form ``4 ln(1 + sqrt 2) h / (pi E*)``;
* dimensional analysis (u scales like h / E* at fixed positions in units of h).

Tolerances
----------
``ROUND_OFF`` (1e-12 relative): an FFT of length n has a relative round-off of
about eps * log2(n) ~ 1e-15 on the largest entry; the dense matrix product sums
up to 4096 terms in a different order (~1e-14).  1e-12 leaves two decades of
margin and is still eight decades below any modelling error we care about.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from scipy import integrate

from brushbem.physics.halfspace import HalfSpace, influence_coefficients

ROUND_OFF = 1e-12
EPS = np.finfo(np.float64).eps


def _relative_max(a, b) -> float:
    """max |a - b| over max |b| (a norm-wise relative difference)."""
    return float(np.max(np.abs(a - b)) / np.max(np.abs(b)))


# ---------------------------------------------------------------------------
# Padded FFT convolution against the dense influence matrix
# ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("elements", "window"),
    [
        (8, (8, 8)),  # the whole domain
        (8, (5, 5)),  # a square sub-window
        (8, (7, 3)),  # non-square windows, both orientations
        (8, (2, 8)),
        (12, (1, 9)),  # a single row (degenerate padding 2 x 18)
        (12, (11, 6)),
        (33, (33, 17)),  # odd sizes (odd FFT lengths after padding are even: 66 x 34)
        (64, (64, 64)),  # large enough that the wrap-around would be visible if wrong
    ],
)
@pytest.mark.slow
def test_padded_fft_equals_dense_product(elements, window):
    h, modulus = 0.37, 2.5  # arbitrary units: nothing here may depend on h = 1 or E* = 1
    halfspace = HalfSpace(elements, h, modulus)
    rng = np.random.default_rng(20240601)
    pressure = rng.standard_normal(window)
    fft = halfspace.apply(pressure)
    dense = (halfspace.dense_matrix(*window) @ pressure.ravel()).reshape(window)
    assert fft.shape == window
    assert _relative_max(fft, dense) < ROUND_OFF


def test_padded_fft_is_non_periodic():
    """A load in one corner must not reach round the domain to the opposite edge.

    With a periodic (unpadded) convolution the deflection at the far corner would
    be that at distance one element; here it must be the true value at distance
    (N - 1) h, which is computed directly from the coefficients.
    """
    n, h, modulus = 16, 1.0, 1.0
    halfspace = HalfSpace(n, h, modulus)
    pressure = np.zeros((n, n))
    pressure[0, 0] = 1.0
    u = halfspace.apply(pressure)
    far = influence_coefficients((n - 1) * h, (n - 1) * h, h, modulus)
    near = influence_coefficients(h, h, h, modulus)
    assert abs(u[-1, -1] - far) < ROUND_OFF * halfspace.diagonal()
    assert abs(u[-1, -1] - near) > 0.1 * near  # the periodic answer is far from it


def test_apply_on_a_stack_of_pressures():
    """``apply`` works on the last two axes: a stack gives the stack of products."""
    halfspace = HalfSpace(10, 0.1, 3.0)
    rng = np.random.default_rng(7)
    stack = rng.standard_normal((3, 6, 4))
    matrix = halfspace.dense_matrix(6, 4)
    result = halfspace.apply(stack)
    for k in range(3):
        assert _relative_max(result[k], (matrix @ stack[k].ravel()).reshape(6, 4)) < ROUND_OFF


def test_window_larger_than_domain_is_refused():
    halfspace = HalfSpace(8, 1.0, 1.0)
    with pytest.raises(ValueError, match="exceeds"):
        halfspace.apply(np.zeros((9, 8)))


# ---------------------------------------------------------------------------
# Symmetry and positive definiteness
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("window", [(16, 16), (16, 7), (3, 29)])
def test_operator_is_symmetric(window):
    """x . K y = y . K x (Maxwell-Betti reciprocity), through the FFT operator."""
    halfspace = HalfSpace(32, 0.5, 1.7)
    rng = np.random.default_rng(11)
    for _ in range(5):
        x = rng.standard_normal(window)
        y = rng.standard_normal(window)
        xky = float(np.sum(x * halfspace.apply(y)))
        ykx = float(np.sum(y * halfspace.apply(x)))
        # Scale: |x| |K y|, the size of either product before cancellation.
        scale = np.linalg.norm(x) * np.linalg.norm(halfspace.apply(y))
        assert abs(xky - ykx) < ROUND_OFF * scale


@pytest.mark.parametrize("window", [(12, 12), (20, 5), (1, 30)])
def test_dense_matrix_is_symmetric_positive_definite(window):
    """The influence matrix is the Gram matrix of an energy: symmetric, eigenvalues > 0.

    The smallest eigenvalue is not close to zero (the highest-frequency
    checkerboard mode still has a deflection of order h / E*), so "> 0" is a
    robust test; we also check it against a floor with a wide margin.
    """
    h, modulus = 0.2, 5.0
    matrix = HalfSpace(32, h, modulus).dense_matrix(*window)
    # K(-x, -y) is evaluated with its four corner terms in another order: equal up
    # to round-off (measured 6e-16 of the largest entry), not bit for bit.
    assert np.max(np.abs(matrix - matrix.T)) < ROUND_OFF * np.max(matrix)
    eigenvalues = np.linalg.eigvalsh(matrix)
    assert eigenvalues.min() > 0.0
    # The checkerboard mode gives about 0.3 h / E*; 0.05 h / E* is a safe floor.
    assert eigenvalues.min() > 0.05 * h / modulus


def test_energy_is_positive_for_random_pressures():
    """x . K x > 0 for random (and for rough, sign-alternating) pressures on a large grid."""
    n = 96
    halfspace = HalfSpace(n, 0.01, 1.0)
    rng = np.random.default_rng(3)
    checker = (-1.0) ** np.add.outer(np.arange(n), np.arange(n))
    samples = [rng.standard_normal((n, n)) for _ in range(10)] + [checker, checker * rng.random((n, n))]
    for x in samples:
        assert float(np.sum(x * halfspace.apply(x))) > 0.0


# ---------------------------------------------------------------------------
# The coefficients against quadrature of the Boussinesq integral
# ---------------------------------------------------------------------------


def _adaptive_quadrature(x: float, y: float, h: float, modulus: float) -> float:
    """(1 / (pi E*)) * integral over the element of 1 / |(x, y) - (xi, eta)|, by dblquad.

    When the point lies on or inside the element the square is split at the
    point, so that every piece has the (integrable) 1/r singularity at a corner,
    which QUADPACK's extrapolation handles to ~1e-13.
    """
    half = 0.5 * h
    xs = sorted({-half, half, *([x] if -half < x < half else [])})
    ys = sorted({-half, half, *([y] if -half < y < half else [])})
    total = 0.0
    for a, b in itertools.pairwise(xs):
        for c, d in itertools.pairwise(ys):
            value, _ = integrate.dblquad(
                lambda eta, xi: 1.0 / math.hypot(x - xi, y - eta), a, b, c, d, epsabs=0.0, epsrel=1e-12
            )
            total += value
    return total / (math.pi * modulus)


def _gauss_quadrature(x, y, h: float, modulus: float, order: int = 24) -> float:
    """Tensor Gauss-Legendre quadrature of the same integral (for points away from the element).

    For a point at distance r >= 2h the integrand is analytic on the element with
    its nearest singularity at relative distance >= 3; 24 x 24 nodes converge to
    machine precision there, and the sum of positive terms has no cancellation.
    """
    nodes, weights = np.polynomial.legendre.leggauss(order)
    xi, w = 0.5 * h * nodes, 0.5 * h * weights
    X, Y = np.meshgrid(xi, xi, indexing="ij")
    return float(np.sum(np.outer(w, w) / np.hypot(x - X, y - Y)) / (math.pi * modulus))


@pytest.mark.filterwarnings("ignore::scipy.integrate.IntegrationWarning")
@pytest.mark.parametrize(
    ("x", "y"),
    [
        (0.0, 0.0),  # centre
        (0.2, 0.1),  # inside
        (0.5, 0.0),  # edge midpoint
        (0.5, 0.5),  # corner
        (0.7, 0.2),  # just outside
        (1.0, 1.0),  # diagonal neighbour's centre
        (-1.5, 0.3),
        (3.0, -2.0),
    ],
)
def test_kernel_matches_adaptive_quadrature_near_the_element(x, y):
    """Relative agreement 1e-10: dblquad is asked for 1e-12 and reaches ~1e-15 here;
    the closed form is exact.  1e-10 would still catch a wrong factor or a sign error
    in one of the four corner terms (errors of order 1)."""
    h, modulus = 2.0, 0.7
    expected = _adaptive_quadrature(x * h, y * h, h, modulus)
    actual = float(influence_coefficients(x * h, y * h, h, modulus))
    assert actual == pytest.approx(expected, rel=1e-10, abs=0.0)


@pytest.mark.parametrize("distance", [2.0, 3.0, 10.0, 30.0, 100.0])
@pytest.mark.parametrize("angle", [0.0, 0.3, math.pi / 4, 2.0])
def test_kernel_matches_gauss_quadrature_at_moderate_distance(distance, angle):
    """Within 100 h the asinh form keeps 1e-12 relative accuracy (measured <= 4e-13)."""
    h, modulus = 1.0, 1.0
    x, y = distance * math.cos(angle), distance * math.sin(angle)
    assert float(influence_coefficients(x, y, h, modulus)) == pytest.approx(
        _gauss_quadrature(x, y, h, modulus), rel=1e-12
    )


@pytest.mark.parametrize("distance", [300.0, 1000.0, 3000.0, 10000.0])
@pytest.mark.parametrize("angle", [0.0, 0.3, math.pi / 4])
def test_kernel_far_field_round_off_is_bounded(distance, angle):
    """Far away the four corner terms (each ~ r ln r) cancel to ~ h^2 / r.

    Any closed form built from corner primitives then loses about eps (r/h)^2
    relative accuracy (measured: 1e-11 at 300 h, 8e-11 at 1000 h, 2e-9 at 3000 h,
    5e-8 at 10^4 h; the literal logarithm form is 3-10x worse).  The absolute error
    stays ~ eps * K[0, 0], harmless in the convolution; this test pins the bound
    4 eps (r/h)^2 so that a regression to a worse form is caught.
    """
    h, modulus = 1.0, 1.0
    x, y = distance * math.cos(angle), distance * math.sin(angle)
    expected = _gauss_quadrature(x, y, h, modulus)
    actual = float(influence_coefficients(x, y, h, modulus))
    bound = max(1e-12, 4.0 * EPS * (distance / h) ** 2)
    assert abs(actual / expected - 1.0) < bound


@pytest.mark.parametrize("distance", [3.0, 5.0, 10.0, 20.0, 50.0, 100.0])
@pytest.mark.parametrize("angle", [0.0, 0.3, math.pi / 4])
def test_far_field_tends_to_point_load(distance, angle):
    """K -> h^2 / (pi E* r) with relative error (h/r)^2 / 24 + O((h/r)^4).

    Expanding 1/|r - xi| about xi = 0 and averaging over the square
    (<xi_x^2> = <xi_y^2> = h^2/12, odd moments zero) gives the isotropic
    second-order correction (3 h^2/12 - 2 h^2/12) / (2 r^2) = (h/r)^2 / 24.  The
    fourth-order term is anisotropic; its coefficient was measured between
    -0.0037 (axis) and +0.0146 (diagonal), so the remainder is bounded by
    0.02 (h/r)^4.
    """
    h, modulus = 0.25, 3.0
    r = distance * h
    x, y = r * math.cos(angle), r * math.sin(angle)
    point = h**2 / (math.pi * modulus * r)
    error = float(influence_coefficients(x, y, h, modulus)) / point - 1.0
    ratio = h / r
    assert 0.0 < error < 0.05 * ratio  # O((h/r)^2): small, positive, vanishing
    assert abs(error - ratio**2 / 24.0) <= 0.02 * ratio**4


def test_far_field_relative_error_scales_as_h_over_r_squared():
    """The observed order of the point-load error, from r = 10 h to 100 h, is 2."""
    h, modulus = 1.0, 1.0
    distances = np.array([10.0, 20.0, 40.0, 80.0])
    errors = np.array([float(influence_coefficients(r, 0.0, h, modulus)) * math.pi * modulus * r / h**2 - 1 for r in distances])
    orders = np.log(errors[:-1] / errors[1:]) / np.log(distances[1:] / distances[:-1])
    assert np.all(np.abs(orders - 2.0) < 0.01), orders


def test_centre_value():
    """K[0, 0] = 4 ln(1 + sqrt 2) h / (pi E*) = 1.122... h / E* (Johnson eq. 3.25 at the centre)."""
    for h, modulus in [(1.0, 1.0), (1e-3, 2e6), (7.5, 0.3)]:
        expected = 4.0 * math.log(1.0 + math.sqrt(2.0)) * h / (math.pi * modulus)
        assert HalfSpace(4, h, modulus).diagonal() == pytest.approx(expected, rel=1e-14, abs=0.0)
        assert float(influence_coefficients(0.0, 0.0, h, modulus)) == pytest.approx(expected, rel=1e-14, abs=0.0)


def _cancellation_bound(xx, yy, h):
    """Round-off bound of the corner-term form at offset (x, y): 8 eps (1 + (r/h)^2).

    The four corner terms are each ~ r ln(r/h) while their sum is ~ h^2 / r, so
    evaluating them in another order (or on scaled arguments) changes the result
    by up to a few eps (r/h)^2 relative (see the far-field round-off test).
    """
    return 8.0 * EPS * (1.0 + (xx**2 + yy**2) / h**2)


def test_kernel_is_even_in_both_offsets():
    x = np.array([0.0, 0.3, 1.0, 2.5, 7.0, 40.0])
    xx, yy = np.meshgrid(x, x, indexing="ij")
    k = influence_coefficients(xx, yy, 1.0, 1.0)
    bound = _cancellation_bound(xx, yy, 1.0)
    for sx, sy in [(-1, 1), (1, -1), (-1, -1)]:
        assert np.all(np.abs(influence_coefficients(sx * xx, sy * yy, 1.0, 1.0) / k - 1) <= bound)
    assert np.all(np.abs(influence_coefficients(yy, xx, 1.0, 1.0) / k - 1) <= bound)


# ---------------------------------------------------------------------------
# Units
# ---------------------------------------------------------------------------


def test_unit_neutrality_of_the_coefficients():
    """u ~ 1/E* at fixed geometry; u ~ s when h and positions are scaled by s (1/r kernel over area h^2)."""
    x = np.array([0.0, 0.4, 1.0, 3.0, 40.0])
    xx, yy = np.meshgrid(x, x, indexing="ij")
    base = influence_coefficients(xx, yy, 1.0, 1.0)
    for modulus in (1e-3, 2.0, 7.1e6):
        # A division by E* and nothing else: exact up to one rounding.
        assert np.allclose(influence_coefficients(xx, yy, 1.0, modulus) * modulus, base, rtol=4 * EPS, atol=0)
    for scale in (1e-6, 0.3, 17.0, 1e4):
        scaled = influence_coefficients(scale * xx, scale * yy, scale, 1.0)
        # asinh(y/|x|) is scale invariant and the prefactor scales exactly; only
        # the rounding of the scaled arguments enters, amplified by the corner-term
        # cancellation (measured 5e-13 at r = 40 h, bound 8 eps (1 + (r/h)^2)).
        assert np.all(np.abs(scaled / scale / base - 1) <= _cancellation_bound(xx, yy, 1.0))


def test_unit_neutrality_of_the_operator():
    """The same pressure on grids of element size s h and modulus c E* gives (s / c) u."""
    rng = np.random.default_rng(5)
    pressure = rng.standard_normal((20, 13))
    reference = HalfSpace(20, 1.0, 1.0).apply(pressure)
    for scale, modulus in [(1e-3, 1.0), (1.0, 2e6), (0.02, 3.5), (40.0, 1e-2)]:
        u = HalfSpace(20, scale, modulus).apply(pressure)
        assert _relative_max(u * modulus / scale, reference) < ROUND_OFF


def test_invalid_parameters_are_refused():
    for args in [(0, 1.0, 1.0), (4, 0.0, 1.0), (4, 1.0, -1.0), (4, math.inf, 1.0), (4, 1.0, math.nan)]:
        with pytest.raises(ValueError):
            HalfSpace(*args)


@pytest.mark.parametrize(
    ("window", "support"),
    [
        ((150, 150), (25, 125, 25, 125)),  # centred: period ~ m + extent instead of 2m
        ((151, 140), (30, 119, 10, 130)),
        ((120, 90), (50, 60, 40, 50)),  # small support, odd periods
        ((9, 7), (2, 5, 1, 6)),
        ((64, 64), (0, 64, 0, 64)),  # whole window: falls back to 2m
    ],
)
def test_support_aware_period_gives_the_same_deflection(window, support):
    """apply(p, support=box) on the shorter wrapped period equals the 2m-padded product."""
    halfspace = HalfSpace(256, 1.0 / 256, 1.0)
    r0, r1, c0, c1 = support
    pressure = np.zeros(window)
    pressure[r0:r1, c0:c1] = np.random.default_rng(r1 * c1).standard_normal((r1 - r0, c1 - c0))
    expected = halfspace.apply(pressure)
    assert _relative_max(halfspace.apply(pressure, support=support), expected) < ROUND_OFF


def test_row_pruned_convolution_equals_the_full_one():
    """padded_convolution_rows on the loaded rows = padded_convolution kept on those rows."""
    from brushbem import backend

    rng = np.random.default_rng(0)
    halfspace = HalfSpace(40, 0.025, 1.0)
    pressure = np.zeros((24, 30))
    rows = np.array([1, 2, 7, 15, 16, 23])
    pressure[rows] = rng.standard_normal((rows.size, 30))
    spectrum = halfspace.spectrum(24, 30)
    full = backend.padded_convolution(np, pressure, spectrum)
    pruned = backend.padded_convolution_rows(np, pressure[rows], rows, spectrum, (48, 60))
    np.testing.assert_allclose(pruned, full[rows], rtol=0, atol=1e-13 * np.abs(full).max())


def test_block_inverse_is_the_inverse_of_the_dense_block():
    halfspace = HalfSpace(32, 1.0 / 32, 2.0)
    offsets = np.array([[0, 1], [0, 2], [1, 0], [1, 1], [1, 2], [1, 3], [2, 1], [2, 2], [3, 2]])
    dense = halfspace.dense_matrix(4, 4)
    flat = offsets[:, 0] * 4 + offsets[:, 1]
    block = dense[np.ix_(flat, flat)]
    inverse = halfspace.block_inverse(offsets)
    np.testing.assert_allclose(inverse @ block, np.eye(len(offsets)), rtol=0, atol=1e-10)
    assert halfspace.block_inverse(offsets.copy()) is inverse  # cached by shape
