"""The conversions every layer uses, written once: E*, k = k~ E* L and the JKR contact radius.

Configuration rules, the builders, the closed forms and the summaries call
these; none retypes them.  Plain arithmetic on floats or arrays (NumPy only),
so that validating a file, which reads them, loads no solver and no SciPy.

- ``E* = E / (1 - nu**2)``, the contact modulus of the half-space under a
  rigid indenter (thesis eq. 2.1);
- ``k = k~ E* L``, the spring stiffness of the normalised stiffness
  k~ = k / (E* L), L the side of the domain (`Grid.size`, eq. 4.13);
- ``a_JKR = (9 pi dgamma R**2 / (8 E*))**(1/3)``, the JKR contact radius at
  pull-off (eq. 2.20b).
"""

from __future__ import annotations

import numpy as np

__all__ = ["contact_modulus", "jkr_contact_radius", "normalized_stiffness", "stiffness_of_ratio"]


def contact_modulus(youngs_modulus, poisson_ratio):
    """E* = E / (1 - nu**2) (thesis eq. 2.1), in units of stress; no checks (`theory.contact_modulus_from` checks)."""
    return youngs_modulus / (1.0 - poisson_ratio**2)


def stiffness_of_ratio(stiffness_ratio, contact_modulus, size):
    """k = k~ E* L (thesis eq. 4.13): the stiffness of the normalised stiffness k~ on a domain of side L."""
    return stiffness_ratio * contact_modulus * size


def normalized_stiffness(stiffness, contact_modulus, size):
    """k~ = k / (E* L) (thesis eq. 4.13): the inverse of `stiffness_of_ratio`."""
    return stiffness / (contact_modulus * size)


def jkr_contact_radius(radius, contact_modulus, work_of_adhesion):
    """a_JKR = (9 pi dgamma R**2 / (8 E*))**(1/3) (thesis eq. 2.20b): the contact radius at the JKR pull-off.

    A float for floats, an array for arrays; no checks (`theory.jkr_pull_off_radius` checks its arguments).
    """
    value = np.cbrt(9.0 * np.pi * work_of_adhesion * np.square(radius) / (8.0 * contact_modulus))
    return float(value) if np.ndim(value) == 0 else value
