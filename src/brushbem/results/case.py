"""Typed records of a pull-off: the curve, the snapshots and the summary.

Sign convention (the same everywhere in brushbem): the base displacement ``d``
is positive when the indenter presses into the half-space, the pressure and the
force are positive when compressive.  Adhesive (tensile) forces are negative.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from brushbem.results.design import DesignNumbers, ResolutionRecord
from brushbem.results.mapping import MappingRecord
from brushbem.results.normalization import BrushNormalization
from brushbem.results.provenance import Provenance
from brushbem.results.refinement import Refinement

__all__ = ["BrushTheory", "CaseResult", "Curve", "PullOffSummary", "PunchTheory", "ReferenceCurve", "RunSummary",
           "Snapshot", "SphereTheory", "Theory", "theory_from_mapping"]


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


@dataclass(frozen=True, kw_only=True)
class PullOffSummary(MappingRecord):
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
    stages_not_reached : dict or None
        Snapshot stages the path does not pass through (``zero_force`` where
        the force jumps across zero in a cascade, ``half_detached`` where the
        pillars all come off at once), with the reason; not a key when every
        stage was reached.
    """

    _ABSENT_WHEN_NONE = frozenset({"stages_not_reached"})

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
    stages_not_reached: dict | None = None


@dataclass(frozen=True, kw_only=True)
class PunchTheory(MappingRecord):
    """A flat punch against Kendall (eq. 2.4) and, on a spring, the work of eq. 2.18-2.19.

    Attributes
    ----------
    model : str
    equivalent_radius : float
        sqrt(A / pi) of the rasterised footprint's area A: the radius the closed forms use.
    adhesive_force, pull_off_displacement, work_of_separation : float
        The closed forms' values (the displacement of the base, the spring included).
    normalized_stiffness : float or None
        k / (2 E* a) on a finite spring (absent on a rigid punch).
    ratios : dict
        Computed over closed form, per quantity (none where the closed form does not apply).
    not_applicable : dict or None
        Quantity -> why its closed form does not apply (a viscoelastic or nonlinear spring).
    """

    _ABSENT_WHEN_NONE = frozenset({"normalized_stiffness", "not_applicable"})

    model: str = "Kendall flat punch (thesis eq. 2.4, 2.18-2.19)"
    equivalent_radius: float
    adhesive_force: float
    pull_off_displacement: float
    work_of_separation: float
    normalized_stiffness: float | None = None
    ratios: dict = field(default_factory=dict)
    not_applicable: dict | None = None


@dataclass(frozen=True, kw_only=True)
class SphereTheory(MappingRecord):
    """A sphere against JKR (eq. 2.20-2.24) and, on a spring, the work of eq. 2.32-2.37.

    The work is eq. 2.37's energy at the exact separation of the sphere on its
    spring (where the base displacement stops decreasing, dD/da = 0,
    `theory.sphere_spring_work`), not the thesis's piecewise eq. 2.38-2.39.

    Attributes
    ----------
    preload_contact_radius, zero_force_radius : float or None
        The Hertz contact radius of the preload and JKR's a_o (eq. 2.27), when
        the load path is known.
    work_counted_from : str or None
        Where the work of separation starts (B of eq. 2.27, or the zero-force
        crossing of the fixed-contact unloading below a_o).
    adhesive_force_from : str or None
        Which closed form ``adhesive_force`` (and ``pull_off_displacement``)
        is: JKR's pull-off (eq. 2.24), or, when the preload contact radius is
        below JKR's pull-off radius, the JKR curve at the preload radius (the
        most the unloading can reach).
    normalized_stiffness : float or None
        The spring's normalised stiffness (absent on a rigid sphere).
    model : str
    adhesive_force, pull_off_displacement, work_of_separation : float
    ratios : dict
        Computed over closed form, per quantity.
    """

    _ABSENT_WHEN_NONE = frozenset({"preload_contact_radius", "zero_force_radius", "work_counted_from",
                                   "adhesive_force_from", "normalized_stiffness", "not_applicable"})

    preload_contact_radius: float | None = None
    zero_force_radius: float | None = None
    work_counted_from: str | None = None
    adhesive_force_from: str | None = None
    normalized_stiffness: float | None = None
    model: str = "JKR sphere (thesis eq. 2.20-2.24, 2.32-2.37; work to the exact separation, dD/da = 0)"
    adhesive_force: float
    pull_off_displacement: float
    work_of_separation: float
    ratios: dict = field(default_factory=dict)
    not_applicable: dict | None = None


