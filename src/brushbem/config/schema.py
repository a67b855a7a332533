"""The section models of a run configuration: the fields and the rules between a table's keys.

One model per TOML table (`HalfSpaceConfig`, `GridConfig`, `IndenterConfig`
with `RoughnessConfig`, `ProfileConfig` and `LevelConfig`, `ProtocolConfig`,
`SolverConfig`) and `RunConfig`, the whole run.  A table's rules between keys
are its `_rule_problems`; `RunConfig` runs the rules between sections
(`brushbem.config.rules`).
"""

from __future__ import annotations

import itertools
import math
from typing import Any, Literal

import numpy as np
from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
    ValidationInfo,
    field_validator,
    model_validator,
)

from .errors import _describe_allowed, _show
from .files import _check_height_map, _existing_file, _read_numbers
from .limits import MAGNITUDE_RANGE, MAX_PRELOAD_DOMAIN_SIZES
from .rules import Problem, _cross_section_problems, _resource_problems, _rules_error

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
    "ViscoelasticConfig",
]


# Strict: a TOML ``size = "1.0"`` or ``elements = true`` is a mistake to report,
# not a value to coerce.  Frozen: the numerics may cache on a config safely.
_MODEL_CONFIG = ConfigDict(extra="forbid", frozen=True, strict=True)


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
    "brush": ("layout",),
}

# Keys a shape accepts but does not require (rejected by the other shapes).
_SHAPE_OPTIONAL: dict[str, tuple[str, ...]] = {
    "flat_punch": ("viscoelastic", "pillar_law"),
    "sphere": ("viscoelastic", "pillar_law"),
    "height_map": ("viscoelastic", "pillar_law"),
    "brush": (
        "region", "region_size", "pillars_per_side", "spacing", "pillar_count", "min_gap", "pillar_radius",
        "filling_factors", "stiffness_ratio", "seed", "roughness", "profile", "lengths_file", "levels", "tip", "tilt",
        "grading", "viscoelastic", "pillar_law",
    ),
}

# Keys of a brush that belong to some layouts only: required by the first
# table's layouts, accepted by the second's, rejected by the others.  A
# clustered brush derives its pillar radius from its filling factors.
_LAYOUT_KEYS: dict[str, tuple[str, ...]] = {
    "square": ("pillars_per_side", "pillar_radius"),
    "random": ("pillar_count", "pillar_radius"),
    "clustered": ("pillars_per_side", "levels", "filling_factors"),
}
_LAYOUT_OPTIONAL: dict[str, tuple[str, ...]] = {
    "square": ("spacing", "levels"),
    "random": ("min_gap",),
    "clustered": (),
}


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


def _per_pillar_file(value: Any, info: ValidationInfo) -> Any:
    """A tip parameter given as a file name: resolved and read as 1-D numbers > 0 (one per pillar)."""
    if not isinstance(value, str):
        return value
    path = _existing_file(value, info)
    numbers = _read_numbers(path)
    if numbers.ndim != 1:
        raise ValueError(f"holds an array of shape {numbers.shape} ({path}); must hold a 1-D array of one value > 0 "
                         "per pillar")
    if numbers.size and not bool(np.all(numbers > 0)):
        smallest = float(numbers.min())
        raise ValueError(f"holds values down to {smallest:g} (at index {int(np.argmin(numbers))}, {path}); every "
                         f"value must be > 0, between {MAGNITUDE_RANGE[0]:g} and {MAGNITUDE_RANGE[1]:g}")
    if numbers.size and float(numbers.min()) < MAGNITUDE_RANGE[0]:
        raise ValueError(f"holds values down to {float(numbers.min()):g} ({path}); every value must be at least "
                         f"{MAGNITUDE_RANGE[0]:g}")
    return str(path)


