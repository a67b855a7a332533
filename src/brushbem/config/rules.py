"""The rules between keys that no single field can express, and the problems they find.

A rule reports a `Problem`; `_rules_error` carries problems through
pydantic's error list to the formatter (`brushbem.config.errors`).  The rules
between the keys of one table are the `_rule_problems` methods of its model
(`brushbem.config.schema`); the rules between sections are here
(`_cross_section_problems`, `_resource_problems`), with the protocol of the
rules on the rasterised structure that `brushbem.runs.assembly` supplies
(`StructureRules`).
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import TYPE_CHECKING, Protocol

from pydantic_core import PydanticCustomError

from brushbem.config.errors import _show
from brushbem.config.files import _height_map_shape
from brushbem.errors import ParameterError, ParameterProblem
from brushbem.physics.scales import jkr_contact_radius

if TYPE_CHECKING:
    from brushbem.config.schema import (
        GridConfig,
        HalfSpaceConfig,
        IndenterConfig,
        RunConfig,
    )

__all__ = ["PARAMETER_KEYS", "SPHERE_MIN_PULL_OFF_ELEMENTS", "Problem", "StructureRules", "configuration_key",
           "configuration_text", "parameter_problems"]


@dataclass(frozen=True)
class Problem:
    """One problem found by a rule that a single field's constraints cannot express.

    ``key`` is relative to the model that found it (``""`` for the model
    itself); the formatter prefixes the location of that model.
    """

    key: str
    value: str
    allowed: str


class StructureRules(Protocol):
    """Rules on the rasterised structure, supplied by `brushbem.runs.assembly` (keys absolute).

    ``structure_problems`` runs with the other rules between sections, on the
    sections that validated (so it is reported beside their problems);
    ``rasterised_problems`` runs on a configuration that passed every other
    rule.
    """

    def structure_problems(self, grid: GridConfig, indenter: IndenterConfig,
                           halfspace: HalfSpaceConfig) -> list[Problem]: ...

    def rasterised_problems(self, config: RunConfig) -> list[Problem]: ...


#: The configuration key of every parameter a numerics object checks (`ParameterError`): the one place
#: that maps the numerics' names (``LoadPath.step``, ``Grid.elements``) back to the keys a user wrote.
PARAMETER_KEYS: dict[tuple[str, str], str] = {
    ("LoadPath", "method"): "protocol.method",
    ("LoadPath", "preload_displacement"): "protocol.preload_displacement",
    ("LoadPath", "preload_force"): "protocol.preload_force",
    ("LoadPath", "step"): "protocol.step",
    ("LoadPath", "max_steps"): "protocol.max_steps",
    ("LoadPath", "speed"): "protocol.speed",
    ("LoadPath", "event_window"): "protocol.event_window",
    ("LoadPath", "pillar_modes"): "protocol.pillar_modes",
    ("LoadPath", "pillar_near"): "protocol.pillar_near",
    ("LoadPath", "pillar_solve"): "protocol.pillar_solve",
    ("LoadPath", "pillar_tip_resolution"): "protocol.pillar_tip_resolution",
    ("LoadPath", "pillar_tip_calibration"): "protocol.pillar_tip_calibration",
    ("LoadPath", "pillar_tip_peel"): "protocol.pillar_tip_peel",
    ("LoadPath", "tolerance"): "solver.tolerance",
    ("LoadPath", "max_iterations"): "solver.max_iterations",
    ("LoadPath", "cascade"): "solver.cascade",
    ("ContactProblem", "coupling"): "solver.coupling",
    ("ContactProblem", "contact_modulus"): "halfspace.contact_modulus",
    ("ContactProblem", "work_of_adhesion"): "halfspace.work_of_adhesion",
    ("Grid", "size"): "grid.size",
    ("Grid", "elements"): "grid.elements",
    ("Indenter", "viscoelastic"): "indenter.viscoelastic",
    ("Indenter", "pillar_law"): "indenter.pillar_law",
    ("Indenter", "levels"): "indenter.stiffness",
    ("flat_punch", "radius"): "indenter.radius",
    ("flat_punch", "stiffness"): "indenter.stiffness",
    ("sphere", "radius"): "indenter.radius",
    ("sphere", "stiffness"): "indenter.stiffness",
    ("height_map", "heights"): "indenter.file",
    ("height_map", "stiffness"): "indenter.stiffness",
}


def configuration_key(exc: ParameterError) -> str | None:
    """The configuration key of ``exc``'s parameter (`PARAMETER_KEYS`; a brush parameter is ``indenter.<name>``)."""
    key = PARAMETER_KEYS.get((exc.owner, exc.parameter))
    if key is None and exc.owner == "brush":
        key = f"indenter.{exc.parameter}"
    return key


