"""The materials: the half-space's contact modulus ``E* = E / (1 - nu**2)`` (thesis eq. 2.1) and a fibril's
axial spring ``k = pi r^2 E_f / l`` (thesis sec. 6.3, line "k = E_p pi r_n^2 / L_n") and Euler buckling load.
"""

from __future__ import annotations

import numpy as np

from brushbem.physics.theory._common import _check, _out, _positive
from brushbem.physics import scales

__all__ = [
    "BUCKLING_LENGTH_FACTORS",
    "contact_modulus_from",
    "euler_buckling_force",
    "fibril_stiffness",
]

#: Euler's effective-length factor K of a column by how its two ends are held (P_cr = pi^2 E I / (K l)^2):
#: the textbook values of an elastic column (Timoshenko and Gere, *Theory of Elastic Stability*, ch. 2).
#: The first end named is the backing's, which holds the fibril clamped; the tip end is held by the
#: adhesive contact, clamped (no rotation, no sliding), pinned (no sliding) or free.
BUCKLING_LENGTH_FACTORS = {"clamped-clamped": 0.5, "clamped-pinned": 0.699, "clamped-free": 2.0}


# ---------------------------------------------------------------------------
# Material
# ---------------------------------------------------------------------------


def contact_modulus_from(*, youngs_modulus, poisson_ratio):
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
    return _out(scales.contact_modulus(youngs, nu))


def fibril_stiffness(length, radius, *, youngs_modulus):
    """Axial stiffness of a cylindrical fibril, ``k = pi r^2 E_f / l`` (thesis sec. 6.3, ``k = E_p pi r_n^2 / L_n``).

    The fibril is a linear elastic bar in uniaxial tension and compression
    (no bending, no lateral constraint of its ends).

    Parameters
    ----------
    length : float or array_like
        Fibril length l, in units of length; ``0 < l < inf``.
    radius : float or array_like
        Fibril radius r, in units of length; ``0 < r < inf``.
    youngs_modulus : float or array_like
        The fibril's Young's modulus E_f, in units of stress; ``0 < E_f < inf``.

    Returns
    -------
    float or ndarray
        k, in units of force / length.
    """
    length = _positive("length", length)
    radius = _positive("radius", radius)
    youngs = _positive("youngs_modulus", youngs_modulus)
    return _out(np.pi * radius**2 * youngs / length)


def euler_buckling_force(length, radius, *, youngs_modulus, ends="clamped-clamped"):
    """Euler's critical compressive force of a cylindrical fibril, ``P_cr = pi^2 E_f I / (K l)^2``, ``I = pi r^4 / 4``.

    Parameters
    ----------
    length, radius : float or array_like
        Fibril length l and radius r, in units of length; both > 0.
    youngs_modulus : float or array_like
        The fibril's Young's modulus E_f, in units of stress; > 0.
    ends : str
        How the ends are held, one of `BUCKLING_LENGTH_FACTORS` (K = 0.5, 0.699, 2).

    Returns
    -------
    float or ndarray
        P_cr (> 0, compressive), in units of force.
    """
    if ends not in BUCKLING_LENGTH_FACTORS:
        raise ValueError(f"ends = {ends!r}: must be one of {', '.join(BUCKLING_LENGTH_FACTORS)}")
    length = _positive("length", length)
    radius = _positive("radius", radius)
    youngs = _positive("youngs_modulus", youngs_modulus)
    moment = np.pi * radius**4 / 4.0
    return _out(np.pi**2 * youngs * moment / (BUCKLING_LENGTH_FACTORS[ends] * length) ** 2)
