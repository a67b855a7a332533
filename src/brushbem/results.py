"""Typed records of a pull-off: the curve, the snapshots and the summary.

Sign convention (the same everywhere in brushbem): the base displacement ``d``
is positive when the indenter presses into the half-space, the pressure and the
force are positive when compressive.  Adhesive (tensile) forces are negative.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field, fields
from typing import Any

import numpy as np

__all__ = ["CaseResult", "Curve", "PullOffSummary", "RunSummary", "Snapshot"]


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


class _MappingRecord(Mapping):
    """A frozen record that also reads as the mapping of its fields (the keys of ``summary.json``).

    Code reads the attributes (``summary.adhesive_force``); JSON, NetCDF
    attributes and sweep tables read it as a mapping, in field order.  A field
    named in ``_ABSENT_WHEN_NONE`` that is None is not a key (a punch has no
    brush normalisations).
    """

    _ABSENT_WHEN_NONE: frozenset[str] = frozenset()

    def _keys(self) -> list[str]:
        return [f.name for f in fields(self)
                if not (f.name in self._ABSENT_WHEN_NONE and getattr(self, f.name) is None)]

    def __getitem__(self, key: str) -> Any:
        if key in self._keys():
            return getattr(self, key)
        raise KeyError(key)

    def __iter__(self) -> Iterator[str]:
        return iter(self._keys())

    def __len__(self) -> int:
        return len(self._keys())

    def to_dict(self) -> dict[str, Any]:
        """The plain mapping (nested mappings as they are)."""
        return {key: getattr(self, key) for key in self._keys()}


@dataclass(frozen=True, kw_only=True)
class PullOffSummary(_MappingRecord):
    """The numbers of one pull-off (`brushbem.protocol.record_pull_off`), as in ``summary.json``.

    Attributes
    ----------
    adhesive_force : float
        F_A = -min F over the pull-off, a positive magnitude (0 without tension).
    pull_off_displacement, separation_displacement : float or None
        d at the adhesive force, and the last d with contact.
    work_of_separation : float
        The area of the tensile part of the unloading curve.
    preload_force, max_displacement : float
        F and d at the end of loading.
    converged, interrupted : bool
    reason : str
    n_solves, n_cg_iterations, n_states, attached_pillars_at_pull_off : int
    mean_cg_iterations_per_solve, wall_time_s : float
    """

    adhesive_force: float
    pull_off_displacement: float | None
    separation_displacement: float | None
    work_of_separation: float
    preload_force: float
    max_displacement: float
    converged: bool
    reason: str
    interrupted: bool
    n_solves: int
    n_cg_iterations: int
    mean_cg_iterations_per_solve: float
    attached_pillars_at_pull_off: int
    n_states: int
    wall_time_s: float


@dataclass(frozen=True, kw_only=True)
class RunSummary(PullOffSummary):
    """`PullOffSummary` with what a run adds: the mesh's critical stress, the closed forms, the warnings.

    Attributes
    ----------
    critical_stress : float
        Sigma_c of the mesh (eq. 2.14).
    normalized : mapping or None
        A brush's thesis normalisations (``force_by_compact_punch``, ...);
        not a key for other indenters.
    theory : mapping
        The closed-form values and the ratios of the computed ones to them.
    warnings : list of str
    """

    _ABSENT_WHEN_NONE = frozenset({"normalized"})

    critical_stress: float
    normalized: Mapping[str, Any] | None = None
    theory: Mapping[str, Any] = field(default_factory=dict)
    warnings: list[str] = field(default_factory=list)


@dataclass(frozen=True)
class CaseResult:
    """Everything one run produces.

    Attributes
    ----------
    curve : Curve
    snapshots : tuple of Snapshot
    summary : RunSummary
        The ``summary.json`` contract (see README; a mapping of these keys): adhesive_force,
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
    summary: Mapping[str, Any]
    attributes: dict[str, Any] = field(default_factory=dict)
    element_size: float = 1.0
    pillars: dict[str, np.ndarray] = field(default_factory=dict)
