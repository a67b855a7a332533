"""One case: a validated configuration in, a `PullOff` (the record with its closed-form references) out."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np

from brushbem import __version__
from brushbem.physics import theory
from brushbem.runs.assembly import (
    Assembly,
    assemble,
    build_indenter,
    build_path,
    build_problem,
    configuration_errors,
    configuration_text,
)
from brushbem.backend import backend_name
from brushbem.config import RunConfig, advice, config_to_dict
from brushbem.protocol import ContactProblem, LoadPath, PullOffRecord, record_pull_off
from brushbem.runs.pulloff import PullOff
from brushbem.results import (
    BrushNormalization,
    BrushTheory,
    CaseResult,
    PunchTheory,
    ReferenceCurve,
    RunSummary,
    SphereTheory,
)
from brushbem.physics.structure import BrushGeometry
from brushbem.physics.scales import normalized_stiffness

__all__ = ["PullOff", "brush_normalizations", "brush_scales", "build_indenter", "build_path", "build_problem",
           "design_numbers", "reference_for", "run_case", "run_problem", "run_warnings", "theory_for"]

# A fixed-step pull-off whose tensile part spans fewer steps than this samples
# the force minimum and the tensile area too coarsely to be read as results.
MIN_TENSILE_STEPS = 10


def theory_for(problem: ContactProblem, summary: Mapping[str, Any],
               path: LoadPath | None = None) -> tuple[Mapping[str, Any], ReferenceCurve | None]:
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
    shape = problem.indenter.description.shape
    if shape == "brush" and problem.work_of_adhesion > 0:
        return _brush_theory(problem, summary)[0], None
    if problem.work_of_adhesion <= 0 or shape not in ("flat_punch", "sphere"):
        return {}, None
    if shape == "flat_punch":
        return _punch_theory(problem, summary)
    return _sphere_theory(problem, summary, path)


def _stiffness(problem: ContactProblem) -> float:
    levels = problem.indenter.elastic_levels
    return _level_stiffness(levels[0]) if levels else math.inf


def _level_stiffness(level) -> float:
    """A level's stiffness as one number: its springs' own, or their mean for a graded level."""
    return float(level.stiffnesses[0]) if level.uniform else float(np.mean(level.stiffnesses))


#: The closed forms that assume a linear elastic spring: the base displacement and the work.
_SPRING_QUANTITIES = ("pull_off_displacement", "work_of_separation")


def _not_applicable_reasons(problem: ContactProblem, stiffness: float) -> dict[str, str] | None:
    """Quantity -> why its closed form does not apply: a spring that is viscoelastic or nonlinear.

    The adhesive force still compares (the contact detaches at its critical force whatever the spring
    law); the base displacement and the work of eq. 2.18-2.19 and 2.37 are of a linear elastic spring.
    """
    if not math.isfinite(stiffness):
        return None
    kind = ("viscoelastic" if problem.indenter.viscoelastic is not None
            else "nonlinear (indenter.pillar_law)" if problem.indenter.pillar_law is not None else None)
    if kind is None:
        return None
    reason = f"the closed form is of a linear elastic spring; this spring is {kind}"
    return dict.fromkeys(_SPRING_QUANTITIES, reason)


def _not_applicable(problem: ContactProblem, stiffness: float) -> dict[str, None]:
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


def _punch_theory(problem: ContactProblem, summary: Mapping[str, Any]) -> tuple[PunchTheory, ReferenceCurve]:
    """Kendall's punch (eq. 2.4) on its spring (eq. 2.18-2.19), with the reference curve (eq. 2.1)."""
    modulus, dgamma, stiffness = problem.contact_modulus, problem.work_of_adhesion, _stiffness(problem)
    radius = math.sqrt(problem.indenter.description.rasterised_area / math.pi)
    force = theory.kendall_force(radius, contact_modulus=modulus, work_of_adhesion=dgamma)
    tip = theory.kendall_displacement(radius, contact_modulus=modulus, work_of_adhesion=dgamma)
    base = tip - (force / stiffness if math.isfinite(stiffness) else 0.0)
    work = theory.punch_spring_work_of_separation(radius, stiffness, contact_modulus=modulus,
                                                  work_of_adhesion=dgamma)
    record = PunchTheory(
        equivalent_radius=radius, adhesive_force=force, pull_off_displacement=base, work_of_separation=work,
        normalized_stiffness=(theory.normalized_punch_stiffness(stiffness, radius, contact_modulus=modulus)
                              if math.isfinite(stiffness) else None),
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


def _sphere_theory(problem: ContactProblem, summary: Mapping[str, Any],
                   path: LoadPath | None) -> tuple[SphereTheory, ReferenceCurve]:
    """JKR (eq. 2.20-2.24) on a spring (eq. 2.32-2.37, exact separation), with the JKR curve (eq. 2.22)."""
    modulus, dgamma, stiffness = problem.contact_modulus, problem.work_of_adhesion, _stiffness(problem)
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
        normalized_stiffness=(theory.sphere_normalized_stiffness(stiffness, radius, contact_modulus=modulus,
                                                                 work_of_adhesion=dgamma)
                              if math.isfinite(stiffness) else None),
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


def brush_scales(problem: ContactProblem) -> dict[str, Any]:
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


def brush_normalizations(problem: ContactProblem, summary: Mapping[str, Any]) -> BrushNormalization | None:
    """The thesis's normalisations of an adhesive brush's summary numbers (``normalized``), else None."""
    if not isinstance(problem.indenter.description, BrushGeometry) or problem.work_of_adhesion <= 0:
        return None
    return BrushNormalization(**_brush_theory(problem, summary)[1])


def _brush_theory(problem: ContactProblem, summary: Mapping[str, Any]) -> tuple[BrushTheory, dict[str, Any]]:
    """The closed forms and the thesis's normalisations of a brush."""
    indenter = problem.indenter
    info = indenter.description
    scales = brush_scales(problem)
    n = info.n_pillars
    # A graded level is normalised by its mean stiffness.
    stiffnesses = [_level_stiffness(level) for level in indenter.levels] or [math.inf]
    # L of eq. 4.13: the brush's side (region_size), not the domain around it (brush_scales' stiffness_scale).
    ratios = [normalized_stiffness(k, problem.contact_modulus, float(info.region_size)) for k in stiffnesses]
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


def run_warnings(problem: ContactProblem, path: LoadPath, record: PullOffRecord) -> list[str]:
    """What makes a finished run's numbers questionable although every solve converged.

    * The contact at the preload reaches the edge of the domain on an indenter
      that continues beyond it (a sphere, a height map): the pressure outside
      the domain is taken as zero, so the indenter is cut there.
    * The fixed-step path resolved the tensile part of the pull-off by fewer
      than `MIN_TENSILE_STEPS` steps.
    * The preload displacement exceeds the domain size: far outside the small
      strains of linear elasticity.
    """
    warnings = []
    summary = record.summary
    shape = problem.indenter.description.shape
    preload = next((s for s in record.snapshots if s.name == "max_preload"), None)
    if shape in ("sphere", "height_map") and preload is not None:
        contact = np.asarray(preload.contact)
        if contact[0].any() or contact[-1].any() or contact[:, 0].any() or contact[:, -1].any():
            warnings.append(
                f"the contact at the preload reaches the edge of the domain (grid.size = {problem.grid.size:g}): "
                "the indenter is cut there (no pressure outside the domain); enlarge grid.size or lower the preload"
            )
    curve = record.curve
    if path.method == "fixed" and summary.get("adhesive_force", 0.0) > 0.0:
        # Step ends only: the events located inside the steps resolve the unloading, but the step
        # also sets the loading branch (an adhesive step that attaches every overlapping element
        # holds ones the exact path never lets touch: a JKR sphere pressed in one step is 26 % strong).
        unloading = ~curve.loading & (curve.force < 0.0)
        steps_back = (np.max(curve.displacement) - curve.displacement[unloading]) / path.step
        tensile = int(np.count_nonzero(np.abs(steps_back - np.round(steps_back)) < 1e-6))
        if tensile < MIN_TENSILE_STEPS:
            warnings.append(
                f"the tensile part of the pull-off spans only {tensile} fixed steps (protocol.step = {path.step:g}): "
                "the adhesive force and the work of separation are coarse; lower protocol.step or use "
                'method = "events"'
            )
    if summary.get("max_displacement", 0.0) > problem.grid.size:
        warnings.append(
            f"the preload displacement {summary['max_displacement']:g} exceeds the domain size "
            f"(grid.size = {problem.grid.size:g}): far beyond the small strains the linear half-space assumes"
        )
    return warnings


def run_case(
    config: RunConfig | Assembly,
    *,
    progress: Callable[[float, str], None] | None = None,
    stop: Callable[[], bool] | None = None,
) -> PullOff:
    """Run one validated configuration (or its `Assembly`, built from its validation's rasterisation).

    Returns the `PullOff`: its ``result`` (curve, snapshots, summary with its
    ``theory`` object, provenance attributes), the closed-form ``reference``
    curve for the figure and the ``config`` it ran from.  ``stop`` (polled
    after every state, `record_pull_off`) ends the run early: the result then
    holds the path so far, ``interrupted`` and not converged.
    """
    built = config if isinstance(config, Assembly) else assemble(config)
    with configuration_errors():  # a parameter the run refuses, named by its configuration key
        pulled = run_problem(built.problem, built.path, progress=progress, stop=stop,
                             config=config_to_dict(built.config))
    result = pulled.result
    reason = result.summary.reason
    if isinstance(reason, str) and configuration_text(reason) != reason:  # a parameter's limit, as its key
        result = dataclasses.replace(result, summary=dataclasses.replace(result.summary,
                                                                         reason=configuration_text(reason)))
    found = advice.resolution(built.config)
    result = dataclasses.replace(result, summary=dataclasses.replace(
        result.summary, warnings=[*advice.advice(built.config), *result.summary.warnings],
        resolution=None if found is None else found.to_dict(),
        design=design_numbers(built.problem, result.summary, built.config)))
    return PullOff(result, pulled.reference, built.config)


def reference_for(assembly: Assembly, summary: Mapping[str, Any]) -> ReferenceCurve | None:
    """The closed-form reference curve of a run of ``assembly`` whose summary is ``summary`` (its figure's)."""
    return theory_for(assembly.problem, summary, assembly.path)[1]


def design_numbers(problem: ContactProblem, summary: Mapping[str, Any], config: RunConfig) -> dict[str, Any]:
    """What a designer reports, with the unit of each number (``summary.json``'s ``design``).

    * ``adhesion_strength``: F_A / A0, A0 the apparent area (a brush's placement region, a punch's
      pi r^2 as typed); absent for a sphere and a height map, which have none.
    * ``adhesive_force_per_pillar``: F_A / N_p (a brush).
    * ``spring``: the stiffness k of the (pillars') spring, where it came from (``indenter.fibril``:
      k = pi r^2 E_f / l; ``indenter.stiffness``; ``indenter.stiffness_ratio``: k~ E* L), its k~ as the
      run normalises it (``normalized.stiffness_ratio`` of a brush, ``theory.normalized_stiffness`` of a
      punch or sphere) and, with ``fibril.buckling``, Euler's buckling force.
    * ``units``: the unit of each dimensional number (`brushbem.results.units.Units`; "1" without ``[units]``).
    """
    from brushbem.results.units import Units

    units = Units.from_config(config)
    spec = config.indenter
    force = float(summary.get("adhesive_force") or 0.0)
    out: dict[str, Any] = {}
    info = problem.indenter.description
    if isinstance(info, BrushGeometry):
        out["apparent_area"] = float(info.apparent_area)
        out["adhesion_strength"] = force / float(info.apparent_area)
        out["pillars"] = int(info.n_pillars)
        out["adhesive_force_per_pillar"] = force / int(info.n_pillars)
    elif spec.shape == "flat_punch" and spec.radius is not None:
        out["apparent_area"] = math.pi * spec.radius**2
        out["adhesion_strength"] = force / out["apparent_area"]
    stiffness = _stiffness(problem)
    if math.isfinite(stiffness):
        if spec.fibril is not None:
            origin = (f"indenter.fibril: k = pi r^2 E_f / l (E_f = {spec.fibril.youngs_modulus:g}, l = "
                      f"{spec.fibril.length:g}, r = {spec.fibril.radius or advice.fibril_radius(config):g})")
        elif spec.stiffness_ratio is not None:
            origin = "indenter.stiffness_ratio: k = k~ E* L"
        else:
            origin = "indenter.stiffness"
        normalized = summary.get("normalized") or {}
        theory_record = summary.get("theory") or {}
        ratio = normalized.get("stiffness_ratio", theory_record.get("normalized_stiffness"))
        spring: dict[str, Any] = {"stiffness": stiffness, "from": origin, "stiffness_ratio": ratio}
        if spec.fibril is not None and spec.pillar_law is not None and spec.fibril.buckling is not None:
            spring["buckling_force"] = float(spec.pillar_law.forces[0])
        out["spring"] = spring
    out["units"] = {"adhesion_strength": units.of("stress"), "apparent_area": units.of("length^2"),
                    "adhesive_force_per_pillar": units.of("force"), "stiffness": units.of("force / length"),
                    "buckling_force": units.of("force")}
    return out


def run_problem(
    problem: ContactProblem,
    path: LoadPath,
    *,
    progress: Callable[[float, str], None] | None = None,
    stop: Callable[[], bool] | None = None,
    config: dict[str, Any] | None = None,
) -> PullOff:
    """Run the pull-off of a built problem: `run_case` without a configuration.

    ``config`` (the resolved configuration as a mapping, if there is one) is
    recorded in the provenance attributes; the `PullOff`'s ``config`` is None.
    """
    record = record_pull_off(problem, path, progress=progress, stop=stop)
    theory, reference = theory_for(problem, record.summary, path)
    summary = RunSummary(
        **record.summary.to_dict(),
        critical_stress=problem.critical_stress,
        normalized=brush_normalizations(problem, record.summary),
        theory=theory,
        warnings=run_warnings(problem, path, record),
    )
    attributes = {"brushbem_version": __version__, "seeds": [], "backend": backend_name(problem.xp)}
    if config is not None:
        attributes["config"] = config
    pillars = dict(record.pillars)
    info = problem.indenter.description
    if isinstance(info, BrushGeometry):
        pillars.update({
            "y": np.asarray(info.centres)[:, 0],
            "x": np.asarray(info.centres)[:, 1],
            "offset": np.asarray(info.offsets),
            "elements": np.asarray(info.pillar_elements),
        })
        if problem.indenter.levels and not problem.indenter.levels[0].rigid:
            pillars["stiffness"] = np.array(problem.indenter.levels[0].stiffnesses)
        attributes["seeds"] = [info.seed]
    result = CaseResult(
        curve=record.curve,
        snapshots=record.snapshots,
        summary=summary,
        attributes=attributes,
        element_size=problem.grid.element_size,
        pillars=pillars,
    )
    return PullOff(result, reference, None)
