"""The closed-form comparison of a run: the thesis's closed forms at the run's parameters, beside them.

`theory_for` gives a finished run's ``theory`` record (`PunchTheory`, `SphereTheory`, `BrushTheory` of
`brushbem.results`: the closed forms of `brushbem.physics.theory` at the rasterised indenter's parameters
and the computed values' ratios to them) and the reference curve of its figure; `brush_scales` and
`brush_normalizations` give a brush's scales and the thesis's normalisations (``normalized``).  The closed
forms are called, never retyped.  A case is anything with the contact problem's ``grid``, ``indenter``,
``contact_modulus`` and ``work_of_adhesion`` (`brushbem.protocol.ContactProblem`); a preload, anything
with ``preload_force`` and ``preload_displacement`` (`brushbem.protocol.LoadPath`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any, Protocol

import numpy as np

from brushbem.physics import theory
from brushbem.physics.scales import normalized_stiffness
from brushbem.physics.structure import BrushGeometry, Grid, Indenter
from brushbem.results import (
    BrushNormalization,
    BrushTheory,
    PunchTheory,
    ReferenceCurve,
    SphereTheory,
)

__all__ = ["Case", "Preload", "brush_normalizations", "brush_scales", "spring_numbers", "spring_stiffness",
           "theory_for"]


class Case(Protocol):
    """What the comparison reads of a contact problem (`brushbem.protocol.ContactProblem`)."""

    grid: Grid
    indenter: Indenter
    contact_modulus: float
    work_of_adhesion: float


class Preload(Protocol):
    """What the comparison reads of a load path (`brushbem.protocol.LoadPath`)."""

    preload_force: float | None
    preload_displacement: float | None


def theory_for(problem: Case, summary: Mapping[str, Any],
               path: Preload | None = None) -> tuple[Mapping[str, Any], ReferenceCurve | None]:
    """Closed-form values for this case and the ratios of the computed ones to them.

    A flat punch is compared with Kendall (eq. 2.4) at the radius of the
    rasterised footprint's area, sqrt(A/pi), and, on a spring, with the work
    of separation of eq. 2.18-2.19; a sphere with JKR (eq. 2.20) and, on a
    spring, the work of eq. 2.37 at the exact separation (dD/da = 0 for the
    sphere on its spring, `theory.sphere_spring_work`; not the thesis's
    piecewise eq. 2.38-2.39, up to 12 % low).  The sphere's work counts from the
    zero-force crossing of the unloading: from B (eq. 2.27) where the
    preload (``path``, Hertz loading) pressed the contact beyond a_o, from
    the fixed-contact line below it (`theory.sphere_spring_work_from_preload`).
    Returns the ``theory`` record of ``summary.json`` (`PunchTheory`,
    `SphereTheory`, `BrushTheory`, or an empty mapping where no closed form
    applies) and a reference curve for the figure (or None).
    """
    kind = _closed_form(problem)
    if kind == "brush":
        return _brush_theory(problem, summary)[0], None
    if kind is None:
        return {}, None
    if kind == "flat_punch":
        return _punch_theory(problem, summary)
    return _sphere_theory(problem, summary, path)


def _closed_form(problem: Case) -> str | None:
    """Which closed forms compare with the case: ``"brush"``, ``"flat_punch"``, ``"sphere"``, or None (no
    adhesion, another indenter)."""
    shape = problem.indenter.description.shape
    return shape if problem.work_of_adhesion > 0 and shape in ("brush", "flat_punch", "sphere") else None


def spring_stiffness(problem: Case) -> float:
    """The stiffness of the (pillars') spring as one number (a graded level's mean; inf: rigid)."""
    levels = problem.indenter.elastic_levels
    return _level_stiffness(levels[0]) if levels else math.inf


def spring_numbers(problem: Case) -> tuple[float, float | None] | None:
    """The (pillars') spring as a designer reads it: its stiffness k (`spring_stiffness`) and its k~ as the run
    normalises it, by the rule of the case's closed forms: a brush's k / (E* L) (``normalized.stiffness_ratio``),
    a punch's k / (2 E* a) and a sphere's (``theory.normalized_stiffness``), k~ None where none applies; None for
    a rigid indenter (no spring to report)."""
    stiffness = spring_stiffness(problem)
    if not math.isfinite(stiffness):
        return None
    kind = _closed_form(problem)
    if kind == "brush":
        return stiffness, _stiffness_ratios(problem)[0]
    if kind is None:
        return stiffness, None
    return stiffness, _normalized_spring(problem, kind, stiffness)


def _stiffness_ratios(problem: Case) -> list[float]:
    """A brush's k~ = k / (E* L) of every level (a graded level by its mean stiffness; rigid: [inf])."""
    stiffnesses = [_level_stiffness(level) for level in problem.indenter.levels] or [math.inf]
    # L of eq. 4.13: the brush's side (region_size), not the domain around it (brush_scales' stiffness_scale).
    size = float(problem.indenter.description.region_size)
    return [normalized_stiffness(k, problem.contact_modulus, size) for k in stiffnesses]


def _normalized_spring(problem: Case, kind: str, stiffness: float) -> float:
    """A punch's k / (2 E* a) at the footprint's radius, or a sphere's normalised stiffness (finite k)."""
    if kind == "flat_punch":
        return theory.normalized_punch_stiffness(stiffness, _punch_radius(problem),
                                                 contact_modulus=problem.contact_modulus)
    return theory.sphere_normalized_stiffness(stiffness, problem.indenter.description.radius,
                                              contact_modulus=problem.contact_modulus,
                                              work_of_adhesion=problem.work_of_adhesion)


def _punch_radius(problem: Case) -> float:
    """A flat punch's radius: of its rasterised footprint's area, sqrt(A / pi)."""
    return math.sqrt(problem.indenter.description.rasterised_area / math.pi)


def _level_stiffness(level) -> float:
    """A level's stiffness as one number: its springs' own, or their mean for a graded level."""
    return float(level.stiffnesses[0]) if level.uniform else float(np.mean(level.stiffnesses))


#: The closed forms that assume a linear elastic spring: the base displacement and the work.
_SPRING_QUANTITIES = ("pull_off_displacement", "work_of_separation")


def _not_applicable_reasons(problem: Case, stiffness: float) -> dict[str, str] | None:
    """Quantity -> why its closed form does not apply: a spring that is viscoelastic or nonlinear.

    The adhesive force still compares (the contact detaches at its critical force whatever the spring
    law); the base displacement and the work of eq. 2.18-2.19 and 2.37 are of a linear elastic spring.
    """
    if not math.isfinite(stiffness):
        return None
    kind = ("viscoelastic" if problem.indenter.viscoelastic is not None
            else "nonlinear (Indenter.pillar_law)" if problem.indenter.pillar_law is not None else None)
    if kind is None:
        return None
    reason = f"the closed form is of a linear elastic spring; this spring is {kind}"
    return dict.fromkeys(_SPRING_QUANTITIES, reason)


def _not_applicable(problem: Case, stiffness: float) -> dict[str, None]:
    """``_ratios`` keywords that drop the quantities whose closed form does not apply."""
    return dict.fromkeys(_not_applicable_reasons(problem, stiffness) or {}, None)


def _ratios(summary: Mapping[str, Any], **closed_forms: float | None) -> dict[str, float]:
    """Computed over closed form, for the quantities both have (and a non-zero closed form; None: skipped)."""
    ratios = {}
    for key, value in closed_forms.items():
        computed = summary.get(key)
        if computed is not None and value:
            ratios[key] = computed / value
    return ratios


def _punch_theory(problem: Case, summary: Mapping[str, Any]) -> tuple[PunchTheory, ReferenceCurve]:
    """Kendall's punch (eq. 2.4) on its spring (eq. 2.18-2.19), with the reference curve (eq. 2.1)."""
    modulus, dgamma, stiffness = problem.contact_modulus, problem.work_of_adhesion, spring_stiffness(problem)
    radius = _punch_radius(problem)
    force = theory.kendall_force(radius, contact_modulus=modulus, work_of_adhesion=dgamma)
    tip = theory.kendall_displacement(radius, contact_modulus=modulus, work_of_adhesion=dgamma)
    base = tip - (force / stiffness if math.isfinite(stiffness) else 0.0)
    work = theory.punch_spring_work_of_separation(radius, stiffness, contact_modulus=modulus,
                                                  work_of_adhesion=dgamma)
    record = PunchTheory(
        equivalent_radius=radius, adhesive_force=force, pull_off_displacement=base, work_of_separation=work,
        normalized_stiffness=_normalized_spring(problem, "flat_punch", stiffness) if math.isfinite(stiffness) else None,
        ratios=_ratios(summary, **({"adhesive_force": force, "pull_off_displacement": base,
                                    "work_of_separation": work} | _not_applicable(problem, stiffness))),
        not_applicable=_not_applicable_reasons(problem, stiffness),
    )
    compliance = (1.0 / theory.punch_stiffness(radius, contact_modulus=modulus)
                  + (1.0 / stiffness if math.isfinite(stiffness) else 0.0))
    d_max = summary.get("max_displacement") or 0.0
    reference = ReferenceCurve(displacement=np.array([d_max, base, base]),
                               force=np.array([d_max / compliance, -force, 0.0]), label="Kendall (eq. 2.1, 2.4)")
    return record, reference


def _sphere_theory(problem: Case, summary: Mapping[str, Any],
                   path: Preload | None) -> tuple[SphereTheory, ReferenceCurve]:
    """JKR (eq. 2.20-2.24) on a spring (eq. 2.32-2.37, exact separation), with the JKR curve (eq. 2.22)."""
    modulus, dgamma, stiffness = problem.contact_modulus, problem.work_of_adhesion, spring_stiffness(problem)
    radius = problem.indenter.description.radius
    force = theory.jkr_pull_off_force(radius, work_of_adhesion=dgamma)
    tip = theory.jkr_pull_off_displacement(radius, contact_modulus=modulus, work_of_adhesion=dgamma)
    base = tip - (force / stiffness if math.isfinite(stiffness) else 0.0)
    preload_radius = math.inf
    preload: dict[str, Any] = {}
    if path is not None:
        preload_radius = theory.sphere_preload_contact_radius(
            radius, stiffness, preload_force=path.preload_force,
            preload_displacement=path.preload_displacement, contact_modulus=modulus,
        )
        zero_force_radius = theory.jkr_zero_force_radius(radius, contact_modulus=modulus, work_of_adhesion=dgamma)
        preload = {
            "preload_contact_radius": preload_radius,
            "zero_force_radius": zero_force_radius,
            "work_counted_from": (
                "B, the zero-force point of the JKR curve (eq. 2.27)"
                if preload_radius >= zero_force_radius
                else "the zero-force crossing of the fixed-contact unloading line (the preload contact "
                "radius is below a_o, so the unloading does not pass B)"
            ),
        }
    work = theory.sphere_spring_work_of_separation(radius, stiffness, preload_radius=preload_radius,
                                                   contact_modulus=modulus, work_of_adhesion=dgamma)
    # The contact never grows beyond the preload's radius: below JKR's pull-off radius the unloading (the
    # contact pinned at a_p) meets the JKR curve at a_p, and along it to smaller radii the tension only
    # falls, so the largest tension the path can reach is the curve's at a_p, not 3/2 pi dgamma R.
    pull_off_radius = theory.jkr_pull_off_radius(radius, contact_modulus=modulus, work_of_adhesion=dgamma)
    if preload_radius < pull_off_radius:
        force = -float(theory.jkr_force_from_radius(preload_radius, radius, contact_modulus=modulus,
                                                    work_of_adhesion=dgamma))
        base = float(theory.jkr_displacement_from_radius(preload_radius, radius, contact_modulus=modulus,
                                                         work_of_adhesion=dgamma))
        base -= force / stiffness if math.isfinite(stiffness) else 0.0
        preload["adhesive_force_from"] = (
            f"the JKR curve (eq. 2.22) at the preload contact radius a_p = {preload_radius:.6g}, below JKR's "
            f"pull-off radius {pull_off_radius:.6g}: the unloading never reaches 3/2 pi dgamma R (eq. 2.24)")
    elif path is not None:
        preload["adhesive_force_from"] = "JKR's pull-off force 3/2 pi dgamma R (eq. 2.24)"
    record = SphereTheory(
        **preload,
        normalized_stiffness=_normalized_spring(problem, "sphere", stiffness) if math.isfinite(stiffness) else None,
        adhesive_force=force, pull_off_displacement=base, work_of_separation=work,
        ratios=_ratios(summary, **({"adhesive_force": force, "pull_off_displacement": base,
                                    "work_of_separation": work} | _not_applicable(problem, stiffness))),
        not_applicable=_not_applicable_reasons(problem, stiffness),
    )
    a_sep = theory.jkr_separation_radius(radius, contact_modulus=modulus, work_of_adhesion=dgamma)
    a_max = max(a_sep * 4.0, theory.jkr_pull_off_radius(radius, contact_modulus=modulus, work_of_adhesion=dgamma) * 2.5)
    a = np.linspace(a_sep, a_max, 200)
    f = theory.jkr_force_from_radius(a, radius, contact_modulus=modulus, work_of_adhesion=dgamma)
    d = theory.jkr_displacement_from_radius(a, radius, contact_modulus=modulus, work_of_adhesion=dgamma)
    if math.isfinite(stiffness):
        d = d + f / stiffness
    keep = d <= (summary.get("max_displacement") or d.max())
    return record, ReferenceCurve(displacement=d[keep], force=f[keep], label="JKR (eq. 2.22)")


def brush_scales(problem: Case) -> dict[str, Any]:
    """The thesis's force, displacement and stiffness scales of a brush (ch. 4-7).

    Areas are those of the rasterised footprints (what the computation sees):
    A = real area, A0 = apparent area of the placement region, phi = A / A0.

    * ``compact_punch_force``: Kendall's force of one punch of area A (eq. 4.11).
    * ``rigid_brush_force``: F_c = sqrt(8 pi E* dgamma phi (sqrt(A0/pi))^3) (eq. 4.5, 5.3, 6.23).
    * ``ideal_sharing_force``: N F_K, the sum of the pillars' Kendall forces,
      each at the radius of its rasterised footprint (eq. 7.4 with the area
      seen by the mesh).
    * ``rigid_brush_displacement``: |d_c| = sqrt(2 pi phi dgamma sqrt(A0/pi) / E*)
      (eq. 4.12, 5.4, 7.5), a magnitude as in the thesis.
    * ``stiffness_scale``: E* L, L the brush's side ``region_size`` (eq. 4.13, 5.5, 6.24, 7.6; the domain
      side where the brush fills it, as in the thesis), so a margin of domain around the brush leaves k~.
    """
    indenter = problem.indenter
    info = indenter.description
    modulus, dgamma = problem.contact_modulus, problem.work_of_adhesion
    h2 = problem.grid.element_size**2
    phi = min(info.filling_factor, 1.0)
    radii = np.sqrt(np.asarray(info.pillar_elements, dtype=float) * h2 / math.pi)
    return {
        "compact_punch_force": float(theory.compact_punch_force(info.real_area, contact_modulus=modulus,
                                                                work_of_adhesion=dgamma)),
        "rigid_brush_force": float(theory.rigid_brush_force(phi, info.apparent_area, contact_modulus=modulus,
                                                            work_of_adhesion=dgamma)),
        "ideal_sharing_force": float(np.sum(theory.kendall_force(radii, contact_modulus=modulus,
                                                                 work_of_adhesion=dgamma))),
        "rigid_brush_displacement": abs(float(theory.rigid_brush_displacement(
            phi, info.apparent_area, contact_modulus=modulus, work_of_adhesion=dgamma))),
        "stiffness_scale": modulus * float(info.region_size),  # E* L, L the brush's side
        "filling_factor": phi,
    }


def brush_normalizations(problem: Case, summary: Mapping[str, Any]) -> BrushNormalization | None:
    """The thesis's normalisations of an adhesive brush's summary numbers (``normalized``), else None."""
    if not isinstance(problem.indenter.description, BrushGeometry) or problem.work_of_adhesion <= 0:
        return None
    return BrushNormalization(**_brush_theory(problem, summary)[1])


def _brush_theory(problem: Case, summary: Mapping[str, Any]) -> tuple[BrushTheory, dict[str, Any]]:
    """The closed forms and the thesis's normalisations of a brush."""
    indenter = problem.indenter
    info = indenter.description
    scales = brush_scales(problem)
    n = info.n_pillars
    ratios = _stiffness_ratios(problem)
    force = summary.get("adhesive_force") or 0.0
    d_c = scales["rigid_brush_displacement"]

    def ratio(value, scale):
        return None if value is None or not scale else value / scale

    normalized = {
        "force_by_compact_punch": ratio(force, scales["compact_punch_force"]),
        "force_by_rigid_brush": ratio(force, scales["rigid_brush_force"]),
        "force_by_ideal_sharing": ratio(force, scales["ideal_sharing_force"]),
        "displacement_by_rigid_brush": ratio(summary.get("pull_off_displacement"), d_c),
        "separation_displacement_by_rigid_brush": ratio(summary.get("separation_displacement"), d_c),
        "max_displacement_by_rigid_brush": ratio(summary.get("max_displacement"), d_c),
        "preload_by_rigid_brush": ratio(summary.get("preload_force"), scales["rigid_brush_force"]),
        "preload_by_compact_punch": ratio(summary.get("preload_force"), scales["compact_punch_force"]),
        "roughness_by_rigid_brush": ratio(info.roughness, d_c),
        "stiffness_ratio": ratios[0],
        "level_stiffness_ratios": ratios,
        "filling_factor": info.filling_factor,
        "pillars": n,
        "attached_pillars_at_pull_off": summary.get("attached_pillars_at_pull_off"),
        "profile_amplification": info.profile_amplification,
    }
    clusters = info.level_clusters
    if clusters:
        counts = [float(c * c) for c in clusters]
        normalized["equivalent_single_level_stiffness_ratio"] = theory.equivalent_single_level_stiffness(
            ratios, counts)
    out = BrushTheory(
        compact_punch_force=scales["compact_punch_force"],
        rigid_brush_force=scales["rigid_brush_force"],
        ideal_sharing_force=scales["ideal_sharing_force"],
        rigid_brush_displacement=-d_c,
        rigid_brush_enhancement=float(theory.rigid_brush_enhancement(scales["filling_factor"])),
        soft_brush_enhancement=float(theory.soft_brush_enhancement(n)),
        ratios={
            "adhesive_force_by_rigid_brush": normalized["force_by_rigid_brush"],
            "adhesive_force_by_ideal_sharing": normalized["force_by_ideal_sharing"],
        },
    )
    return out, normalized
