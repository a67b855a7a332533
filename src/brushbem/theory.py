"""Closed-form limits of adhesive contact: the thesis's analytical reference solutions.

Every function here is a pure function of plain floats (most broadcast over NumPy
arrays): no state, no side effects, no logging.  They are the rungs the numerical
model is checked against (DESIGN.md, section 5) and the scales the thesis uses to
make its results dimensionless.

Sign convention (the same as everywhere in brushbem)
----------------------------------------------------
* The base displacement ``d`` is positive when the indenter presses *into* the
  half-space; a negative ``d`` means the indenter is pulled away from the surface.
* Forces and pressures are positive when *compressive*.  A curve ``F(a)`` or
  ``F(d)`` (for example :func:`jkr_force_from_radius`) is therefore negative in the
  adhesive (tensile) part of a pull-off.
* Characteristic adhesive forces (Kendall, JKR, DMT, rigid and soft brushes,
  functions named ``..._force``) are returned as POSITIVE MAGNITUDES: the adhesive
  force ``F_A = -min F`` of DESIGN.md.
* Critical displacements (functions named ``..._displacement``) are returned
  SIGNED in the brushbem convention: negative means pulled away from the surface.
  The thesis writes some of them with a sign (eq. 2.4a, 2.20b) and some as
  magnitudes (eq. 2.15, 4.12, 5.4); here they all carry their sign.

Material and units
------------------
The half-space enters only through the contact modulus ``contact_modulus``
``E* = E / (1 - nu**2)`` (a rigid indenter on an elastic half-space; see
:func:`contact_modulus_from`) and the work of adhesion ``work_of_adhesion``
``dgamma`` (energy per unit area, the thesis's "surface energy per unit area").
Any consistent system of units works: lengths in L, stresses and moduli in F/L**2,
works of adhesion in F/L, forces in F, stiffnesses in F/L, energies in F*L.

Input validation
----------------
Every function checks its arguments and raises :class:`ValueError` naming the
parameter, the offending value and the allowed range (NaN, zero or negative
moduli, radii, areas and so on).  A spring ``stiffness`` may be ``inf`` where that
means a rigid connection.  The work of adhesion may be zero in the curve formulas
(which then reduce to the non-adhesive solution) but must be positive where it sets
a scale.

References are to equation numbers of the thesis (seed document): Kendall flat
punch eq. 2.1-2.8, punch on a spring eq. 2.17-2.19, JKR eq. 2.20-2.24, sphere on a
spring eq. 2.32-2.39, brushes eq. 4.5-4.18 and 5.3-5.8, hierarchy eq. 6.20-6.28,
concave profile eq. 7.1-7.4, Tabor and Maugis eq. 1.3-1.5.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Final

import numpy as np
from scipy import optimize, special

__all__ = [  # noqa: RUF022 - grouped by thesis chapter
    # material
    "contact_modulus_from",
    # Kendall flat punch
    "punch_stiffness",
    "kendall_force",
    "kendall_displacement",
    "kendall_work_of_separation",
    # punch on a spring
    "normalized_punch_stiffness",
    "punch_spring_work_of_separation",
    "punch_spring_separation_displacement",
    # Hertz
    "hertz_force",
    "hertz_contact_radius",
    "hertz_max_pressure",
    # JKR
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
    # DMT, Tabor, Maugis
    "dmt_pull_off_force",
    "tabor_parameter",
    "maugis_parameter",
    # sphere on a spring
    "SPHERE_ABAR_ZERO_FORCE",
    "SPHERE_ABAR_SEPARATION",
    "SPHERE_ABAR_PULL_OFF",
    "SPHERE_WORK_SWITCH",
    "sphere_normalization_radius",
    "sphere_normalization_energy",
    "sphere_normalized_stiffness",
    "sphere_spring_energy_normalized",
    "sphere_spring_work_high",
    "sphere_spring_work_low",
    "sphere_spring_work",
    "sphere_spring_work_of_separation",
    "sphere_spring_work_from_preload",
    "sphere_preload_contact_radius",
    # brushes
    "rigid_brush_force",
    "rigid_brush_displacement",
    "compact_punch_force",
    "rigid_brush_enhancement",
    "soft_brush_enhancement",
    "soft_brush_force",
    "ideal_sharing_force",
    "soft_brush_work_of_separation",
    "soft_brush_work_normalized",
    "adhesion_coefficient",
    "critical_roughness",
    # hierarchy
    "hierarchy_stiffnesses",
    "total_filling_factor",
    "equivalent_single_level_stiffness",
    # concave profile
    "concave_reference_stress",
    "concave_profile",
    "concave_pillar_profile",
    "concave_offsets",
]

# ---------------------------------------------------------------------------
# Input validation (private helpers)
# ---------------------------------------------------------------------------


def _as_real_array(name: str, value: object) -> np.ndarray:
    """Return ``value`` as a float array or raise ValueError naming ``name``."""
    if np.iscomplexobj(value):
        raise ValueError(f"{name} must be real; got {value!r}")
    try:
        array = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as error:
        raise ValueError(f"{name} must be a real number or an array of real numbers; got {value!r}") from error
    return array


def _first_offender(array: np.ndarray, bad: np.ndarray) -> str:
    """Describe the first element of ``array`` flagged by ``bad`` (for messages)."""
    if array.ndim == 0:
        return repr(float(array))
    index = tuple(int(i) for i in np.argwhere(bad)[0])
    return f"{float(array[index])!r} at index {index}"


def _check(name: str, value: object, allowed: str, is_ok) -> np.ndarray:
    """Validate ``value`` elementwise with ``is_ok``; ``allowed`` goes in the message."""
    array = _as_real_array(name, value)
    bad = ~is_ok(array)  # NaN fails every comparison, so it is always flagged
    if np.any(bad):
        raise ValueError(f"{name} must be {allowed}; got {_first_offender(array, bad)}")
    return array


def _positive(name: str, value: object, *, allow_inf: bool = False) -> np.ndarray:
    if allow_inf:
        return _check(name, value, f"positive (0 < {name} <= inf)", lambda x: x > 0)
    return _check(name, value, f"positive and finite (0 < {name} < inf)", lambda x: (x > 0) & np.isfinite(x))


def _nonnegative(name: str, value: object) -> np.ndarray:
    return _check(name, value, f"non-negative and finite (0 <= {name} < inf)", lambda x: (x >= 0) & np.isfinite(x))


def _finite(name: str, value: object) -> np.ndarray:
    return _check(name, value, f"a finite real number (-inf < {name} < inf)", np.isfinite)


def _filling_factor(name: str, value: object) -> np.ndarray:
    return _check(name, value, f"a filling factor in (0, 1] (0 < {name} <= 1)", lambda x: (x > 0) & (x <= 1))


def _count(name: str, value: object) -> np.ndarray:
    return _check(name, value, f"at least one and finite (1 <= {name} < inf)", lambda x: (x >= 1) & np.isfinite(x))


def _out(value: np.ndarray | float) -> float | np.ndarray:
    """Return a Python float for 0-d results, the array otherwise."""
    array = np.asarray(value, dtype=float)
    return float(array) if array.ndim == 0 else array


# ---------------------------------------------------------------------------
# Material
# ---------------------------------------------------------------------------


def contact_modulus_from(youngs_modulus, poisson_ratio):
    """Contact modulus of an elastic half-space pressed by a rigid indenter.

    ``E* = E / (1 - nu**2)`` (thesis eq. 2.1).  For two elastic bodies the
    compliances ``(1 - nu_i**2) / E_i`` would add; the thesis's indenters are rigid.

    Parameters
    ----------
    youngs_modulus : float or array_like
        Young's modulus E of the half-space, in units of stress; ``0 < E < inf``.
    poisson_ratio : float or array_like
        Poisson's ratio nu of the half-space, dimensionless; ``-1 < nu <= 0.5``.

    Returns
    -------
    float or ndarray
        Contact modulus E*, in units of stress.
    """
    youngs = _positive("youngs_modulus", youngs_modulus)
    nu = _check("poisson_ratio", poisson_ratio, "in (-1, 0.5] (-1 < poisson_ratio <= 0.5)", lambda x: (x > -1) & (x <= 0.5))
    return _out(youngs / (1.0 - nu**2))


# ---------------------------------------------------------------------------
# Kendall flat punch (eq. 2.1-2.7)
# ---------------------------------------------------------------------------


def punch_stiffness(contact_modulus, radius):
    """Normal contact stiffness of a rigid flat circular punch, ``2 E* r`` (eq. 2.2).

    Parameters
    ----------
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    radius : float or array_like
        Punch radius r, in units of length; positive.

    Returns
    -------
    float or ndarray
        Stiffness ``dF/dd``, in units of force per length.
    """
    modulus = _positive("contact_modulus", contact_modulus)
    r = _positive("radius", radius)
    return _out(2.0 * modulus * r)


def kendall_force(contact_modulus, work_of_adhesion, radius):
    """Kendall adhesive force of a rigid flat punch, ``sqrt(8 pi E* dgamma r**3)`` (eq. 2.4b).

    Parameters
    ----------
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.
    radius : float or array_like
        Punch radius r, in units of length; positive.

    Returns
    -------
    float or ndarray
        Magnitude of the pull-off force F_K (the force at detachment is ``-F_K``),
        in units of force.
    """
    modulus = _positive("contact_modulus", contact_modulus)
    dgamma = _nonnegative("work_of_adhesion", work_of_adhesion)
    r = _positive("radius", radius)
    return _out(np.sqrt(8.0 * np.pi * modulus * dgamma * r**3))


def kendall_displacement(contact_modulus, work_of_adhesion, radius):
    """Critical displacement of a rigid flat punch, ``-sqrt(2 pi dgamma r / E*)`` (eq. 2.4a).

    Parameters
    ----------
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.
    radius : float or array_like
        Punch radius r, in units of length; positive.

    Returns
    -------
    float or ndarray
        Signed punch displacement d_K at which the punch detaches (negative:
        pulled away from the surface), in units of length.
    """
    modulus = _positive("contact_modulus", contact_modulus)
    dgamma = _nonnegative("work_of_adhesion", work_of_adhesion)
    r = _positive("radius", radius)
    return _out(-np.sqrt(2.0 * np.pi * dgamma * r / modulus))


def kendall_work_of_separation(work_of_adhesion, radius):
    """External work to separate a rigid flat punch, ``2 pi dgamma r**2`` (eq. 2.5, 4.14).

    Half of it creates the new surface (eq. 2.7); the other half is the elastic
    energy radiated away at the unstable detachment.

    Parameters
    ----------
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.
    radius : float or array_like
        Punch radius r, in units of length; positive.

    Returns
    -------
    float or ndarray
        Work w_K done from zero indentation to separation, in units of energy.
    """
    dgamma = _nonnegative("work_of_adhesion", work_of_adhesion)
    r = _positive("radius", radius)
    return _out(2.0 * np.pi * dgamma * r**2)


# ---------------------------------------------------------------------------
# Punch on a spring (eq. 2.8, 2.16-2.19)
# ---------------------------------------------------------------------------


def normalized_punch_stiffness(stiffness, contact_modulus, radius):
    """Pillar stiffness over the punch contact stiffness, ``k~ = k / (2 E* r)`` (eq. 2.16).

    Parameters
    ----------
    stiffness : float or array_like
        Spring (pillar) stiffness k, in units of force per length; ``0 < k <= inf``
        (``inf``: rigid connection).
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    radius : float or array_like
        Punch radius r, in units of length; positive.

    Returns
    -------
    float or ndarray
        Dimensionless stiffness k~ (``inf`` for a rigid connection).
    """
    k = _positive("stiffness", stiffness, allow_inf=True)
    modulus = _positive("contact_modulus", contact_modulus)
    r = _positive("radius", radius)
    return _out(k / (2.0 * modulus * r))


def punch_spring_work_of_separation(contact_modulus, work_of_adhesion, radius, stiffness):
    """Work to separate a flat punch held by a spring, ``2 pi dgamma r**2 (1 + 1/k~)`` (eq. 2.18-2.19).

    The spring does not change the pull-off force or the punch's critical
    displacement; it stores the extra energy ``F_K**2 / (2 k)`` (eq. 2.8, 2.17).

    Parameters
    ----------
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.
    radius : float or array_like
        Punch radius r, in units of length; positive.
    stiffness : float or array_like
        Spring stiffness k, in units of force per length; ``0 < k <= inf``.
        ``inf`` gives the rigid value ``2 pi dgamma r**2``.

    Returns
    -------
    float or ndarray
        Work of separation w_ad from zero indentation, in units of energy.
    """
    k_tilde = np.asarray(normalized_punch_stiffness(stiffness, contact_modulus, radius))
    rigid_work = np.asarray(kendall_work_of_separation(work_of_adhesion, radius))
    return _out(rigid_work * (1.0 + 1.0 / k_tilde))


def punch_spring_separation_displacement(contact_modulus, work_of_adhesion, radius, stiffness):
    """Base displacement at which a flat punch on a spring separates, ``d_K - F_K / k``.

    The punch itself detaches at ``d_K`` (eq. 2.4a); the spring is then stretched
    by ``F_K / k`` (eq. 2.17), so the base has moved further away (eq. 2.8).

    Parameters
    ----------
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.
    radius : float or array_like
        Punch radius r, in units of length; positive.
    stiffness : float or array_like
        Spring stiffness k, in units of force per length; ``0 < k <= inf``.

    Returns
    -------
    float or ndarray
        Signed base displacement at separation (negative), in units of length.
    """
    k = _positive("stiffness", stiffness, allow_inf=True)
    d_k = np.asarray(kendall_displacement(contact_modulus, work_of_adhesion, radius))
    f_k = np.asarray(kendall_force(contact_modulus, work_of_adhesion, radius))
    return _out(d_k - f_k / k)


# ---------------------------------------------------------------------------
# Hertz (no adhesion)
# ---------------------------------------------------------------------------


def hertz_force(contact_modulus, radius, displacement):
    """Hertz force of a paraboloid ``r**2 / (2 R)``, ``4/3 E* sqrt(R) d**1.5``.

    Parameters
    ----------
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    radius : float or array_like
        Radius of curvature R of the tip, in units of length; positive.
    displacement : float or array_like
        Indentation d, in units of length; finite.  ``d <= 0`` means no contact
        and gives zero.

    Returns
    -------
    float or ndarray
        Normal force (compressive positive), in units of force.
    """
    modulus = _positive("contact_modulus", contact_modulus)
    r = _positive("radius", radius)
    d = np.maximum(_finite("displacement", displacement), 0.0)
    return _out(4.0 / 3.0 * modulus * np.sqrt(r) * d**1.5)


def hertz_contact_radius(radius, displacement):
    """Hertz contact radius of a paraboloid, ``sqrt(R d)``.

    Parameters
    ----------
    radius : float or array_like
        Radius of curvature R of the tip, in units of length; positive.
    displacement : float or array_like
        Indentation d, in units of length; finite (``d <= 0`` gives zero).

    Returns
    -------
    float or ndarray
        Contact radius a, in units of length.
    """
    r = _positive("radius", radius)
    d = np.maximum(_finite("displacement", displacement), 0.0)
    return _out(np.sqrt(r * d))


def hertz_max_pressure(contact_modulus, radius, displacement):
    """Hertz pressure at the centre of the contact, ``2 E* a / (pi R) = 3 F / (2 pi a**2)``.

    Parameters
    ----------
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    radius : float or array_like
        Radius of curvature R of the tip, in units of length; positive.
    displacement : float or array_like
        Indentation d, in units of length; finite (``d <= 0`` gives zero).

    Returns
    -------
    float or ndarray
        Maximum pressure p_0 (compressive positive), in units of stress.
    """
    modulus = _positive("contact_modulus", contact_modulus)
    r = _positive("radius", radius)
    d = np.maximum(_finite("displacement", displacement), 0.0)
    return _out(2.0 * modulus / np.pi * np.sqrt(d / r))


# ---------------------------------------------------------------------------
# JKR (eq. 1.1, 2.20-2.27), tip profile r**2 / (2 R)
# ---------------------------------------------------------------------------


def jkr_force_from_radius(contact_radius, contact_modulus, work_of_adhesion, radius):
    """JKR force at contact radius a, ``4 E* a**3 / (3 R) - sqrt(8 pi dgamma E* a**3)`` (eq. 2.22).

    Parameters
    ----------
    contact_radius : float or array_like
        Contact radius a, in units of length; non-negative.
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative
        (zero gives Hertz).
    radius : float or array_like
        Radius of curvature R of the tip, in units of length; positive.

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


