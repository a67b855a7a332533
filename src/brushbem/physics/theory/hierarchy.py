"""Hierarchical brush closed forms (thesis ch. 6, eq. 6.20-6.28).

The stiffness of every level, the total filling factor and the equivalent
single-level stiffness.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from brushbem.physics.theory._common import _as_real_array, _count, _filling_factor, _positive

__all__ = [  # noqa: RUF022 - in the thesis's order
    "hierarchy_stiffnesses",
    "total_filling_factor",
    "equivalent_single_level_stiffness",
]


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