@dataclass(frozen=True, kw_only=True)
class BrushTheory(MappingRecord):
    """A brush's closed-form limits (eq. 4.5-4.13, 5.3-5.5, 7.4), against which its force is read.

    Attributes
    ----------
    model : str
    compact_punch_force, rigid_brush_force, ideal_sharing_force : float
        Kendall's force of one punch of the real area (eq. 4.11), F_c of the
        rigid brush (eq. 4.5) and N F_K (eq. 7.4).
    rigid_brush_displacement : float
        -|d_c| (eq. 4.12).
    rigid_brush_enhancement, soft_brush_enhancement : float
        phi^-1/4 (eq. 4.9) and N^1/4 (eq. 4.18).
    ratios : dict
        The adhesive force over F_c and over N F_K.
    """

    model: str = "brush limits (thesis eq. 4.5-4.13, 5.3-5.5, 7.4)"
    compact_punch_force: float
    rigid_brush_force: float
    ideal_sharing_force: float
    rigid_brush_displacement: float
    rigid_brush_enhancement: float
    soft_brush_enhancement: float
    ratios: dict = field(default_factory=dict)


@dataclass(frozen=True, kw_only=True)
class ReferenceCurve(MappingRecord):
    """A closed-form force-displacement curve drawn beside the computed one."""

    displacement: np.ndarray
    force: np.ndarray
    label: str


@dataclass(frozen=True, kw_only=True)
class RunSummary(PullOffSummary):
    """`PullOffSummary` with what a run adds: the mesh's critical stress, the closed forms, the warnings.

    Attributes
    ----------
    critical_stress : float
        Sigma_c of the mesh (eq. 2.14).
    normalized : BrushNormalization or None
        A brush's thesis normalisations (``force_by_compact_punch``, ...);
        not a key for other indenters.
    theory : PunchTheory, SphereTheory, BrushTheory or an empty mapping
        The closed-form values and the ratios of the computed ones to them
        (empty where no closed form applies).
    warnings : list of str
    refinement : Refinement or None
        With ``brushbem run --refine``: the grids and the Richardson-
        extrapolated adhesive force and work with their error estimates
        (`brushbem.runs.refine.Refinement`); not a key otherwise.
    resolution : ResolutionRecord or None
        The elements across the length that decides F_A and the estimated
        discretisation error of F_A and the work
        (`brushbem.config.advice.resolution`); not a key where no
        length decides (a height map, no adhesion) or without a configuration.
    design : DesignNumbers or None
        What a designer reports (`brushbem.runs.case.design_numbers`):
        the adhesion strength F_A / A0, F_A per pillar, the spring k, k~ and
        where k came from, the units of each; not a key without a configuration.
    run_id : str or None
        The id ``summary.json`` and ``result.nc`` share (`brushbem.io.write_case`); not a key before saving.
    provenance : Provenance or None
        Where the numbers come from (version, commit, time, backend, units, configuration), recorded
        when the run is saved; not a key before saving.
    """

    _ABSENT_WHEN_NONE = frozenset({"normalized", "refinement", "stages_not_reached", "resolution", "design",
                                   "run_id", "provenance"})

    critical_stress: float
    normalized: BrushNormalization | None = None
    theory: Theory | Mapping[str, Any] = field(default_factory=dict)
    warnings: list[str] = field(default_factory=list)
    refinement: Refinement | None = None
    resolution: ResolutionRecord | None = None
    design: DesignNumbers | None = None
    run_id: str | None = None
    provenance: Provenance | None = None

    @classmethod
    def _nested(cls):
        return {"normalized": BrushNormalization.from_mapping, "theory": theory_from_mapping,
                "refinement": Refinement.from_mapping, "provenance": Provenance.from_mapping,
                "resolution": ResolutionRecord.from_mapping, "design": DesignNumbers.from_mapping}


#: The closed-form record of a run (``summary.json``'s ``theory``).
Theory = PunchTheory | SphereTheory | BrushTheory


def theory_from_mapping(mapping: Mapping[str, Any]) -> Theory | dict:
    """The typed ``theory`` record of ``mapping`` (as ``summary.json`` holds it); an empty one stays empty.

    The kind is told by a field only it has: ``equivalent_radius`` (a punch), ``compact_punch_force``
    (a brush), else a sphere.
    """
    if isinstance(mapping, (PunchTheory, SphereTheory, BrushTheory)):
        return mapping
    if not mapping:
        return {}
    if "equivalent_radius" in mapping:
        return PunchTheory.from_mapping(mapping)
    if "compact_punch_force" in mapping:
        return BrushTheory.from_mapping(mapping)
    return SphereTheory.from_mapping(mapping)


@dataclass(frozen=True)
class CaseResult:
    """Everything one run produces.

    Attributes
    ----------
    curve : Curve
    snapshots : tuple of Snapshot
    summary : RunSummary
        The ``summary.json`` contract (docs/site/outputs.md; a mapping of these keys): adhesive_force,
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
    summary: RunSummary
    attributes: dict[str, Any] = field(default_factory=dict)
    element_size: float = 1.0
    pillars: dict[str, np.ndarray] = field(default_factory=dict)