def jkr_displacement_from_radius(contact_radius, contact_modulus, work_of_adhesion, radius):
    """JKR displacement at contact radius a, ``a**2 / R - sqrt(2 pi dgamma a / E*)``.

    The Hertz indentation minus the rigid-punch lift-off of the adhesive stress
    field (the relation substituted into eq. 2.23 to get eq. 2.32).

    Parameters
    ----------
    contact_radius : float or array_like
        Contact radius a, in units of length; non-negative.
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.
    radius : float or array_like
        Radius of curvature R of the tip, in units of length; positive.

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


def jkr_total_energy(contact_radius, displacement, contact_modulus, work_of_adhesion, radius):
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
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.
    radius : float or array_like
        Radius of curvature R of the tip, in units of length; positive.

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


def jkr_pull_off_force(work_of_adhesion, radius):
    """JKR adhesive force ``F_JKR = 3/2 pi R dgamma`` (eq. 1.1, 2.20a); force minimum, point C.

    Independent of the contact modulus, like :func:`dmt_pull_off_force`.

    Parameters
    ----------
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.
    radius : float or array_like
        Radius of curvature R of the tip, in units of length; positive.

    Returns
    -------
    float or ndarray
        Magnitude of the pull-off force (the force at C is ``-F_JKR``), in units of force.
    """
    dgamma = _nonnegative("work_of_adhesion", work_of_adhesion)
    r = _positive("radius", radius)
    return _out(1.5 * np.pi * r * dgamma)


def jkr_pull_off_radius(contact_modulus, work_of_adhesion, radius):
    """Contact radius at the JKR force minimum, ``a_JKR = (9 pi dgamma R**2 / (8 E*))**(1/3)`` (eq. 2.20b).

    Parameters
    ----------
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.
    radius : float or array_like
        Radius of curvature R of the tip, in units of length; positive.

    Returns
    -------
    float or ndarray
        Contact radius a_JKR at point C, in units of length.
    """
    modulus = _positive("contact_modulus", contact_modulus)
    dgamma = _nonnegative("work_of_adhesion", work_of_adhesion)
    r = _positive("radius", radius)
    return _out(np.cbrt(9.0 * np.pi * dgamma * r**2 / (8.0 * modulus)))


def jkr_pull_off_displacement(contact_modulus, work_of_adhesion, radius):
    """Displacement at the JKR force minimum, ``d_JKR = -(3 pi**2 dgamma**2 R / (64 E*^2))**(1/3)`` (eq. 2.20b).

    This is the displacement at point C (largest tensile force); under
    displacement control the contact survives beyond it, down to
    :func:`jkr_separation_displacement`.

    Parameters
    ----------
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.
    radius : float or array_like
        Radius of curvature R of the tip, in units of length; positive.

    Returns
    -------
    float or ndarray
        Signed displacement d_JKR (negative), in units of length.
    """
    modulus = _positive("contact_modulus", contact_modulus)
    dgamma = _nonnegative("work_of_adhesion", work_of_adhesion)
    r = _positive("radius", radius)
    return _out(-np.cbrt(3.0 * np.pi**2 * dgamma**2 * r / (64.0 * modulus**2)))


def jkr_zero_force_radius(contact_modulus, work_of_adhesion, radius):
    """Contact radius at zero load (point B), ``2**(2/3) a_JKR`` (from eq. 2.24 with F~ = 0).

    Parameters
    ----------
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.
    radius : float or array_like
        Radius of curvature R of the tip, in units of length; positive.

    Returns
    -------
    float or ndarray
        Contact radius a_0, in units of length.
    """
    return _out(2.0 ** (2.0 / 3.0) * np.asarray(jkr_pull_off_radius(contact_modulus, work_of_adhesion, radius)))


def jkr_separation_radius(contact_modulus, work_of_adhesion, radius):
    """Contact radius at separation under displacement control (point D), ``(1/3)**(2/3) a_JKR``.

    Point D is the minimum of the displacement, ``dd/da = 0`` (eq. 2.24 and text).

    Parameters
    ----------
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.
    radius : float or array_like
        Radius of curvature R of the tip, in units of length; positive.

    Returns
    -------
    float or ndarray
        Contact radius a_s, in units of length.
    """
    return _out((1.0 / 3.0) ** (2.0 / 3.0) * np.asarray(jkr_pull_off_radius(contact_modulus, work_of_adhesion, radius)))


def jkr_separation_force(work_of_adhesion, radius):
    """Force magnitude at separation under displacement control (point D), ``5/9 F_JKR = 5/6 pi R dgamma``.

    Parameters
    ----------
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.
    radius : float or array_like
        Radius of curvature R of the tip, in units of length; positive.

    Returns
    -------
    float or ndarray
        Magnitude of the (tensile) force at D, in units of force.
    """
    return _out(5.0 / 9.0 * np.asarray(jkr_pull_off_force(work_of_adhesion, radius)))


def jkr_separation_displacement(contact_modulus, work_of_adhesion, radius):
    """Displacement at separation under displacement control (point D), ``3**(2/3) d_JKR``.

    From eq. 2.24 at ``a~ = (1/3)**(2/3)``: ``d / |d_JKR| = -3**(2/3)``.

    Parameters
    ----------
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.
    radius : float or array_like
        Radius of curvature R of the tip, in units of length; positive.

    Returns
    -------
    float or ndarray
        Signed displacement d_s (negative, the most negative reachable), in units of length.
    """
    return _out(3.0 ** (2.0 / 3.0) * np.asarray(jkr_pull_off_displacement(contact_modulus, work_of_adhesion, radius)))


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


def jkr_radius_from_displacement(displacement, contact_modulus, work_of_adhesion, radius):
    """JKR contact radius on the stable branch for a given indentation.

    Inverts ``d(a) = a**2 / R - sqrt(2 pi dgamma a / E*)`` for the largest root
    ``a >= a_s`` (the branch followed under displacement control) with
    :func:`scipy.optimize.brentq` on the dimensionless form of eq. 2.24.

    Parameters
    ----------
    displacement : float or array_like
        Indentation d, in units of length; ``d >= d_s``
        (:func:`jkr_separation_displacement`).
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative (zero:
        Hertz, ``d >= 0`` required).
    radius : float or array_like
        Radius of curvature R of the tip, in units of length; positive.

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


