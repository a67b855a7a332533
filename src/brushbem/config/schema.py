"""The section models of a run configuration: the fields and the rules between a table's keys.

One model per TOML table (`HalfSpaceConfig`, `GridConfig`, `IndenterConfig`
with `RoughnessConfig`, `ProfileConfig` and `LevelConfig`, `ProtocolConfig`,
`SolverConfig`) and `RunConfig`, the whole run.  A table's rules between keys
are its `_rule_problems`; `RunConfig` runs the rules between sections
(`brushbem.config.rules`).

The section models live in sibling modules and are re-exported here:
`brushbem.config.sections_base` (`_Model`, `_Section` and the helpers their
validators share), `brushbem.config.sections_domain` (half-space, grid),
`brushbem.config.sections_pillars` (the indenter's sub-tables),
`brushbem.config.sections_indenter` (`IndenterConfig`) and
`brushbem.config.sections_run` (protocol, solver, units).
"""

from __future__ import annotations

import math

from pydantic import BaseModel, ValidationInfo, model_validator

from brushbem.config.errors import _show
from brushbem.config.limits import MAX_PRELOAD_DOMAIN_SIZES
from brushbem.config.rules import (
    Problem,
    _cross_section_problems,
    _resource_problems,
    _rules_error,
    parameter_problems,
)
from brushbem.config.sections_base import _MODEL_CONFIG
from brushbem.config.sections_base import (
    _Model as _Model,  # re-exported: imported from this module
)
from brushbem.config.sections_base import (
    _Section as _Section,  # re-exported: `brushbem.config.loading`
)
from brushbem.config.sections_domain import GridConfig, HalfSpaceConfig
from brushbem.config.sections_indenter import IndenterConfig
from brushbem.config.sections_pillars import (
    GradingConfig,
    LevelConfig,
    PillarLawConfig,
    ProfileConfig,
    RoughnessConfig,
    TiltConfig,
    TipConfig,
    ViscoelasticConfig,
)
from brushbem.config.sections_run import ProtocolConfig, SolverConfig, UnitsConfig
from brushbem.physics.pillar_laws import law_path_problems
from brushbem.physics.viscoelastic import time_stepping_problems

__all__ = [
    "GradingConfig",
    "GridConfig",
    "HalfSpaceConfig",
    "IndenterConfig",
    "LevelConfig",
    "PillarLawConfig",
    "ProfileConfig",
    "ProtocolConfig",
    "RoughnessConfig",
    "RunConfig",
    "SolverConfig",
    "TiltConfig",
    "TipConfig",
    "UnitsConfig",
    "ViscoelasticConfig",
]


