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

This module is the schema: the fields and the rules between keys.  Rules that
need the rasterised structure (overlapping pillars, a preload that never
reaches the lowest element) belong to `brushbem.assembly`, which passes them
in as ``rules`` (`StructureRules`) and builds the problem from the same
rasterisation; ``brushbem.assembly.load_config`` is the complete check.
"""

from __future__ import annotations

import math
import os
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from types import NoneType, UnionType
from typing import Any, Literal, Protocol, Union, get_args, get_origin

import numpy as np
from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
    ValidationError,
    ValidationInfo,
    field_validator,
    model_validator,
)
from pydantic_core import PydanticCustomError

__all__ = [
    "ConfigError",
    "GridConfig",
    "HalfSpaceConfig",
    "IndenterConfig",
    "LevelConfig",
    "Problem",
    "ProfileConfig",
    "ProtocolConfig",
    "RoughnessConfig",
    "RunConfig",
    "SolverConfig",
    "StructureRules",
    "config_to_dict",
    "load_config",
    "parse_config",
    "show_value",
    "to_json_safe",
]

# Strict: a TOML ``size = "1.0"`` or ``elements = true`` is a mistake to report,
# not a value to coerce.  Frozen: the numerics may cache on a config safely.
_MODEL_CONFIG = ConfigDict(extra="forbid", frozen=True, strict=True)

# Longest value representation echoed back in a problem line; random or
# pasted input can be arbitrarily long and the line must stay readable.
_MAX_SHOWN = 60

# Every nonzero finite number of a configuration must have a magnitude in this
# range.  The numerics form products and quotients of a few inputs (E* h,
# dgamma / (E* h), r^2 / R, areas h^2 N^2, works F d); inside this range they
# stay far from overflow (1e308) and from the subnormal range (1e-308), so no
# input can turn into an inf, a 0 or a division by zero downstream.  Any
# consistent set of units (SI, or E* = L = 1) keeps physical inputs in it.
MAGNITUDE_RANGE = (1e-30, 1e30)

# Deepest nesting of tables and arrays a configuration may have: the schema
# needs 4 (``indenter.levels[i].cluster``); a deeper document is a mistake and
# would exhaust the recursion of the TOML reader and the validators.
_MAX_DEPTH = 32

# Largest configuration file read: a run configuration is a few kB.
MAX_CONFIG_BYTES = 1 << 20

# Most problem lines reported for one document; the rest are counted.
_MAX_PROBLEMS = 100


class ConfigError(ValueError):
    """A run configuration that cannot be used.

    Parameters
    ----------
    problems : list of str
        One human-readable line per problem, each of the form
        ``"`dotted.key`: value — what is allowed"``.
    """

    def __init__(self, problems: list[str]) -> None:
        self.problems = list(problems)
        super().__init__("\n".join(self.problems))


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
    """Rules on the rasterised structure, supplied by `brushbem.assembly` (keys absolute).

    ``structure_problems`` runs with the other rules between sections, on the
    sections that validated (so it is reported beside their problems);
    ``rasterised_problems`` runs on a configuration that passed every other
    rule.
    """

    def structure_problems(self, grid: GridConfig, indenter: IndenterConfig,
                           halfspace: HalfSpaceConfig) -> list[Problem]: ...

    def rasterised_problems(self, config: RunConfig) -> list[Problem]: ...


def show_value(value: Any) -> str:
    """Short representation of a user value for a problem line."""
    return _show(value)


def _show(value: Any) -> str:
    """Short representation of a user value for a problem line."""
    if value is None:  # an optional key left out (TOML has no null)
        return "not given"
    # repr gives "nan", "inf", "0.003" for floats: what the user wrote in TOML.
    text = repr(value)
    if len(text) > _MAX_SHOWN:
        text = text[: _MAX_SHOWN - 3] + "..."
    return text


def _rules_error(problems: list[Problem]) -> PydanticCustomError:
    """Wrap rule problems so that they travel through pydantic's error list."""
    return PydanticCustomError(
        "config_rules",
        "{summary}",
        {"problems": problems, "summary": "; ".join(p.allowed for p in problems)},
    )


class _Model(BaseModel):
    """A table of the configuration: strict, frozen, closed, numbers within `MAGNITUDE_RANGE`."""

    model_config = _MODEL_CONFIG

    @field_validator("*", mode="after")
    @classmethod
    def _magnitude(cls, value: Any, info: ValidationInfo) -> Any:
        low, high = MAGNITUDE_RANGE
        number = isinstance(value, (int, float)) and not isinstance(value, bool)
        finite = number and (isinstance(value, int) or math.isfinite(value))  # a TOML integer may exceed 1e308
        if finite and value != 0 and not low <= abs(value) <= high:
            raise ValueError(f"must be {_describe_allowed(cls.model_fields[info.field_name])}")
        return value


class _Section(_Model):
    """A table of the configuration, with rules between its keys.

    A rule between keys ("exactly one of ...", "the keys each shape needs")
    is `_rule_problems`; it reads only which keys are given and the values of
    choice keys, so `rule_problems_of_raw` can apply it to a table whose values
    failed their own checks - pydantic skips an after-validator then, and the
    rule's problem would otherwise surface one run later.
    """

    model_config = _MODEL_CONFIG

    def _rule_problems(self) -> list[Problem]:
        return []

    @model_validator(mode="after")
    def _rules(self) -> _Section:
        problems = self._rule_problems()
        if problems:
            raise _rules_error(problems)
        return self


