"""JKR sphere on a spring: works of separation (thesis ch. 2, eq. 2.28-2.39).

The normalisation scales a_nor, U_nor and k_bar (eq. 2.33-2.36), the normalised
total energy along the JKR curve (eq. 2.37), the contact radius at which the
sphere on a spring separates under base-displacement control and the exact
work of separation it gives, the thesis's stiff- and soft-spring
approximations (eq. 2.38-2.39) and its switch between them, the work counted
from a small preload's contact radius, the Hertz preload contact radius and
the dimensional work of separation.

The exact work (the default of every ``sphere_spring_work*`` function)
-----------------------------------------------------------------------
In the units a_nor (eq. 2.33), ``d_nor = a_nor**2 / R``,
``F_nor = 2/3 pi dgamma R`` and U_nor (eq. 2.34, ``U_nor = 3/4 F_nor d_nor``),
with ``a = a_bar`` and compressive-positive F and d (``_common``), the JKR curve
(eq. 2.22 and its d) and the base displacement of the spring read::

    F_bar = a**3 - 3 a**1.5,   d_bar = a**2 - 2 a**0.5,
    D_bar = d_bar + F / k = a**2 - 2 a**0.5 + 4 / (3 k_bar) (a**3 - 3 a**1.5).

On retraction (D decreasing) the contact follows the JKR curve while
``dD/da > 0`` and jumps off where ``dD/da = 0``.  With ``t = a**1.5``,
``a**0.5 dD_bar/da = (2 t - 1) - (4 / k_bar) a (3/2 - t)``, so the jump is at
the root t* of::

    (2 t - 1) / (t**(2/3) (3/2 - t)) = 4 / k_bar.

The left side increases strictly from 0 at t = 1/2 to +inf at t = 3/2 (its
logarithmic derivative ``1/(t - 1/2) - 2/(3t) + 1/(3/2 - t)`` is positive there)
and ``dD/da`` has the sign of ``2t - 1 < 0`` below 1/2 and of ``t - 3/2 > 0``
above 3/2, so for every ``0 < k_bar < inf`` there is exactly one root,
``1/2 < t* < 3/2``: the separation always happens strictly between D
(``t = 1/2``, the rigid sphere's jump, reached as k_bar -> inf) and C
(``t = 3/2``, the force minimum, reached as k_bar -> 0); it is never at
``a -> 0`` (dD/da -> -inf there) and there is no stiffness at which the rigid
jump at D itself applies other than ``k_bar = inf``.  (Equivalently
``4 s**5 + 2 k_bar s**3 - 6 s**2 - k_bar = 0`` with ``s = a**0.5``, a quintic
with one sign change, hence one positive root; it has no closed form, so t* is
found by :func:`scipy.optimize.brentq` on ``[1/2, 3/2]``.)

Along the JKR branch the system is in equilibrium, so ``dU_tot,sp = F dD``
(eq. 2.28 with eq. 2.23): the work of the tensile force from F = 0 (B) to the
jump is the energy difference, and nothing is added after it (the force drops
to zero)::

    w_bar = (U_bar_sp(a*) - U_bar(a_o)) / (U_bar(a_s) - U_bar(a_o))      (eq. 2.37 at a*),

the thesis's eq. 2.38 with a_s replaced by ``a* = (t*)**(2/3)``.  Since
``dU_sp/da = F dD/da`` with F < 0 on (0, a_o), U_sp rises as a falls from a_o
to a* and falls below it: a* is the maximum of U_sp over the branch, so

* eq. 2.38 (U_sp at D) and eq. 2.39 (U_sp at C) are both LOWER BOUNDS of the
  exact work, at every k_bar;
* the error of a root a* is of second order in the work;
* ``w_bar - w_bar_h = (40/9) 4**(-1/3) / (W_0 k_bar**2) + O(k_bar**-3)`` as
  k_bar -> inf and ``w_bar - w_bar_l = (2/3)**(4/3) k_bar / W_0 + O(k_bar**2)``
  as k_bar -> 0 (``W_0 = U_bar(a_s) - U_bar(a_o) = 5.509``; from the
  second-order expansion of U_sp about D and C), so the exact work shares the
  1/k_bar terms of eq. 2.38 (stiff) and eq. 2.39 (soft) and tends to 1 and to
  ``4.5 / (W_0 k_bar)`` respectively.

The thesis instead uses eq. 2.39 below k_bar = 1.7 and eq. 2.38 above
(Fig. 2-9): 11.6 % below the exact work just above the switch, with a jump of
2 % there.  ``switch=`` reproduces that piecewise curve.
"""

