"""One case: a validated configuration in, a pull-off record with its closed-form references out."""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from . import __version__, theory
from .backend import backend_name
from .config import RunConfig, config_to_dict
from .protocol import ContactProblem, LoadPath, record_pull_off
from .results import CaseResult
from .structure import Grid, Indenter, flat_punch, height_map, sphere

__all__ = ["build_problem", "build_path", "run_case", "theory_for"]


def build_indenter(config: RunConfig) -> Indenter:
    """Rasterise the configured indenter on the configured grid."""
    grid = Grid(config.grid.size, config.grid.elements)
    spec = config.indenter
    if spec.shape == "flat_punch":
        return flat_punch(grid, spec.radius, spec.stiffness)
    if spec.shape == "sphere":
        return sphere(grid, spec.radius, spec.stiffness)
    if spec.shape == "height_map":
        return height_map(grid, np.load(spec.file, allow_pickle=False), spec.stiffness)
    raise ValueError(f"indenter.shape = {spec.shape!r} is not known")


def build_problem(config: RunConfig) -> ContactProblem:
    """The contact problem of a validated configuration."""
    grid = Grid(config.grid.size, config.grid.elements)
    return ContactProblem(
        grid=grid,
        indenter=build_indenter(config),
        contact_modulus=config.halfspace.effective_modulus,
        work_of_adhesion=config.halfspace.work_of_adhesion,
        coupling=config.solver.coupling,
    )


def build_path(config: RunConfig) -> LoadPath:
    """The load path of a validated configuration."""
    p = config.protocol
    return LoadPath(
        method=p.method,
        preload_displacement=p.preload_displacement,
        preload_force=p.preload_force,
        step=p.step,
        max_steps=p.max_steps,
        tolerance=config.solver.tolerance,
        max_iterations=config.solver.max_iterations,
    )


def theory_for(problem: ContactProblem, summary: dict[str, Any]) -> tuple[dict[str, Any], dict | None]:
    """Closed-form values for this case and the ratios of the computed ones to them.

    A flat punch is compared with Kendall (eq. 2.4) at the radius of the
    rasterised footprint's area, sqrt(A/pi), and, on a spring, with the work
    of separation of eq. 2.18-2.19; a sphere with JKR (eq. 2.20) and, on a
    spring, the work of eq. 2.37-2.39.  Returns the ``theory`` object of
    ``summary.json`` and a reference curve for the figure (or None).
    """
    indenter = problem.indenter
    shape = indenter.description.get("shape")
    modulus, dgamma = problem.contact_modulus, problem.work_of_adhesion
    levels = indenter.elastic_levels
    stiffness = levels[0].stiffness if levels else math.inf
    out: dict[str, Any] = {}
    reference = None
    if dgamma <= 0 or shape not in ("flat_punch", "sphere"):
        return out, None
    if shape == "flat_punch":
        radius = math.sqrt(indenter.description["rasterised_area"] / math.pi)
        force = theory.kendall_force(modulus, dgamma, radius)
        tip = theory.kendall_displacement(modulus, dgamma, radius)
        base = tip - (force / stiffness if math.isfinite(stiffness) else 0.0)
        work = theory.punch_spring_work_of_separation(modulus, dgamma, radius, stiffness)
        out.update({
            "model": "Kendall flat punch (thesis eq. 2.4, 2.18-2.19)",
            "equivalent_radius": radius,
            "adhesive_force": force,
            "pull_off_displacement": base,
            "work_of_separation": work,
        })
        if math.isfinite(stiffness):
            out["normalized_stiffness"] = theory.normalized_punch_stiffness(stiffness, modulus, radius)
        compliance = 1.0 / theory.punch_stiffness(modulus, radius) + (1.0 / stiffness if math.isfinite(stiffness) else 0.0)
        d_max = summary.get("max_displacement") or 0.0
        d = np.array([d_max, base, base])
        reference = {"displacement": d, "force": np.array([d_max / compliance, -force, 0.0]),
                     "label": "Kendall (eq. 2.1, 2.4)"}
    else:
        radius = indenter.description["radius"]
        force = theory.jkr_pull_off_force(dgamma, radius)
        tip = theory.jkr_pull_off_displacement(modulus, dgamma, radius)
        base = tip - (force / stiffness if math.isfinite(stiffness) else 0.0)
        if math.isfinite(stiffness):
            work = theory.sphere_spring_work_of_separation(modulus, dgamma, radius, stiffness)
            out["normalized_stiffness"] = theory.sphere_normalized_stiffness(stiffness, modulus, dgamma, radius)
        else:
            work = theory.jkr_work_of_separation(modulus, dgamma, radius)
        out.update({
            "model": "JKR sphere (thesis eq. 2.20-2.24, 2.32-2.39)",
            "adhesive_force": force,
            "pull_off_displacement": base,
            "work_of_separation": work,
        })
        a_sep = theory.jkr_separation_radius(modulus, dgamma, radius)
        a_max = max(a_sep * 4.0, theory.jkr_pull_off_radius(modulus, dgamma, radius) * 2.5)
        a = np.linspace(a_sep, a_max, 200)
        f = theory.jkr_force_from_radius(a, modulus, dgamma, radius)
        d = theory.jkr_displacement_from_radius(a, modulus, dgamma, radius)
        if math.isfinite(stiffness):
            d = d + f / stiffness
        keep = d <= (summary.get("max_displacement") or d.max())
        reference = {"displacement": d[keep], "force": f[keep], "label": "JKR (eq. 2.22)"}
    ratios = {}
    for key, computed_key in (("adhesive_force", "adhesive_force"),
                              ("pull_off_displacement", "pull_off_displacement"),
                              ("work_of_separation", "work_of_separation")):
        computed = summary.get(computed_key)
        if computed is not None and out.get(key):
            ratios[key] = computed / out[key]
    out["ratios"] = ratios
    return out, reference


def run_case(
    config: RunConfig,
    *,
    progress: Callable[[float, str], None] | None = None,
) -> tuple[CaseResult, dict | None]:
    """Run one validated configuration.

    Returns the result (curve, snapshots, summary with its ``theory`` object,
    provenance attributes) and the closed-form reference curve for the figure.
    """
    problem = build_problem(config)
    path = build_path(config)
    record = record_pull_off(problem, path, progress=progress)
    summary = dict(record.summary)
    summary["critical_stress"] = problem.critical_stress
    summary["theory"], reference = theory_for(problem, summary)
    attributes = {
        "brushbem_version": __version__,
        "config": config_to_dict(config),
        "seeds": [],
        "backend": backend_name(problem.xp),
    }
    result = CaseResult(
        curve=record.curve,
        snapshots=record.snapshots,
        summary=summary,
        attributes=attributes,
        element_size=problem.grid.element_size,
    )
    return result, reference
