"""The sub-tables of an indenter: a brush's pillars, their tips and connections, and its levels.

`RoughnessConfig`, `ProfileConfig`, `TipConfig`, `TiltConfig`,
`GradingConfig`, `ViscoelasticConfig`, `PillarLawConfig`, `FibrilConfig` and `LevelConfig`,
each with the rules between its keys (`IndenterConfig` holds them).
"""

from __future__ import annotations

import itertools
import math
from typing import Any, Literal

from pydantic import Field, ValidationInfo, field_validator

from brushbem.config.errors import _show
from brushbem.config.files import _existing_file, _read_numbers
from brushbem.config.limits import MAGNITUDE_RANGE
from brushbem.config.rules import Problem
from brushbem.config.sections_base import _MODEL_CONFIG, _choice_problems, _inf_from_string, _Model, _per_pillar_file, _Section


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
        (`brushbem.physics.theory.concave_reference_stress`).
    """

    model_config = _MODEL_CONFIG

    amplification: float = Field(ge=0, allow_inf_nan=False)
    reference_stress: float | None = Field(None, gt=0, allow_inf_nan=False)


#: What a tip's radius or depth accepts (a number or a file: its type alone does not say it).
_LENGTH_OR_FILE = (f"a finite number > 0 (units of length), between {MAGNITUDE_RANGE[0]:g} and {MAGNITUDE_RANGE[1]:g}, "
                   "or the name of a .npy file of one such value per pillar")

_TIP_USES = {"flat": ((), ()), "spherical_cap": (("radius",), ()), "concave": (("depth",), ()),
             "profile": (("file",), ())}


class TipConfig(_Section):
    """The tip shape of every pillar (`brushbem.physics.structure.Tip`).

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
    """A tilted base (`brushbem.physics.structure.Tilt`).

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
    """A level's stiffness graded over the brush (`brushbem.physics.structure.Grading`).

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
    (`brushbem.physics.structure.Grading.apply`): one on a rigid level, and a rule on a
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
    """Viscoelastic pillar connections (`brushbem.physics.viscoelastic`); the pillar stiffness is the relaxed one.

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
    """A nonlinear force-compression law of the pillars' connections (`brushbem.physics.pillar_laws.PiecewiseLinear`).

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
        k~ = k / (E* L) of this level's springs (L the brush's side: indenter.region_size, by default
        grid.size).
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


#: How a fibril's ends are held for its Euler buckling law (`brushbem.physics.theory.BUCKLING_LENGTH_FACTORS`).
BUCKLING_ENDS = ("clamped-clamped", "clamped-pinned", "clamped-free")


class FibrilConfig(_Section):
    """The indenter's spring from the fibril that carries it: ``k = pi r^2 E_f / l`` (thesis sec. 6.3).

    Given instead of ``stiffness`` / ``stiffness_ratio`` (a brush: each pillar's
    spring; a punch or sphere: the one spring).  With ``buckling`` the spring
    also follows Euler's buckling law of the same geometry, carried as
    ``indenter.pillar_law``: slope k up to P_cr = pi^2 E_f (pi r^4 / 4) / (K l)^2,
    then ``post_buckling_factor`` k (`brushbem.physics.pillar_laws`).

    Attributes
    ----------
    youngs_modulus : float
        The fibril's Young's modulus E_f, in units of stress.
    length : float
        The fibril's length l, in units of length.
    radius : float or None
        The fibril's radius r, in units of length; default the pillar radius
        (a square or random brush) or the punch's radius.  Required for a
        sphere, a height map and a clustered brush.
    buckling : {"clamped-clamped", "clamped-pinned", "clamped-free"} or None
        How the ends are held (backing end first): K = 0.5, 0.699, 2.  None
        (default): no buckling, a linear spring.
    post_buckling_factor : float
        The post-buckled plateau's slope as a factor of k (> 0, the law must
        stay increasing); default 0.01.  Only with ``buckling``.
    """

    model_config = _MODEL_CONFIG

    youngs_modulus: float = Field(gt=0, allow_inf_nan=False)
    length: float = Field(gt=0, allow_inf_nan=False)
    radius: float | None = Field(None, gt=0, allow_inf_nan=False)
    buckling: Literal["clamped-clamped", "clamped-pinned", "clamped-free"] | None = None
    post_buckling_factor: float | None = Field(None, gt=0, le=1, allow_inf_nan=False)

    def _rule_problems(self) -> list[Problem]:
        if self.post_buckling_factor is not None and self.buckling is None:
            return [Problem("post_buckling_factor", _show(self.post_buckling_factor),
                            "only used with fibril.buckling; remove it")]
        return []

    def stiffness(self, radius: float) -> float:
        """k = pi r^2 E_f / l at the fibril radius ``radius`` (this table's own where given)."""
        from brushbem.physics.theory import fibril_stiffness

        return float(fibril_stiffness(self.length, self.radius or radius, youngs_modulus=self.youngs_modulus))

    def buckling_law(self, radius: float) -> dict[str, Any] | None:
        """The ``indenter.pillar_law`` table of the Euler buckling law, or None without ``buckling``."""
        if self.buckling is None:
            return None
        from brushbem.physics.theory import euler_buckling_force

        force = float(euler_buckling_force(self.length, self.radius or radius, youngs_modulus=self.youngs_modulus,
                                           ends=self.buckling))
        return {"forces": [force], "factors": [1.0, self.post_buckling_factor or 0.01]}