class HalfSpaceConfig(_Section):
    """The elastic half-space.

    Give either ``contact_modulus`` (E*) or both ``youngs_modulus`` and
    ``poisson_ratio``; the numerics use only E*, see `effective_modulus`.

    Attributes
    ----------
    contact_modulus : float or None
        E*, in units of stress.
    youngs_modulus : float or None
        Young's modulus E of the half-space, in units of stress.
    poisson_ratio : float or None
        Poisson's ratio nu of the half-space, dimensionless, in [0, 0.5).
    work_of_adhesion : float
        Delta gamma, in units of energy per area (stress x length); 0 means no
        adhesion.
    """

    model_config = _MODEL_CONFIG

    contact_modulus: float | None = Field(None, gt=0, allow_inf_nan=False)
    youngs_modulus: float | None = Field(None, gt=0, allow_inf_nan=False)
    poisson_ratio: float | None = Field(None, ge=0, lt=0.5, allow_inf_nan=False)
    work_of_adhesion: float = Field(0.0, ge=0, allow_inf_nan=False)

    def _rule_problems(self) -> list[Problem]:
        by_contact = self.contact_modulus is not None
        by_young = self.youngs_modulus is not None or self.poisson_ratio is not None
        complete_young = self.youngs_modulus is not None and self.poisson_ratio is not None
        if by_contact == by_young or (by_young and not complete_young):
            given = ", ".join(
                f"{name} = {_show(getattr(self, name))}"
                for name in ("contact_modulus", "youngs_modulus", "poisson_ratio")
            )
            return [Problem("", given, "give either contact_modulus (E*) or both youngs_modulus and poisson_ratio")]
        return []

    @property
    def effective_modulus(self) -> float:
        """E* = E / (1 - nu^2), in units of stress."""
        if self.contact_modulus is not None:
            return self.contact_modulus
        # The validator guarantees both are set when contact_modulus is not.
        assert self.youngs_modulus is not None and self.poisson_ratio is not None
        return self.youngs_modulus / (1.0 - self.poisson_ratio**2)


class GridConfig(_Model):
    """The square computational domain.

    Attributes
    ----------
    size : float
        Side L of the square domain, in units of length.
    elements : int
        Number N of elements along each side (N x N elements in all).
    """

    model_config = _MODEL_CONFIG

    size: float = Field(gt=0, allow_inf_nan=False)
    elements: int = Field(ge=8, le=8192)

    @property
    def element_size(self) -> float:
        """h = L / N, in units of length."""
        return self.size / self.elements


# Which optional keys each indenter shape needs.  Every key listed for some
# shape is required by that shape and rejected by the others, so a stray key is
# never silently ignored.  A new shape adds its fields to IndenterConfig and one
# entry here.
_SHAPE_KEYS: dict[str, tuple[str, ...]] = {
    "flat_punch": ("radius",),
    "sphere": ("radius",),
    "height_map": ("file",),
    "brush": ("layout", "pillar_radius"),
}

# Keys a shape accepts but does not require (rejected by the other shapes).
_SHAPE_OPTIONAL: dict[str, tuple[str, ...]] = {
    "flat_punch": (),
    "sphere": (),
    "height_map": (),
    "brush": (
        "region", "region_size", "pillars_per_side", "spacing", "pillar_count", "min_gap",
        "stiffness_ratio", "seed", "roughness", "profile", "lengths_file", "levels",
    ),
}

# Keys of a brush that belong to one layout only.
_LAYOUT_KEYS: dict[str, tuple[str, ...]] = {
    "square": ("pillars_per_side",),
    "random": ("pillar_count",),
}
_LAYOUT_OPTIONAL: dict[str, tuple[str, ...]] = {
    "square": ("spacing", "levels"),
    "random": ("min_gap",),
}


def _existing_file(value: str, info: ValidationInfo) -> Path:
    """``value`` resolved against the configuration's folder; ValueError if it is not a regular file.

    A relative name is resolved against the folder of the configuration file
    (``base_dir`` of the validation context); an absolute name, or one that
    leads out of that folder, is allowed: the file is only read as ``.npy``
    data (`_read_numbers`), never executed or unpickled.
    """
    base_dir = Path((info.context or {}).get("base_dir") or Path.cwd())
    try:
        path = (base_dir / value).resolve()
        exists, regular, folder = path.exists(), path.is_file(), path.is_dir()
    except (OSError, ValueError) as exc:  # e.g. an embedded NUL or a name too long
        raise ValueError(f"not a usable path ({exc})") from None
    if folder:
        raise ValueError(f"is a folder, not a .npy file ({path})")
    if exists and not regular:
        raise ValueError(f"is not a regular file ({path})")
    if not exists:
        raise ValueError(f"file not found (looked for {path})")
    return path