def _choice_problems(table: _Section, choice: str, uses: dict[str, tuple[tuple[str, ...], tuple[str, ...]]],
                     prefix: str) -> list[Problem]:
    """The keys a choice key's value needs and allows: ``uses[value] = (required, optional)``.

    A required key that is absent and a given key that this value does not
    use are problems; a value outside ``uses`` is the choice key's own
    problem (reported by its field).
    """
    value = getattr(table, choice, None)
    if not isinstance(value, str) or value not in uses:
        return []
    required, optional = uses[value]
    keys = sorted({key for need, allow in uses.values() for key in (*need, *allow)})
    problems = []
    for key in keys:
        given = getattr(table, key, None)
        if key in required and given is None:
            problems.append(Problem(key, "missing", f"required when {prefix}.{choice} = {value!r}"))
        elif key not in required and key not in optional and given is not None:
            users = " or ".join(repr(v) for v, (need, allow) in uses.items() if key in need or key in allow)
            problems.append(Problem(key, _show(given), f"only used with {prefix}.{choice} = {users}; remove it"))
    return problems


#: What a tip's radius or depth accepts (a number or a file: its type alone does not say it).
_LENGTH_OR_FILE = (f"a finite number > 0 (units of length), between {MAGNITUDE_RANGE[0]:g} and {MAGNITUDE_RANGE[1]:g}, "
                   "or the name of a .npy file of one such value per pillar")

_TIP_USES = {"flat": ((), ()), "spherical_cap": (("radius",), ()), "concave": (("depth",), ()),
             "profile": (("file",), ())}


class TipConfig(_Section):
    """The tip shape of every pillar (`brushbem.structure.Tip`).

    Attributes
    ----------
    shape : {"flat", "spherical_cap", "concave", "profile"}
    radius : float or str
        Curvature radius R of a spherical cap (z = rho^2 / (2 R)), in units of
        length; or a ``.npy`` file of one radius per pillar.
    depth : float or str
        Depth of a concave dish (z = depth (1 - rho^2 / r^2)), in units of
        length; or a ``.npy`` file of one depth per pillar.
    file : str
        ``.npy`` file of the profile z(rho) >= 0 at K >= 2 evenly spaced rho
        from 0 to the pillar radius (``shape = "profile"``).
    """

    model_config = _MODEL_CONFIG

    shape: Literal["flat", "spherical_cap", "concave", "profile"]
    radius: float | str | None = Field(None, description=_LENGTH_OR_FILE)
    depth: float | str | None = Field(None, description=_LENGTH_OR_FILE)
    file: str | None = Field(None, description="the name of a .npy file of K >= 2 heights >= 0 (units of length) "
                                               "at evenly spaced rho from 0 to the pillar radius")

    @field_validator("radius", "depth", mode="before")
    @classmethod
    def _number_or_name(cls, value: Any) -> Any:
        if value is None or isinstance(value, str) or (isinstance(value, (int, float))
                                                       and not isinstance(value, bool)):
            return float(value) if isinstance(value, int) and abs(value) <= MAGNITUDE_RANGE[1] else value
        raise ValueError(f"must be {_LENGTH_OR_FILE}")

    @field_validator("radius", "depth")
    @classmethod
    def _positive_or_file(cls, value: Any, info: ValidationInfo) -> Any:
        if isinstance(value, (int, float)) and not (math.isfinite(value) and value > 0):
            raise ValueError(f"must be {_LENGTH_OR_FILE}")
        return _per_pillar_file(value, info)

    @field_validator("file")
    @classmethod
    def _profile_file(cls, value: str | None, info: ValidationInfo) -> str | None:
        if value is None:
            return None
        path = _existing_file(value, info)
        numbers = _read_numbers(path)
        if numbers.ndim != 1 or numbers.size < 2:
            raise ValueError(f"holds an array of shape {numbers.shape} ({path}); must hold a 1-D array of K >= 2 "
                             "heights >= 0 at evenly spaced rho from 0 to the pillar radius")
        if float(numbers.min()) < 0:
            raise ValueError(f"holds heights down to {float(numbers.min()):g} ({path}); every height must be >= 0 "
                             "(the tip's lowest point is z = 0)")
        return str(path)

    def _rule_problems(self) -> list[Problem]:
        return _choice_problems(self, "shape", _TIP_USES, "tip")


class TiltConfig(_Model):
    """A tilted base (`brushbem.structure.Tilt`).

    Attributes
    ----------
    angle : float
        Tilt angle in degrees, in [0, 45).
    azimuth : float
        In-plane direction (degrees from the x axis towards y, in [0, 360)) in
        which the tips recede from the surface; default 0.
    """

    model_config = _MODEL_CONFIG

    angle: float = Field(ge=0, lt=45, allow_inf_nan=False)
    azimuth: float = Field(0.0, ge=0, lt=360, allow_inf_nan=False)