from __future__ import annotations

import math
from typing import Final

import numpy as np
from scipy import optimize

from brushbem.physics.theory._common import _nonnegative, _out, _positive

__all__ = [  # noqa: RUF022 - in the thesis's order
    "SPHERE_ABAR_ZERO_FORCE",
    "SPHERE_ABAR_SEPARATION",
    "SPHERE_ABAR_PULL_OFF",
    "SPHERE_WORK_SWITCH",
    "sphere_normalization_radius",
    "sphere_normalization_energy",
    "sphere_normalized_stiffness",
    "sphere_spring_energy_normalized",
    "sphere_spring_separation_radius",
    "sphere_spring_work_high",
    "sphere_spring_work_low",
    "sphere_spring_work",
    "sphere_spring_work_of_separation",
    "sphere_spring_work_from_preload",
    "sphere_preload_contact_radius",
]


# ---------------------------------------------------------------------------
# Sphere on a spring: works of separation (eq. 2.28-2.39)
# ---------------------------------------------------------------------------
# In the a_bar = a / a_nor scale, a_JKR / a_nor = (9/4)**(1/3), so the points of the
# JKR curve (eq. 2.24, a~ = a / a_JKR) are a_bar = a~ * (9/4)**(1/3):
#   B (F = 0):      a~ = 2**(2/3)      -> a_bar = 9**(1/3) = 3**(2/3)  (a_bar**1.5 = 3)
#   D (dd/da = 0):  a~ = (1/3)**(2/3)  -> a_bar = 4**(-1/3)            (a_bar**1.5 = 1/2)
#   C (F = -F_JKR): a~ = 1             -> a_bar = (9/4)**(1/3)         (a_bar**1.5 = 3/2)

SPHERE_ABAR_ZERO_FORCE: Final[float] = 3.0 ** (2.0 / 3.0)
"""Normalised contact radius a_bar_o at zero force (point B), ``3**(2/3)``."""

SPHERE_ABAR_SEPARATION: Final[float] = 4.0 ** (-1.0 / 3.0)
"""Normalised contact radius a_bar_s at displacement-controlled separation (point D), ``4**(-1/3)``."""

SPHERE_ABAR_PULL_OFF: Final[float] = (9.0 / 4.0) ** (1.0 / 3.0)
"""Normalised contact radius a_bar_c at the force minimum (point C), ``(9/4)**(1/3)``."""

SPHERE_WORK_SWITCH: Final[float] = 1.7
"""k_bar below which the thesis uses the low-stiffness work (eq. 2.39), above it eq. 2.38 (Fig. 2-9).

Not used by default: pass ``switch=SPHERE_WORK_SWITCH`` to the ``sphere_spring_work*``
functions to get the thesis's piecewise approximation instead of the exact work.
"""


def sphere_normalization_radius(radius, *, contact_modulus, work_of_adhesion):
    """Length scale of eq. 2.33, ``a_nor = (pi dgamma R**2 / (2 E*))**(1/3) = (4/9)**(1/3) a_JKR``.

    Parameters
    ----------
    radius : float or array_like
        Radius of curvature R of the tip, in units of length; positive.
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; positive.

    Returns
    -------
    float or ndarray
        a_nor, in units of length.
    """
    modulus = _positive("contact_modulus", contact_modulus)
    dgamma = _positive("work_of_adhesion", work_of_adhesion)
    r = _positive("radius", radius)
    return _out(np.cbrt(np.pi * dgamma * r**2 / (2.0 * modulus)))