def _read_numbers(path: Path) -> np.ndarray:
    """The array of real numbers in the ``.npy`` file ``path``, as float64.

    The header is read first, so that a file of Python objects is refused
    without unpickling anything (``allow_pickle`` stays off), and a file of
    another format is named as such.

    Raises
    ------
    ValueError
        With a message saying what is wrong: not ``.npy`` data, an object
        (pickled) array, not real numbers, or values that are not finite or
        lie outside `MAGNITUDE_RANGE`.
    """
    try:
        with path.open("rb") as stream:
            try:
                version = np.lib.format.read_magic(stream)
            except ValueError:
                raise ValueError(
                    f"cannot be read as a .npy array: {path} is not a .npy file (it does not start with "
                    "the NumPy format's magic bytes); save the array with numpy.save"
                ) from None
            if version not in ((1, 0), (2, 0)):  # 3.0 only serves structured arrays with unicode names
                raise ValueError(f"unsupported .npy format version {version[0]}.{version[1]}")
            read_header = np.lib.format.read_array_header_1_0 if version == (1, 0) else np.lib.format.read_array_header_2_0
            shape, _, dtype = read_header(stream)
    except OSError as exc:
        raise ValueError(f"cannot be read ({path}: {exc.strerror or exc})") from None
    except ValueError as exc:
        if str(exc).startswith("cannot be read"):
            raise
        raise ValueError(f"cannot be read as a .npy array ({path}: {exc})") from None
    if dtype.hasobject:
        raise ValueError(
            f"holds Python objects ({path}); brushbem loads numeric .npy arrays only and never unpickles "
            "(allow_pickle is off): save a float array"
        )
    if dtype.kind not in "fiu":
        raise ValueError(f"holds {dtype} values ({path}); must hold real numbers (float or integer)")
    try:
        values = np.load(path, allow_pickle=False)
    except (OSError, ValueError, EOFError) as exc:  # e.g. a truncated file
        raise ValueError(f"cannot be read as a .npy array ({path}: {exc})") from None
    with np.errstate(over="ignore"):  # float128 beyond float64 becomes inf, refused below
        values = np.asarray(values, dtype=np.float64)
    if values.size and not np.all(np.isfinite(values)):
        raise ValueError(f"must hold finite values ({path} holds nan or inf)")
    largest = float(np.max(np.abs(values))) if values.size else 0.0
    if largest > MAGNITUDE_RANGE[1]:
        raise ValueError(f"holds values up to {largest:g} ({path}); must be at most {MAGNITUDE_RANGE[1]:g} in magnitude")
    assert shape == values.shape
    return values


def _inf_from_string(value: Any) -> Any:
    # `config_to_dict` writes infinity as the string "inf" (JSON has no
    # infinity); accept it back so a recorded config re-parses.
    if isinstance(value, str) and value == "inf":
        return math.inf
    return value


class RoughnessConfig(_Model):
    """Gaussian pillar lengths (thesis eq. 5.1).

    Attributes
    ----------
    sigma : float
        Standard deviation of the pillar lengths, in units of length; 0 = flat.
    """

    model_config = _MODEL_CONFIG

    sigma: float = Field(ge=0, allow_inf_nan=False)


class ProfileConfig(_Model):
    """Concave macroscopic profile S_p = h~ S_c (thesis eq. 7.1-7.3).

    Attributes
    ----------
    amplification : float
        h~, dimensionless; 0 = flat.
    reference_stress : float or None
        Uniform stress p_c of S_c that makes h~ dimensionless, in units of
        stress.  Default: one pillar's Kendall mean stress F_K / (pi r^2)
        (`brushbem.theory.concave_reference_stress`).
    """

    model_config = _MODEL_CONFIG

    amplification: float = Field(ge=0, allow_inf_nan=False)
    reference_stress: float | None = Field(None, gt=0, allow_inf_nan=False)


class LevelConfig(_Section):
    """One hierarchy level above the pillars (thesis ch. 6).

    Attributes
    ----------
    cluster : int
        n: n x n units of the level below form one unit of this level.
    stiffness_ratio : float or None
        k~ = k / (E* L) of this level's springs (L = grid.size).
    stiffness : float or None
        k of this level's springs, in units of force / length; inf = rigid.
        Exactly one of the two.
    """

    model_config = _MODEL_CONFIG

    cluster: int = Field(ge=1, le=4096)
    stiffness_ratio: float | None = Field(None, gt=0)
    stiffness: float | None = Field(None, gt=0)

    @field_validator("stiffness", "stiffness_ratio", mode="before")
    @classmethod
    def _inf_string(cls, value: Any) -> Any:
        return _inf_from_string(value)

    def _rule_problems(self) -> list[Problem]:
        if (self.stiffness is None) == (self.stiffness_ratio is None):
            return [Problem(
                "stiffness_ratio",
                f"stiffness_ratio = {_show(self.stiffness_ratio)}, stiffness = {_show(self.stiffness)}",
                "give exactly one of stiffness_ratio and stiffness (inf = rigid)",
            )]
        return []


