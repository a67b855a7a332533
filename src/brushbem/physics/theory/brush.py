"""Flat brush closed forms (thesis ch. 4, with the scales used by ch. 5-7).

The rigid brush (eq. 4.5, 5.3-5.4: adhesive force F_c and critical displacement
d_c), the compact punch of equal real area (eq. 4.11), the rigid- and soft-brush
enhancements (eq. 4.6-4.10), the very soft brush's force and work (eq. 4.7,
4.16-4.18) and the equal-load-sharing force (eq. 7.4).
"""

from __future__ import annotations

import numpy as np

from brushbem.physics.theory._common import _count, _filling_factor, _nonnegative, _out, _positive
from brushbem.physics.theory.punch import kendall_force

__all__ = [  # noqa: RUF022 - in the thesis's order
    "rigid_brush_force",
    "rigid_brush_displacement",
    "compact_punch_force",
    "rigid_brush_enhancement",
    "soft_brush_enhancement",
    "soft_brush_force",
    "ideal_sharing_force",
    "soft_brush_work_of_separation",
    "soft_brush_work_normalized",
]


# ---------------------------------------------------------------------------
# Flat brushes (eq. 4.5-4.18; the scales of eq. 5.3-5.4 and 7.4)
# ---------------------------------------------------------------------------


def rigid_brush_force(filling_factor, apparent_area, *, contact_modulus, work_of_adhesion):
    """Adhesive force of a flat rigid brush, ``sqrt(8 pi E* dgamma phi (sqrt(A0/pi))**3)`` (eq. 4.5, 5.3).

    Kendall's force for a punch of the apparent radius with dgamma replaced by
    ``phi * dgamma``; the scale F_c of chapters 5 and 6.

    Parameters
    ----------
    filling_factor : float or array_like
        phi = real (pillar cross-section) area / apparent area, dimensionless; in (0, 1].
    apparent_area : float or array_like
        Apparent area A0 of the brush, in units of area; positive.
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.

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


def rigid_brush_displacement(filling_factor, apparent_area, *, contact_modulus, work_of_adhesion):
    """Critical displacement of a flat rigid brush, ``-sqrt(2 pi phi dgamma sqrt(A0/pi) / E*)`` (eq. 5.4).

    The displacement scale d_c of eq. 4.12, 5.4, 6.23 and 7.5 (which the thesis
    writes as a magnitude), here with its sign.

    Parameters
    ----------
    filling_factor : float or array_like
        phi, dimensionless; in (0, 1].
    apparent_area : float or array_like
        Apparent area A0, in units of area; positive.
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.

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


def compact_punch_force(real_area, *, contact_modulus, work_of_adhesion):
    """Kendall force of a compact punch with the same real area, radius ``sqrt(A/pi)`` (eq. 4.11).

    The force scale of chapter 4.

    Parameters
    ----------
    real_area : float or array_like
        Real (total pillar cross-section) area A, in units of area; positive.
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.

    Returns
    -------
    float or ndarray
        Magnitude of the adhesive force, in units of force.
    """
    area = _positive("real_area", real_area)
    return kendall_force(np.sqrt(area / np.pi), contact_modulus=contact_modulus, work_of_adhesion=work_of_adhesion)


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


def soft_brush_force(pillar_count, pillar_radius, *, contact_modulus, work_of_adhesion):
    """Adhesive force of a very soft brush, ``N sqrt(8 pi E* dgamma a**3)`` (eq. 4.7).

    Every pillar detaches on its own at its Kendall force.

    Parameters
    ----------
    pillar_count : float or array_like
        Number of pillars N, dimensionless; ``N >= 1``.
    pillar_radius : float or array_like
        Pillar radius a, in units of length; positive.
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.

    Returns
    -------
    float or ndarray
        Magnitude of the adhesive force F_S, in units of force.
    """
    n = _count("pillar_count", pillar_count)
    r = _positive("pillar_radius", pillar_radius)
    return _out(n * np.asarray(kendall_force(r, contact_modulus=contact_modulus, work_of_adhesion=work_of_adhesion)))


def ideal_sharing_force(pillar_count, pillar_radius, *, contact_modulus, work_of_adhesion):
    """Equal-load-sharing adhesive force ``N F_K(r)`` (eq. 7.4), the force scale of chapter 7.

    The same number as :func:`soft_brush_force` (eq. 4.7): both are all pillars
    reaching their Kendall force.

    Parameters
    ----------
    pillar_count : float or array_like
        Number of pillars N, dimensionless; ``N >= 1``.
    pillar_radius : float or array_like
        Pillar radius r, in units of length; positive.
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.

    Returns
    -------
    float or ndarray
        Magnitude of the maximum adhesive force, in units of force.
    """
    return soft_brush_force(pillar_count, pillar_radius,
                            contact_modulus=contact_modulus, work_of_adhesion=work_of_adhesion)


def soft_brush_work_of_separation(pillar_count, real_area, stiffness, *, contact_modulus, work_of_adhesion):
    """Spring energy of a very soft brush at separation, ``N**(-1/2) F_K**2 / (2 k)`` (eq. 4.16-4.17).

    F_K is :func:`compact_punch_force` of the real area; each of the N pillars
    stores ``(N**(-3/4) F_K)**2 / (2 k)``.

    Parameters
    ----------
    pillar_count : float or array_like
        Number of pillars N, dimensionless; ``N >= 1``.
    real_area : float or array_like
        Real area A = N pi a**2, in units of area; positive.
    stiffness : float or array_like
        Pillar stiffness k, in units of force per length; ``0 < k <= inf``.
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.

    Returns
    -------
    float or ndarray
        Work W_S, in units of energy.
    """
    n = _count("pillar_count", pillar_count)
    k = _positive("stiffness", stiffness, allow_inf=True)
    f_k = np.asarray(compact_punch_force(real_area, contact_modulus=contact_modulus, work_of_adhesion=work_of_adhesion))
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