def sphere_normalization_energy(radius, *, contact_modulus, work_of_adhesion):
    """Energy scale of eq. 2.34, ``U_nor = (pi**5 dgamma**5 R**4 / (2**5 E*^2))**(1/3)``.

    Equal to ``E* a_nor**5 / R**2``.

    Parameters
    ----------
    radius : float or array_like
        Radius of curvature R of the tip, in units of length; positive.
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; positive.

    Returns
    -------
    float or ndarray
        U_nor, in units of energy.
    """
    modulus = _positive("contact_modulus", contact_modulus)
    dgamma = _positive("work_of_adhesion", work_of_adhesion)
    r = _positive("radius", radius)
    # Written as (pi dgamma / 2)**(5/3) R**(4/3) E***(-2/3) to avoid overflowing dgamma**5.
    return _out((np.pi * dgamma / 2.0) ** (5.0 / 3.0) * r ** (4.0 / 3.0) * modulus ** (-2.0 / 3.0))


def sphere_normalized_stiffness(stiffness, radius, *, contact_modulus, work_of_adhesion):
    """Dimensionless pillar stiffness of eq. 2.36, ``k_bar = k / (E* a_nor)``.

    Not the same as eq. 2.21's ``k~ = k / (E* a_JKR)``: ``k_bar = (9/4)**(1/3) k~ = 1.31 k~``.

    Parameters
    ----------
    stiffness : float or array_like
        Spring stiffness k, in units of force per length; ``0 < k <= inf``.
    radius : float or array_like
        Radius of curvature R of the tip, in units of length; positive.
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; positive.

    Returns
    -------
    float or ndarray
        k_bar, dimensionless (``inf`` for a rigid connection).
    """
    k = _positive("stiffness", stiffness, allow_inf=True)
    modulus = np.asarray(_positive("contact_modulus", contact_modulus))
    a_nor = np.asarray(sphere_normalization_radius(radius, contact_modulus=contact_modulus,
                                                   work_of_adhesion=work_of_adhesion))
    return _out(k / (modulus * a_nor))


def sphere_spring_energy_normalized(normalized_radius, normalized_stiffness):
    """Normalised total energy of a JKR sphere on a spring along the JKR curve (eq. 2.37).

    ``U_bar = 8/15 a**5 - 8/3 a**3.5 + 2 a**2 + 8/9 (1/k_bar) a**3 (a**1.5 - 3)**2``
    with ``a = a_bar = a / a_nor``: half-space elastic energy plus surface energy
    (eq. 2.23 with d from the JKR curve) plus the spring energy ``F**2 / (2 k)``.
    (Eq. 2.35 prints the prefactor of the spring term as ``E* a_bar / k``; it is
    ``E* a_nor / k = 1 / k_bar``, as eq. 2.37 has it.)

    Parameters
    ----------
    normalized_radius : float or array_like
        a_bar = a / a_nor, dimensionless; non-negative.
    normalized_stiffness : float or array_like
        k_bar (:func:`sphere_normalized_stiffness`), dimensionless; ``0 < k_bar <= inf``
        (``inf``: rigid, the spring term vanishes).

    Returns
    -------
    float or ndarray
        U_bar = U / U_nor, dimensionless.
    """
    a = _nonnegative("normalized_radius", normalized_radius)
    kbar = _positive("normalized_stiffness", normalized_stiffness, allow_inf=True)
    half_space_and_surface = 8.0 / 15.0 * a**5 - 8.0 / 3.0 * a**3.5 + 2.0 * a**2
    spring = 8.0 / 9.0 / kbar * a**3 * (a**1.5 - 3.0) ** 2
    return _out(half_space_and_surface + spring)