class IndenterConfig(_Section):
    """The indenter and the spring that carries it.

    Attributes
    ----------
    shape : {"flat_punch", "sphere", "height_map"}
        Flat cylindrical punch, paraboloid ``z = r^2 / (2 R)``, or a profile
        read from a file.
    radius : float or None
        Punch radius, or the sphere's radius of curvature R, in units of length.
        Required for ``flat_punch`` and ``sphere``.
    stiffness : float
        Spring stiffness k between the base and the indenter, in units of
        force / length; ``inf`` is a rigid connection.
    file : str or None
        ``.npy`` file of an N x N array of tip heights z (units of length; rows
        y, columns x; N = grid.elements).  Relative paths are resolved against
        the configuration file's folder; after validation the path is absolute.
        Required for ``height_map``.

    Brush keys (``shape = "brush"``, thesis ch. 3-7; k~ = k / (E* L) with L = grid.size)
        layout : ``"square"`` (regular lattice, ``pillars_per_side``, optional
        ``spacing``, default region_size / pillars_per_side) or ``"random"``
        (``pillar_count`` non-overlapping positions, optional ``min_gap``
        between pillar edges, default 2 h); region : ``"square"`` (default) or
        ``"circle"``, where pillars are placed, of side / diameter
        ``region_size`` (default grid.size), whose area is the apparent area
        A0; pillar_radius; stiffness_ratio or stiffness (exactly one, the
        pillars' own springs); seed (random layout and roughness, default 0);
        ``[indenter.roughness] sigma``; ``[indenter.profile] amplification``
        (and optionally ``reference_stress``); lengths_file (``.npy`` of one
        extra length per pillar); ``[[indenter.levels]]`` ``cluster`` and
        ``stiffness_ratio`` or ``stiffness``, bottom-up (square layout only).
    """

    model_config = _MODEL_CONFIG

    shape: Literal["flat_punch", "sphere", "height_map", "brush"]
    radius: float | None = Field(None, gt=0, allow_inf_nan=False)
    stiffness: float = Field(math.inf, gt=0)
    file: str | None = None
    layout: Literal["square", "random"] | None = None
    region: Literal["square", "circle"] | None = None
    region_size: float | None = Field(None, gt=0, allow_inf_nan=False)
    pillars_per_side: int | None = Field(None, ge=1, le=4096)
    spacing: float | None = Field(None, gt=0, allow_inf_nan=False)
    pillar_count: int | None = Field(None, ge=1, le=1_000_000)
    min_gap: float | None = Field(None, ge=0, allow_inf_nan=False)
    pillar_radius: float | None = Field(None, gt=0, allow_inf_nan=False)
    stiffness_ratio: float | None = Field(None, gt=0)
    seed: int | None = Field(None, ge=0, le=2**63 - 1)
    roughness: RoughnessConfig | None = None
    profile: ProfileConfig | None = None
    lengths_file: str | None = None
    levels: tuple[LevelConfig, ...] | None = None

    @field_validator("stiffness", "stiffness_ratio", mode="before")
    @classmethod
    def _inf_string(cls, value: Any) -> Any:
        return _inf_from_string(value)

    @field_validator("levels", mode="before")
    @classmethod
    def _levels_list(cls, value: Any) -> Any:
        # TOML arrays of tables arrive as lists; the frozen model stores a tuple.
        return tuple(value) if isinstance(value, list) else value

    @field_validator("lengths_file")
    @classmethod
    def _resolve_lengths_file(cls, value: str | None, info: ValidationInfo) -> str | None:
        if value is None:
            return None
        path = _existing_file(value, info)
        lengths = _read_numbers(path)
        if lengths.ndim != 1:
            raise ValueError(
                f"holds an array of shape {lengths.shape} ({path}); must hold a 1-D array of pillar lengths "
                "(one per pillar)"
            )
        return str(path)

    @property
    def is_brush(self) -> bool:
        return self.shape == "brush"

    @field_validator("file")
    @classmethod
    def _resolve_and_check_file(cls, value: str | None, info: ValidationInfo) -> str | None:
        if value is None:
            return None
        path = _existing_file(value, info)
        _check_height_map(path)
        return str(path)

    def _rule_problems(self) -> list[Problem]:
        shape = getattr(self, "shape", None)  # absent on a failed table built from what was given
        if not isinstance(shape, str) or shape not in _SHAPE_KEYS:  # a problem of `shape` itself
            return []
        needed = set(_SHAPE_KEYS[self.shape])
        allowed = needed | set(_SHAPE_OPTIONAL[self.shape])
        every = {k for keys in (*_SHAPE_KEYS.values(), *_SHAPE_OPTIONAL.values()) for k in keys}
        problems = []
        for key in sorted(every):
            value = getattr(self, key)
            if key in needed and value is None:
                problems.append(Problem(key, "missing", f"required when shape = {self.shape!r}"))
            elif key not in allowed and value is not None:
                users = " or ".join(
                    repr(s) for s in _SHAPE_KEYS if key in _SHAPE_KEYS[s] or key in _SHAPE_OPTIONAL[s]
                )
                problems.append(
                    Problem(key, _show(value), f"only used when shape = {users}; remove it")
                )
        if self.is_brush:
            problems.extend(self._brush_problems())
        return problems

    def _brush_problems(self) -> list[Problem]:
        problems = []
        if isinstance(self.layout, str) and self.layout in _LAYOUT_KEYS:
            needed = set(_LAYOUT_KEYS[self.layout])
            allowed = needed | set(_LAYOUT_OPTIONAL[self.layout])
            for key in sorted({k for keys in (*_LAYOUT_KEYS.values(), *_LAYOUT_OPTIONAL.values()) for k in keys}):
                value = getattr(self, key)
                if key in needed and value is None:
                    problems.append(Problem(key, "missing", f"required when layout = {self.layout!r}"))
                elif key not in allowed and value is not None:
                    users = " or ".join(
                        repr(s) for s in _LAYOUT_KEYS if key in _LAYOUT_KEYS[s] or key in _LAYOUT_OPTIONAL[s]
                    )
                    problems.append(Problem(key, _show(value), f"only used when layout = {users}; remove it"))
        if ("stiffness" in self.model_fields_set) == (self.stiffness_ratio is not None):
            problems.append(Problem(
                "stiffness_ratio",
                f"stiffness_ratio = {_show(self.stiffness_ratio)}, stiffness = "
                f"{_show(self.stiffness) if 'stiffness' in self.model_fields_set else 'not given'}",
                "give exactly one of stiffness_ratio (k / (E* L)) and stiffness (inf = rigid)",
            ))
        return problems

    def pillar_stiffness(self, contact_modulus: float, size: float) -> float:
        """k of the pillars' own springs, from ``stiffness`` or ``stiffness_ratio`` (k~ E* L)."""
        if self.stiffness_ratio is not None:
            return self.stiffness_ratio * contact_modulus * size
        return self.stiffness