def configuration_text(text: str, keys: dict[tuple[str, str], str] | None = None) -> str:
    """``text`` (a numerics message, or a run's reason) with every ``Owner.parameter`` of ``keys`` (by default
    `PARAMETER_KEYS`) as its key."""
    for (owner, parameter), key in (PARAMETER_KEYS if keys is None else keys).items():
        text = text.replace(f"{owner}.{parameter}", key)
    return text


def parameter_problems(found: list[ParameterProblem], keys: dict[tuple[str, str], str] | None = None,
                       names: dict[str, str] | None = None) -> list[Problem]:
    """A domain rule's problems (`brushbem.errors.ParameterProblem`) as configuration problems, by key.

    Each ``(owner, parameter)`` reads as its key (`PARAMETER_KEYS`, ``keys`` first: where the key depends on
    the configuration, such as ``indenter.stiffness_ratio`` or ``indenter.stiffness``), every
    ``Owner.parameter`` in the text as its key, and ``names`` replaces further words of the text.
    """
    keys = {**PARAMETER_KEYS, **(keys or {})}
    out = []
    for problem in found:
        allowed = configuration_text(problem.allowed, keys)
        for old, new in (names or {}).items():
            allowed = allowed.replace(old, new)
        out.append(Problem(keys.get((problem.owner, problem.parameter), problem.name), _show(problem.value), allowed))
    return out


def _rules_error(problems: list[Problem]) -> PydanticCustomError:
    """Wrap rule problems so that they travel through pydantic's error list."""
    return PydanticCustomError(
        "config_rules",
        "{summary}",
        {"problems": problems, "summary": "; ".join(p.allowed for p in problems)},
    )


def _resource_problems(config: RunConfig) -> list[Problem]:
    """A run that would not fit in memory (`brushbem.config.resources`), refused before it starts."""
    from brushbem.config.resources import MEMORY_LIMIT_VARIABLE, memory_problem

    try:
        problem = memory_problem(config)
    except ValueError as exc:  # the limit variable itself is unusable
        return [Problem(MEMORY_LIMIT_VARIABLE, _show(os.environ.get(MEMORY_LIMIT_VARIABLE)), str(exc))]
    return [] if problem is None else [Problem("grid.elements", _show(config.grid.elements), problem)]


def _cross_section_problems(
    grid: GridConfig | None, indenter: IndenterConfig | None, halfspace: HalfSpaceConfig | None = None,
    rules: StructureRules | None = None,
) -> list[Problem]:
    """Rules between sections; each runs only if the sections it needs validated.

    Keys of the returned problems are absolute (``"indenter.radius"``).
    """
    if grid is None or indenter is None:
        return []
    problems = []
    h = grid.element_size
    if indenter.shape == "flat_punch" and indenter.radius is not None:
        radius = indenter.radius
        # With fewer than 2 elements in radius the rasterised footprint is a
        # handful of elements and no longer approximates a circular punch.
        if radius < 2 * h:
            problems.append(
                Problem(
                    "indenter.radius",
                    _show(radius),
                    f"under 2 elements (h = {h:g}); the punch needs at least 2 elements in radius",
                )
            )
        if 2 * radius > grid.size:
            problems.append(
                Problem(
                    "indenter.radius",
                    _show(radius),
                    f"the punch (diameter {2 * radius:g}) is larger than the domain "
                    f"(grid.size = {grid.size:g})",
                )
            )
    if indenter.shape == "sphere" and indenter.radius is not None and halfspace is not None:
        problems.extend(_sphere_resolution_problems(grid, indenter.radius, halfspace))
    tip = getattr(indenter, "tip", None)
    if (indenter.shape == "brush" and halfspace is not None and tip is not None
            and getattr(tip, "shape", None) == "spherical_cap" and tip.radius is not None):
        problems.extend(_cap_resolution_problems(grid, tip.radius, indenter.pillar_radius, halfspace))
    if halfspace is not None and rules is not None:
        problems.extend(rules.structure_problems(grid, indenter, halfspace))
    if indenter.shape == "height_map" and indenter.file is not None:
        shape = _height_map_shape(indenter.file)
        if shape != (grid.elements, grid.elements):
            problems.append(
                Problem(
                    "indenter.file",
                    _show(indenter.file),
                    f"holds a {shape[0]} x {shape[1]} array ({indenter.file}); grid.elements = {grid.elements} "
                    f"needs {grid.elements} x {grid.elements}",
                )
            )
    return problems