def _sphere_rigid_work_normalized() -> float:
    """U_bar(a_bar_s) - U_bar(a_bar_o) for the rigid sphere: the denominator of eq. 2.38-2.39."""
    return float(
        sphere_spring_energy_normalized(SPHERE_ABAR_SEPARATION, np.inf)
        - sphere_spring_energy_normalized(SPHERE_ABAR_ZERO_FORCE, np.inf)
    )


def sphere_spring_work_high(normalized_stiffness):
    """The thesis's stiff-spring approximation of the work of separation, separation at D (eq. 2.38).

    ``w_bar_h = (U_bar_sp(a_s) - U_bar(a_o)) / (U_bar(a_s) - U_bar(a_o)) = 1 + (25/18) / (k_bar * 5.509...)``;
    1 for a rigid connection.  It assumes the spring leaves the rigid sphere's
    separation point D unchanged; the spring moves it towards C
    (:func:`sphere_spring_separation_radius`), so this is a lower bound of the
    exact work (:func:`sphere_spring_work`), below it by ``0.508 / k_bar**2``
    for large k_bar (2 % at k_bar = 5, 12 % at 1.7).

    Parameters
    ----------
    normalized_stiffness : float or array_like
        k_bar (:func:`sphere_normalized_stiffness`), dimensionless; ``0 < k_bar <= inf``.

    Returns
    -------
    float or ndarray
        w_bar_h, the work over the rigid sphere's work (eq. 2.27), dimensionless.
    """
    kbar = _positive("normalized_stiffness", normalized_stiffness, allow_inf=True)
    numerator = np.asarray(sphere_spring_energy_normalized(SPHERE_ABAR_SEPARATION, kbar)) - float(
        sphere_spring_energy_normalized(SPHERE_ABAR_ZERO_FORCE, np.inf)
    )
    return _out(numerator / _sphere_rigid_work_normalized())


def sphere_spring_work_low(normalized_stiffness):
    """The thesis's soft-spring approximation of the work of separation, separation at C (eq. 2.39).

    Soft springs make the contact unstable right after the force minimum, so the
    thesis evaluates the energy at point C instead of D.  The true separation is
    a little before C (:func:`sphere_spring_separation_radius`), so this is a
    lower bound of the exact work (:func:`sphere_spring_work`), below it by
    ``0.106 k_bar`` for small k_bar (0.25 % at k_bar = 0.15, 5 % at 1).

    Parameters
    ----------
    normalized_stiffness : float or array_like
        k_bar (:func:`sphere_normalized_stiffness`), dimensionless; ``0 < k_bar <= inf``.

    Returns
    -------
    float or ndarray
        w_bar_l, the work over the rigid sphere's work (eq. 2.27), dimensionless.
    """
    kbar = _positive("normalized_stiffness", normalized_stiffness, allow_inf=True)
    numerator = np.asarray(sphere_spring_energy_normalized(SPHERE_ABAR_PULL_OFF, kbar)) - float(
        sphere_spring_energy_normalized(SPHERE_ABAR_ZERO_FORCE, np.inf)
    )
    return _out(numerator / _sphere_rigid_work_normalized())


def _separation_cube(kbar: float) -> float:
    """t* = a_bar*^1.5, the root in (1/2, 3/2) of ``(2t - 1) - (4/k_bar) t**(2/3) (3/2 - t)`` (module docstring)."""
    if kbar <= 1.0:  # scaled by k_bar, so that a tiny k_bar does not overflow
        def rate(t: float) -> float:
            return kbar * (2.0 * t - 1.0) + 4.0 * t ** (2.0 / 3.0) * (t - 1.5)
    else:
        def rate(t: float) -> float:
            return (2.0 * t - 1.0) + 4.0 / kbar * t ** (2.0 / 3.0) * (t - 1.5)
    # The ends give -4 (1/2)**(2/3) min(1, 1/k_bar) < 0 and 2 min(k_bar, 1) > 0 exactly.  The work is
    # stationary at the root (dU_sp/da = F dD/da = 0), so its error is of second order in t's (~1e-15).
    return float(optimize.brentq(rate, 0.5, 1.5, xtol=1e-15, rtol=4.0 * np.finfo(float).eps))