def _check_height_map(path: Path) -> None:
    """Check that ``path`` holds a square 2-D array of finite real numbers.

    Raises
    ------
    ValueError
        With a message saying what is wrong and naming the file.
    """
    heights = _read_numbers(path)
    if heights.ndim != 2 or heights.shape[0] != heights.shape[1]:
        raise ValueError(f"must hold a square N x N array, found shape {heights.shape} ({path})")


def _height_map_shape(path: str) -> tuple[int, ...]:
    """Shape of a validated ``.npy`` file, from its header only (no data read)."""
    return np.load(path, mmap_mode="r", allow_pickle=False).shape


class ProtocolConfig(_Section):
    """The pull-off load path: press to a preload, then retract until separation.

    Attributes
    ----------
    method : {"events", "element_events", "fixed"}
        ``"events"`` follows the exact path: it jumps from one contact
        change to the next, and presses a brush (two or more pillars) as
        non-adhesive contact problems, which is the same branch checked on
        its samples (``brushbem.protocol``); ``"element_events"`` takes
        every element event on the loading branch too (the reference, and
        today's path of single bodies); ``"fixed"`` retracts by constant
        steps (the thesis's method), locating the first detachment inside
        each step.
    preload_displacement : float or None
        Press until the base displacement reaches this value, units of length.
    preload_force : float or None
        Press until the compressive force reaches this value, units of force.
        Exactly one of the two preloads is given.
    step : float
        Displacement step of ``"fixed"``, in units of length.
    max_steps : int
        Most steps (events, or fixed displacement steps) on each branch,
        loading and unloading; a branch that needs more ends the run, which
        reports not converged.
    """

    model_config = _MODEL_CONFIG

    method: Literal["events", "element_events", "fixed"] = "events"
    preload_displacement: float | None = Field(None, gt=0, allow_inf_nan=False)
    preload_force: float | None = Field(None, gt=0, allow_inf_nan=False)
    step: float = Field(1e-4, gt=0, allow_inf_nan=False)
    max_steps: int = Field(200_000, gt=0, le=1_000_000_000)

    def _rule_problems(self) -> list[Problem]:
        if (self.preload_displacement is None) == (self.preload_force is None):
            given = (
                f"preload_displacement = {_show(self.preload_displacement)}, "
                f"preload_force = {_show(self.preload_force)}"
            )
            return [Problem("", given, "give exactly one of preload_displacement or preload_force")]
        return []


class SolverConfig(_Model):
    """Inner linear solver (preconditioned conjugate gradients).

    Attributes
    ----------
    tolerance : float
        Relative residual at which a solve counts as converged, dimensionless.
    max_iterations : int
        Iterations allowed per solve before it is reported as not converged.
    coupling : {"segments", "discriminant"}
        How the spring sums enter the operator: segment sums over the
        element-to-pillar incidence (exact for any layout), or the thesis's
        discriminant-matrix convolution (eq. 3.13-3.17; refused where its size
        condition does not hold).
    cascade : {"local", "global"}
        How a brush's detachment cascade at fixed d runs: the pillars that
        peel solved on their own between global solves ("local"), or a global
        solve for every round (the thesis's loop, "global").
    """

    model_config = _MODEL_CONFIG

    tolerance: float = Field(1e-8, ge=1e-15, lt=1e-2, allow_inf_nan=False)
    max_iterations: int = Field(20_000, gt=0, le=1_000_000_000)
    coupling: Literal["segments", "discriminant"] = "segments"
    cascade: Literal["local", "global"] = "local"


class RunConfig(BaseModel):
    """One run: half-space, grid, indenter, load path and solver settings."""

    model_config = _MODEL_CONFIG

    halfspace: HalfSpaceConfig
    grid: GridConfig
    indenter: IndenterConfig
    protocol: ProtocolConfig
    solver: SolverConfig = SolverConfig()

    @model_validator(mode="after")
    def _consistent(self, info: ValidationInfo) -> RunConfig:
        rules = (info.context or {}).get("rules")
        problems = _cross_section_problems(self.grid, self.indenter, self.halfspace, rules)
        if self.protocol.method == "fixed" and self.protocol.step > self.grid.size:
            # The first detachment is located inside a step to the rounding of
            # the step's length: a step of 1e30 put it 250 x off.  A base
            # displacement beyond the domain size is outside linear elasticity.
            problems.append(Problem(
                "protocol.step", _show(self.protocol.step),
                f"must be at most grid.size = {self.grid.size:g} (a fixed step beyond the domain size)",
            ))
        problems.extend(_resource_problems(self))  # before the indenter is rasterised
        if not problems and rules is not None:
            problems = rules.rasterised_problems(self)
        if problems:
            raise _rules_error(problems)
        return self