class GradingConfig(_Section):
    """A level's stiffness graded over the brush (`brushbem.structure.Grading`).

    Attributes
    ----------
    rule : {"radial", "linear", "file"}
        k_n = k (1 + amplitude s_n^exponent), s_n the spring's distance from
        the centre over the outermost's (radial) or its coordinate along
        ``azimuth`` over the largest (linear, -1..1); or k_n = k f_n with the
        factors f_n of ``file`` (one per spring of the level).
    amplitude : float
        > -1 (radial) or in (-1, 1) (linear): every k_n stays > 0.
    exponent : float
        Radial only; default 1.
    azimuth : float
        Linear only, degrees in [0, 360); default 0 (along x).
    file : str
        ``.npy`` file of one factor > 0 per spring (rule = "file").

    A grading that can have no effect is refused when the structure is built
    (`brushbem.structure.Grading.apply`): one on a rigid level, and a rule on a
    level of one spring (a single pillar, one cluster).
    """

    model_config = _MODEL_CONFIG

    rule: Literal["radial", "linear", "file"]
    amplitude: float | None = Field(None, allow_inf_nan=False)
    exponent: float | None = Field(None, gt=0, allow_inf_nan=False)
    azimuth: float | None = Field(None, ge=0, lt=360, allow_inf_nan=False)
    file: str | None = Field(None, description=f"the name of a .npy file of one stiffness factor > 0 per spring, "
                                               f"each between {MAGNITUDE_RANGE[0]:g} and {MAGNITUDE_RANGE[1]:g}")

    @field_validator("file")
    @classmethod
    def _factors_file(cls, value: str | None, info: ValidationInfo) -> str | None:
        return None if value is None else _per_pillar_file(value, info)

    def _rule_problems(self) -> list[Problem]:
        rule = getattr(self, "rule", None)
        problems = _choice_problems(self, "rule", {"radial": (("amplitude",), ("exponent",)),
                                                   "linear": (("amplitude",), ("azimuth",)),
                                                   "file": (("file",), ())}, "grading")
        amplitude = getattr(self, "amplitude", None)
        if not (isinstance(amplitude, float) and math.isfinite(amplitude)):  # the field's own problem
            return problems
        if rule == "radial" and not amplitude > -1:
            problems.append(Problem("amplitude", _show(amplitude),
                                    "must be > -1 with rule = 'radial' (the rim's stiffness k (1 + amplitude) "
                                    "must stay > 0)"))
        if rule == "linear" and not abs(amplitude) < 1:
            problems.append(Problem("amplitude", _show(amplitude),
                                    "must lie in (-1, 1) with rule = 'linear' (the stiffness k (1 +- amplitude) "
                                    "at both ends must stay > 0)"))
        return problems


class ViscoelasticConfig(_Section):
    """Viscoelastic pillar connections (`brushbem.viscoelastic`); the pillar stiffness is the relaxed one.

    Attributes
    ----------
    model : {"kelvin_voigt", "standard_linear_solid"}
    relaxation_time : float
        tau (> 0), in the time units of ``protocol.speed``: eta / k
        (Kelvin-Voigt) or eta / k_1 of the Maxwell arm (standard linear solid).
    instantaneous_factor : float
        k_0 / k_inf > 1, the standard linear solid's instantaneous over its
        relaxed stiffness (that model only).
    """

    model_config = _MODEL_CONFIG

    model: Literal["kelvin_voigt", "standard_linear_solid"]
    relaxation_time: float = Field(gt=0, allow_inf_nan=False)
    instantaneous_factor: float | None = Field(None, gt=1, allow_inf_nan=False)

    def _rule_problems(self) -> list[Problem]:
        return _choice_problems(self, "model", {"kelvin_voigt": ((), ()),
                                                "standard_linear_solid": (("instantaneous_factor",), ())},
                                "viscoelastic")


