"""The adhesion criterion of the element grid (Pohrt and Popov 2015; thesis sec. 2.2.2, eq. 2.13-2.14).

An element in contact detaches when its tensile stress exceeds the critical
stress of the mesh, Sigma_c = sqrt(E* dgamma / (0.473201 h)): the stress at
which the elastic energy of a uniformly loaded square element,
0.473201 p^2 h^3 / E* (eq. 2.13), equals the work of adhesion of its area,
h^2 dgamma.  The solvers (`brushbem.numerics.solver.equilibria`) and the
pillar-level model apply it; this module states it once.
"""

from __future__ import annotations

import math

__all__ = ["ELEMENT_ENERGY_COEFFICIENT", "critical_stress"]

#: Elastic energy of a uniformly loaded square element, in units of p^2 h^3 / E* (eq. 2.13).
ELEMENT_ENERGY_COEFFICIENT = 0.473201


def critical_stress(contact_modulus: float, work_of_adhesion: float, element_size: float) -> float:
    """Sigma_c = sqrt(E* dgamma / (0.473201 h)), thesis eq. 2.14, in units of stress."""
    return math.sqrt(contact_modulus * work_of_adhesion / (ELEMENT_ENERGY_COEFFICIENT * element_size))
