"""Validated run configuration: the TOML file a user writes, checked at the edge.

A run is described by one TOML file with the tables ``[halfspace]``, ``[grid]``,
``[indenter]``, ``[protocol]`` and (optionally) ``[solver]``.  Every number is
dimensional, in whatever consistent units the user chooses (length, stress,
force = stress x length^2, stiffness = force / length).

Sign convention (the same everywhere in brushbem): the base displacement ``d``
is positive when the indenter presses into the half-space; pressure and force
are positive when compressive.

The numerics never see these models' validation logic: they receive the frozen,
already-checked values.  Validation reports *every* problem of a file at once,
one line per problem, each naming the dotted key, the value found and what is
allowed, so that a user fixes a file in one pass instead of one error per run.

This package is the schema: the fields and the rules between keys.  Rules that
need the rasterised structure (overlapping pillars, a preload that never
reaches the lowest element) belong to `brushbem.runs.assembly`, which passes them
in as ``rules`` (`StructureRules`) and builds the problem from the same
rasterisation; ``brushbem.runs.assembly.load_config`` is the complete check.

Modules (each imports only those above it; `rules` names the models for
type checking only):

- `brushbem.config.limits`: the bounds on input (`MAGNITUDE_RANGE`,
  `MAX_CONFIG_BYTES`, `MAX_PRELOAD_DOMAIN_SIZES`, the springs' rounding
  floor, `MAX_SWEEP_BYTES`, `MAX_SWEEP_DEPTH`, `MAX_SWEEP_CASES`, the
  deepest nesting, the most problems listed, the
  longest value shown).
- `brushbem.config.errors`: `ConfigError` and the problem lines:
  `show_value`, what a field allows, pydantic errors turned into lines.
- `brushbem.config.files`: the ``.npy`` files a configuration names,
  resolved and read header first, never unpickled.
- `brushbem.config.rules`: `Problem`, `StructureRules`, and the rules
  between sections (punch and sphere resolution, height-map shape, memory).
- `brushbem.config.schema`: the section models (`HalfSpaceConfig`,
  `GridConfig`, `IndenterConfig` and its tables, `ProtocolConfig`,
  `SolverConfig`, `RunConfig`) with the rules between a table's keys.
- `brushbem.config.loading`: `load_config`, `parse_config`, `read_toml`
  (a TOML file within size and nesting limits), `nesting_depth`,
  and `config_to_dict` (JSON through `brushbem.results.plain.to_json_safe`).
"""

from __future__ import annotations

from brushbem.config.errors import ConfigError, show_value
from brushbem.config.limits import MAGNITUDE_RANGE as MAGNITUDE_RANGE
from brushbem.config.limits import MAX_CONFIG_BYTES as MAX_CONFIG_BYTES
from brushbem.config.limits import MAX_PRELOAD_DOMAIN_SIZES as MAX_PRELOAD_DOMAIN_SIZES
from brushbem.config.limits import MAX_SWEEP_BYTES as MAX_SWEEP_BYTES
from brushbem.config.limits import MAX_SWEEP_CASES as MAX_SWEEP_CASES
from brushbem.config.limits import MAX_SWEEP_DEPTH as MAX_SWEEP_DEPTH
from brushbem.config.loading import case_identity, config_to_dict, load_config, nesting_depth, parse_config, read_toml
from brushbem.config.rules import SPHERE_MIN_PULL_OFF_ELEMENTS as SPHERE_MIN_PULL_OFF_ELEMENTS
from brushbem.config.rules import Problem, StructureRules
from brushbem.config.schema import (
    GradingConfig,
    GridConfig,
    HalfSpaceConfig,
    IndenterConfig,
    LevelConfig,
    PillarLawConfig,
    ProfileConfig,
    ProtocolConfig,
    RoughnessConfig,
    RunConfig,
    SolverConfig,
    TiltConfig,
    TipConfig,
    ViscoelasticConfig,
)

__all__ = [
    "ConfigError",
    "GradingConfig",
    "GridConfig",
    "HalfSpaceConfig",
    "IndenterConfig",
    "LevelConfig",
    "PillarLawConfig",
    "Problem",
    "ProfileConfig",
    "ProtocolConfig",
    "RoughnessConfig",
    "RunConfig",
    "SolverConfig",
    "StructureRules",
    "TiltConfig",
    "TipConfig",
    "ViscoelasticConfig",
    "case_identity",
    "config_to_dict",
    "load_config",
    "nesting_depth",
    "parse_config",
    "read_toml",
    "show_value",
]
