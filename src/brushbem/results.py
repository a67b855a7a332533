"""Typed records of a pull-off: the curve, the snapshots and the summary.

Sign convention (the same everywhere in brushbem): the base displacement ``d``
is positive when the indenter presses into the half-space, the pressure and the
force are positive when compressive.  Adhesive (tensile) forces are negative.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

__all__ = ["CaseResult", "Curve", "Snapshot"]


@dataclass(frozen=True)
class Snapshot:
    """The state of the contact at one marked moment of a pull-off.

    Attributes
    ----------
    name : str
        ``"max_preload"``, ``"zero_force"`` (first unloading state with
        F <= 0), ``"adhesive_force"``, ``"half_detached"`` (first state with at
        most half of the pillars attached that were attached at the end of
        loading) or ``"before_separation"``.
    displacement : float
        Base displacement d at that moment, in units of length.
    force : float
        Normal force F at that moment, compressive positive, in units of force.
    pressure : ndarray, shape (N, N)
        Normal pressure on every element, compressive positive, in units of stress.
    contact : ndarray of bool, shape (N, N)
        The contact set.
    pillar_force : ndarray of float, shape (M,), optional
        Force carried by every pillar (h^2 sum of its pressure), compressive
        positive.
    """

    name: str
    displacement: float
    force: float
    pressure: np.ndarray
    contact: np.ndarray
    pillar_force: np.ndarray | None = None


@dataclass(frozen=True)
class Curve:
    """One row per recorded equilibrium of the load path (all arrays of length n).

    Attributes
    ----------
    displacement : ndarray of float
        Base displacement d.
    force : ndarray of float
        Normal force F = h^2 sum p (after any detachment cascade at that d).
    contact_area : ndarray of float
        h^2 times the number of elements in contact.
    cg_iterations : ndarray of int
        Conjugate-gradient iterations spent to reach this row.
    converged : ndarray of bool
        Whether every solve behind this row converged.
    loading : ndarray of bool
        True on the loading branch, False on the unloading (pull-off) branch.
    attached_pillars : ndarray of int
        Number of pillars with at least one element in contact.
    """

    displacement: np.ndarray
    force: np.ndarray
    contact_area: np.ndarray
    cg_iterations: np.ndarray
    converged: np.ndarray
    loading: np.ndarray
    attached_pillars: np.ndarray


@dataclass(frozen=True)
class CaseResult:
    """Everything one run produces.

    Attributes
    ----------
    curve : Curve
    snapshots : tuple of Snapshot
    summary : dict
        The ``summary.json`` contract (see README): adhesive_force,
        pull_off_displacement, separation_displacement, work_of_separation,
        preload_force, max_displacement, converged, n_solves,
        n_cg_iterations, wall_time_s, theory {...}.
    attributes : dict
        Provenance written as NetCDF attributes (version, resolved config, seeds).
    element_size : float
        h, in units of length.
    pillars : dict of str to ndarray
        Per-pillar arrays of length M (``x``, ``y``: centre; ``offset``: length
        offset g; ``elements``: rasterised footprint; ``separation_displacement``:
        last d with contact on the pull-off; ``max_tension``: the largest
        tensile force the pillar carried on the pull-off, >= 0).
    """

    curve: Curve
    snapshots: tuple[Snapshot, ...]
    summary: dict[str, Any]
    attributes: dict[str, Any] = field(default_factory=dict)
    element_size: float = 1.0
    pillars: dict[str, np.ndarray] = field(default_factory=dict)