def sphere_spring_separation_radius(normalized_stiffness):
    """Normalised contact radius a_bar* at which a JKR sphere on a spring separates.

    Under base-displacement control the contact follows the JKR curve until the
    base displacement ``D = d_JKR(a) + F_JKR(a) / k`` stops decreasing with a:
    ``dD/da = 0``, i.e. ``(2t - 1) / (t**(2/3) (3/2 - t)) = 4 / k_bar`` with
    ``t = a_bar**1.5`` (derivation and uniqueness in the module docstring).
    ``1/2 < t* < 3/2``: between D (``a_bar_s = 4**(-1/3)``, returned exactly
    for ``k_bar = inf``) and C (``a_bar_c = (9/4)**(1/3)``, the limit k_bar -> 0).

    Parameters
    ----------
    normalized_stiffness : float or array_like
        k_bar (:func:`sphere_normalized_stiffness`), dimensionless; ``0 < k_bar <= inf``.

    Returns
    -------
    float or ndarray
        a_bar* = a* / a_nor, dimensionless.
    """
    kbar = _positive("normalized_stiffness", normalized_stiffness, allow_inf=True)

    def radius(k: float) -> float:
        return SPHERE_ABAR_SEPARATION if math.isinf(k) else _separation_cube(k) ** (2.0 / 3.0)

    return _out(np.vectorize(radius, otypes=[float])(kbar))


def _end_radius(kbar: np.ndarray, switch) -> np.ndarray:
    """Contact radius at separation: exact (``switch is None``) or the thesis's C / D."""
    if switch is None:
        return np.asarray(sphere_spring_separation_radius(kbar))
    threshold = _positive("switch", switch, allow_inf=True)
    return np.where(kbar < threshold, SPHERE_ABAR_PULL_OFF, SPHERE_ABAR_SEPARATION)


def sphere_spring_work(normalized_stiffness, switch=None):
    """Normalised work of separation of a JKR sphere on a spring, from zero load (B) to separation.

    By default the exact work: the energy of eq. 2.37 at the contact radius
    where the sphere on its spring separates under base-displacement control
    (:func:`sphere_spring_separation_radius`) minus that at B, over the rigid
    sphere's work (eq. 2.27):
    ``w_bar = (U_bar_sp(a*) - U_bar(a_o)) / (U_bar(a_s) - U_bar(a_o))``.  It is
    continuous and decreasing in k_bar, 1 for a rigid connection, above both of
    the thesis's approximations (eq. 2.38-2.39) everywhere, and tends to eq. 2.38
    as ``O(k_bar**-2)`` for a stiff spring and to eq. 2.39 as ``O(k_bar)`` for a
    soft one (module docstring).

    With ``switch`` given, the thesis's piecewise approximation instead (its
    Figure 2-9): eq. 2.39 for ``k_bar < switch``, eq. 2.38 otherwise
    (``switch=SPHERE_WORK_SWITCH`` is the thesis's 1.7).  The two branches are
    equal at ``k_bar = 1.84`` (``(81/18 - 25/18) / (U_bar(a_s) - U_bar(a_c))``), so
    the thesis's switch at 1.7 leaves a jump of about 2 % (1.174 vs 1.148),
    where the exact work is 1.299.

    Parameters
    ----------
    normalized_stiffness : float or array_like
        k_bar (:func:`sphere_normalized_stiffness`), dimensionless; ``0 < k_bar <= inf``.
    switch : float, optional
        None (default): the exact work.  A positive k_bar: the thesis's
        piecewise approximation switching from eq. 2.39 to eq. 2.38 there.

    Returns
    -------
    float or ndarray
        w_bar, dimensionless.
    """
    kbar = _positive("normalized_stiffness", normalized_stiffness, allow_inf=True)
    end = _end_radius(kbar, switch)
    numerator = np.asarray(sphere_spring_energy_normalized(end, kbar)) - float(
        sphere_spring_energy_normalized(SPHERE_ABAR_ZERO_FORCE, np.inf)
    )
    return _out(numerator / _sphere_rigid_work_normalized())