#: What a pillar law's arrays accept.
_LAW_FORCES = (f"an array of force breakpoints (units of force, compressive positive), strictly increasing, each 0 "
               f"or between {MAGNITUDE_RANGE[0]:g} and {MAGNITUDE_RANGE[1]:g} in magnitude; [] for none")
_LAW_FACTORS = (f"an array of len(forces) + 1 slope factors, each > 0 and between {MAGNITUDE_RANGE[0]:g} and "
                f"{MAGNITUDE_RANGE[1]:g}")


class PillarLawConfig(_Section):
    """A nonlinear force-compression law of the pillars' connections (`brushbem.pillar_laws.PiecewiseLinear`).

    Attributes
    ----------
    forces : list of float
        Force breakpoints, strictly increasing (compressive positive), units
        of force; default none.
    factors : list of float
        The slope of each of the len(forces) + 1 pieces as a factor (> 0) of
        the pillar stiffness, from the most tensile piece up; default [1].
    tension_limit : float or None
        A pillar whose tension exceeds this force breaks.
    """

    model_config = _MODEL_CONFIG

    forces: tuple[float, ...] = Field((), description=_LAW_FORCES)
    factors: tuple[float, ...] = Field((1.0,), description=_LAW_FACTORS)
    tension_limit: float | None = Field(None, gt=0, allow_inf_nan=False)

    @field_validator("forces", "factors", mode="before")
    @classmethod
    def _list(cls, value: Any, info: ValidationInfo) -> Any:
        if isinstance(value, (list, tuple)) and all(isinstance(v, (int, float)) and not isinstance(v, bool)
                                                    for v in value):
            return tuple(value)
        raise ValueError(f"must be {_LAW_FORCES if info.field_name == 'forces' else _LAW_FACTORS}")

    def _rule_problems(self) -> list[Problem]:
        forces, factors = getattr(self, "forces", ()), getattr(self, "factors", (1.0,))
        if not all(isinstance(values, (tuple, list)) and all(isinstance(v, (int, float)) and not isinstance(v, bool)
                                                              for v in values) for values in (forces, factors)):
            return []  # not arrays of numbers: the fields' own problems
        problems = []
        smallest, largest = MAGNITUDE_RANGE
        for key, values, allowed in (("forces", forces, _LAW_FORCES), ("factors", factors, _LAW_FACTORS)):
            finite = all(math.isfinite(v) for v in values)
            if not finite or any(abs(v) > largest or (v != 0 and abs(v) < smallest) for v in values):
                problems.append(Problem(key, _show(list(values)), f"must be {allowed}"))
        if problems:
            return problems
        if any(b <= a for a, b in itertools.pairwise(forces)):
            problems.append(Problem("forces", _show(list(forces)), "must be strictly increasing"))
        if len(factors) != len(forces) + 1:
            problems.append(Problem("factors", _show(list(factors)),
                                    f"must hold {len(forces) + 1} values: one per piece between the "
                                    f"{len(forces)} force breakpoints"))
        if any(f <= 0 for f in factors):
            problems.append(Problem("factors", _show(list(factors)),
                                    "must all be > 0: the law must be increasing (monotone); a falling "
                                    "(snapping) piece is not supported - give a post-buckling plateau a small "
                                    "positive factor"))
        return problems


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
    grading : GradingConfig or None
        Grades the level's springs over its clusters' centres.
    """

    model_config = _MODEL_CONFIG

    cluster: int = Field(ge=1, le=4096)
    stiffness_ratio: float | None = Field(None, gt=0)
    stiffness: float | None = Field(None, gt=0)
    grading: GradingConfig | None = None

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
        ``spacing``, default region_size / pillars_per_side), ``"random"``
        (``pillar_count`` non-overlapping positions, optional ``min_gap``
        between pillar edges, default 2 h) or ``"clustered"`` (thesis Fig.
        6-3: ``pillars_per_side`` sub-pillars per side in square clusters of
        the ``levels``, ``filling_factors`` phi1, phi2, ... one per level
        bottom-up, the pillar radius derived from them;
        `brushbem.structure.clustered_lattice`); region : ``"square"``
        (default) or ``"circle"`` (not clustered), where pillars are placed, of
        side / diameter ``region_size`` (default grid.size), whose area is the
        apparent area A0; pillar_radius (square and random layouts);
        stiffness_ratio or stiffness (exactly one, the
        pillars' own springs); seed (random layout and roughness, default 0);
        ``[indenter.roughness] sigma``; ``[indenter.profile] amplification``
        (and optionally ``reference_stress``); lengths_file (``.npy`` of one
        extra length per pillar); ``[[indenter.levels]]`` ``cluster`` and
        ``stiffness_ratio`` or ``stiffness``, bottom-up (square or clustered layout),
        each with an optional ``grading``; ``[indenter.tip]`` (`TipConfig`),
        ``[indenter.tilt]`` (`TiltConfig`), ``[indenter.grading]``
        (`GradingConfig`, the pillars' own springs).

    Every shape: ``[indenter.viscoelastic]`` (`ViscoelasticConfig`) makes
    the spring (a brush: the pillars' own springs) a viscoelastic
    connection whose relaxed stiffness is ``stiffness`` or
    ``stiffness_ratio``; it needs ``protocol.speed``.
    ``[indenter.pillar_law]`` (`PillarLawConfig`) makes it nonlinear (with
    ``protocol.method = "fixed"``).
    """

    model_config = _MODEL_CONFIG

    shape: Literal["flat_punch", "sphere", "height_map", "brush"]
    radius: float | None = Field(None, gt=0, allow_inf_nan=False)
    stiffness: float = Field(math.inf, gt=0)
    file: str | None = None
    layout: Literal["square", "random", "clustered"] | None = None
    region: Literal["square", "circle"] | None = None
    region_size: float | None = Field(None, gt=0, allow_inf_nan=False)
    pillars_per_side: int | None = Field(None, ge=1, le=4096)
    spacing: float | None = Field(None, gt=0, allow_inf_nan=False)
    pillar_count: int | None = Field(None, ge=1, le=1_000_000)
    min_gap: float | None = Field(None, ge=0, allow_inf_nan=False)
    pillar_radius: float | None = Field(None, gt=0, allow_inf_nan=False)
    filling_factors: tuple[float, ...] | None = None
    stiffness_ratio: float | None = Field(None, gt=0)
    seed: int | None = Field(None, ge=0, le=2**63 - 1)
    roughness: RoughnessConfig | None = None
    profile: ProfileConfig | None = None
    lengths_file: str | None = None
    levels: tuple[LevelConfig, ...] | None = None
    tip: TipConfig | None = None
    tilt: TiltConfig | None = None
    grading: GradingConfig | None = None
    viscoelastic: ViscoelasticConfig | None = None
    pillar_law: PillarLawConfig | None = None

    @field_validator("stiffness", "stiffness_ratio", mode="before")
    @classmethod
    def _inf_string(cls, value: Any) -> Any:
        return _inf_from_string(value)

    @field_validator("levels", mode="before")
    @classmethod
    def _levels_list(cls, value: Any) -> Any:
        # TOML arrays of tables arrive as lists; the frozen model stores a tuple.
        return tuple(value) if isinstance(value, list) else value

    @field_validator("filling_factors", mode="before")
    @classmethod
    def _numbers_list(cls, value: Any) -> Any:
        value = tuple(value) if isinstance(value, list) else value
        if value is not None and not (isinstance(value, tuple) and all(
                isinstance(v, (int, float)) and not isinstance(v, bool) for v in value)):
            raise ValueError("must be an array of numbers in (0, 1), one filling factor per level bottom-up "
                             "(phi1, phi2, ...)")
        return value

    @field_validator("filling_factors")
    @classmethod
    def _filling_factors(cls, value: tuple[float, ...] | None) -> tuple[float, ...] | None:
        if value is None:
            return None
        if not value:
            raise ValueError("must hold one filling factor per level, bottom-up (phi1, phi2, ...)")
        smallest = MAGNITUDE_RANGE[0]
        bad = [i for i, phi in enumerate(value, start=1) if not (math.isfinite(phi) and smallest <= phi < 1)]
        if bad:
            raise ValueError(f"phi{bad[0]} = {value[bad[0] - 1]!r}: every filling factor must be a finite number in "
                             f"(0, 1), at least {smallest:g}")
        return value

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
                    derived = (" (layout = 'clustered' derives it from filling_factors and pillars_per_side)"
                               if key == "pillar_radius" else "")
                    problems.append(Problem(key, _show(value), f"only used when layout = {users}{derived}; remove it"))
        if self.layout == "clustered":
            problems.extend(self._clustered_problems())
        if ("stiffness" in self.model_fields_set) == (self.stiffness_ratio is not None):
            problems.append(Problem(
                "stiffness_ratio",
                f"stiffness_ratio = {_show(self.stiffness_ratio)}, stiffness = "
                f"{_show(self.stiffness) if 'stiffness' in self.model_fields_set else 'not given'}",
                "give exactly one of stiffness_ratio (k / (E* L)) and stiffness (inf = rigid)",
            ))
        return problems

    def _clustered_problems(self) -> list[Problem]:
        """A clustered brush tiles a square region, with one filling factor per level (the sub-pillars' too)."""
        problems = []
        if self.region not in (None, "square"):
            problems.append(Problem("region", _show(self.region), "layout = 'clustered' tiles a square region"))
        levels, factors = self.levels, self.filling_factors
        # Read as given: the values may not have passed their own checks (`loading._skipped_rule_lines`).
        if isinstance(levels, (tuple, list)) and levels and isinstance(factors, (tuple, list)) and factors \
                and len(factors) != len(levels) + 1:
            problems.append(Problem(
                "filling_factors", _show(list(factors)),
                f"must hold {len(levels) + 1} values for {len(levels)} level(s) above the pillars: phi1 (the "
                "sub-pillars in a level-2 cluster), then each level's clusters in the next level's, the last the "
                "top level's clusters in the region",
            ))
        return problems

    def pillar_stiffness(self, contact_modulus: float, size: float) -> float:
        """k of the pillars' own springs, from ``stiffness`` or ``stiffness_ratio`` (k~ E* L)."""
        if self.stiffness_ratio is not None:
            return self.stiffness_ratio * contact_modulus * size
        return self.stiffness


