"""Rough brush closed forms (thesis ch. 5): the fitted adhesion coefficient (eq. 5.8) and the
brush of independent pillars (the limit without half-space coupling, eq. 5.7's model).

The rough brush's force and displacement scales are the rigid brush's
(:mod:`brushbem.physics.theory.brush`, eq. 5.3-5.4).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from brushbem.physics.theory._common import _count, _filling_factor, _finite, _nonnegative, _out, _positive

__all__ = [
    "ROUGHNESS_SCALES",
    "IndependentPullOff",
    "IndependentRoughBrush",
    "adhesion_coefficient",
    "critical_roughness",
    "independent_gaussian_plateau",
    "independent_pillars_pull_off",
    "independent_rough_brush",
]


# ---------------------------------------------------------------------------
# Rough brushes: adhesion coefficient at small preload (eq. 5.8)
# ---------------------------------------------------------------------------


def adhesion_coefficient(normalized_roughness, alpha, beta):
    """Adhesion coefficient of a rough brush at small preload, ``c = alpha / sigma~ - beta`` (eq. 5.8).

    ``F~_A = c F~_P`` in the linear region.  The fit is not clipped: ``c <= 0``
    (``sigma~ >= alpha / beta``) means no macroscopic adhesion.

    Parameters
    ----------
    normalized_roughness : float or array_like
        sigma~ = sigma / |d_c| (eq. 5.5), dimensionless; positive.
    alpha : float or array_like
        Fitted amplification factor alpha(k~) (Table 1), dimensionless; positive.
    beta : float or array_like
        Fitted bias beta(k~) (Table 1), dimensionless; non-negative.

    Returns
    -------
    float or ndarray
        c, dimensionless.
    """
    sigma = _positive("normalized_roughness", normalized_roughness)
    a = _positive("alpha", alpha)
    b = _nonnegative("beta", beta)
    return _out(a / sigma - b)


def critical_roughness(alpha, beta):
    """Roughness at which the fitted adhesion coefficient vanishes, ``sigma~_c = alpha / beta``.

    Parameters
    ----------
    alpha : float or array_like
        Fitted amplification factor, dimensionless; positive.
    beta : float or array_like
        Fitted bias, dimensionless; positive.

    Returns
    -------
    float or ndarray
        sigma~_c, dimensionless.
    """
    a = _positive("alpha", alpha)
    b = _positive("beta", beta)
    return _out(a / b)


# ---------------------------------------------------------------------------
# Rough brushes of independent pillars (the limit of no half-space coupling)
# ---------------------------------------------------------------------------
#
# Each pillar is a rigid flat punch (radius r) on its own linear spring k, and
# the half-space under it responds to that pillar's force alone.  The punch and
# its spring are two springs in series, of stiffness k_s = 1 / (1/k + 1/(2 E* r))
# (eq. 2.2), and a punch on a spring detaches at Kendall's force F_K whatever
# the spring (eq. 2.16-2.17): each pillar detaches when stretched by
# Delta_l = F_K / k_s.  Pillar i of tip height z_i (longer pillars higher)
# carries k_s (d + z_i - z_max) once touched, d being the base displacement from
# the first touch (d > 0 presses).  This is the brush of [109] (thesis L922-929)
# with the punch's own compliance in series: for exponential lengths it gives
# c = Delta_l / sigma - 1 exactly, the thesis's eq. 5.7 with sigma normalised
# by the pillar's critical elongation Delta_l.


@dataclass(frozen=True)
class IndependentPullOff:
    """Pull-off of a brush of independent pillars (:func:`independent_pillars_pull_off`).

    Attributes
    ----------
    adhesive_force : float
        F_A = -min F over the retraction, a magnitude, in units of force (0 if
        no pillar is ever in tension).
    preload_displacement : float
        Base displacement d_0 at the preload, from the first touch, in units of length.
    attached : int
        Pillars in contact at the preload.
    pull_off_displacement : float
        Base displacement at which -F reaches F_A (just before a pillar detaches), in
        units of length; the preload displacement when F_A = 0.
    work_of_separation : float
        Work done against the tensile force from F = 0 to complete separation, in
        units of energy (exact for the piecewise linear force).
    """

    adhesive_force: float
    preload_displacement: float
    attached: int
    pull_off_displacement: float
    work_of_separation: float


def independent_pillars_pull_off(heights, preload_force, *, series_stiffness, critical_force):
    """Exact pull-off of a brush of independent pillars after a force-controlled preload.

    The brush is pressed until its force reaches ``preload_force`` and pulled
    off: every pillar touched at the preload stays attached until its tension
    reaches ``critical_force``; pillars never touched stay free.  The force is
    piecewise linear in the base displacement between detachments, so F_A (the
    force just before one of the detachments) and the work are exact.

    Parameters
    ----------
    heights : array_like, shape (n,)
        Tip height of every pillar (length above a common reference: the
        longest touches first), in units of length; finite.
    preload_force : float
        Compressive force at the end of pressing, in units of force; positive.
    series_stiffness : float
        Stiffness of one pillar's spring in series with its contact,
        ``1 / (1/k + 1/(2 E* r))``, in units of force per length; positive.
    critical_force : float
        Tension at which one pillar detaches (Kendall's force, eq. 2.4b), in
        units of force; positive.

    Returns
    -------
    IndependentPullOff
    """
    z = np.sort(_finite("heights", heights).ravel())[::-1]
    if z.size == 0:
        raise ValueError("heights must hold at least one pillar; got an empty array")
    force = float(_positive("preload_force", preload_force))
    ks = float(_positive("series_stiffness", series_stiffness))
    fc = float(_positive("critical_force", critical_force))
    z = z - z[0]  # 0 for the longest pillar, negative below it
    count = np.arange(1, z.size + 1)
    sums = np.cumsum(z)
    # With the m longest pillars touching, F = ks (m d + sum z); that m whose interval
    # [-z_(m-1), -z_m) holds the d that gives the preload force.
    d_each = (force / ks - sums) / count
    upper = np.append(-z[1:], np.inf)
    m = int(np.flatnonzero(d_each <= upper)[0]) + 1
    d0 = float(d_each[m - 1])
    stretch = fc / ks
    # Pillar j (j-th longest) detaches at d = -stretch - z_j; just before, the pillars
    # 0..j pull: F_j = ks ((j+1) e_j + sum_{i<=j} z_i).  Detachments run from j = m-1 down.
    e = -stretch - z[:m]
    f = ks * (count[:m] * e + sums[:m])
    j = int(np.argmin(f))
    adhesive = max(0.0, -float(f[j]))
    # Work: between e_j and e_(j+1) (and from e_(m-1) up to d0) the force is linear,
    # F = a d + b with a = ks (j+1), b = ks sum_{i<=j} z_i; integrate its tensile part.
    hi = np.append(e[1:], d0)
    lo = e
    a = ks * count[:m]
    b = ks * sums[:m]
    top = np.minimum(hi, -b / a)  # F < 0 below d* = -b/a
    span = np.clip(top - lo, 0.0, None)
    work = float(np.sum(-(0.5 * a * (top**2 - lo**2) + b * (top - lo)) * (span > 0)))
    return IndependentPullOff(
        adhesive_force=adhesive,
        preload_displacement=d0,
        attached=m,
        pull_off_displacement=float(e[j]) if adhesive > 0 else d0,
        work_of_separation=max(work, 0.0),
    )


@dataclass(frozen=True)
class IndependentRoughBrush:
    """Mean pull-off of Gaussian rough brushes of independent pillars, in the thesis's ch. 5 scales.

    Attributes
    ----------
    adhesive_force : float
        Mean F~_A = F_A / F_c (eq. 5.3) over the realisations.
    standard_error : float
        Standard error of that mean (0 for one realisation).
    adhesion_coefficient : float
        c = F~_A / F~_P (eq. 5.6) of the mean.
    attached : float
        Mean number of pillars touched at the preload.
    critical_elongation : float
        One pillar's detachment stretch Delta_l = F_K / k_s over |d_c| (eq. 5.4).
    single_pillar_force : float
        One pillar's F_K over F_c: the least non-zero F~_A of a brush of this many pillars.
    """

    adhesive_force: float
    standard_error: float
    adhesion_coefficient: float
    attached: float
    critical_elongation: float
    single_pillar_force: float


#: Normalisations of sigma~ that :func:`independent_rough_brush` accepts: the rigid
#: brush's critical displacement d_c (eq. 5.4-5.5, the thesis's statement) or one
#: pillar's critical elongation Delta_l = F_K / k_s (the convention of eq. 5.7's [109]).
ROUGHNESS_SCALES = ("rigid_brush", "pillar")


def independent_rough_brush(normalized_roughness, normalized_preload, *, pillar_count, filling_factor,
                            stiffness_ratio, realizations=10, seed=0, roughness_scale="rigid_brush"):
    """F~_A of a rough brush of independent pillars with Gaussian lengths (eq. 5.1), in ch. 5's scales.

    ``pillar_count`` pillars of equal radius ``r = L sqrt(phi / (pi n))`` on an
    apparent area L x L, each on a spring k = k~ E* L (eq. 5.5) in series with its
    punch contact 2 E* r and detaching at Kendall's force; lengths drawn from
    N(0, sigma) with ``numpy.random.default_rng(seed)``; pressed to F~_P F_c and
    pulled off by :func:`independent_pillars_pull_off`.  The result is
    dimensionless and independent of E*, dgamma and L (they cancel in F~, sigma~,
    k~), so it is the half-space-coupling-free limit of the simulated brush.

    Parameters
    ----------
    normalized_roughness : float
        sigma~, dimensionless; non-negative.  sigma = sigma~ |d_c| for
        ``roughness_scale = "rigid_brush"`` (eq. 5.5), sigma~ Delta_l for ``"pillar"``.
    normalized_preload : float
        F~_P = F_P / F_c (eq. 5.3), dimensionless; positive.
    pillar_count : int
        Number of pillars n; at least 1.
    filling_factor : float
        phi, dimensionless; in (0, 1].
    stiffness_ratio : float
        k~ = k / (E* L), dimensionless; positive (inf: rigid pillars).
    realizations : int
        Number of independent draws averaged; at least 1.
    seed : int
        Seed of the draws.
    roughness_scale : str
        One of `ROUGHNESS_SCALES`.

    Returns
    -------
    IndependentRoughBrush
    """
    sigma_n = float(_nonnegative("normalized_roughness", normalized_roughness))
    preload_n = float(_positive("normalized_preload", normalized_preload))
    n = int(_count("pillar_count", pillar_count))
    phi = float(_filling_factor("filling_factor", filling_factor))
    k_n = float(_positive("stiffness_ratio", stiffness_ratio, allow_inf=True))
    reps = int(_count("realizations", realizations))
    if roughness_scale not in ROUGHNESS_SCALES:
        raise ValueError(f"roughness_scale must be one of {ROUGHNESS_SCALES}; got {roughness_scale!r}")
    # Units E* = 1, dgamma = 1, L = 1: every output is a ratio in which they cancel.
    radius = math.sqrt(phi / (math.pi * n))
    fk = math.sqrt(8.0 * math.pi * radius**3)
    contact = 2.0 * radius
    ks = contact if math.isinf(k_n) else 1.0 / (1.0 / k_n + 1.0 / contact)
    fc = math.sqrt(8.0 * math.pi * phi * (1.0 / math.sqrt(math.pi)) ** 3)
    dc = math.sqrt(2.0 * math.pi * phi / math.sqrt(math.pi))
    stretch = fk / ks
    sigma = sigma_n * (dc if roughness_scale == "rigid_brush" else stretch)
    rng = np.random.default_rng(seed)
    forces = np.empty(reps)
    attached = np.empty(reps)
    for i in range(reps):
        result = independent_pillars_pull_off(sigma * rng.standard_normal(n), preload_n * fc,
                                              series_stiffness=ks, critical_force=fk)
        forces[i] = result.adhesive_force / fc
        attached[i] = result.attached
    mean = float(forces.mean())
    return IndependentRoughBrush(
        adhesive_force=mean,
        standard_error=float(forces.std(ddof=1) / math.sqrt(reps)) if reps > 1 else 0.0,
        adhesion_coefficient=mean / preload_n,
        attached=float(attached.mean()),
        critical_elongation=stretch / dc,
        single_pillar_force=fk / fc,
    )


def independent_gaussian_plateau(roughness_by_elongation):
    """Plateau force of an infinite Gaussian brush of independent pillars, per pillar, over F_K.

    Every pillar attached (a preload far beyond the reach of the shortest), lengths
    N(0, sigma), each pillar detaching at stretch Delta_l = F_K / k_s: the mean
    force per pillar at base displacement d (from the mean length) is
    ``k_s [d Q(a) + sigma phi(a)]`` with ``a = -(d + Delta_l) / sigma`` (Q the
    normal upper tail, phi its density: the pillars still attached are those
    with z > -d - Delta_l).  The plateau is its largest tension over d, a
    one-dimensional maximisation, returned as F_A / (n F_K).  It is 1 at
    sigma = 0 (every pillar detaches at once) and falls as sigma / Delta_l grows
    (only the pillars within Delta_l of detachment pull while the others still push).

    Parameters
    ----------
    roughness_by_elongation : float
        sigma / Delta_l, dimensionless; non-negative.

    Returns
    -------
    float
        F_A / (n F_K), dimensionless, in [0, 1].
    """
    from scipy.optimize import minimize_scalar
    from scipy.stats import norm

    s = float(_nonnegative("roughness_by_elongation", roughness_by_elongation))
    if s == 0.0:
        return 1.0

    def force(d):  # mean force per pillar over F_K = k_s Delta_l, with d in units of Delta_l
        a = -(d + 1.0) / s
        return d * norm.sf(a) + s * norm.pdf(a)

    result = minimize_scalar(force, bounds=(-1.0 - 10.0 * s, 10.0 * s), method="bounded",
                             options={"xatol": 1e-12})
    return float(min(1.0, max(0.0, -result.fun)))