def jkr_force_from_displacement(displacement, contact_modulus, work_of_adhesion, radius):
    """JKR force on the stable branch for a given indentation (displacement control).

    Parameters
    ----------
    displacement : float or array_like
        Indentation d, in units of length; ``d >= d_s``
        (:func:`jkr_separation_displacement`).
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.
    radius : float or array_like
        Radius of curvature R of the tip, in units of length; positive.

    Returns
    -------
    float or ndarray
        Normal force, compressive positive, in units of force.

    Raises
    ------
    ValueError
        If ``displacement`` is below the separation displacement or any input is invalid.
    """
    a = jkr_radius_from_displacement(displacement, contact_modulus, work_of_adhesion, radius)
    return jkr_force_from_radius(a, contact_modulus, work_of_adhesion, radius)


def jkr_work_of_separation(contact_modulus, work_of_adhesion, radius):
    """Work to separate a rigid sphere from zero load (B) to separation (D), ``U_tot(a_s) - U_tot(a_0)`` (eq. 2.27).

    Equal to ``U_nor * (4/5 * 4**(-2/3) + 6/5 * 3**(4/3))`` with U_nor from
    :func:`sphere_normalization_energy`.

    Parameters
    ----------
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; positive.
    radius : float or array_like
        Radius of curvature R of the tip, in units of length; positive.

    Returns
    -------
    float or ndarray
        Work of separation w_0, in units of energy.
    """
    return sphere_spring_work_of_separation(contact_modulus, work_of_adhesion, radius, np.inf)