class ProtocolConfig(_Section):
    """The pull-off load path: press to a preload, then retract until separation.

    Attributes
    ----------
    method : {"events", "element_events", "fixed", "pillars"}
        ``"events"`` follows the exact path: it jumps from one contact
        change to the next, and presses a brush (two or more pillars) as
        non-adhesive contact problems, which is the same branch checked on
        its samples (``brushbem.protocol``); ``"element_events"`` takes
        every element event on the loading branch too (the reference, and
        today's path of single bodies); ``"fixed"`` retracts by constant
        steps (the thesis's method), locating every detachment (and a
        pillar law's break) inside each step; ``"pillars"`` is the
        pillar-level model of a brush of flat tips (a few modes per tip,
        events exact in the reduced model; ``brushbem.protocol.pillars``).
    preload_displacement : float or None
        Press until the base displacement reaches this value, units of length;
        at most `MAX_PRELOAD_DOMAIN_SIZES` (1000) x grid.size.
    preload_force : float or None
        Press until the compressive force reaches this value, units of force;
        at most the force that presses the stiffest contact the domain allows
        (2 E* L / sqrt(2)) that deep.  Exactly one of the two preloads is given.
    step : float
        Displacement step of ``"fixed"``, in units of length: at most
        grid.size, and at least the preload's depth / max_steps.
    max_steps : int
        Most steps (events, or fixed displacement steps) on each branch,
        loading and unloading; a branch that needs more ends the run, which
        reports not converged.
    speed : float or None
        Pulling (and pressing) speed of viscoelastic pillars, in units of
        length per time: each ``step`` is the time step step / speed.  Needs
        ``indenter.viscoelastic``, ``method = "fixed"`` and
        ``preload_displacement``.
    """

    model_config = _MODEL_CONFIG

    method: Literal["events", "element_events", "fixed", "pillars"] = "events"
    preload_displacement: float | None = Field(None, gt=0, allow_inf_nan=False)
    preload_force: float | None = Field(None, gt=0, allow_inf_nan=False)
    step: float = Field(1e-4, gt=0, allow_inf_nan=False)
    max_steps: int = Field(200_000, gt=0, le=1_000_000_000)
    speed: float | None = Field(None, gt=0, allow_inf_nan=False)

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


