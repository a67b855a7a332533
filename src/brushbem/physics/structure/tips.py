"""The pillars' lengths and tips: the concave length `Profile`, tip shapes (`Tip`), the base's `Tilt`, and
the grading of springs over the brush (`graded_stiffness`, `Grading`).

`_pillar_offsets` and `_brush_heights` are the steps of `brushbem.physics.structure.brush`
that turn them into every pillar's offset and every element's height.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from brushbem.physics.structure.errors import StructureError
from brushbem.physics.structure.grid import Grid

__all__ = ["GRADING_RULES", "TIP_SHAPES", "Grading", "Profile", "Tilt", "Tip", "graded_stiffness"]


@dataclass(frozen=True)
class Profile:
    """Concave macroscopic profile S_p = h~ S_c (thesis eq. 7.1-7.3).

    ``reference_stress`` is the uniform stress p_c that makes h~ dimensionless;
    None means one pillar's Kendall mean stress F_K / (pi r^2)
    (:func:`brushbem.physics.theory.concave_reference_stress`).
    """

    amplification: float
    reference_stress: float | None = None


TIP_SHAPES = ("flat", "spherical_cap", "concave", "profile")


@dataclass(frozen=True)
class Tip:
    """The shape of a pillar's tip: its height z(rho) above the tip's lowest point at the distance rho from the axis.

    Attributes
    ----------
    shape : {"flat", "spherical_cap", "concave", "profile"}
        ``flat``: z = 0 (the thesis's pillars).  ``spherical_cap``: z =
        rho^2 / (2 R), the cap of curvature radius R in the parabolic
        approximation of the sphere of ch. 2 (so one such pillar is the sphere
        on a spring).  ``concave``: z = depth (1 - rho^2 / r^2), a dish whose
        rim (rho = r, the pillar radius) touches first and whose centre lies
        ``depth`` higher.  ``profile``: z(rho) from ``profile``.
    radius : float, optional
        R of the spherical cap (> 0), in units of length.
    depth : float, optional
        Depth of the concave dish (> 0), in units of length.
    profile : callable or 1-D array, optional
        z(rho) as a vectorised function of rho (units of length), or its values
        at K >= 2 evenly spaced rho from 0 to the pillar radius (linear
        interpolation between them); finite, and >= 0 (the tip's lowest point
        is z = 0).
    """

    shape: str = "flat"
    radius: float | None = None
    depth: float | None = None
    profile: object = None

    def __post_init__(self):
        if self.shape not in TIP_SHAPES:
            raise StructureError("tip.shape", self.shape, f"must be one of {', '.join(map(repr, TIP_SHAPES))}")
        need = {"spherical_cap": "radius", "concave": "depth", "profile": "profile"}.get(self.shape)
        for key in ("radius", "depth", "profile"):
            given = getattr(self, key) is not None
            if key == need and not given:
                raise StructureError(f"tip.{key}", None, f"required when tip.shape = {self.shape!r}")
            if key != need and given:
                raise StructureError(f"tip.{key}", getattr(self, key),
                                     f"only used with tip.shape = {({'radius': 'spherical_cap', 'depth': 'concave'}).get(key, 'profile')!r}")
        for key in ("radius", "depth"):
            value = getattr(self, key)
            if value is not None and not (math.isfinite(value) and value > 0):
                raise StructureError(f"tip.{key}", value, "must be finite and > 0")
        if self.shape == "profile" and not callable(self.profile):
            values = np.asarray(self.profile, dtype=np.float64)
            if values.ndim != 1 or values.size < 2 or not np.all(np.isfinite(values)) or values.min() < 0:
                raise StructureError("tip.profile", f"{values.size} values",
                                     "must hold K >= 2 finite heights >= 0, at evenly spaced rho from 0 to the "
                                     "pillar radius")

    def heights(self, rho: np.ndarray, pillar_radius: float) -> np.ndarray:
        """z at the distances ``rho`` from the pillar's axis (units of length)."""
        rho = np.asarray(rho, dtype=np.float64)
        if self.shape == "flat":
            return np.zeros_like(rho)
        if self.shape == "spherical_cap":
            return rho**2 / (2.0 * self.radius)
        if self.shape == "concave":
            return self.depth * np.clip(1.0 - (rho / pillar_radius) ** 2, 0.0, 1.0)
        if callable(self.profile):
            z = np.broadcast_to(np.asarray(self.profile(rho), dtype=np.float64), rho.shape)
            if not np.all(np.isfinite(z)) or (z.size and z.min() < 0):
                raise StructureError("tip.profile", "function", "must return finite heights >= 0 on the footprint")
            return np.array(z)
        values = np.asarray(self.profile, dtype=np.float64)
        return np.interp(rho, np.linspace(0.0, pillar_radius, values.size), values)

    def describe(self) -> str:
        """The tip in one line, for the record."""
        if self.shape == "spherical_cap":
            return f"spherical_cap(radius={self.radius:g})"
        if self.shape == "concave":
            return f"concave(depth={self.depth:g})"
        if self.shape == "profile":
            return "profile(function)" if callable(self.profile) else f"profile({np.size(self.profile)} values)"
        return "flat"


@dataclass(frozen=True)
class Tilt:
    """A base tilted by ``angle`` (degrees, in [0, 45)) towards the in-plane direction ``azimuth`` (degrees).

    The base, and with it every pillar and tip face, is the rigid rotation of
    the untilted brush: the tip height grows by tan(angle) (x cos(azimuth) +
    y sin(azimuth)), so the pillars on the side the azimuth points to are the
    farthest from the surface (small slopes: the in-plane positions are kept).
    """

    angle: float = 0.0
    azimuth: float = 0.0

    def __post_init__(self):
        if not (math.isfinite(self.angle) and 0.0 <= self.angle < 45.0):
            raise StructureError("tilt.angle", self.angle,
                                 "must be in [0, 45) degrees (a half-space contact needs small slopes)")
        if not math.isfinite(self.azimuth):
            raise StructureError("tilt.azimuth", self.azimuth, "must be finite (degrees)")

    def heights(self, y: np.ndarray, x: np.ndarray) -> np.ndarray:
        """The tilt's height at the in-plane positions (y, x), in units of length."""
        a = math.radians(self.azimuth)
        return math.tan(math.radians(self.angle)) * (np.asarray(x) * math.cos(a) + np.asarray(y) * math.sin(a))


GRADING_RULES = ("radial", "linear")


def graded_stiffness(stiffness: float, centres: np.ndarray, *, rule: str, amplitude: float,
                     exponent: float = 1.0, azimuth: float = 0.0, key: str = "grading") -> np.ndarray:
    """Stiffness of every spring graded over the brush: k_n = k (1 + amplitude s_n^exponent).

    ``radial``: s_n = r_n / R, the distance of the spring's centre from the
    brush's centre over that of the outermost one (0 at the centre, 1 at the
    rim; amplitude < 0 makes the rim softer).  ``linear``: s_n = the centre's
    coordinate along the direction ``azimuth`` (degrees) over the largest
    such |coordinate| (-1 to 1; ``exponent`` must be 1).  Every k_n must stay
    > 0: amplitude > -1 (radial) or |amplitude| < 1 (linear), else a
    StructureError names ``key``.amplitude.
    """
    centres = np.asarray(centres, dtype=np.float64).reshape(-1, 2)
    if rule not in GRADING_RULES:
        raise StructureError(f"{key}.rule", rule, f"must be one of {', '.join(map(repr, GRADING_RULES))}")
    if not math.isfinite(amplitude):
        raise StructureError(f"{key}.amplitude", amplitude, "must be finite")
    if not (math.isfinite(exponent) and exponent > 0):
        raise StructureError(f"{key}.exponent", exponent, "must be finite and > 0")
    if rule == "radial":
        r = np.hypot(centres[:, 0], centres[:, 1])
        s = r / r.max() if r.max() > 0 else np.zeros_like(r)
        factor = 1.0 + amplitude * s**exponent
        if not amplitude > -1.0:
            raise StructureError(f"{key}.amplitude", amplitude,
                                 "must be > -1 with rule = 'radial' (the rim's stiffness k (1 + amplitude) must "
                                 "stay > 0)")
    else:
        if exponent != 1.0:
            raise StructureError(f"{key}.exponent", exponent, "only rule = 'radial' takes an exponent")
        a = math.radians(azimuth)
        t = centres[:, 1] * math.cos(a) + centres[:, 0] * math.sin(a)
        s = t / np.abs(t).max() if np.abs(t).max() > 0 else np.zeros_like(t)
        factor = 1.0 + amplitude * s
        if not abs(amplitude) < 1.0:
            raise StructureError(f"{key}.amplitude", amplitude,
                                 "must lie in (-1, 1) with rule = 'linear' (the stiffness k (1 +- amplitude) at "
                                 "both ends must stay > 0)")
    return float(stiffness) * factor


@dataclass(frozen=True)
class Grading:
    """A level's stiffness graded from spring to spring: a rule of `graded_stiffness`, or factors.

    ``rule`` is ``"radial"`` or ``"linear"`` (with ``amplitude``, ``exponent``,
    ``azimuth`` as in `graded_stiffness`) or ``"factors"``: k_n = k
    factors[n], one factor > 0 per spring of the level.
    """

    rule: str
    amplitude: float = 0.0
    exponent: float = 1.0
    azimuth: float = 0.0
    factors: np.ndarray | None = None

    def given(self) -> dict:
        """The grading's parameters as a configuration gives them (for messages)."""
        if self.rule == "factors":
            return {"rule": "file", "factors": f"{np.size(self.factors)} values"}
        keys = {"radial": ("amplitude", "exponent"), "linear": ("amplitude", "azimuth")}.get(self.rule, ())
        return {"rule": self.rule, **{k: getattr(self, k) for k in keys}}

    def apply(self, stiffness: float | np.ndarray, centres: np.ndarray, key: str) -> np.ndarray:
        """The stiffness of every spring whose centres are ``centres`` (StructureError names ``key``).

        A grading that can have no effect is refused: on a rigid level (k = inf, graded or not, stays
        inf), a rule on a level of one spring (a single pillar, a level of one cluster: nothing to grade
        it against), and a rule whose every factor is 1 although its amplitude is not 0 (every spring at
        s = 0, as centres on the line across a linear rule's direction, or an amplitude below rounding).
        """
        if np.all(np.isinf(np.asarray(stiffness, dtype=np.float64))):
            raise StructureError(key, self.given(),
                                 "grades a rigid level (stiffness = inf), which stays rigid whatever the factors: "
                                 "give the level a finite stiffness (or stiffness_ratio), or remove the grading")
        if self.rule != "factors" and len(centres) == 1 and self.amplitude != 0:
            raise StructureError(key, self.given(),
                                 "grades nothing: the level has one spring (a single pillar, or one cluster), which "
                                 f"rule = {self.rule!r} cannot grade against another; a grading needs two or more "
                                 "springs (or remove it; rule = 'file' scales a single spring)")
        if self.rule != "factors":
            graded = graded_stiffness(stiffness, centres, rule=self.rule, amplitude=self.amplitude,
                                      exponent=self.exponent, azimuth=self.azimuth, key=key)
            if self.amplitude != 0 and np.array_equal(graded, np.broadcast_to(stiffness, graded.shape)):
                if abs(self.amplitude) < np.finfo(np.float64).eps:
                    why = f"|amplitude| = {abs(self.amplitude):g} is below the rounding of 1 (2.2e-16)"
                else:
                    why = f"all {len(centres)} springs lie at s = 0 of rule = {self.rule!r}"
                raise StructureError(key, self.given(),
                                     f"grades nothing: {why}, so every factor 1 + amplitude s^exponent is exactly "
                                     "1; a grading needs two or more springs at different s and |amplitude| >= "
                                     "2.2e-16 (or remove it)")
            return graded
        factors = np.asarray(self.factors, dtype=np.float64).ravel()
        if factors.shape != (len(centres),):
            raise StructureError(f"{key}.file", f"{factors.size} values",
                                 f"holds {factors.size} values; must hold one stiffness factor per spring "
                                 f"({len(centres)}), each > 0")
        if not np.all(np.isfinite(factors) & (factors > 0)):
            raise StructureError(f"{key}.file", float(np.min(factors)), "every factor must be finite and > 0")
        return float(stiffness) * factors if np.ndim(stiffness) == 0 else np.asarray(stiffness) * factors


def _pillar_offsets(centres: np.ndarray, pillar_radius: float, roughness: float, roughness_seed: np.random.SeedSequence,
                    profile: Profile | None, lengths: np.ndarray | None, contact_modulus: float,
                    work_of_adhesion: float) -> tuple[np.ndarray, float | None, float | None]:
    """The brush step "lengths": every pillar's offset g_n = max(length) - length_n, and the profile's p_c and R.

    The pillar length is roughness + concave profile + explicit lengths (see `brushbem.physics.structure.brush`);
    the reference stress and radius are None without a profile.
    """
    n_pillars = len(centres)
    # Pillar lengths: roughness + concave profile + explicit lengths.
    length = np.zeros(n_pillars)
    if roughness < 0 or not math.isfinite(roughness):
        raise StructureError("roughness.sigma", roughness, "must be finite and >= 0")
    if roughness > 0:
        length += roughness * np.random.default_rng(roughness_seed).standard_normal(n_pillars)
    radial = np.hypot(centres[:, 0], centres[:, 1])
    reference_stress = None
    profile_radius = None
    if profile is not None and profile.amplification > 0:
        from brushbem.physics import theory

        reference_stress = profile.reference_stress
        if reference_stress is None:
            if not work_of_adhesion > 0:
                raise StructureError(
                    "profile.amplification", profile.amplification,
                    "the default reference stress needs brush(work_of_adhesion=...) > 0 "
                    "(or give profile.reference_stress)",
                )
            reference_stress = float(theory.concave_reference_stress(
                pillar_radius, contact_modulus=contact_modulus, work_of_adhesion=work_of_adhesion))
        profile_radius = float(radial.max()) if radial.max() > 0 else float(pillar_radius)
        length -= np.asarray(theory.concave_offsets(
            radial, profile_radius, profile.amplification, reference_stress, contact_modulus=contact_modulus))
    if lengths is not None:
        lengths = np.asarray(lengths, dtype=float).ravel()
        if lengths.shape != (n_pillars,) or not np.all(np.isfinite(lengths)):
            raise StructureError("lengths_file", f"{lengths.shape[0]} values",
                                 f"holds {lengths.shape[0]} values; must hold {n_pillars} finite pillar lengths "
                                 "(one per pillar)")
        length += lengths
    offsets = length.max() - length
    return offsets, reference_stress, profile_radius


def _brush_heights(grid: Grid, labels: np.ndarray, centres: np.ndarray, pillar_radius: float, offsets: np.ndarray,
                   tip: Tip | Sequence[Tip] | None, tilt: Tilt | None) -> tuple[np.ndarray, np.ndarray, str]:
    """The brush step "tips": every element's height, the pillars' offsets with the tilt, and the tip for the record.

    Where the tilt puts an element below the lowest pillar's tip, every height
    (and offset) is shifted so the lowest is 0.
    """
    height = np.where(labels >= 0, offsets[np.maximum(labels, 0)], np.inf)
    tip_record = "flat"
    if tip is not None or tilt is not None:
        height, tip_record = _tip_heights(grid, labels, centres, pillar_radius, height, tip, tilt)
        if tilt is not None:
            offsets = offsets + tilt.heights(centres[:, 0], centres[:, 1])
            lowest = float(height[labels >= 0].min())
            if lowest < 0:
                height = np.where(labels >= 0, height - lowest, np.inf)
            offsets = offsets - min(lowest, 0.0)
    return height, offsets, tip_record


def _tip_heights(grid: Grid, labels: np.ndarray, centres: np.ndarray, pillar_radius: float, height: np.ndarray,
                 tip: Tip | Sequence[Tip] | None, tilt: Tilt | None) -> tuple[np.ndarray, str]:
    """The element heights with every pillar's tip shape and the base's tilt added; and the tip for the record."""
    rows, cols = np.nonzero(labels >= 0)
    owner = labels[rows, cols]
    x = grid.centres()
    y_el, x_el = x[rows], x[cols]
    rho = np.hypot(y_el - centres[owner, 0], x_el - centres[owner, 1])
    extra = np.zeros(rows.size)
    record = "flat"
    if isinstance(tip, Tip):
        extra += tip.heights(rho, pillar_radius)
        record = tip.describe()
    elif tip is not None:
        tips = list(tip)
        if len(tips) != len(centres) or not all(isinstance(t, Tip) for t in tips):
            raise StructureError("tip", f"{len(tips)} values",
                                 f"holds {len(tips)} values; must hold one per pillar ({len(centres)})")
        order = np.argsort(owner, kind="stable")
        bounds = np.searchsorted(owner[order], np.arange(len(centres) + 1))
        for n, t in enumerate(tips):
            if t.shape != "flat":
                where = order[bounds[n]:bounds[n + 1]]
                extra[where] += t.heights(rho[where], pillar_radius)
        shapes = {t.describe() for t in tips}
        record = shapes.pop() if len(shapes) == 1 else "per pillar"
    if tilt is not None:
        extra += tilt.heights(y_el, x_el)
    out = height.copy()
    out[rows, cols] += extra
    return out, record