def sphere_spring_work_from_preload(normalized_stiffness, normalized_preload_radius, switch=None):
    """Normalised work of separation when the unloading starts from contact radius ``a_bar_m``.

    The thesis counts the work from point B of the JKR curve (zero force,
    ``a_bar_o = 3**(2/3)``), which the unloading passes only when the preload
    pressed the contact beyond a_o.  A smaller preload contact a_m (the
    loading branch of the model is Hertz's: elements join where the tip
    touches) is first unloaded at fixed contact radius, like a punch of
    radius a_m, until the edge meets the Griffith condition on the JKR curve
    at a_m; the force crosses zero on that line, at d = a_m^2 / (3R), where
    eq. 2.23 gives the total energy ``E* 4/45 a_m^5 / R^2 - pi dgamma a_m^2``,
    in units of U_nor ``4/45 a_bar_m**5 - 2 a_bar_m**2`` (equal to eq. 2.37's
    U_bar(a_bar_o) at a_bar_m = a_bar_o).  Both stretches are free of
    dissipation, so the work from the zero crossing to the end is the
    difference of total energies:

        w_bar = (U_bar_sp(min(a_bar_m, a_bar_end)) - U_bar_start) / (U_bar(a_bar_s) - U_bar(a_bar_o)),
        U_bar_start = 4/45 a_z**5 - 2 a_z**2,  a_z = min(a_bar_m, a_bar_o),

    with the end at the exact separation radius a_bar* of the sphere on its
    spring (:func:`sphere_spring_separation_radius`) or, with ``switch`` given,
    the thesis's approximation of it: D (a_bar_s, eq. 2.38) at and above
    ``switch``, C (a_bar_c, eq. 2.39) below.  A contact that never grew past
    the end radius comes off where the fixed-contact line meets the JKR curve
    (dD/da < 0 there, so the JKR branch is unstable at once).  For
    ``a_bar_m >= a_bar_o`` this is :func:`sphere_spring_work`.

    Parameters
    ----------
    normalized_stiffness : float or array_like
        k_bar (:func:`sphere_normalized_stiffness`), dimensionless; ``0 < k_bar <= inf``.
    normalized_preload_radius : float or array_like
        a_bar_m = a_m / a_nor, the largest contact radius of the loading; positive (inf: beyond B).
    switch : float, optional
        None (default): the exact end a_bar*.  A positive k_bar: the thesis's
        approximation, C (eq. 2.39) below it and D (eq. 2.38) from it on.

    Returns
    -------
    float or ndarray
        w_bar, the work over the rigid sphere's work from B (eq. 2.27), dimensionless.
    """
    kbar = _positive("normalized_stiffness", normalized_stiffness, allow_inf=True)
    a_m = _positive("normalized_preload_radius", normalized_preload_radius, allow_inf=True)
    end = np.minimum(a_m, _end_radius(kbar, switch))
    a_z = np.minimum(a_m, SPHERE_ABAR_ZERO_FORCE)
    start = 4.0 / 45.0 * a_z**5 - 2.0 * a_z**2
    numerator = np.asarray(sphere_spring_energy_normalized(end, kbar)) - start
    return _out(numerator / _sphere_rigid_work_normalized())