class UnitsConfig(_Section):
    """The unit system of the inputs (`brushbem.units`): names only, the numbers do not change.

    Attributes
    ----------
    length : {"m", "cm", "mm", "um", "nm"} or None
        The unit of ``grid.size`` and every length.
    stress : {"Pa", "kPa", "MPa", "GPa"} or None
        The unit of E* and every stress; forces, works and the work of
        adhesion follow.  Both or neither; neither (the default) is
        dimensionless.
    """

    model_config = _MODEL_CONFIG

    length: Literal["m", "cm", "mm", "um", "nm"] | None = None
    stress: Literal["Pa", "kPa", "MPa", "GPa"] | None = None

    def _rule_problems(self) -> list[Problem]:
        length, stress = getattr(self, "length", None), getattr(self, "stress", None)
        if (length is None) == (stress is None):
            return []
        missing = "stress" if stress is None else "length"
        return [Problem(missing, "missing", "give units.length and units.stress together, or neither "
                                            "(dimensionless)")]


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

    def _pillar_law_problems(self) -> list[Problem]:
        """A nonlinear pillar law: fixed steps to a displacement, a finite stiffness, no viscoelasticity."""
        spec, protocol = self.indenter, self.protocol
        if spec.pillar_law is None:
            return []
        problems = []
        if protocol.method != "fixed":
            problems.append(Problem("protocol.method", _show(protocol.method),
                                    "must be 'fixed' with indenter.pillar_law (the law is followed step by step)"))
        if protocol.preload_displacement is None:
            problems.append(Problem("protocol.preload_force", _show(protocol.preload_force),
                                    "a nonlinear pillar law is pressed to protocol.preload_displacement instead"))
        if spec.viscoelastic is not None:
            problems.append(Problem("indenter.pillar_law", _show(spec.pillar_law),
                                    "cannot be combined with indenter.viscoelastic: remove one of them"))
        stiffness = spec.stiffness_ratio if spec.stiffness_ratio is not None else spec.stiffness
        if not math.isfinite(stiffness):
            problems.append(Problem("indenter.stiffness_ratio" if spec.stiffness_ratio is not None
                                    else "indenter.stiffness", _show(stiffness),
                                    "must be finite with indenter.pillar_law (its slopes are factors of it)"))
        return problems

    def _time_stepping_problems(self) -> list[Problem]:
        """Viscoelastic pillars and the pulling speed go together, on a fixed-step path to a displacement."""
        viscoelastic, protocol = self.indenter.viscoelastic, self.protocol
        if viscoelastic is None:
            if protocol.speed is None:
                return []
            return [Problem("protocol.speed", _show(protocol.speed),
                            "only used with viscoelastic pillars (indenter.viscoelastic); remove it")]
        problems = []
        if protocol.speed is None:
            problems.append(Problem("protocol.speed", "missing",
                                    "required with indenter.viscoelastic: the pulling speed (> 0)"))
        if protocol.method != "fixed":
            problems.append(Problem("protocol.method", _show(protocol.method),
                                    "must be 'fixed' with indenter.viscoelastic (the path is stepped in time: "
                                    "dt = step / speed)"))
        if protocol.preload_displacement is None:
            problems.append(Problem("protocol.preload_force", _show(protocol.preload_force),
                                    "viscoelastic pillars are pressed to protocol.preload_displacement instead"))
        spec = self.indenter
        stiffness = (spec.stiffness_ratio if spec.stiffness_ratio is not None else spec.stiffness)
        if not math.isfinite(stiffness):
            problems.append(Problem("indenter.stiffness_ratio" if spec.stiffness_ratio is not None
                                    else "indenter.stiffness", _show(stiffness),
                                    "must be finite with indenter.viscoelastic (it is the relaxed stiffness)"))
        return problems


_SECTIONS: dict[str, type[BaseModel]] = {
    "halfspace": HalfSpaceConfig,
    "grid": GridConfig,
    "indenter": IndenterConfig,
    "protocol": ProtocolConfig,
    "solver": SolverConfig,
    "units": UnitsConfig,
}
