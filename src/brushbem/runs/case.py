"""One case: a validated configuration in, a `PullOff` (the record with its closed-form references) out."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np

from brushbem import __version__
from brushbem.backend import backend_name
from brushbem.config import RunConfig, advice, config_to_dict
from brushbem.physics.comparison import (
    brush_normalizations,
    brush_scales,
    spring_numbers,
    theory_for,
)
from brushbem.physics.structure import BrushGeometry
from brushbem.protocol import ContactProblem, LoadPath, PullOffRecord, record_pull_off
from brushbem.results import (
    CaseResult,
    DesignNumbers,
    ReferenceCurve,
    RunSummary,
    Spring,
)
from brushbem.runs.assembly import (
    Assembly,
    assemble,
    build_indenter,
    build_path,
    build_problem,
    configuration_errors,
    configuration_text,
)
from brushbem.runs.pulloff import PullOff

__all__ = ["PullOff", "brush_normalizations", "brush_scales", "build_indenter", "build_path", "build_problem",
           "design_numbers", "reference_for", "run_case", "run_problem", "run_warnings", "theory_for"]

# A fixed-step pull-off whose tensile part spans fewer steps than this samples
# the force minimum and the tensile area too coarsely to be read as results.
MIN_TENSILE_STEPS = 10


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
    # The spring's k and k~ as the run normalises them, taken here, before the run's records, and handed to
    # its design record: k~ goes from the physics to the records and the file, never back (docs/site/internals.md).
    spring = spring_numbers(built.problem)
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
        resolution=found,
        design=design_numbers(built.problem, result.summary, built.config, spring)))
    return PullOff(result, pulled.reference, built.config)


def reference_for(assembly: Assembly, summary: Mapping[str, Any]) -> ReferenceCurve | None:
    """The closed-form reference curve of a run of ``assembly`` whose summary is ``summary`` (its figure's)."""
    return theory_for(assembly.problem, summary, assembly.path)[1]


def design_numbers(problem: ContactProblem, summary: RunSummary, config: RunConfig,
                   spring: tuple[float, float | None] | None) -> DesignNumbers:
    """What a designer reports, with the unit of each number (``summary.json``'s ``design``).

    * ``adhesion_strength``: F_A / A0, A0 the apparent area (a brush's placement region, a punch's
      pi r^2 as typed); absent for a sphere and a height map, which have none.
    * ``adhesive_force_per_pillar``: F_A / N_p (a brush).
    * ``spring``: the stiffness k of the (pillars') spring, where it came from (``indenter.fibril``:
      k = pi r^2 E_f / l; ``indenter.stiffness``; ``indenter.stiffness_ratio``: k~ E* L), its k~ as the
      run normalises it (``normalized.stiffness_ratio`` of a brush, ``theory.normalized_stiffness`` of a
      punch or sphere) and, with ``fibril.buckling``, Euler's buckling force.  ``spring`` is (k, k~) of
      `brushbem.physics.comparison.spring_numbers`, handed on as it is (None: rigid, no ``spring``).
    * ``units``: the unit of each dimensional number (`brushbem.results.units.Units`; "1" without ``[units]``).
    """
    from brushbem.results.units import Units

    units = Units.from_config(config)
    spec = config.indenter
    force = float(summary.adhesive_force or 0.0)
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
    if spring is not None:
        if spec.fibril is not None:
            origin = (f"indenter.fibril: k = pi r^2 E_f / l (E_f = {spec.fibril.youngs_modulus:g}, l = "
                      f"{spec.fibril.length:g}, r = {spec.fibril.radius or advice.fibril_radius(config):g})")
        elif spec.stiffness_ratio is not None:
            origin = "indenter.stiffness_ratio: k = k~ E* L"
        else:
            origin = "indenter.stiffness"
        buckling = (float(spec.pillar_law.forces[0])
                    if spec.fibril is not None and spec.pillar_law is not None and spec.fibril.buckling is not None
                    else None)
        out["spring"] = Spring(stiffness=spring[0], origin=origin, stiffness_ratio=spring[1], buckling_force=buckling)
    out["units"] = {"adhesion_strength": units.of("stress"), "apparent_area": units.of("length^2"),
                    "adhesive_force_per_pillar": units.of("force"), "stiffness": units.of("force / length"),
                    "buckling_force": units.of("force")}
    return DesignNumbers(**out)


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
    if getattr(theory, "not_applicable", None):  # the reasons name parameters: as their keys
        theory = dataclasses.replace(theory, not_applicable={
            quantity: configuration_text(reason) for quantity, reason in theory.not_applicable.items()})
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