def _resource_problems(config: RunConfig) -> list[Problem]:
    """A run that would not fit in memory (`brushbem.resources`), refused before it starts."""
    from .resources import MEMORY_LIMIT_VARIABLE, memory_problem

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


def _sphere_resolution_problems(grid: GridConfig, radius: float, halfspace: HalfSpaceConfig) -> list[Problem]:
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
    a_jkr = (9 * math.pi * halfspace.work_of_adhesion * radius**2 / (8 * modulus)) ** (1 / 3)
    if a_jkr >= SPHERE_MIN_PULL_OFF_ELEMENTS * h:
        return []
    return [Problem(
        "indenter.radius", _show(radius),
        f"the JKR contact radius at pull-off, a = (9 pi dgamma R^2 / (8 E*))^(1/3) = {a_jkr:.3g}, spans "
        f"{a_jkr / h:.3g} elements (h = {h:g}); the criterion needs at least "
        f"{SPHERE_MIN_PULL_OFF_ELEMENTS:g}: raise indenter.radius or halfspace.work_of_adhesion, "
        "or refine grid.elements",
    )]


_SECTIONS: dict[str, type[BaseModel]] = {
    "halfspace": HalfSpaceConfig,
    "grid": GridConfig,
    "indenter": IndenterConfig,
    "protocol": ProtocolConfig,
    "solver": SolverConfig,
}


def _dotted(loc: tuple[Any, ...]) -> str:
    return ".".join(str(part) for part in loc if part != "")


def _field_at(model: type[BaseModel], loc: tuple[Any, ...]) -> Any:
    """The pydantic FieldInfo at ``loc`` below ``model``, or None."""
    field = None
    current: Any = model
    for part in loc:
        if get_origin(current) in (Union, UnionType):  # X | None
            members = [a for a in get_args(current) if a is not NoneType]
            current = members[0] if len(members) == 1 else current
        if isinstance(part, int) and get_origin(current) is tuple:  # tuple[Model, ...] item
            current = get_args(current)[0]
            continue
        if not (isinstance(current, type) and issubclass(current, BaseModel)):
            return None
        field = current.model_fields.get(part) if isinstance(part, str) else None
        if field is None:
            return None
        current = field.annotation
    return field


def _describe_allowed(field: Any) -> str:
    """What a field accepts, derived from its type and constraints."""
    annotation = field.annotation
    if get_origin(annotation) in (Union, UnionType):
        members = [a for a in get_args(annotation) if a is not NoneType]
        annotation = members[0] if len(members) == 1 else annotation
    finite = any(getattr(m, "allow_inf_nan", None) is False for m in field.metadata)
    if get_origin(annotation) is Literal:
        return "one of " + ", ".join(repr(a) for a in get_args(annotation))
    if annotation is int:
        kind = "an integer"
    elif annotation is float:
        kind = "a finite number" if finite else "a number"
    elif annotation is str:
        kind = "a string"
    elif isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return "a table with keys " + ", ".join(annotation.model_fields)
    else:
        kind = "a value"
    # Field(gt=..., le=...) stores one annotated-types object per bound, each
    # with an attribute named after the bound.
    low = high = None
    for m in field.metadata:
        if getattr(m, "gt", None) is not None:
            low = f"> {m.gt:g}", "(", m.gt
        elif getattr(m, "ge", None) is not None:
            low = f">= {m.ge:g}", "[", m.ge
        elif getattr(m, "lt", None) is not None:
            high = f"< {m.lt:g}", ")", m.lt
        elif getattr(m, "le", None) is not None:
            high = f"<= {m.le:g}", "]", m.le
    if low and high:
        text = f"{kind} in {low[1]}{low[2]:g}, {high[2]:g}{high[1]}"
    elif low or high:
        text = f"{kind} {(low or high)[0]}"
    else:
        text = kind
    if annotation is float:
        text += _magnitude_clause(low, high)
    if annotation is float and not finite:
        text += ", or inf"
    return text


def _magnitude_clause(low: tuple | None, high: tuple | None) -> str:
    """The part of `MAGNITUDE_RANGE` that a float field's own bounds do not already imply.

    ``low`` and ``high`` are the ``(text, bracket, value)`` bounds of
    `_describe_allowed` (None where unbounded).
    """
    smallest, largest = MAGNITUDE_RANGE
    below = low is None or low[2] < smallest  # nonzero values under `smallest` pass the bounds
    above = high is None or high[2] > largest
    negative = low is None or low[2] < 0
    zero = (low is None or low[2] < 0 or (low[2] == 0 and low[1] == "[")) and (high is None or high[2] > 0)
    what = "in magnitude" if negative else ""
    zero_text = "0 or " if zero else ""
    sep = ": " if zero else ", "
    if below and above:
        return f"{sep}{zero_text}between {smallest:g} and {largest:g}{' ' + what if what else ''}"
    if below:
        return f"{sep}{zero_text}at least {smallest:g}{' ' + what if what else ''}"
    if above:
        return f", at most {largest:g}"
    return ""