def sphere_preload_contact_radius(radius, stiffness, preload_force=None, preload_displacement=None, *,
                                  contact_modulus):
    """Contact radius at the end of the loading of a sphere on a spring (Hertz, eq. 2.22 with dgamma = 0).

    Elements join where the tip touches, so the loading branch is Hertz's:
    ``F = 4 E* a^3 / (3 R)`` at a base displacement ``d = a^2 / R + F / k``.
    Give exactly one of ``preload_force`` and ``preload_displacement``.

    Parameters
    ----------
    radius : float
        Radius of curvature R of the tip, in units of length; positive.
    stiffness : float
        Spring stiffness k, in units of force per length; ``0 < k <= inf``.
    preload_force, preload_displacement : float, optional
        The preload, in units of force or of length; positive.
    contact_modulus : float
        Contact modulus E*, in units of stress; positive.

    Returns
    -------
    float
        a_m, in units of length.
    """
    modulus = float(_positive("contact_modulus", contact_modulus))
    r = float(_positive("radius", radius))
    k = float(_positive("stiffness", stiffness, allow_inf=True))
    if (preload_force is None) == (preload_displacement is None):
        raise ValueError("give exactly one of preload_force and preload_displacement")
    if preload_force is not None:
        force = float(_positive("preload_force", preload_force))
        return float(np.cbrt(3.0 * force * r / (4.0 * modulus)))
    d = float(_positive("preload_displacement", preload_displacement))
    a_rigid = math.sqrt(d * r)
    if not math.isfinite(k):
        return a_rigid

    def excess(a: float) -> float:
        return a * a / r + 4.0 * modulus * a**3 / (3.0 * r * k) - d

    return float(optimize.brentq(excess, 0.0, a_rigid, xtol=1e-15 * a_rigid, rtol=1e-14))


def sphere_spring_work_of_separation(radius, stiffness, switch=None, preload_radius=math.inf, *,
                                     contact_modulus, work_of_adhesion):
    """Work of separation of a JKR sphere on a spring, from zero load to separation.

    ``w = w_bar(k_bar) * (U_tot(a_s) - U_tot(a_o))`` (eq. 2.27-2.37), with
    w_bar the exact work of :func:`sphere_spring_work` (separation where the
    base displacement is stationary, dD/da = 0), or with ``switch`` given the
    thesis's piecewise eq. 2.38-2.39, and, where the preload contact radius is
    below a_o (point B), counted from the zero crossing of the fixed-contact
    unloading line (:func:`sphere_spring_work_from_preload`).

    Parameters
    ----------
    radius : float or array_like
        Radius of curvature R of the tip, in units of length; positive.
    stiffness : float or array_like
        Spring stiffness k, in units of force per length; ``0 < k <= inf``.
    switch : float, optional
        None (default): the exact work.  A positive k_bar: the thesis's
        approximation, eq. 2.39 below it and eq. 2.38 from it on.
    preload_radius : float or array_like, optional
        Largest contact radius of the loading (:func:`sphere_preload_contact_radius`),
        in units of length; default inf (beyond B, the thesis's case).
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; positive.

    Returns
    -------
    float or ndarray
        Work of separation, in units of energy.
    """
    kbar = np.asarray(sphere_normalized_stiffness(stiffness, radius, contact_modulus=contact_modulus,
                                                  work_of_adhesion=work_of_adhesion))
    u_nor = np.asarray(sphere_normalization_energy(radius, contact_modulus=contact_modulus,
                                                   work_of_adhesion=work_of_adhesion))
    a_m = np.asarray(_positive("preload_radius", preload_radius, allow_inf=True)) / np.asarray(
        sphere_normalization_radius(radius, contact_modulus=contact_modulus, work_of_adhesion=work_of_adhesion))
    w_bar = np.asarray(sphere_spring_work_from_preload(kbar, a_m, switch))
    return _out(w_bar * _sphere_rigid_work_normalized() * u_nor)
