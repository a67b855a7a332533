"""Sphere (paraboloid) contact outside the JKR theory (thesis ch. 1).

The two limits that bracket JKR and the numbers that place a contact between
them: Hertz without adhesion (force, contact radius, maximum pressure), the DMT
pull-off force (eq. 1.2), and the Tabor and Maugis parameters (eq. 1.3-1.5).
The JKR closed forms are in :mod:`brushbem.physics.theory.sphere`, which re-exports
these names.
"""

from __future__ import annotations

import numpy as np

from brushbem.physics.theory._common import _finite, _nonnegative, _out, _positive

__all__ = [  # noqa: RUF022 - in the thesis's order
    "hertz_force",
    "hertz_contact_radius",
    "hertz_max_pressure",
    "dmt_pull_off_force",
    "tabor_parameter",
    "maugis_parameter",
]


# ---------------------------------------------------------------------------
# Hertz (no adhesion)
# ---------------------------------------------------------------------------


def hertz_force(radius, displacement, *, contact_modulus):
    """Hertz force of a paraboloid ``r**2 / (2 R)``, ``4/3 E* sqrt(R) d**1.5``.

    Parameters
    ----------
    radius : float or array_like
        Radius of curvature R of the tip, in units of length; positive.
    displacement : float or array_like
        Indentation d, in units of length; finite.  ``d <= 0`` means no contact
        and gives zero.
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.

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


def hertz_max_pressure(radius, displacement, *, contact_modulus):
    """Hertz pressure at the centre of the contact, ``2 E* a / (pi R) = 3 F / (2 pi a**2)``.

    Parameters
    ----------
    radius : float or array_like
        Radius of curvature R of the tip, in units of length; positive.
    displacement : float or array_like
        Indentation d, in units of length; finite (``d <= 0`` gives zero).
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.

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
# DMT, Tabor, Maugis (eq. 1.2-1.5)
# ---------------------------------------------------------------------------


def dmt_pull_off_force(radius, *, work_of_adhesion):
    """DMT adhesive force ``2 pi R dgamma`` (eq. 1.2).

    Parameters
    ----------
    radius : float or array_like
        Combined radius of curvature R, in units of length; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.

    Returns
    -------
    float or ndarray
        Magnitude of the pull-off force, in units of force.
    """
    dgamma = _nonnegative("work_of_adhesion", work_of_adhesion)
    r = _positive("radius", radius)
    return _out(2.0 * np.pi * r * dgamma)


def tabor_parameter(radius, *, work_of_adhesion, contact_modulus, equilibrium_separation):
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


def maugis_parameter(radius, *, adhesive_stress, contact_modulus, work_of_adhesion):
    """Maugis parameter ``lambda = sigma0 (9 R / (2 pi E*^2 dgamma))**(1/3)`` (eq. 1.5).

    With the Dugdale stress matched to a Lennard-Jones law,
    ``sigma0 = 16 dgamma / (9 sqrt(3) z0)``, ``lambda = 1.157 mu_T`` (the "1.16" of eq. 1.5).

    Parameters
    ----------
    radius : float or array_like
        Combined radius of curvature R, in units of length; positive.
    adhesive_stress : float or array_like
        Dugdale adhesive stress sigma0 (``dgamma = sigma0 h0``, eq. 1.4), in units
        of stress; positive.
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