def _problem_lines(
    error: ValidationError, model: type[BaseModel], prefix: tuple[str, ...]
) -> list[str]:
    """One line per pydantic error, ``"`dotted.key`: value — what is allowed"``."""
    lines = []
    for item in error.errors(include_url=False):
        loc = tuple(item["loc"])
        kind = item["type"]
        if kind == "config_rules":
            for problem in item["ctx"]["problems"]:
                key = _dotted(prefix + loc + (problem.key,))
                lines.append(f"`{key}`: {problem.value} — {problem.allowed}")
            continue
        key = _dotted(prefix + loc)
        field = _field_at(model, loc)
        if kind == "extra_forbidden":
            parent = _field_at(model, loc[:-1]) if len(loc) > 1 else None
            owner = parent.annotation if parent is not None else model
            known = ", ".join(owner.model_fields) if hasattr(owner, "model_fields") else ""
            lines.append(f"`{key}`: {_show(item['input'])} — unknown key (allowed: {known})")
        elif kind == "missing":
            allowed = _describe_allowed(field) if field is not None else "a value"
            lines.append(f"`{key}`: missing — required, {allowed}")
        elif kind == "value_error":
            # Raised by our own field validators: their message is the explanation.
            lines.append(f"`{key}`: {_show(item['input'])} — {item['ctx']['error']}")
        elif kind == "model_type" and not loc:
            # The whole section is not a table (e.g. ``grid = 5``).
            allowed = "a table with keys " + ", ".join(model.model_fields)
            lines.append(f"`{key}`: {_show(item['input'])} — must be {allowed}")
        elif field is not None:
            lines.append(f"`{key}`: {_show(item['input'])} — must be {_describe_allowed(field)}")
        else:
            lines.append(f"`{key}`: {_show(item['input'])} — {item['msg']}")
    return lines


def _skipped_rule_lines(
    items: list[dict[str, Any]], model: type[BaseModel], raw: Any, prefix: tuple[Any, ...]
) -> list[str]:
    """Problems of the rules between keys that pydantic skipped in a failed table.

    ``items`` are the table's pydantic errors (locations relative to it).  If
    any of its values failed, its after-validator did not run; its rules are
    applied here to the keys as given, so that one pass reports them too.
    The same holds for each ``[[indenter.levels]]`` table.
    """
    if not (isinstance(raw, Mapping) and isinstance(model, type) and issubclass(model, _Section)):
        return []
    lines = []
    rules_ran = any(item["type"] == "config_rules" and not item["loc"] for item in items)
    if items and not rules_ran and any(item["loc"] for item in items):
        given = model.model_construct(**{k: v for k, v in raw.items() if k in model.model_fields})
        for problem in given._rule_problems():
            lines.append(f"`{_dotted(prefix + (problem.key,))}`: {problem.value} — {problem.allowed}")
    for name, field in model.model_fields.items():  # lists of tables, e.g. [[indenter.levels]]
        annotation = field.annotation
        if get_origin(annotation) in (Union, UnionType):  # X | None
            annotation = next(a for a in get_args(annotation) if a is not NoneType)
        if get_origin(annotation) is not tuple or not isinstance(raw.get(name), list):
            continue
        for i, table in enumerate(raw[name]):
            nested = [
                {**item, "loc": tuple(item["loc"])[2:]}
                for item in items
                if tuple(item["loc"])[:2] == (name, i)
            ]
            lines.extend(_skipped_rule_lines(nested, get_args(annotation)[0], table, prefix + (name, i)))
    return lines


def parse_config(mapping: Mapping[str, Any], base_dir: str | Path | None = None, *,
                 rules: StructureRules | None = None) -> RunConfig:
    """Validate a configuration mapping (a parsed TOML document).

    Parameters
    ----------
    mapping : mapping
        The document: tables ``halfspace``, ``grid``, ``indenter``,
        ``protocol`` and optionally ``solver``.
    base_dir : path, optional
        Folder against which relative file names (``indenter.file``) are
        resolved; the current directory if not given.
    rules : StructureRules, optional
        The rules on the rasterised structure (`brushbem.assembly`); without
        them only the schema and the rules between keys are checked.

    Returns
    -------
    RunConfig

    Raises
    ------
    ConfigError
        Listing every problem found: each section is validated on its own, and
        the rules between sections run on every section that validated, so one
        pass reports them all.
    """
    if not isinstance(mapping, Mapping):
        raise ConfigError([f"``: {_show(mapping)} — must be a table of sections"])
    deep = _too_deep(mapping)
    if deep is not None:
        where = _dotted(deep)
        raise ConfigError([f"`{where}`: nested more than {_MAX_DEPTH} levels deep — a configuration nests at most 4"])
    context = {"base_dir": Path(base_dir) if base_dir is not None else Path.cwd()}
    problems: list[str] = []
    for key in mapping:
        if key not in _SECTIONS:
            problems.append(
                f"`{key}`: {_show(mapping[key])} — unknown key (allowed: {', '.join(_SECTIONS)})"
            )
    sections: dict[str, BaseModel] = {}
    for name, model in _SECTIONS.items():
        if name not in mapping:
            if RunConfig.model_fields[name].is_required():
                keys = ", ".join(model.model_fields)
                problems.append(f"`{name}`: missing — required table with keys {keys}")
            continue
        try:
            sections[name] = model.model_validate(mapping[name], context=context)
        except ValidationError as exc:
            problems.extend(_problem_lines(exc, model, (name,)))
            problems.extend(
                _skipped_rule_lines(exc.errors(include_url=False), model, mapping[name], (name,))
            )
    if problems:
        for problem in _cross_section_problems(
            sections.get("grid"), sections.get("indenter"), sections.get("halfspace"), rules
        ):
            problems.append(f"`{problem.key}`: {problem.value} — {problem.allowed}")
        raise ConfigError(_capped(problems))
    try:
        # The sections are already validated instances: this runs only the
        # rules between sections.
        return RunConfig.model_validate(sections, context={"rules": rules})
    except ValidationError as exc:
        raise ConfigError(_problem_lines(exc, RunConfig, ())) from None