class RunConfig(BaseModel):
    """One run: half-space, grid, indenter, load path, solver settings and the inputs' units."""

    model_config = _MODEL_CONFIG

    halfspace: HalfSpaceConfig
    grid: GridConfig
    indenter: IndenterConfig
    protocol: ProtocolConfig
    solver: SolverConfig = SolverConfig()
    units: UnitsConfig = UnitsConfig()

    @model_validator(mode="after")
    def _consistent(self, info: ValidationInfo) -> RunConfig:
        rules = (info.context or {}).get("rules")
        problems = _cross_section_problems(self.grid, self.indenter, self.halfspace, rules)
        problems.extend(self._preload_problems())
        problems.extend(self._step_problems())
        problems.extend(self._time_stepping_problems())
        problems.extend(self._pillar_law_problems())
        problems.extend(self._pillar_model_problems())
        problems.extend(_resource_problems(self))  # before the indenter is rasterised
        if not problems and rules is not None:
            problems = rules.rasterised_problems(self)
        if problems:
            raise _rules_error(problems)
        return self


    def _deepest_preload(self) -> float:
        """The largest base displacement a preload may reach: `MAX_PRELOAD_DOMAIN_SIZES` x grid.size."""
        return MAX_PRELOAD_DOMAIN_SIZES * self.grid.size

    def _stiffest_contact(self) -> float:
        """An upper bound on the half-space's stiffness under any indenter on the grid: 2 E* L / sqrt(2).

        A rigid contact is stiffer the larger it is; every footprint lies inside the disc of radius
        L / sqrt(2) around the domain, whose rigid punch has the stiffness 2 E* L / sqrt(2).  A force F
        therefore presses the base at least F / (2 E* L / sqrt(2)) deep (springs only add to it).
        """
        return 2.0 * self.halfspace.effective_modulus * self.grid.size / math.sqrt(2.0)

    def _least_preload_depth(self) -> float | None:
        """The smallest base displacement the configured preload can reach (None without a preload)."""
        protocol = self.protocol
        if protocol.preload_displacement is not None:
            return protocol.preload_displacement
        if protocol.preload_force is not None:
            return protocol.preload_force / self._stiffest_contact()
        return None

    def _preload_problems(self) -> list[Problem]:
        """A preload far beyond the domain's scale, where the displacement's rounding swamps the pull-off."""
        protocol, deepest = self.protocol, self._deepest_preload()
        reason = ("deeper, the linear half-space's small strains are long left and the rounding of the base "
                  "displacement (2.2e-16 d) swamps the pull-off's displacements")
        if protocol.preload_displacement is not None and protocol.preload_displacement > deepest:
            return [Problem("protocol.preload_displacement", _show(protocol.preload_displacement),
                            f"must be in (0, {deepest:g}], at most {MAX_PRELOAD_DOMAIN_SIZES:g} x grid.size (grid.size "
                            f"= {self.grid.size:g}): {reason}")]
        if protocol.preload_force is not None and protocol.preload_force / self._stiffest_contact() > deepest:
            largest = deepest * self._stiffest_contact()
            return [Problem("protocol.preload_force", _show(protocol.preload_force),
                            f"must be in (0, {largest:.3g}]: a force F presses the base at least F / (2 E* L / "
                            f"sqrt(2)) = {protocol.preload_force / self._stiffest_contact():.3g} deep (the stiffest "
                            f"contact the domain allows, E* = {self.halfspace.effective_modulus:g}, L = grid.size = "
                            f"{self.grid.size:g}), more than {MAX_PRELOAD_DOMAIN_SIZES:g} x grid.size = {deepest:g}: {reason}")]
        return []

    def _step_problems(self) -> list[Problem]:
        """A fixed step beyond the domain, or so small that the pressing alone needs more than max_steps."""
        protocol = self.protocol
        if protocol.method != "fixed":
            return []
        # The first detachment is located inside a step to the rounding of the step's length: a step of
        # 1e30 put it 250 x off.  A base displacement beyond the domain size is outside linear elasticity.
        # Retracting from the preload to the surface alone takes (at least) depth / step steps (and so
        # does a stepped pressing); more than max_steps cannot finish, and would run for hours before
        # saying so (step = 1e-12 on a 1e-3 preload: 1e9 steps).
        largest, depth = self.grid.size, self._least_preload_depth()
        smallest = None if depth is None else depth / protocol.max_steps
        if smallest is not None and smallest > largest:  # no step fits: the budget is the problem
            return [Problem("protocol.max_steps", _show(protocol.max_steps),
                            f"must be at least {math.ceil(depth / largest)} with method = 'fixed': the preload lies "
                            f"{depth:.3g} deep, and even steps of grid.size = {largest:g} (the largest allowed) need "
                            "that many")]
        allowed = f"[{smallest:.3g}, {largest:g}]" if smallest is not None else f"(0, {largest:g}]"
        if protocol.step > largest:
            return [Problem("protocol.step", _show(protocol.step),
                            f"must be in {allowed}: at most grid.size = {largest:g} (a fixed step beyond the domain "
                            "size locates the pull-off only to the rounding of the step)")]
        if smallest is not None and protocol.step < smallest:
            pressing = depth / protocol.step
            preload = ("protocol.preload_displacement = " + f"{depth:g}" if protocol.preload_displacement is not None
                       else f"protocol.preload_force = {protocol.preload_force:g} (at least {depth:.3g} deep)")
            return [Problem("protocol.step", _show(protocol.step),
                            f"must be in {allowed}: between the surface and {preload} lie {pressing:.3g} steps or "
                            f"more, beyond protocol.max_steps = {protocol.max_steps} (on each branch); raise the step "
                            f"to at least {smallest:.3g} (or max_steps, knowing the run's length grows with it)")]
        return []

    def _pillar_model_problems(self) -> list[Problem]:
        """Keys the pillar model (protocol.method = "pillars") does not use, set to a value of their own: refused,
        not ignored.

        A key written at its default is what the resolved configuration (`config_to_dict`) holds of every
        key, so it is accepted: the resolved form of a pillar-model file re-parses to an equal configuration.
        """
        if self.protocol.method != "pillars":
            return []
        why = {
            ("solver", "tolerance"): "its pillar-level solves have their own tolerances",
            ("solver", "max_iterations"): "its pillar-level solves have their own bounds",
            ("solver", "coupling"): "it couples the pillars by their modes, not by the element operator",
            ("solver", "cascade"): "its cascades peel pillar by pillar on the pillar-level system",
            ("protocol", "step"): "it jumps from event to event (a step is method = 'fixed''s)",
        }
        problems = []
        for (section, name), reason in why.items():
            model = getattr(self, section)
            value = getattr(model, name)
            if name in model.model_fields_set and value != type(model).model_fields[name].default:
                problems.append(Problem(f"{section}.{name}", _show(value),
                                        f"is not used by protocol.method = 'pillars' ({reason}): remove it, "
                                        "or choose another method"))
        return problems

    def _stiffness_keys(self) -> dict[tuple[str, str], str]:
        """The key of the pillars' stiffness as given (``Indenter.levels`` of the domain rules)."""
        given = "indenter.stiffness_ratio" if self.indenter.stiffness_ratio is not None else "indenter.stiffness"
        return {("Indenter", "levels"): given}

    def _given_stiffness(self) -> float:
        spec = self.indenter
        return spec.stiffness_ratio if spec.stiffness_ratio is not None else spec.stiffness

    def _pillar_law_problems(self) -> list[Problem]:
        """A nonlinear pillar law's rule (`brushbem.physics.pillar_laws.law_path_problems`), by key."""
        spec, protocol = self.indenter, self.protocol
        names = ({"indenter.pillar_law": "indenter.fibril.buckling (Euler's law, an indenter.pillar_law)"}
                 if spec.fibril is not None and spec.fibril.buckling is not None else None)
        found = law_path_problems(spec.pillar_law, method=protocol.method,
                                  preload_displacement=protocol.preload_displacement,
                                  preload_force=protocol.preload_force,
                                  viscoelastic=spec.viscoelastic is not None,
                                  stiffness=None if spec.pillar_law is None else self._given_stiffness())
        return parameter_problems(found, self._stiffness_keys(), names)

    def _time_stepping_problems(self) -> list[Problem]:
        """Viscoelastic pillars' rule (`brushbem.physics.viscoelastic.time_stepping_problems`), by key."""
        spec, protocol = self.indenter, self.protocol
        found = time_stepping_problems(spec.viscoelastic is not None, method=protocol.method, speed=protocol.speed,
                                       preload_displacement=protocol.preload_displacement,
                                       preload_force=protocol.preload_force,
                                       stiffness=None if spec.viscoelastic is None else self._given_stiffness())
        return parameter_problems(found, self._stiffness_keys())


_SECTIONS: dict[str, type[BaseModel]] = {
    "halfspace": HalfSpaceConfig,
    "grid": GridConfig,
    "indenter": IndenterConfig,
    "protocol": ProtocolConfig,
    "solver": SolverConfig,
    "units": UnitsConfig,
}
