"""Flat punch closed forms (thesis ch. 2).

Kendall's rigid flat circular punch (eq. 2.1-2.7: stiffness, adhesive force,
critical displacement, work of separation) and the flat punch held by a spring
(eq. 2.8, 2.16-2.19: normalised stiffness, work and base displacement at
separation).
"""

from __future__ import annotations

import numpy as np

from brushbem.physics.theory._common import _nonnegative, _out, _positive

__all__ = [  # noqa: RUF022 - in the thesis's order
    "punch_stiffness",
    "kendall_force",
    "kendall_displacement",
    "kendall_work_of_separation",
    "normalized_punch_stiffness",
    "punch_spring_work_of_separation",
    "punch_spring_separation_displacement",
]


# ---------------------------------------------------------------------------
# Kendall flat punch (eq. 2.1-2.7)
# ---------------------------------------------------------------------------


def punch_stiffness(radius, *, contact_modulus):
    """Normal contact stiffness of a rigid flat circular punch, ``2 E* r`` (eq. 2.2).

    Parameters
    ----------
    radius : float or array_like
        Punch radius r, in units of length; positive.
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.

    Returns
    -------
    float or ndarray
        Stiffness ``dF/dd``, in units of force per length.
    """
    modulus = _positive("contact_modulus", contact_modulus)
    r = _positive("radius", radius)
    return _out(2.0 * modulus * r)


def kendall_force(radius, *, contact_modulus, work_of_adhesion):
    """Kendall adhesive force of a rigid flat punch, ``sqrt(8 pi E* dgamma r**3)`` (eq. 2.4b).

    Parameters
    ----------
    radius : float or array_like
        Punch radius r, in units of length; positive.
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.

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


def kendall_displacement(radius, *, contact_modulus, work_of_adhesion):
    """Critical displacement of a rigid flat punch, ``-sqrt(2 pi dgamma r / E*)`` (eq. 2.4a).

    Parameters
    ----------
    radius : float or array_like
        Punch radius r, in units of length; positive.
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.

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


def kendall_work_of_separation(radius, *, work_of_adhesion):
    """External work to separate a rigid flat punch, ``2 pi dgamma r**2`` (eq. 2.5, 4.14).

    Half of it creates the new surface (eq. 2.7); the other half is the elastic
    energy radiated away at the unstable detachment.

    Parameters
    ----------
    radius : float or array_like
        Punch radius r, in units of length; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.

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


def normalized_punch_stiffness(stiffness, radius, *, contact_modulus):
    """Pillar stiffness over the punch contact stiffness, ``k~ = k / (2 E* r)`` (eq. 2.16).

    Parameters
    ----------
    stiffness : float or array_like
        Spring (pillar) stiffness k, in units of force per length; ``0 < k <= inf``
        (``inf``: rigid connection).
    radius : float or array_like
        Punch radius r, in units of length; positive.
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.

    Returns
    -------
    float or ndarray
        Dimensionless stiffness k~ (``inf`` for a rigid connection).
    """
    k = _positive("stiffness", stiffness, allow_inf=True)
    modulus = _positive("contact_modulus", contact_modulus)
    r = _positive("radius", radius)
    return _out(k / (2.0 * modulus * r))


def punch_spring_work_of_separation(radius, stiffness, *, contact_modulus, work_of_adhesion):
    """Work to separate a flat punch held by a spring, ``2 pi dgamma r**2 (1 + 1/k~)`` (eq. 2.18-2.19).

    The spring does not change the pull-off force or the punch's critical
    displacement; it stores the extra energy ``F_K**2 / (2 k)`` (eq. 2.8, 2.17).

    Parameters
    ----------
    radius : float or array_like
        Punch radius r, in units of length; positive.
    stiffness : float or array_like
        Spring stiffness k, in units of force per length; ``0 < k <= inf``.
        ``inf`` gives the rigid value ``2 pi dgamma r**2``.
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.

    Returns
    -------
    float or ndarray
        Work of separation w_ad from zero indentation, in units of energy.
    """
    k_tilde = np.asarray(normalized_punch_stiffness(stiffness, radius, contact_modulus=contact_modulus))
    rigid_work = np.asarray(kendall_work_of_separation(radius, work_of_adhesion=work_of_adhesion))
    return _out(rigid_work * (1.0 + 1.0 / k_tilde))


def punch_spring_separation_displacement(radius, stiffness, *, contact_modulus, work_of_adhesion):
    """Base displacement at which a flat punch on a spring separates, ``d_K - F_K / k``.

    The punch itself detaches at ``d_K`` (eq. 2.4a); the spring is then stretched
    by ``F_K / k`` (eq. 2.17), so the base has moved further away (eq. 2.8).

    Parameters
    ----------
    radius : float or array_like
        Punch radius r, in units of length; positive.
    stiffness : float or array_like
        Spring stiffness k, in units of force per length; ``0 < k <= inf``.
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.

    Returns
    -------
    float or ndarray
        Signed base displacement at separation (negative), in units of length.
    """
    k = _positive("stiffness", stiffness, allow_inf=True)
    d_k = np.asarray(kendall_displacement(radius, contact_modulus=contact_modulus, work_of_adhesion=work_of_adhesion))
    f_k = np.asarray(kendall_force(radius, contact_modulus=contact_modulus, work_of_adhesion=work_of_adhesion))
    return _out(d_k - f_k / k)