def _too_deep(document: Any) -> tuple[Any, ...] | None:
    """Location of a value nested deeper than `_MAX_DEPTH`, or None (iterative: no recursion)."""
    stack: list[tuple[Any, tuple[Any, ...]]] = [(document, ())]
    while stack:
        value, loc = stack.pop()
        if len(loc) > _MAX_DEPTH:
            return loc[:_MAX_DEPTH]
        if isinstance(value, Mapping):
            stack.extend((item, (*loc, key)) for key, item in value.items())
        elif isinstance(value, (list, tuple)):
            stack.extend((item, (*loc, i)) for i, item in enumerate(value))
    return None


def _capped(problems: list[str]) -> list[str]:
    """At most `_MAX_PROBLEMS` lines; a file with thousands of problems is counted, not listed."""
    if len(problems) <= _MAX_PROBLEMS:
        return problems
    return [*problems[:_MAX_PROBLEMS], f"`...`: {len(problems) - _MAX_PROBLEMS} more problems not shown"]


def load_config(path: str | Path, *, rules: StructureRules | None = None) -> RunConfig:
    """Read and validate a TOML run configuration (``rules``: see `parse_config`).

    Parameters
    ----------
    path : path
        The TOML file.  Relative file names inside it are resolved against its
        folder.

    Returns
    -------
    RunConfig

    Raises
    ------
    ConfigError
        If the file is missing or unreadable, is not valid TOML, or any value
        is not allowed (every problem listed).
    """
    path = Path(path)
    try:
        with path.open("rb") as stream:
            data = stream.read(MAX_CONFIG_BYTES + 1)
    except FileNotFoundError:
        raise ConfigError([f"`{path}`: file not found"]) from None
    except OSError as exc:
        raise ConfigError([f"`{path}`: cannot be read ({exc.strerror or exc})"]) from None
    if len(data) > MAX_CONFIG_BYTES:
        raise ConfigError([
            f"`{path}`: larger than {MAX_CONFIG_BYTES} bytes — not a run configuration (a few kB of TOML)"
        ])
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise ConfigError([f"`{path}`: not UTF-8 text ({exc.reason} at byte {exc.start})"]) from None
    try:
        document = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError([f"`{path}`: not valid TOML ({exc})"]) from None
    except RecursionError:  # tomllib recurses once per nested array or inline table
        raise ConfigError([
            f"`{path}`: arrays or tables nested too deeply (a configuration needs at most {_MAX_DEPTH} levels)"
        ]) from None
    return parse_config(document, base_dir=path.resolve().parent, rules=rules)


def to_json_safe(value: Any) -> Any:
    """Convert to plain JSON data; non-finite floats become strings.

    JSON has no infinity or NaN, and ``null`` would read as "missing", so
    ``inf``, ``-inf`` and ``nan`` become ``"inf"``, ``"-inf"`` and ``"nan"``.
    NumPy scalars and arrays become Python numbers and lists.

    Parameters
    ----------
    value : any
        Nested dicts, lists, tuples, numbers, strings, booleans, None, NumPy
        scalars or arrays.

    Returns
    -------
    any
        The same structure with JSON-representable leaves only.
    """
    if isinstance(value, Mapping):
        return {str(key): to_json_safe(item) for key, item in value.items()}
    if isinstance(value, (list, tuple)):
        return [to_json_safe(item) for item in value]
    if isinstance(value, np.ndarray):
        return to_json_safe(value.tolist())
    if isinstance(value, np.generic):
        return to_json_safe(value.item())
    if isinstance(value, float) and not math.isfinite(value):
        return "nan" if math.isnan(value) else ("inf" if value > 0 else "-inf")
    return value


def config_to_dict(config: RunConfig) -> dict[str, Any]:
    """The resolved configuration as plain JSON-able data.

    Defaults are filled in, ``indenter.file`` is absolute, and an infinite
    value (a rigid ``stiffness``) is written as the string ``"inf"``.  The
    result re-parses with `parse_config` to an equal `RunConfig`.

    Parameters
    ----------
    config : RunConfig

    Returns
    -------
    dict
    """
    data = config.model_dump(mode="python")
    indenter = data["indenter"]
    # Keys a shape does not use are dropped, and the default rigid
    # `stiffness` is not written beside a `stiffness_ratio` (exactly one of
    # them may be given), so the result re-parses to an equal config.
    for key in [k for k, v in indenter.items() if v is None]:
        del indenter[key]
    if indenter.get("stiffness_ratio") is not None:
        indenter.pop("stiffness", None)
    for level in indenter.get("levels") or ():
        for key in [k for k, v in level.items() if v is None]:
            del level[key]
    for table in ("roughness", "profile"):
        if isinstance(indenter.get(table), dict):
            indenter[table] = {k: v for k, v in indenter[table].items() if v is not None}
    return to_json_safe(data)