# ---------------------------------------------------------------------------
# DMT, Tabor, Maugis (eq. 1.2-1.5)
# ---------------------------------------------------------------------------


def dmt_pull_off_force(work_of_adhesion, radius):
    """DMT adhesive force ``2 pi R dgamma`` (eq. 1.2).

    Parameters
    ----------
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.
    radius : float or array_like
        Combined radius of curvature R, in units of length; positive.

    Returns
    -------
    float or ndarray
        Magnitude of the pull-off force, in units of force.
    """
    dgamma = _nonnegative("work_of_adhesion", work_of_adhesion)
    r = _positive("radius", radius)
    return _out(2.0 * np.pi * r * dgamma)


def tabor_parameter(radius, work_of_adhesion, contact_modulus, equilibrium_separation):
    """Tabor parameter ``mu_T = (R dgamma**2 / (E*^2 z0**3))**(1/3)`` (eq. 1.3).

    Large values: JKR (compliant, large bodies); small values: DMT.

    Parameters
    ----------
    radius : float or array_like
        Combined radius of curvature R, in units of length; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    equilibrium_separation : float or array_like
        Equilibrium separation z0 of the surfaces, in units of length; positive.

    Returns
    -------
    float or ndarray
        Tabor parameter mu_T, dimensionless.
    """
    r = _positive("radius", radius)
    dgamma = _nonnegative("work_of_adhesion", work_of_adhesion)
    modulus = _positive("contact_modulus", contact_modulus)
    z0 = _positive("equilibrium_separation", equilibrium_separation)
    return _out(np.cbrt(r * dgamma**2 / (modulus**2 * z0**3)))


def maugis_parameter(adhesive_stress, radius, contact_modulus, work_of_adhesion):
    """Maugis parameter ``lambda = sigma0 (9 R / (2 pi E*^2 dgamma))**(1/3)`` (eq. 1.5).

    With the Dugdale stress matched to a Lennard-Jones law,
    ``sigma0 = 16 dgamma / (9 sqrt(3) z0)``, ``lambda = 1.157 mu_T`` (the "1.16" of eq. 1.5).

    Parameters
    ----------
    adhesive_stress : float or array_like
        Dugdale adhesive stress sigma0 (``dgamma = sigma0 h0``, eq. 1.4), in units
        of stress; positive.
    radius : float or array_like
        Combined radius of curvature R, in units of length; positive.
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; positive.

    Returns
    -------
    float or ndarray
        Maugis parameter lambda, dimensionless.
    """
    sigma0 = _positive("adhesive_stress", adhesive_stress)
    r = _positive("radius", radius)
    modulus = _positive("contact_modulus", contact_modulus)
    dgamma = _positive("work_of_adhesion", work_of_adhesion)
    return _out(sigma0 * np.cbrt(9.0 * r / (2.0 * np.pi * modulus**2 * dgamma)))


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
"""k_bar below which the thesis uses the low-stiffness work (eq. 2.39), above it eq. 2.38."""


