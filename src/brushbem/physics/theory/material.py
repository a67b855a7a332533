"""The half-space's material: the contact modulus ``E* = E / (1 - nu**2)`` (thesis eq. 2.1).
"""

from __future__ import annotations

from brushbem.physics.theory._common import _check, _out, _positive

__all__ = [
    "contact_modulus_from",
]


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
    return _out(youngs / (1.0 - nu**2))
