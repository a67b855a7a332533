"""The ``[indenter]`` table: `IndenterConfig`, its shapes and brush layouts and the keys each needs."""

from __future__ import annotations

import math
from typing import Any, Literal

from pydantic import Field, ValidationError, ValidationInfo, field_validator, model_validator

from brushbem.config.errors import _show
from brushbem.config.files import _check_height_map, _existing_file, _read_numbers
from brushbem.config.limits import MAGNITUDE_RANGE
from brushbem.config.rules import Problem
from brushbem.config.sections_base import _MODEL_CONFIG, _inf_from_string, _Section
from brushbem.config.sections_pillars import (
    FibrilConfig,
    GradingConfig,
    LevelConfig,
    PillarLawConfig,
    ProfileConfig,
    RoughnessConfig,
    TiltConfig,
    TipConfig,
    ViscoelasticConfig,
)


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
    "flat_punch": ("viscoelastic", "pillar_law", "fibril"),
    "sphere": ("viscoelastic", "pillar_law", "fibril"),
    "height_map": ("viscoelastic", "pillar_law", "fibril"),
    "brush": (
        "region", "region_size", "pillars_per_side", "spacing", "pillar_count", "min_gap", "pillar_radius",
        "filling_factors", "stiffness_ratio", "seed", "roughness", "profile", "lengths_file", "levels", "tip", "tilt",
        "grading", "viscoelastic", "pillar_law", "fibril",
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

    Brush keys (``shape = "brush"``, thesis ch. 3-7; k~ = k / (E* L) with L the brush's side, region_size,
    by default grid.size)
        layout : ``"square"`` (regular lattice, ``pillars_per_side``, optional
        ``spacing``, default region_size / pillars_per_side), ``"random"``
        (``pillar_count`` non-overlapping positions, optional ``min_gap``
        between pillar edges, default 2 h) or ``"clustered"`` (thesis Fig.
        6-3: ``pillars_per_side`` sub-pillars per side in square clusters of
        the ``levels``, ``filling_factors`` phi1, phi2, ... one per level
        bottom-up, the pillar radius derived from them;
        `brushbem.physics.structure.clustered_lattice`); region : ``"square"``
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
    ``protocol.method = "fixed"``).  ``[indenter.fibril]`` (`FibrilConfig`)
    gives the spring from the fibril's modulus, length and radius instead of
    ``stiffness`` / ``stiffness_ratio`` (and, with its ``buckling``, the
    pillar law of Euler buckling): the derived ``stiffness`` (and
    ``pillar_law``) are filled in before validation.
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
    fibril: FibrilConfig | None = None

    @model_validator(mode="before")
    @classmethod
    def _spring_from_fibril(cls, data: Any, info: ValidationInfo) -> Any:
        """Fill in ``stiffness`` (and ``pillar_law``) from a valid ``fibril`` table (`FibrilConfig`).

        A given ``stiffness`` equal to the derived one (a recorded
        configuration, `brushbem.config.config_to_dict`) is accepted; any other
        spring given beside ``fibril`` is `_fibril_problems`'s.
        """
        if not isinstance(data, dict) or not isinstance(data.get("fibril"), dict):
            return data
        try:
            fibril = FibrilConfig.model_validate(data["fibril"], context=info.context)
        except ValidationError:  # the table's own problems, reported by its field
            return data
        radius = fibril.radius or _fibril_default_radius(data)
        if radius is None:  # `_fibril_problems` asks for fibril.radius
            return data
        data = dict(data)
        if "stiffness" not in data and "stiffness_ratio" not in data:
            data["stiffness"] = fibril.stiffness(radius)
        law = fibril.buckling_law(radius)
        if law is not None and "pillar_law" not in data:
            data["pillar_law"] = law
        return data

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
        if self.fibril is not None:
            problems.extend(self._fibril_problems())
        return problems

    def _fibril_problems(self) -> list[Problem]:
        """A fibril needs its radius, and is the only spring given (its derived stiffness and law aside)."""
        fibril = self.fibril
        assert fibril is not None
        radius = fibril.radius or _fibril_default_radius(self)
        if radius is None:
            return [Problem("fibril.radius", "missing", f"required with shape = {self.shape!r}"
                            + (f", layout = {self.layout!r}" if self.is_brush else "")
                            + " (no pillar or punch radius to take it from)")]
        problems = []
        derived = fibril.stiffness(radius)
        if self.stiffness_ratio is not None or ("stiffness" in self.model_fields_set
                                                and not math.isclose(self.stiffness, derived, rel_tol=1e-12)):
            given = (f"stiffness_ratio = {_show(self.stiffness_ratio)}" if self.stiffness_ratio is not None
                     else f"stiffness = {_show(self.stiffness)}")
            problems.append(Problem("fibril", given, f"give either fibril (k = pi r^2 E_f / l = {derived:.6g}) or "
                                                     "stiffness / stiffness_ratio, not both"))
        law = fibril.buckling_law(radius)
        if law is not None and self.pillar_law is not None and (
                list(self.pillar_law.forces) != law["forces"] or list(self.pillar_law.factors) != law["factors"]):
            problems.append(Problem("fibril.buckling", _show(fibril.buckling),
                                    "gives the pillar law of Euler buckling; remove indenter.pillar_law or "
                                    "fibril.buckling"))
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


def _fibril_default_radius(indenter: Any) -> float | None:
    """The radius a fibril takes by default: a square or random brush's pillar radius, a punch's radius.

    ``indenter`` is the raw table (a mapping, before validation) or the validated `IndenterConfig`.
    """
    def get(key: str) -> Any:
        return indenter.get(key) if isinstance(indenter, dict) else getattr(indenter, key, None)

    shape = get("shape")
    key = "radius" if shape == "flat_punch" else "pillar_radius" if shape == "brush" else None
    value = get(key) if key is not None else None
    finite = isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value) and value > 0
    return float(value) if finite else None