def sphere_normalization_radius(contact_modulus, work_of_adhesion, radius):
    """Length scale of eq. 2.33, ``a_nor = (pi dgamma R**2 / (2 E*))**(1/3) = (4/9)**(1/3) a_JKR``.

    Parameters
    ----------
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; positive.
    radius : float or array_like
        Radius of curvature R of the tip, in units of length; positive.

    Returns
    -------
    float or ndarray
        a_nor, in units of length.
    """
    modulus = _positive("contact_modulus", contact_modulus)
    dgamma = _positive("work_of_adhesion", work_of_adhesion)
    r = _positive("radius", radius)
    return _out(np.cbrt(np.pi * dgamma * r**2 / (2.0 * modulus)))


def sphere_normalization_energy(contact_modulus, work_of_adhesion, radius):
    """Energy scale of eq. 2.34, ``U_nor = (pi**5 dgamma**5 R**4 / (2**5 E*^2))**(1/3)``.

    Equal to ``E* a_nor**5 / R**2``.

    Parameters
    ----------
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; positive.
    radius : float or array_like
        Radius of curvature R of the tip, in units of length; positive.

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


def sphere_normalized_stiffness(stiffness, contact_modulus, work_of_adhesion, radius):
    """Dimensionless pillar stiffness of eq. 2.36, ``k_bar = k / (E* a_nor)``.

    Not the same as eq. 2.21's ``k~ = k / (E* a_JKR)``: ``k_bar = (9/4)**(1/3) k~ = 1.31 k~``.

    Parameters
    ----------
    stiffness : float or array_like
        Spring stiffness k, in units of force per length; ``0 < k <= inf``.
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; positive.
    radius : float or array_like
        Radius of curvature R of the tip, in units of length; positive.

    Returns
    -------
    float or ndarray
        k_bar, dimensionless (``inf`` for a rigid connection).
    """
    k = _positive("stiffness", stiffness, allow_inf=True)
    modulus = np.asarray(_positive("contact_modulus", contact_modulus))
    a_nor = np.asarray(sphere_normalization_radius(contact_modulus, work_of_adhesion, radius))
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
    """Normalised work of separation for a stiff spring, separation at D (eq. 2.38).

    ``w_bar_h = (U_bar_sp(a_s) - U_bar(a_o)) / (U_bar(a_s) - U_bar(a_o)) = 1 + (25/18) / (k_bar * 5.509...)``;
    1 for a rigid connection.

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
    """Normalised work of separation for a soft spring, separation at C (eq. 2.39).

    Soft springs make the contact unstable right after the force minimum, so the
    thesis evaluates the energy at point C instead of D.

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


def sphere_spring_work(normalized_stiffness, switch=SPHERE_WORK_SWITCH):
    """Normalised work of separation of a sphere on a spring, as the thesis fits it (Figure 2-9).

    Eq. 2.39 for ``k_bar < switch``, eq. 2.38 otherwise.  The two branches are
    equal at ``k_bar = 1.84`` (``(81/18 - 25/18) / (U_bar(a_s) - U_bar(a_c))``), so
    the thesis's switch at 1.7 leaves a jump of about 2 % (1.174 vs 1.148).

    Parameters
    ----------
    normalized_stiffness : float or array_like
        k_bar (:func:`sphere_normalized_stiffness`), dimensionless; ``0 < k_bar <= inf``.
    switch : float, optional
        k_bar at which the formula changes, dimensionless; positive.  Default 1.7.

    Returns
    -------
    float or ndarray
        w_bar, dimensionless.
    """
    kbar = _positive("normalized_stiffness", normalized_stiffness, allow_inf=True)
    threshold = _positive("switch", switch, allow_inf=True)
    low = np.asarray(sphere_spring_work_low(kbar))
    high = np.asarray(sphere_spring_work_high(kbar))
    return _out(np.where(kbar < threshold, low, high))


def sphere_spring_work_from_preload(normalized_stiffness, normalized_preload_radius, switch=SPHERE_WORK_SWITCH):
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

    with the end at D (a_bar_s, eq. 2.38) or, below ``switch``, at C
    (a_bar_c, eq. 2.39); a contact that never grew past the end radius comes
    off where the fixed-contact line meets the JKR curve.  For
    ``a_bar_m >= a_bar_o`` this is :func:`sphere_spring_work`.

    Parameters
    ----------
    normalized_stiffness : float or array_like
        k_bar (:func:`sphere_normalized_stiffness`), dimensionless; ``0 < k_bar <= inf``.
    normalized_preload_radius : float or array_like
        a_bar_m = a_m / a_nor, the largest contact radius of the loading; positive (inf: beyond B).
    switch : float, optional
        k_bar below which the end is C (eq. 2.39), dimensionless; default 1.7.

    Returns
    -------
    float or ndarray
        w_bar, the work over the rigid sphere's work from B (eq. 2.27), dimensionless.
    """
    kbar = _positive("normalized_stiffness", normalized_stiffness, allow_inf=True)
    a_m = _positive("normalized_preload_radius", normalized_preload_radius, allow_inf=True)
    threshold = _positive("switch", switch, allow_inf=True)
    end = np.minimum(a_m, np.where(kbar < threshold, SPHERE_ABAR_PULL_OFF, SPHERE_ABAR_SEPARATION))
    a_z = np.minimum(a_m, SPHERE_ABAR_ZERO_FORCE)
    start = 4.0 / 45.0 * a_z**5 - 2.0 * a_z**2
    numerator = np.asarray(sphere_spring_energy_normalized(end, kbar)) - start
    return _out(numerator / _sphere_rigid_work_normalized())


