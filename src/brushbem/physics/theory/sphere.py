"""Adhesive sphere (paraboloid) contact: JKR closed forms (thesis ch. 1-2).

JKR (eq. 1.1, 2.20-2.27): the force and displacement along the contact radius,
the total energy, the normalised curve, the points B (zero force), C (pull-off,
force minimum) and D (separation under displacement control), the stable branch
for a given displacement and the rigid sphere's work of separation.  Hertz
without adhesion, DMT, Tabor and Maugis (eq. 1.2-1.5) are in
:mod:`brushbem.physics.theory.sphere_regimes` and re-exported here.  The sphere on a
spring is in :mod:`brushbem.physics.theory.sphere_spring`.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import optimize

from brushbem.physics.theory._common import _finite, _nonnegative, _out, _positive
from brushbem.physics.theory.sphere_regimes import (
    dmt_pull_off_force,
    hertz_contact_radius,
    hertz_force,
    hertz_max_pressure,
    maugis_parameter,
    tabor_parameter,
)
from brushbem.physics.theory.sphere_spring import sphere_spring_work_of_separation
from brushbem.physics import scales

__all__ = [  # noqa: RUF022 - in the thesis's order
    "hertz_force",
    "hertz_contact_radius",
    "hertz_max_pressure",
    "jkr_force_from_radius",
    "jkr_displacement_from_radius",
    "jkr_total_energy",
    "jkr_normalized_force",
    "jkr_normalized_displacement",
    "jkr_pull_off_force",
    "jkr_pull_off_radius",
    "jkr_pull_off_displacement",
    "jkr_zero_force_radius",
    "jkr_separation_radius",
    "jkr_separation_force",
    "jkr_separation_displacement",
    "jkr_radius_from_displacement",
    "jkr_force_from_displacement",
    "jkr_work_of_separation",
    "dmt_pull_off_force",
    "tabor_parameter",
    "maugis_parameter",
]


# ---------------------------------------------------------------------------
# JKR (eq. 1.1, 2.20-2.27), tip profile r**2 / (2 R)
# ---------------------------------------------------------------------------


def jkr_force_from_radius(contact_radius, radius, *, contact_modulus, work_of_adhesion):
    """JKR force at contact radius a, ``4 E* a**3 / (3 R) - sqrt(8 pi dgamma E* a**3)`` (eq. 2.22).

    Parameters
    ----------
    contact_radius : float or array_like
        Contact radius a, in units of length; non-negative.
    radius : float or array_like
        Radius of curvature R of the tip, in units of length; positive.
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative
        (zero gives Hertz).

    Returns
    -------
    float or ndarray
        Normal force, compressive positive (negative in the adhesive part), in
        units of force.
    """
    a = _nonnegative("contact_radius", contact_radius)
    modulus = _positive("contact_modulus", contact_modulus)
    dgamma = _nonnegative("work_of_adhesion", work_of_adhesion)
    r = _positive("radius", radius)
    return _out(4.0 * modulus * a**3 / (3.0 * r) - np.sqrt(8.0 * np.pi * dgamma * modulus * a**3))


def jkr_displacement_from_radius(contact_radius, radius, *, contact_modulus, work_of_adhesion):
    """JKR displacement at contact radius a, ``a**2 / R - sqrt(2 pi dgamma a / E*)``.

    The Hertz indentation minus the rigid-punch lift-off of the adhesive stress
    field (the relation substituted into eq. 2.23 to get eq. 2.32).

    Parameters
    ----------
    contact_radius : float or array_like
        Contact radius a, in units of length; non-negative.
    radius : float or array_like
        Radius of curvature R of the tip, in units of length; positive.
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.

    Returns
    -------
    float or ndarray
        Signed indentation d (negative: the tip is above the undeformed surface),
        in units of length.
    """
    a = _nonnegative("contact_radius", contact_radius)
    modulus = _positive("contact_modulus", contact_modulus)
    dgamma = _nonnegative("work_of_adhesion", work_of_adhesion)
    r = _positive("radius", radius)
    return _out(a**2 / r - np.sqrt(2.0 * np.pi * dgamma * a / modulus))


def jkr_total_energy(contact_radius, displacement, radius, *, contact_modulus, work_of_adhesion):
    """Total energy of a rigid paraboloid at contact radius a and indentation d (eq. 2.23).

    ``U = E* (d**2 a - 2/3 d a**3 / R + a**5 / (5 R**2)) - pi dgamma a**2``: elastic
    energy of the half-space plus surface energy.  Its partial derivative in d is
    the force, and it is stationary in a on the JKR curve.

    Parameters
    ----------
    contact_radius : float or array_like
        Contact radius a, in units of length; non-negative.
    displacement : float or array_like
        Indentation d, in units of length; finite.
    radius : float or array_like
        Radius of curvature R of the tip, in units of length; positive.
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.

    Returns
    -------
    float or ndarray
        Total energy U_tot, in units of energy.
    """
    a = _nonnegative("contact_radius", contact_radius)
    d = _finite("displacement", displacement)
    modulus = _positive("contact_modulus", contact_modulus)
    dgamma = _nonnegative("work_of_adhesion", work_of_adhesion)
    r = _positive("radius", radius)
    elastic = modulus * (d**2 * a - 2.0 / 3.0 * d * a**3 / r + a**5 / (5.0 * r**2))
    return _out(elastic - np.pi * dgamma * a**2)


def jkr_normalized_force(normalized_radius):
    """Dimensionless JKR force ``F / F_JKR = a~**3 - 2 a~**1.5`` (eq. 2.24), ``a~ = a / a_JKR``.

    Parameters
    ----------
    normalized_radius : float or array_like
        Contact radius over :func:`jkr_pull_off_radius`, dimensionless; non-negative.

    Returns
    -------
    float or ndarray
        Force over :func:`jkr_pull_off_force`, compressive positive (``-1`` at a~ = 1).
    """
    a = _nonnegative("normalized_radius", normalized_radius)
    return _out(a**3 - 2.0 * a**1.5)


def jkr_normalized_displacement(normalized_radius):
    """Dimensionless JKR displacement ``d / |d_JKR| = 3 a~**2 - 4 a~**0.5`` (eq. 2.24).

    Eq. 2.21 writes ``d~ = d / d_JKR`` with the negative d_JKR of eq. 2.20b, which
    would flip the sign of eq. 2.24; eq. 2.24 (and Figure 2-7) is the form divided
    by the *magnitude* ``|d_JKR|``, so this function returns ``-1`` at ``a~ = 1``.

    Parameters
    ----------
    normalized_radius : float or array_like
        Contact radius over :func:`jkr_pull_off_radius`, dimensionless; non-negative.

    Returns
    -------
    float or ndarray
        Signed displacement over ``|d_JKR|``, dimensionless.
    """
    a = _nonnegative("normalized_radius", normalized_radius)
    return _out(3.0 * a**2 - 4.0 * np.sqrt(a))


def jkr_pull_off_force(radius, *, work_of_adhesion):
    """JKR adhesive force ``F_JKR = 3/2 pi R dgamma`` (eq. 1.1, 2.20a); force minimum, point C.

    Independent of the contact modulus, like :func:`dmt_pull_off_force`.

    Parameters
    ----------
    radius : float or array_like
        Radius of curvature R of the tip, in units of length; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.

    Returns
    -------
    float or ndarray
        Magnitude of the pull-off force (the force at C is ``-F_JKR``), in units of force.
    """
    dgamma = _nonnegative("work_of_adhesion", work_of_adhesion)
    r = _positive("radius", radius)
    return _out(1.5 * np.pi * r * dgamma)


def jkr_pull_off_radius(radius, *, contact_modulus, work_of_adhesion):
    """Contact radius at the JKR force minimum, ``a_JKR = (9 pi dgamma R**2 / (8 E*))**(1/3)`` (eq. 2.20b).

    Parameters
    ----------
    radius : float or array_like
        Radius of curvature R of the tip, in units of length; positive.
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.

    Returns
    -------
    float or ndarray
        Contact radius a_JKR at point C, in units of length.
    """
    modulus = _positive("contact_modulus", contact_modulus)
    dgamma = _nonnegative("work_of_adhesion", work_of_adhesion)
    r = _positive("radius", radius)
    return _out(scales.jkr_contact_radius(r, modulus, dgamma))


def jkr_pull_off_displacement(radius, *, contact_modulus, work_of_adhesion):
    """Displacement at the JKR force minimum, ``d_JKR = -(3 pi**2 dgamma**2 R / (64 E*^2))**(1/3)`` (eq. 2.20b).

    This is the displacement at point C (largest tensile force); under
    displacement control the contact survives beyond it, down to
    :func:`jkr_separation_displacement`.

    Parameters
    ----------
    radius : float or array_like
        Radius of curvature R of the tip, in units of length; positive.
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.

    Returns
    -------
    float or ndarray
        Signed displacement d_JKR (negative), in units of length.
    """
    modulus = _positive("contact_modulus", contact_modulus)
    dgamma = _nonnegative("work_of_adhesion", work_of_adhesion)
    r = _positive("radius", radius)
    return _out(-np.cbrt(3.0 * np.pi**2 * dgamma**2 * r / (64.0 * modulus**2)))


def jkr_zero_force_radius(radius, *, contact_modulus, work_of_adhesion):
    """Contact radius at zero load (point B), ``2**(2/3) a_JKR`` (from eq. 2.24 with F~ = 0).

    Parameters
    ----------
    radius : float or array_like
        Radius of curvature R of the tip, in units of length; positive.
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.

    Returns
    -------
    float or ndarray
        Contact radius a_0, in units of length.
    """
    a_jkr = jkr_pull_off_radius(radius, contact_modulus=contact_modulus, work_of_adhesion=work_of_adhesion)
    return _out(2.0 ** (2.0 / 3.0) * np.asarray(a_jkr))


def jkr_separation_radius(radius, *, contact_modulus, work_of_adhesion):
    """Contact radius at separation under displacement control (point D), ``(1/3)**(2/3) a_JKR``.

    Point D is the minimum of the displacement, ``dd/da = 0`` (eq. 2.24 and text).

    Parameters
    ----------
    radius : float or array_like
        Radius of curvature R of the tip, in units of length; positive.
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.

    Returns
    -------
    float or ndarray
        Contact radius a_s, in units of length.
    """
    a_jkr = jkr_pull_off_radius(radius, contact_modulus=contact_modulus, work_of_adhesion=work_of_adhesion)
    return _out((1.0 / 3.0) ** (2.0 / 3.0) * np.asarray(a_jkr))


def jkr_separation_force(radius, *, work_of_adhesion):
    """Force magnitude at separation under displacement control (point D), ``5/9 F_JKR = 5/6 pi R dgamma``.

    Parameters
    ----------
    radius : float or array_like
        Radius of curvature R of the tip, in units of length; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.

    Returns
    -------
    float or ndarray
        Magnitude of the (tensile) force at D, in units of force.
    """
    return _out(5.0 / 9.0 * np.asarray(jkr_pull_off_force(radius, work_of_adhesion=work_of_adhesion)))


def jkr_separation_displacement(radius, *, contact_modulus, work_of_adhesion):
    """Displacement at separation under displacement control (point D), ``3**(2/3) d_JKR``.

    From eq. 2.24 at ``a~ = (1/3)**(2/3)``: ``d / |d_JKR| = -3**(2/3)``.

    Parameters
    ----------
    radius : float or array_like
        Radius of curvature R of the tip, in units of length; positive.
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.

    Returns
    -------
    float or ndarray
        Signed displacement d_s (negative, the most negative reachable), in units of length.
    """
    d_jkr = jkr_pull_off_displacement(radius, contact_modulus=contact_modulus, work_of_adhesion=work_of_adhesion)
    return _out(3.0 ** (2.0 / 3.0) * np.asarray(d_jkr))


def _jkr_radius_scalar(d: float, modulus: float, dgamma: float, r: float) -> float:
    """Stable-branch JKR contact radius for one displacement (see the public function)."""
    if dgamma == 0.0:  # Hertz: d = a**2 / R, separation at d = 0
        if d < 0.0:
            raise ValueError(
                f"displacement must be >= 0 (the separation displacement) without adhesion; got {d!r}"
            )
        return math.sqrt(r * d)
    a_jkr = math.cbrt(9.0 * math.pi * dgamma * r**2 / (8.0 * modulus))
    d_jkr_magnitude = math.cbrt(3.0 * math.pi**2 * dgamma**2 * r / (64.0 * modulus**2))
    target = d / d_jkr_magnitude
    a_sep = (1.0 / 3.0) ** (2.0 / 3.0)
    d_sep = -(3.0 ** (2.0 / 3.0))
    # Below d_sep there is no equilibrium; allow a rounding-sized excess at d_sep itself.
    if target < d_sep * (1.0 + 8.0 * np.finfo(float).eps):
        raise ValueError(
            f"displacement must be >= the JKR separation displacement {d_sep * d_jkr_magnitude!r}; got {d!r}"
        )
    if target <= d_sep:
        return a_sep * a_jkr
    # 3 a**2 - 4 sqrt(a) is increasing for a > a_sep; at a = 2 + sqrt|target| it is
    # >= 4 + 8 x + 3 x**2 > |target| (using sqrt(2 + x) <= 2 + x), so the bracket holds.
    upper = 2.0 + math.sqrt(abs(target))

    def residual(a: float) -> float:
        return 3.0 * a**2 - 4.0 * math.sqrt(a) - target

    root = optimize.brentq(residual, a_sep, upper, xtol=1e-15, rtol=4.0 * np.finfo(float).eps, maxiter=200)
    return root * a_jkr


def jkr_radius_from_displacement(displacement, radius, *, contact_modulus, work_of_adhesion):
    """JKR contact radius on the stable branch for a given indentation.

    Inverts ``d(a) = a**2 / R - sqrt(2 pi dgamma a / E*)`` for the largest root
    ``a >= a_s`` (the branch followed under displacement control) with
    :func:`scipy.optimize.brentq` on the dimensionless form of eq. 2.24.

    Parameters
    ----------
    displacement : float or array_like
        Indentation d, in units of length; ``d >= d_s``
        (:func:`jkr_separation_displacement`).
    radius : float or array_like
        Radius of curvature R of the tip, in units of length; positive.
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative (zero:
        Hertz, ``d >= 0`` required).

    Returns
    -------
    float or ndarray
        Contact radius a, in units of length.

    Raises
    ------
    ValueError
        If ``displacement`` is below the separation displacement (no contact
        equilibrium exists there) or any input is invalid.
    """
    d = _finite("displacement", displacement)
    modulus = _positive("contact_modulus", contact_modulus)
    dgamma = _nonnegative("work_of_adhesion", work_of_adhesion)
    r = _positive("radius", radius)
    d, modulus, dgamma, r = np.broadcast_arrays(d, modulus, dgamma, r)
    result = np.empty(d.shape)
    for index in np.ndindex(d.shape):
        result[index] = _jkr_radius_scalar(float(d[index]), float(modulus[index]), float(dgamma[index]), float(r[index]))
    return _out(result)


def jkr_force_from_displacement(displacement, radius, *, contact_modulus, work_of_adhesion):
    """JKR force on the stable branch for a given indentation (displacement control).

    Parameters
    ----------
    displacement : float or array_like
        Indentation d, in units of length; ``d >= d_s``
        (:func:`jkr_separation_displacement`).
    radius : float or array_like
        Radius of curvature R of the tip, in units of length; positive.
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.

    Returns
    -------
    float or ndarray
        Normal force, compressive positive, in units of force.

    Raises
    ------
    ValueError
        If ``displacement`` is below the separation displacement or any input is invalid.
    """
    a = jkr_radius_from_displacement(displacement, radius,
                                     contact_modulus=contact_modulus, work_of_adhesion=work_of_adhesion)
    return jkr_force_from_radius(a, radius, contact_modulus=contact_modulus, work_of_adhesion=work_of_adhesion)


def jkr_work_of_separation(radius, *, contact_modulus, work_of_adhesion):
    """Work to separate a rigid sphere from zero load (B) to separation (D), ``U_tot(a_s) - U_tot(a_0)`` (eq. 2.27).

    Equal to ``U_nor * (4/5 * 4**(-2/3) + 6/5 * 3**(4/3))`` with U_nor from
    :func:`sphere_normalization_energy`.

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
        Work of separation w_0, in units of energy.
    """
    return sphere_spring_work_of_separation(radius, np.inf,
                                            contact_modulus=contact_modulus, work_of_adhesion=work_of_adhesion)
