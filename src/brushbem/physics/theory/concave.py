"""Concave brush closed forms (thesis ch. 7, eq. 7.1-7.3).

The punch profile that gives a uniform stress over a circle, its reference
stress, the amplified pillar profile and the pillar length offsets.  The force
scale of chapter 7, :func:`~brushbem.physics.theory.brush.ideal_sharing_force` (eq. 7.4),
is in :mod:`brushbem.physics.theory.brush`.
"""

from __future__ import annotations

import numpy as np
from scipy import special

from brushbem.physics.theory._common import _first_offender, _nonnegative, _out, _positive
from brushbem.physics.theory.punch import kendall_force

__all__ = [  # noqa: RUF022 - in the thesis's order
    "concave_reference_stress",
    "concave_profile",
    "concave_pillar_profile",
    "concave_offsets",
]


# ---------------------------------------------------------------------------
# Concave profile for a uniform stress (eq. 7.1-7.3)
# ---------------------------------------------------------------------------


def concave_reference_stress(pillar_radius, *, contact_modulus, work_of_adhesion):
    """Default uniform stress p_c for the concave profile: one pillar's Kendall mean stress.

    ``p_c = F_K / (pi r**2) = sqrt(8 E* dgamma / (pi r))``.  The thesis does not
    state the p_c behind its amplification factor h~ (eq. 7.3).  This choice is
    the mean tensile stress on a pillar's face when it carries its Kendall force,
    i.e. the state of every pillar under ideal equal load sharing (eq. 7.4), so
    it ties h~ to the target of chapter 7 and depends only on pillar data.  The
    half-space, however, feels the stress smeared over the apparent area,
    ``phi * p_c``; with this reference the macroscopic equal-sharing shape is
    therefore ``h~ = phi`` (phi over the profile's radius R).  The stiff brushes of
    chapter 7 (N = 512, 16 x 16: ours) peak there: ``h~ = 1.02 phi`` and ``1.06 phi``
    (k~ = 10, phi = 0.06 and 0.15; the thesis's own optimum, ``h~ = 0.04`` at
    ``phi = 0.06``, is 0.66 phi: ``docs/reproduction/notes.md``, chapter 7).

    Parameters
    ----------
    pillar_radius : float or array_like
        Pillar radius r, in units of length; positive.
    contact_modulus : float or array_like
        Contact modulus E*, in units of stress; positive.
    work_of_adhesion : float or array_like
        Work of adhesion dgamma, in units of energy per area; non-negative.

    Returns
    -------
    float or ndarray
        p_c (magnitude of a tensile stress), in units of stress.
    """
    r = _positive("pillar_radius", pillar_radius)
    force = np.asarray(kendall_force(r, contact_modulus=contact_modulus, work_of_adhesion=work_of_adhesion))
    return _out(force / (np.pi * r**2))


def concave_profile(radial_position, radius, uniform_stress, *, contact_modulus):
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
    uniform_stress : float
        Magnitude p_c of the uniform tensile stress, in units of stress;
        non-negative (see :func:`concave_reference_stress`).
    contact_modulus : float
        Contact modulus E*, in units of stress; positive.

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


def concave_pillar_profile(radial_position, radius, amplification, uniform_stress, *, contact_modulus):
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
    uniform_stress : float
        Reference stress p_c that makes h~ dimensionless, in units of stress;
        non-negative.
    contact_modulus : float
        Contact modulus E*, in units of stress; positive.

    Returns
    -------
    float or ndarray
        S_p(r), in units of length (non-positive).
    """
    h = _nonnegative("amplification", amplification)
    profile = concave_profile(radial_position, radius, uniform_stress, contact_modulus=contact_modulus)
    return _out(h * np.asarray(profile))


def concave_offsets(radial_position, radius, amplification, uniform_stress, *, contact_modulus):
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
    uniform_stress : float
        Reference stress p_c (see :func:`concave_reference_stress`), in units of
        stress; non-negative.
    contact_modulus : float
        Contact modulus E*, in units of stress; positive.

    Returns
    -------
    float or ndarray
        Offsets g (how much shorter than a rim pillar), in units of length.
    """
    profile = np.asarray(concave_pillar_profile(radial_position, radius, amplification, uniform_stress,
                                                contact_modulus=contact_modulus))
    rim = np.asarray(concave_pillar_profile(radius, radius, amplification, uniform_stress,
                                            contact_modulus=contact_modulus))
    return _out(np.maximum(profile - rim, 0.0))