def sphere_preload_contact_radius(contact_modulus, radius, stiffness, preload_force=None, preload_displacement=None):
    """Contact radius at the end of the loading of a sphere on a spring (Hertz, eq. 2.22 with dgamma = 0).

    Elements join where the tip touches, so the loading branch is Hertz's:
    ``F = 4 E* a^3 / (3 R)`` at a base displacement ``d = a^2 / R + F / k``.
    Give exactly one of ``preload_force`` and ``preload_displacement``.

    Parameters
    ----------
    contact_modulus : float
        Contact modulus E*, in units of stress; positive.
    radius : float
        Radius of curvature R of the tip, in units of length; positive.
    stiffness : float
        Spring stiffness k, in units of force per length; ``0 < k <= inf``.
    preload_force, preload_displacement : float, optional
        The preload, in units of force or of length; positive.

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


def sphere_spring_work_of_separation(contact_modulus, work_of_adhesion, radius, stiffness, switch=SPHERE_WORK_SWITCH,
                                     preload_radius=math.inf):
    """Work of separation of a JKR sphere on a spring, from zero load to separation.

    ``w = w_bar(k_bar) * (U_tot(a_s) - U_tot(a_o))`` (eq. 2.27, 2.30-2.31, 2.38-2.39),
    with the branch chosen as in :func:`sphere_spring_work` and, where the
    preload contact radius is below a_o (point B), counted from the zero
    crossing of the fixed-contact unloading line
    (:func:`sphere_spring_work_from_preload`).

    Parameters
    ----------
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; positive.
    radius : float or array_like
        Radius of curvature R of the tip, in units of length; positive.
    stiffness : float or array_like
        Spring stiffness k, in units of force per length; ``0 < k <= inf``.
    switch : float, optional
        k_bar below which eq. 2.39 is used, dimensionless; default 1.7.
    preload_radius : float or array_like, optional
        Largest contact radius of the loading (:func:`sphere_preload_contact_radius`),
        in units of length; default inf (beyond B, the thesis's case).

    Returns
    -------
    float or ndarray
        Work of separation, in units of energy.
    """
    kbar = np.asarray(sphere_normalized_stiffness(stiffness, contact_modulus, work_of_adhesion, radius))
    u_nor = np.asarray(sphere_normalization_energy(contact_modulus, work_of_adhesion, radius))
    a_m = np.asarray(_positive("preload_radius", preload_radius, allow_inf=True)) / np.asarray(
        sphere_normalization_radius(contact_modulus, work_of_adhesion, radius))
    w_bar = np.asarray(sphere_spring_work_from_preload(kbar, a_m, switch))
    return _out(w_bar * _sphere_rigid_work_normalized() * u_nor)


# ---------------------------------------------------------------------------
# Brushes (eq. 4.5-4.18, 5.3-5.8)
# ---------------------------------------------------------------------------


def rigid_brush_force(contact_modulus, work_of_adhesion, filling_factor, apparent_area):
    """Adhesive force of a flat rigid brush, ``sqrt(8 pi E* dgamma phi (sqrt(A0/pi))**3)`` (eq. 4.5, 5.3).

    Kendall's force for a punch of the apparent radius with dgamma replaced by
    ``phi * dgamma``; the scale F_c of chapters 5 and 6.

    Parameters
    ----------
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.
    filling_factor : float or array_like
        phi = real (pillar cross-section) area / apparent area, dimensionless; in (0, 1].
    apparent_area : float or array_like
        Apparent area A0 of the brush, in units of area; positive.

    Returns
    -------
    float or ndarray
        Magnitude of the adhesive force F_R = F_c, in units of force.
    """
    modulus = _positive("contact_modulus", contact_modulus)
    dgamma = _nonnegative("work_of_adhesion", work_of_adhesion)
    phi = _filling_factor("filling_factor", filling_factor)
    area = _positive("apparent_area", apparent_area)
    return _out(np.sqrt(8.0 * np.pi * modulus * dgamma * phi * np.sqrt(area / np.pi) ** 3))


def rigid_brush_displacement(contact_modulus, work_of_adhesion, filling_factor, apparent_area):
    """Critical displacement of a flat rigid brush, ``-sqrt(2 pi phi dgamma sqrt(A0/pi) / E*)`` (eq. 5.4).

    The displacement scale d_c of eq. 4.12, 5.4, 6.23 and 7.5 (which the thesis
    writes as a magnitude), here with its sign.

    Parameters
    ----------
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.
    filling_factor : float or array_like
        phi, dimensionless; in (0, 1].
    apparent_area : float or array_like
        Apparent area A0, in units of area; positive.

    Returns
    -------
    float or ndarray
        Signed critical displacement (negative), in units of length.
    """
    modulus = _positive("contact_modulus", contact_modulus)
    dgamma = _nonnegative("work_of_adhesion", work_of_adhesion)
    phi = _filling_factor("filling_factor", filling_factor)
    area = _positive("apparent_area", apparent_area)
    return _out(-np.sqrt(2.0 * np.pi * phi * dgamma * np.sqrt(area / np.pi) / modulus))


def compact_punch_force(contact_modulus, work_of_adhesion, real_area):
    """Kendall force of a compact punch with the same real area, radius ``sqrt(A/pi)`` (eq. 4.11).

    The force scale of chapter 4.

    Parameters
    ----------
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.
    real_area : float or array_like
        Real (total pillar cross-section) area A, in units of area; positive.

    Returns
    -------
    float or ndarray
        Magnitude of the adhesive force, in units of force.
    """
    area = _positive("real_area", real_area)
    return kendall_force(contact_modulus, work_of_adhesion, np.sqrt(area / np.pi))


def rigid_brush_enhancement(filling_factor):
    """Rigid-brush gain over the compact punch of equal real area, ``phi**(-1/4)`` (eq. 4.6, 4.9).

    Parameters
    ----------
    filling_factor : float or array_like
        phi, dimensionless; in (0, 1].

    Returns
    -------
    float or ndarray
        F_R / F_K(real area), dimensionless.
    """
    phi = _filling_factor("filling_factor", filling_factor)
    return _out(phi**-0.25)


def soft_brush_enhancement(pillar_count):
    """Very-soft-brush gain over the compact punch of equal real area, ``N**(1/4)`` (eq. 4.8, 4.10).

    Parameters
    ----------
    pillar_count : float or array_like
        Number of pillars N (equal radii), dimensionless; ``N >= 1``.

    Returns
    -------
    float or ndarray
        F_S / F_K(real area), dimensionless.
    """
    n = _count("pillar_count", pillar_count)
    return _out(n**0.25)


def soft_brush_force(pillar_count, contact_modulus, work_of_adhesion, pillar_radius):
    """Adhesive force of a very soft brush, ``N sqrt(8 pi E* dgamma a**3)`` (eq. 4.7).

    Every pillar detaches on its own at its Kendall force.

    Parameters
    ----------
    pillar_count : float or array_like
        Number of pillars N, dimensionless; ``N >= 1``.
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.
    pillar_radius : float or array_like
        Pillar radius a, in units of length; positive.

    Returns
    -------
    float or ndarray
        Magnitude of the adhesive force F_S, in units of force.
    """
    n = _count("pillar_count", pillar_count)
    r = _positive("pillar_radius", pillar_radius)
    return _out(n * np.asarray(kendall_force(contact_modulus, work_of_adhesion, r)))


def ideal_sharing_force(pillar_count, contact_modulus, work_of_adhesion, pillar_radius):
    """Equal-load-sharing adhesive force ``N F_K(r)`` (eq. 7.4), the force scale of chapter 7.

    The same number as :func:`soft_brush_force` (eq. 4.7): both are all pillars
    reaching their Kendall force.

    Parameters
    ----------
    pillar_count : float or array_like
        Number of pillars N, dimensionless; ``N >= 1``.
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.
    pillar_radius : float or array_like
        Pillar radius r, in units of length; positive.

    Returns
    -------
    float or ndarray
        Magnitude of the maximum adhesive force, in units of force.
    """
    return soft_brush_force(pillar_count, contact_modulus, work_of_adhesion, pillar_radius)


def soft_brush_work_of_separation(pillar_count, contact_modulus, work_of_adhesion, real_area, stiffness):
    """Spring energy of a very soft brush at separation, ``N**(-1/2) F_K**2 / (2 k)`` (eq. 4.16-4.17).

    F_K is :func:`compact_punch_force` of the real area; each of the N pillars
    stores ``(N**(-3/4) F_K)**2 / (2 k)``.

    Parameters
    ----------
    pillar_count : float or array_like
        Number of pillars N, dimensionless; ``N >= 1``.
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.
    real_area : float or array_like
        Real area A = N pi a**2, in units of area; positive.
    stiffness : float or array_like
        Pillar stiffness k, in units of force per length; ``0 < k <= inf``.

    Returns
    -------
    float or ndarray
        Work W_S, in units of energy.
    """
    n = _count("pillar_count", pillar_count)
    k = _positive("stiffness", stiffness, allow_inf=True)
    f_k = np.asarray(compact_punch_force(contact_modulus, work_of_adhesion, real_area))
    return _out(n**-0.5 * f_k**2 / (2.0 * k))


def soft_brush_work_normalized(pillar_count, filling_factor, normalized_stiffness):
    """Normalised work of a very soft brush as printed in eq. 4.18, ``N**(-1/2) phi**(1/2) / k~``.

    ``k~ = k / (E* L)`` (eq. 4.13).  Dividing eq. 4.17 by ``W_K = 2 pi dgamma a0**2``
    with ``a0 = sqrt(A/pi)`` and ``A = phi L**2`` gives ``(2/sqrt(pi)) N**(-1/2)
    phi**(1/2) / k~``: the printed right-hand side drops the factor
    ``2/sqrt(pi) = 1.128``.  This function returns the printed form; use
    :func:`soft_brush_work_of_separation` for the dimensional estimate.

    Parameters
    ----------
    pillar_count : float or array_like
        Number of pillars N, dimensionless; ``N >= 1``.
    filling_factor : float or array_like
        phi, dimensionless; in (0, 1].
    normalized_stiffness : float or array_like
        k~ = k / (E* L), dimensionless; ``0 < k~ <= inf``.

    Returns
    -------
    float or ndarray
        W~_S, dimensionless.
    """
    n = _count("pillar_count", pillar_count)
    phi = _filling_factor("filling_factor", filling_factor)
    k_tilde = _positive("normalized_stiffness", normalized_stiffness, allow_inf=True)
    return _out(n**-0.5 * np.sqrt(phi) / k_tilde)


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
# Hierarchy (eq. 6.20-6.28)
# ---------------------------------------------------------------------------


def _sequence(name: str, values: object) -> np.ndarray:
    array = _as_real_array(name, values)
    if array.ndim != 1:
        raise ValueError(f"{name} must be a one-dimensional sequence; got shape {array.shape}")
    return array


def hierarchy_stiffnesses(bottom_stiffness: float, filling_factors: Sequence[float]) -> tuple[float, ...]:
    """Pillar stiffness of every level from eq. 6.21, ``k_{i+1} = k_i / phi_i``.

    One entry per level: ``filling_factors`` lists ``phi_1 .. phi_n`` (level i's
    filling factor inside its parent, the top level's inside the domain), as the
    thesis does; ``phi_n`` does not enter the stiffnesses (it only enters
    :func:`total_filling_factor`).

    Eq. 6.21 is the thesis's reading of eq. 6.20 (``k_i / r_i**2`` the same on every
    level, a homogeneous material).  Geometrically ``phi_i = N_i (r_i / r_{i+1})**2``
    with N_i level-i pillars per level-(i+1) pillar, so eq. 6.20 alone would give
    ``k_{i+1} = N_i k_i / phi_i``; this function follows eq. 6.21 as printed.

    Parameters
    ----------
    bottom_stiffness : float
        Stiffness k_1 of a bottom-level pillar, in units of force per length (or
        any normalised stiffness, e.g. k~ = k / (E* L)); positive and finite.
    filling_factors : sequence of float, length n >= 1
        phi_1 .. phi_n, dimensionless; each in (0, 1].

    Returns
    -------
    tuple of float, length n
        (k_1, ..., k_n), in the units of ``bottom_stiffness``.
    """
    k1 = float(_positive("bottom_stiffness", bottom_stiffness))
    phis = _filling_factor("filling_factors", _sequence("filling_factors", filling_factors))
    if phis.size == 0:
        raise ValueError("filling_factors must list at least one level; got an empty sequence")
    stiffnesses = [k1]
    for phi in phis[:-1]:
        stiffnesses.append(stiffnesses[-1] / float(phi))
    return tuple(stiffnesses)


def total_filling_factor(filling_factors: Sequence[float]) -> float:
    """Filling factor of the bottom pillars in the domain, ``phi = phi_1 phi_2 ... phi_n`` (eq. 6.22).

    Parameters
    ----------
    filling_factors : sequence of float, length n >= 1
        phi_1 .. phi_n, dimensionless; each in (0, 1].

    Returns
    -------
    float
        phi, dimensionless.
    """
    phis = _filling_factor("filling_factors", _sequence("filling_factors", filling_factors))
    if phis.size == 0:
        raise ValueError("filling_factors must list at least one level; got an empty sequence")
    return float(np.prod(phis))


def equivalent_single_level_stiffness(stiffnesses: Sequence[float], cluster_counts: Sequence[float]) -> float:
    """Stiffness k_1' of one bottom pillar of the equivalent single-level brush (eq. 6.28).

    Springs in series, pillars in parallel, interaction through the half-space
    ignored: ``1/k_1' = sum_i (prod_{j<i} N_j) / k_i``.  For three levels this is
    eq. 6.28b, ``k_1' = 1 / (N_2 N_1 / k_3 + N_1 / k_2 + 1 / k_1)``.

    Parameters
    ----------
    stiffnesses : sequence of float, length n >= 1
        k_1 (bottom) .. k_n (top), in units of force per length (or normalised);
        each in ``(0, inf]`` (``inf``: rigid level, contributes nothing).
    cluster_counts : sequence of float, length n - 1
        N_1 .. N_{n-1}: N_j is the number of level-j pillars in one level-(j+1)
        pillar (bottom-up); each ``>= 1``.  The number of top-level pillars N_n
        cancels and is not needed.

    Returns
    -------
    float
        k_1', in the units of ``stiffnesses`` (``inf`` if every level is rigid).
    """
    ks = _positive("stiffnesses", _sequence("stiffnesses", stiffnesses), allow_inf=True)
    counts = _count("cluster_counts", _sequence("cluster_counts", cluster_counts))
    if ks.size == 0:
        raise ValueError("stiffnesses must list at least one level; got an empty sequence")
    if counts.size != ks.size - 1:
        raise ValueError(
            f"cluster_counts must have one entry fewer than stiffnesses ({ks.size - 1}); got {counts.size}"
        )
    pillars_below = np.concatenate(([1.0], np.cumprod(counts)))
    compliance = float(np.sum(pillars_below / ks))
    return math.inf if compliance == 0.0 else 1.0 / compliance


# ---------------------------------------------------------------------------
# Concave profile for a uniform stress (eq. 7.1-7.3)
# ---------------------------------------------------------------------------


def concave_reference_stress(contact_modulus, work_of_adhesion, pillar_radius):
    """Default uniform stress p_c for the concave profile: one pillar's Kendall mean stress.

    ``p_c = F_K / (pi r**2) = sqrt(8 E* dgamma / (pi r))``.  The thesis does not
    state the p_c behind its amplification factor h~ (eq. 7.3).  This choice is
    the mean tensile stress on a pillar's face when it carries its Kendall force,
    i.e. the state of every pillar under ideal equal load sharing (eq. 7.4), so
    it ties h~ to the target of chapter 7 and depends only on pillar data.  The
    half-space, however, feels the stress smeared over the apparent area,
    ``phi * p_c``; with this reference the macroscopic equal-sharing shape is
    therefore ``h~ = phi``, in line with the thesis's optimum ``h~ = 0.04`` for
    stiff pillars (``k~ = 10``) at ``phi = 0.06`` (Figure 7-6 a).

    Parameters
    ----------
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.
    pillar_radius : float or array_like
        Pillar radius r, in units of length; positive.

    Returns
    -------
    float or ndarray
        p_c (magnitude of a tensile stress), in units of stress.
    """
    r = _positive("pillar_radius", pillar_radius)
    force = np.asarray(kendall_force(contact_modulus, work_of_adhesion, r))
    return _out(force / (np.pi * r**2))


def concave_profile(radial_position, radius, contact_modulus, uniform_stress):
    """Punch profile giving a uniform stress p_c over a circle (eq. 7.2).

    ``S_c(r) = (4 p_c R / (pi E*)) (E(r/R) - pi/2)``, ``r <= R``, with E the complete
    elliptic integral of the second kind of *modulus* ``k = r/R``; SciPy's
    :func:`scipy.special.ellipe` takes the *parameter* ``m = k**2``.

    Sign: ``S_c(0) = 0`` and ``S_c < 0`` for ``r > 0``, down to
    ``S_c(R) = (4 p_c R / (pi E*)) (1 - pi/2)`` at the rim.  S_c is the tip surface
    measured like brushbem's tip profile z (positive = recessed, away from the
    half-space), relative to the centre: under a uniform *tensile* stress p_c the
    half-space rises most at the centre (eq. 7.1 with ``p = -p_c``), so a punch
    in full contact must be recessed at the centre and the rim must reach further
    towards the half-space: the punch is concave and the rim pillars are the
    longest.  The slope is zero at the centre (``S_c = -p_c r**2 / (2 E* R)`` for
    ``r << R``) and diverges logarithmically at the rim, where the value stays finite.

    Parameters
    ----------
    radial_position : float or array_like
        Distance r from the centre, in units of length; ``0 <= r <= R``.
    radius : float
        Radius R of the circular (apparent) contact, in units of length; positive.
    contact_modulus : float
        Contact modulus E*, in units of stress; positive.
    uniform_stress : float
        Magnitude p_c of the uniform tensile stress, in units of stress;
        non-negative (see :func:`concave_reference_stress`).

    Returns
    -------
    float or ndarray
        S_c(r), in units of length (non-positive).
    """
    r = _nonnegative("radial_position", radial_position)
    big_r = _positive("radius", radius)
    modulus = _positive("contact_modulus", contact_modulus)
    p_c = _nonnegative("uniform_stress", uniform_stress)
    r, big_r = np.broadcast_arrays(r, big_r)
    outside = r > big_r
    if np.any(outside):
        raise ValueError(
            f"radial_position must lie in [0, radius] (the profile is defined inside the contact); "
            f"got {_first_offender(r, outside)} with radius {float(big_r[outside][0])!r}"
        )
    elliptic = special.ellipe((r / big_r) ** 2)
    return _out(4.0 * p_c * big_r / (np.pi * modulus) * (elliptic - np.pi / 2.0))


def concave_pillar_profile(radial_position, radius, amplification, contact_modulus, uniform_stress):
    """Amplified concave profile of the pillar tips, ``S_p = h~ S_c`` (eq. 7.3).

    Same sign as :func:`concave_profile`: zero at the centre, negative outside.

    Parameters
    ----------
    radial_position : float or array_like
        Distance r of the pillar centre from the structure centre, in units of
        length; ``0 <= r <= R``.
    radius : float
        Radius R of the profile, in units of length; positive.
    amplification : float
        Amplification factor h~, dimensionless; non-negative (0: flat brush).
    contact_modulus : float
        Contact modulus E*, in units of stress; positive.
    uniform_stress : float
        Reference stress p_c that makes h~ dimensionless, in units of stress;
        non-negative.

    Returns
    -------
    float or ndarray
        S_p(r), in units of length (non-positive).
    """
    h = _nonnegative("amplification", amplification)
    return _out(h * np.asarray(concave_profile(radial_position, radius, contact_modulus, uniform_stress)))


def concave_offsets(radial_position, radius, amplification, contact_modulus, uniform_stress):
    """Pillar length offsets g >= 0 of a concave brush, ``g = S_p(r) - S_p(R)``.

    The profile of eq. 7.3 shifted to brushbem's offset convention (DESIGN.md:
    ``g >= 0``, the longest pillar has ``g = 0``): rim pillars (``r = R``) get 0,
    the centre pillar is the shortest, ``g(0) = h~ (4 p_c R / (pi E*)) (pi/2 - 1)``.
    The shift is a constant and only moves the origin of the base displacement.

    Parameters
    ----------
    radial_position : float or array_like
        Distance r of each pillar centre from the structure centre, in units of
        length; ``0 <= r <= R`` (choose R as the outermost pillar's distance).
    radius : float
        Radius R of the profile, in units of length; positive.
    amplification : float
        Amplification factor h~, dimensionless; non-negative.
    contact_modulus : float
        Contact modulus E*, in units of stress; positive.
    uniform_stress : float
        Reference stress p_c (see :func:`concave_reference_stress`), in units of
        stress; non-negative.

    Returns
    -------
    float or ndarray
        Offsets g (how much shorter than a rim pillar), in units of length.
    """
    profile = np.asarray(concave_pillar_profile(radial_position, radius, amplification, contact_modulus, uniform_stress))
    rim = np.asarray(concave_pillar_profile(radius, radius, amplification, contact_modulus, uniform_stress))
    return _out(np.maximum(profile - rim, 0.0))