#: Fewest elements across the JKR pull-off contact radius of an adhesive sphere.
SPHERE_MIN_PULL_OFF_ELEMENTS = 2.0


def _cap_resolution_problems(grid: GridConfig, radius: float | str, pillar_radius: float | None,
                             halfspace: HalfSpaceConfig) -> list[Problem]:
    """Spherical-cap tips whose pull-off contact spans fewer than two elements in radius.

    A cap detaches as a JKR sphere of its curvature radius while its contact stays inside the pillar's
    face, so it needs the sphere's resolution (`_sphere_resolution_problems`); a contact wider than
    the face is the flat pillar's, resolved by the pillar's own check.  A file of one radius per
    pillar is checked at its smallest radius.  Without this check N = 64 gave a cap of R = 0.05
    (a_JKR = 0.6 elements) 3.07 times the converged F_A, with no word.
    """
    if isinstance(radius, str):
        try:
            import numpy as np

            radii = np.asarray(np.load(radius, allow_pickle=False), dtype=float).ravel()
        except (OSError, ValueError, TypeError):  # the tip's own rules report an unreadable file
            return []
        radii = radii[np.isfinite(radii) & (radii > 0)]
        if not radii.size:
            return []
        smallest = float(radii.min())
    else:
        smallest = float(radius)
    problems = _sphere_resolution_problems(grid, smallest, halfspace, key="indenter.tip.radius")
    if problems and pillar_radius is not None:
        modulus = halfspace.effective_modulus
        a_jkr = jkr_contact_radius(smallest, modulus, halfspace.work_of_adhesion)
        if a_jkr >= pillar_radius:  # the contact fills the face: the flat pillar's resolution decides
            return []
    return problems


def _sphere_resolution_problems(grid: GridConfig, radius: float, halfspace: HalfSpaceConfig,
                                key: str = "indenter.radius") -> list[Problem]:
    """An adhesive sphere whose pull-off contact spans fewer than two elements in radius.

    The mesh criterion (eq. 2.14) converges at first order in h / a: a JKR
    contact resolved by a_JKR / h = 39 elements is still 4 % strong, and one of
    a tenth of an element is not a contact at all (a sphere of R = 0.1 h gave
    F_A = 34 x JKR).  a_JKR = (9 pi dgamma R^2 / (8 E*))^(1/3) (eq. 2.20b) is
    the contact radius at the force minimum, the smallest one that decides F_A.
    """
    if halfspace.work_of_adhesion <= 0:
        return []
    h = grid.element_size
    try:
        modulus = halfspace.effective_modulus
    except (TypeError, ValueError, ArithmeticError):  # reported by the section's own rules
        return []
    a_jkr = jkr_contact_radius(radius, modulus, halfspace.work_of_adhesion)
    if a_jkr >= SPHERE_MIN_PULL_OFF_ELEMENTS * h:
        return []
    return [Problem(
        key, _show(radius),
        f"the JKR contact radius at pull-off, a = (9 pi dgamma R^2 / (8 E*))^(1/3) = {a_jkr:.3g}, spans "
        f"{a_jkr / h:.3g} elements (h = {h:g}); the criterion needs at least "
        f"{SPHERE_MIN_PULL_OFF_ELEMENTS:g}: raise {key} or halfspace.work_of_adhesion, "
        "or refine grid.elements",
    )]
