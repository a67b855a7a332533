"""Indenters rasterised on the grid: footprints, tip heights, pillars and springs.

An indenter is a set of rigid pillars n = 0..M-1 held by springs to a rigid
base.  On the grid it is described by

* ``height[i, j]``: the height of the tip surface above its lowest point when
  the base is at d = 0 (tip profile z plus the pillar's length offset g);
  ``inf`` where there is no material (outside every footprint).  An element
  penetrates the half-space when ``d - height - (spring deflection) - u > 0``.
* ``pillar[i, j]``: the index of the pillar an element belongs to, -1 outside.
* ``levels``: the springs, bottom-up.  Level l has a stiffness k_l (inf: rigid)
  and a map ``cluster[n]`` from pillars to the clusters of that level (level 0:
  every pillar its own cluster).

A compact punch or a sphere is a structure with one pillar.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from .records import MappingRecord

__all__ = [
    "BrushGeometry",
    "ClusteredLattice",
    "Geometry",
    "Grading",
    "Grid",
    "HeightMapGeometry",
    "Indenter",
    "Level",
    "Profile",
    "PunchGeometry",
    "SphereGeometry",
    "SpringLevel",
    "StructureError",
    "Tilt",
    "Tip",
    "brush",
    "clustered_filling_factors",
    "clustered_lattice",
    "flat_punch",
    "graded_stiffness",
    "height_map",
    "hierarchy_clusters",
    "random_positions",
    "rasterise_pillars",
    "sphere",
    "square_lattice",
]


@dataclass(frozen=True)
class Grid:
    """Square domain L x L of N x N square elements, centred on the origin.

    Parameters
    ----------
    size : float
        Side L of the domain, in units of length.
    elements : int
        N, elements per side.
    """

    size: float
    elements: int

    def __post_init__(self):
        if not (math.isfinite(self.size) and self.size > 0):
            raise ValueError(f"grid.size = {self.size} must be finite and > 0")
        if int(self.elements) != self.elements or self.elements < 2:
            raise ValueError(f"grid.elements = {self.elements} must be an integer >= 2")

    @property
    def element_size(self) -> float:
        """h = L / N, in units of length."""
        return self.size / self.elements

    def centres(self) -> np.ndarray:
        """Coordinates of the element centres along one axis, shape (N,)."""
        return (np.arange(self.elements) + 0.5) * self.element_size - 0.5 * self.size

    def radius_squared(self) -> np.ndarray:
        """Squared distance of every element centre from the domain centre, shape (N, N)."""
        x = self.centres()
        return x[:, None] ** 2 + x[None, :] ** 2


@dataclass(frozen=True)
class SpringLevel:
    """One level of springs.

    Attributes
    ----------
    stiffness : float or ndarray of float, shape (n_clusters,)
        k_l of every spring of the level (one number), or of each cluster's
        spring (graded or per-pillar stiffness), in units of force / length;
        inf = rigid.  A level is rigid or elastic as a whole: an array mixing
        inf and finite values is refused.
    cluster : ndarray of int, shape (M,)
        Cluster of the level that each pillar belongs to, in [0, n_clusters).
    """

    stiffness: float | np.ndarray
    cluster: np.ndarray

    def __post_init__(self):
        if np.ndim(self.stiffness) == 0:
            return
        values = np.asarray(self.stiffness, dtype=np.float64)
        if values.shape != (self.n_clusters,):
            raise ValueError(
                f"stiffness holds {values.size} values; a level of {self.n_clusters} clusters needs one per cluster"
            )
        if not np.all(values > 0):
            raise ValueError(f"stiffness = {float(values.min())} must be > 0 (inf = rigid) for every cluster")
        infinite = np.isinf(values)
        if infinite.any() and not infinite.all():
            raise ValueError("stiffness mixes inf (rigid) and finite values within one level")
        object.__setattr__(self, "stiffness", values)

    @property
    def n_clusters(self) -> int:
        return int(self.cluster.max()) + 1 if self.cluster.size else 0

    @property
    def stiffnesses(self) -> np.ndarray:
        """k of every cluster's spring, shape (n_clusters,)."""
        return np.broadcast_to(np.asarray(self.stiffness, dtype=np.float64), (self.n_clusters,))

    @property
    def uniform(self) -> bool:
        """Whether every spring of the level has the same stiffness."""
        values = self.stiffnesses
        return bool(values.size == 0 or np.all(values == values[0]))

    @property
    def softest(self) -> float:
        """The smallest stiffness of the level (the largest stretch per unit force)."""
        return float(np.min(self.stiffnesses)) if self.n_clusters else math.inf

    @property
    def rigid(self) -> bool:
        return bool(np.all(np.isinf(self.stiffnesses)))


@dataclass(frozen=True, kw_only=True)
class Geometry(MappingRecord):
    """What an indenter is, for the record: its shape and the parameters it was built from.

    The records below read as attributes (``indenter.description.radius``) and
    as the mapping of their fields (``indenter.description["radius"]``).  An
    indenter built from arrays alone has ``shape = "custom"``.
    """

    shape: str = "custom"


@dataclass(frozen=True, kw_only=True)
class PunchGeometry(Geometry):
    """A flat-ended cylindrical punch: nominal radius and the area of its rasterised footprint."""

    shape: str = "flat_punch"
    radius: float
    rasterised_area: float


@dataclass(frozen=True, kw_only=True)
class SphereGeometry(Geometry):
    """A paraboloid tip of curvature radius ``radius``."""

    shape: str = "sphere"
    radius: float


@dataclass(frozen=True, kw_only=True)
class HeightMapGeometry(Geometry):
    """Tip heights read from an array."""

    shape: str = "height_map"


@dataclass(frozen=True, kw_only=True)
class BrushGeometry(Geometry):
    """A brush: layout, region, the pillars as rasterised, roughness and length profile.

    Attributes
    ----------
    layout, region : str
        ``square`` / ``random`` / ``clustered`` placement in a ``square`` /
        ``circle`` region.
    region_size : float
        Side (square) or diameter (circle) of the placement region.
    n_pillars : int
    pillar_radius : float
        Nominal radius of every pillar.
    apparent_area, real_area : float
        Area of the region A0 and of the rasterised footprints A.
    filling_factor, nominal_filling_factor : float
        A / A0, and the same with the nominal circles.
    pillar_elements : ndarray of int, shape (n_pillars,)
        Elements of every pillar's footprint.
    centres : ndarray, shape (n_pillars, 2)
        Pillar centres (y, x).
    offsets : ndarray, shape (n_pillars,)
        Tip height of every pillar (roughness plus length profile).
    roughness : float
        Standard deviation of the Gaussian tip heights.
    seed : int
    profile_amplification : float
        The length profile's amplification h~ (0 without a profile).
    profile_reference_stress, profile_radius : float or None
        The profile's p_c of eq. 7.2 and its radius R (None without a profile).
    level_clusters : list of ndarray
        Per hierarchy level above the pillars, the cluster of every pillar.
    tip : str
        The tip shape (`Tip.describe`), or ``"per pillar"``.
    tilt_angle, tilt_azimuth : float
        The base's tilt, degrees (`Tilt`).
    graded : bool
        Whether some level's springs differ from pillar to pillar.
    nominal_level_filling_factors, level_filling_factors : tuple of float
        ``layout = "clustered"`` only (else empty): the filling factor of every
        level, bottom-up (phi1, phi2, ...; eq. 6.22), as configured and as
        rasterised (`clustered_filling_factors`: phi1 from the sub-pillars'
        elements, the higher levels' exact squares; the product is
        ``filling_factor``).
    cluster_sides : tuple of float
        ``layout = "clustered"`` only: the side 2 r_l of the square clusters
        of every level above the pillars, bottom-up.
    """

    shape: str = "brush"
    layout: str
    region: str
    region_size: float
    n_pillars: int
    pillar_radius: float
    apparent_area: float
    real_area: float
    filling_factor: float
    nominal_filling_factor: float
    pillar_elements: np.ndarray
    centres: np.ndarray
    offsets: np.ndarray
    roughness: float
    seed: int
    profile_amplification: float
    profile_reference_stress: float | None
    profile_radius: float | None
    level_clusters: list
    tip: str = "flat"
    tilt_angle: float = 0.0
    tilt_azimuth: float = 0.0
    graded: bool = False
    nominal_level_filling_factors: tuple[float, ...] = ()
    level_filling_factors: tuple[float, ...] = ()
    cluster_sides: tuple[float, ...] = ()
    contact_modulus: float | None = None
    work_of_adhesion: float | None = None


@dataclass(frozen=True)
class Indenter:
    """A rasterised indenter (see the module docstring).

    Attributes
    ----------
    height : ndarray, shape (N, N)
        Tip height above the lowest tip point at d = 0, in units of length;
        inf outside the footprints.
    pillar : ndarray of int, shape (N, N)
        Pillar index of every element, -1 outside the footprints.
    levels : tuple of SpringLevel
        Springs, bottom-up (empty or all rigid: a rigid indenter).
    description : Geometry
        What the indenter is, for the record (`PunchGeometry`,
        `SphereGeometry`, `HeightMapGeometry`, `BrushGeometry`).
    viscoelastic : brushbem.viscoelastic.Viscoelastic or None
        The rheology of the pillars' own connections (level 1), whose
        ``stiffness`` is then the relaxed one; None: elastic springs.
    pillar_law : brushbem.pillar_laws.PiecewiseLinear or None
        A nonlinear force-compression law of the pillars' own connections
        (slopes as factors of ``stiffness``); None: linear springs.
    """

    height: np.ndarray
    pillar: np.ndarray
    levels: tuple[SpringLevel, ...] = ()
    description: Geometry = field(default_factory=Geometry)
    viscoelastic: object = None
    pillar_law: object = None

    def __post_init__(self):
        if self.height.shape != self.pillar.shape or self.height.ndim != 2:
            raise ValueError("height and pillar must be 2-D arrays of the same shape")
        footprint = np.isfinite(self.height)
        if not np.array_equal(footprint, self.pillar >= 0):
            raise ValueError("pillar labels must cover exactly the finite heights")
        if not footprint.any():
            raise ValueError("the indenter has no element on the grid")
        for level in self.levels:
            if level.cluster.shape != (self.n_pillars,):
                raise ValueError("every spring level needs one cluster index per pillar")
            if not np.all(level.stiffnesses > 0):
                raise ValueError(f"stiffness = {level.softest} must be > 0 (inf = rigid)")
        if self.pillar_law is not None and (not self.levels or self.levels[0].rigid):
            raise ValueError("a nonlinear pillar law needs a finite pillar stiffness (indenter.stiffness or "
                             "stiffness_ratio): its slopes are factors of it")
        if self.viscoelastic is not None and (not self.levels or self.levels[0].rigid):
            raise ValueError(
                "viscoelastic pillars need a finite pillar stiffness (indenter.stiffness or stiffness_ratio): it is "
                "their relaxed stiffness"
            )

    @property
    def footprint(self) -> np.ndarray:
        """Elements that belong to some pillar, bool (N, N)."""
        return self.pillar >= 0

    @property
    def n_pillars(self) -> int:
        return int(self.pillar.max()) + 1

    @property
    def lowest_height(self) -> float:
        """Height of the lowest element: the base displacement at which the tip first touches."""
        return float(np.min(self.height[self.footprint]))

    @property
    def elastic_levels(self) -> tuple[SpringLevel, ...]:
        """The levels with finite stiffness (the rigid ones add nothing to the operator)."""
        return tuple(level for level in self.levels if not level.rigid)

    def element_clusters(self, level: SpringLevel) -> np.ndarray:
        """Cluster index of every element for ``level``, -1 outside the footprints."""
        return np.where(self.pillar >= 0, level.cluster[np.maximum(self.pillar, 0)], -1)


def _single_spring(stiffness: float) -> tuple[SpringLevel, ...]:
    if math.isinf(stiffness):
        return ()
    if not (stiffness > 0 and math.isfinite(stiffness)):
        raise ValueError(f"indenter.stiffness = {stiffness} must be > 0 (inf = rigid)")
    return (SpringLevel(stiffness=float(stiffness), cluster=np.zeros(1, dtype=np.int64)),)


def flat_punch(grid: Grid, radius: float, stiffness: float = math.inf) -> Indenter:
    """Flat-ended cylindrical punch of ``radius`` centred on the domain.

    The footprint is the set of elements whose centre lies inside the circle.
    """
    h = grid.element_size
    if not (math.isfinite(radius) and radius >= 2 * h):
        raise ValueError(f"indenter.radius = {radius} must be >= 2 elements (2h = {2 * h})")
    if 2 * radius > grid.size:
        raise ValueError(f"indenter.radius = {radius} is larger than the domain (L/2 = {grid.size / 2})")
    inside = grid.radius_squared() <= radius**2
    height = np.where(inside, 0.0, np.inf)
    pillar = np.where(inside, 0, -1)
    area = inside.sum() * h * h
    return Indenter(
        height=height,
        pillar=pillar,
        levels=_single_spring(stiffness),
        description=PunchGeometry(radius=radius, rasterised_area=float(area)),
    )


def sphere(grid: Grid, radius: float, stiffness: float = math.inf) -> Indenter:
    """Paraboloid tip r^2 / (2R) of curvature radius ``radius``, centred on the domain."""
    if not (math.isfinite(radius) and radius > 0):
        raise ValueError(f"indenter.radius = {radius} must be finite and > 0")
    height = grid.radius_squared() / (2.0 * radius)
    pillar = np.zeros(height.shape, dtype=np.int64)
    return Indenter(
        height=height,
        pillar=pillar,
        levels=_single_spring(stiffness),
        description=SphereGeometry(radius=radius),
    )


def height_map(grid: Grid, heights: np.ndarray, stiffness: float = math.inf) -> Indenter:
    """Arbitrary tip heights (N x N, units of length) on one spring; shifted so min = 0."""
    heights = np.asarray(heights, dtype=np.float64)
    if heights.shape != (grid.elements, grid.elements):
        raise ValueError(f"indenter.file holds shape {heights.shape}, expected {(grid.elements, grid.elements)}")
    if not np.all(np.isfinite(heights)):
        raise ValueError("indenter.file holds non-finite heights")
    height = heights - heights.min()
    pillar = np.zeros(height.shape, dtype=np.int64)
    return Indenter(
        height=height,
        pillar=pillar,
        levels=_single_spring(stiffness),
        description=HeightMapGeometry(),
    )


# -- brushes ---------------------------------------------------------------------

# A pillar narrower than this (in elements, radius) is a handful of elements
# whose rasterised area and edge stress no longer approximate a cylinder; the
# same bound as for the compact punch.
MIN_PILLAR_RADIUS_ELEMENTS = 2.0


class StructureError(ValueError):
    """A structure that cannot be built as asked: names the key, the value and what is allowed."""

    def __init__(self, key: str, value: object, allowed: str):
        self.key = key
        self.value = value
        self.allowed = allowed
        super().__init__(f"indenter.{key} = {value!r}: {allowed}")


@dataclass(frozen=True)
class Level:
    """One hierarchy level above the pillars: ``cluster`` x ``cluster`` units of the level below.

    ``stiffness``: k of every spring of the level, or an array of one per
    cluster (in the order of `hierarchy_clusters`: row-major over the
    clusters' lattice).
    """

    cluster: int
    stiffness: float | np.ndarray
    grading: Grading | None = None


@dataclass(frozen=True)
class Profile:
    """Concave macroscopic profile S_p = h~ S_c (thesis eq. 7.1-7.3).

    ``reference_stress`` is the uniform stress p_c that makes h~ dimensionless;
    None means one pillar's Kendall mean stress F_K / (pi r^2)
    (:func:`brushbem.theory.concave_reference_stress`).
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


def square_lattice(pillars_per_side: int, spacing: float) -> tuple[np.ndarray, np.ndarray]:
    """Centres of an n x n square lattice centred on the origin, and the lattice indices.

    Returns ``(centres (n*n, 2), index (n*n, 2))`` with rows y, x in lattice order.
    """
    n = int(pillars_per_side)
    offsets = (np.arange(n) - 0.5 * (n - 1)) * spacing
    iy, ix = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    index = np.stack([iy.ravel(), ix.ravel()], axis=1)
    centres = np.stack([offsets[index[:, 0]], offsets[index[:, 1]]], axis=1)
    return centres, index


@dataclass(frozen=True)
class ClusteredLattice:
    """Sub-pillars on square lattices inside square clusters (thesis Fig. 6-3): see `clustered_lattice`.

    Attributes
    ----------
    centres : ndarray, shape (M, 2)
        Sub-pillar centres (y, x), in lattice order (rows, then columns of the
        ``pillars_per_side`` x ``pillars_per_side`` lattice), as `square_lattice`.
    index : ndarray of int, shape (M, 2)
        The (row, column) of every sub-pillar on that lattice: `hierarchy_clusters`
        groups them into the clusters below.
    pillar_radius : float
        r1, derived from the filling factors.
    filling_factors : tuple of float
        The nominal phi1, phi2, ..., bottom-up (eq. 6.22).
    sides : tuple of float
        Side 2 r_l of the square clusters of every level above the pillars, bottom-up.
    pitches : tuple of float
        The sub-pillars' pitch 2 r1 + 2 w inside a level-2 cluster, then the pitch
        of every level's clusters inside the next level's (the top level's: in the
        region), bottom-up.
    square_centres : tuple of ndarray, shape (n_l, 2)
        Centres (y, x) of every level's clusters, in the order of the cluster
        indices of `hierarchy_clusters` (row-major over that level's clusters).
    region_size : float
        Side of the square region the top-level clusters tile.
    """

    centres: np.ndarray
    index: np.ndarray
    pillar_radius: float
    filling_factors: tuple[float, ...]
    sides: tuple[float, ...]
    pitches: tuple[float, ...]
    square_centres: tuple[np.ndarray, ...]
    region_size: float

    @property
    def gaps(self) -> tuple[float, ...]:
        """2 w between adjacent sub-pillars, then 2 D between adjacent clusters of every level, bottom-up."""
        return (self.pitches[0] - 2.0 * self.pillar_radius,
                *(pitch - side for pitch, side in zip(self.pitches[1:], self.sides)))


def clustered_lattice(pillars_per_side: int, clusters: Sequence[int], filling_factors: Sequence[float],
                      region_size: float) -> ClusteredLattice:
    """Sub-pillars regularly distributed inside square clusters of clusters (thesis Fig. 6-3, eq. 6.22).

    ``clusters[l]`` x ``clusters[l]`` units of level l+1 form one square cluster
    of level l+2 (level 1: the sub-pillars), as in `hierarchy_clusters`.  The
    top level's clusters, ``pillars_per_side / prod(clusters)`` per side, are
    squares centred in the cells of a regular lattice that tiles the square
    region (side ``region_size``, centred on the origin); every cluster holds
    the units of the level below centred in the cells of a regular lattice of
    its own square.  ``filling_factors`` holds one value per level, bottom-up:

    * phi1 = pi r1^2 n^2 / (2 r2)^2: the sub-pillars' cross-sections in a
      level-2 cluster over its square, n sub-pillars per side, so the
      sub-pillar pitch is 2 r2 / n = 2 r1 + 2 w and r1 = pitch sqrt(phi1 / pi);
    * phi_l (1 < l < top) = m^2 (2 r_l)^2 / (2 r_(l+1))^2: the level-l squares in a
      level-(l+1) square, m per side, so the gap between adjacent level-l
      clusters is 2 D_l = pitch - 2 r_l = pitch (1 - sqrt(phi_l));
    * the last: the top level's squares over the region's area.

    The product is the brush's filling factor (eq. 6.22), and r1 =
    (region_size / pillars_per_side) sqrt(phi1 phi2 ... / pi): the radius of
    the uniform lattice of the same count and filling factor.

    Raises StructureError (naming ``levels``, ``filling_factors`` or
    ``pillars_per_side``) for no level above the pillars, a count of filling
    factors that is not one per level, a filling factor outside (0, 1),
    sub-pillars that would overlap or touch (phi1 >= pi / 4, 2 r1 >= pitch), or
    a ``pillars_per_side`` that the product of the cluster sizes does not
    divide.

    Notes
    -----
    Fig. 6-3's caption assumes gaps at least the pillars' size, r1 <= w and
    r2 <= D.  On a square lattice of clusters phi2 = (2 r2)^2 / (2 r2 + 2 D)^2
    = (r2 / (r2 + D))^2, so r2 <= D needs phi2 <= 1/4: the thesis's phi2 =
    phi3 = 0.45 (sec. 6.2) give D = r2 (1 / sqrt(0.45) - 1) = 0.49 r2 (and
    D3 = 0.49 r3), so the caption's assumption cannot hold with its own
    parameters.  The sub-pillars do satisfy r1 <= w, which needs phi1 =
    pi r1^2 / (2 r1 + 2 w)^2 <= pi / 16 = 0.196: phi1 = 0.12 gives w = 1.56 r1.
    The segment sums (``solver.coupling = "segments"``) need no such gap; the
    discriminant matrix needs a box that covers a cluster's footprint (about
    2 r2 - 2 w) and reaches no other (about 2 D + 2 w away), which the
    thesis's brush misses (`brushbem.operator.discriminant_half_width`
    refuses it).
    """
    factors = tuple(float(f) for f in filling_factors)
    sizes = tuple(int(c) for c in clusters)
    if not sizes:
        raise StructureError("levels", [], "layout = 'clustered' needs at least one level above the pillars")
    if len(factors) != len(sizes) + 1:
        raise StructureError(
            "filling_factors", list(factors),
            f"must hold {len(sizes) + 1} values, one per level bottom-up (the sub-pillars in a level-2 cluster, "
            f"then each level's clusters in the next level's, the top level's in the region) for "
            f"{len(sizes)} level(s) above the pillars",
        )
    for level, phi in enumerate(factors, start=1):
        if not (math.isfinite(phi) and 0.0 < phi < 1.0):
            raise StructureError("filling_factors", list(factors),
                                 f"phi{level} = {phi:g} must lie in (0, 1) (a cluster's content over its area)")
    if not factors[0] < math.pi / 4.0:
        raise StructureError(
            "filling_factors", list(factors),
            f"phi1 = {factors[0]:g}: the sub-pillars overlap or touch (2 r1 >= the pitch 2 r1 + 2 w); a square "
            f"lattice of disks needs phi1 < pi / 4 = {math.pi / 4:.4f}",
        )
    n = int(pillars_per_side)
    blocks = np.cumprod(sizes)  # sub-pillars per side of a cluster of level 2, 3, ...
    if n < 1 or n % int(blocks[-1]):
        raise StructureError(
            "pillars_per_side", pillars_per_side,
            f"must be a positive multiple of {int(blocks[-1])}, "
            + (f"the product of the cluster sizes {' x '.join(map(str, sizes))}" if len(sizes) > 1
               else "the cluster size")
            + " (the clusters tile the lattice)",
        )
    if not (math.isfinite(region_size) and region_size > 0):
        raise StructureError("region_size", region_size, "must be finite and > 0")
    i = np.arange(n)
    # Along one axis, top down: the centre of the square holding sub-pillar i at every level.
    pitch = region_size / (n // int(blocks[-1]))
    side = pitch * math.sqrt(factors[-1])
    centre = -0.5 * region_size + (i // blocks[-1] + 0.5) * pitch
    sides, pitches, axis_centres = [side], [pitch], [centre]
    for level in range(len(sizes) - 1, 0, -1):  # clusters of level level+1 inside those of level level+2
        pitch = side / sizes[level]
        centre = centre - 0.5 * side + ((i // blocks[level - 1]) % sizes[level] + 0.5) * pitch
        side = pitch * math.sqrt(factors[level])
        sides.insert(0, side)
        pitches.insert(0, pitch)
        axis_centres.insert(0, centre)
    pitch = side / sizes[0]
    axis = centre - 0.5 * side + (i % sizes[0] + 0.5) * pitch
    pitches.insert(0, pitch)
    _, index = square_lattice(n, 1.0)
    squares = []
    for block, along in zip(blocks, axis_centres):
        first = along[:: int(block)]  # the centre of each cluster of the level along the axis
        squares.append(np.stack(np.meshgrid(first, first, indexing="ij"), axis=-1).reshape(-1, 2))
    return ClusteredLattice(
        centres=np.stack([axis[index[:, 0]], axis[index[:, 1]]], axis=1),
        index=index,
        pillar_radius=float(pitch * math.sqrt(factors[0] / math.pi)),
        filling_factors=factors,
        sides=tuple(float(s) for s in sides),
        pitches=tuple(float(p) for p in pitches),
        square_centres=tuple(squares),
        region_size=float(region_size),
    )


# Densest packing of equal disks in the plane, pi / (2 sqrt 3): no layout of
# disks in a container covers a larger fraction of it (Groemer, Oler), so a
# random layout asking for more is refused before any draw.
HEXAGONAL_PACKING_DENSITY = math.pi / (2.0 * math.sqrt(3.0))

# Most candidate positions drawn for one random layout, whatever the count:
# random sequential addition slows down without bound near its jamming limit
# (a covered fraction of about 0.547); beyond this many draws the layout is
# refused instead of searched for minutes.
MAX_RANDOM_DRAWS = 20_000_000


def random_positions(
    count: int, radius: float, min_gap: float, region: str, region_size: float, rng: np.random.Generator,
    max_attempts_per_pillar: int = 2000,
) -> np.ndarray:
    """Non-overlapping pillar centres by random sequential addition (seeded).

    Every pillar lies wholly inside the region (a square of side
    ``region_size`` or a circle of that diameter, centred on the origin) and
    every two centres are at least ``D = 2 radius + min_gap`` apart.
    Candidates are drawn uniformly in batches of 256 and accepted in order if
    they keep that distance from every centre accepted before.

    Raises StructureError, naming the key, before any draw if the disks of
    diameter D cannot fit in the region even in the densest (hexagonal)
    packing, and after ``min(max_attempts_per_pillar * count,
    MAX_RANDOM_DRAWS)`` draws if the layout is still incomplete (the jamming
    limit of random sequential addition is a covered fraction of about 0.55,
    far above the thesis's filling factor 0.12).  The conflicts of a
    candidate are looked up in a background grid of cells of side D / sqrt 2
    (at most one centre each), so a layout of M pillars costs O(M) work.
    """
    half = 0.5 * region_size - radius
    if half <= 0:
        raise StructureError("pillar_radius", radius, f"must be smaller than half the region ({0.5 * region_size:g})")
    spacing = 2.0 * radius + min_gap
    # Disks of diameter D around the centres lie in the region grown by D / 2.
    if region == "circle":
        container = math.pi * (half + 0.5 * spacing) ** 2
    else:
        container = (2.0 * half + spacing) ** 2
    covered = count * math.pi * spacing**2 / 4.0
    if covered > HEXAGONAL_PACKING_DENSITY * container:
        raise StructureError(
            "pillar_count", count,
            f"{count} pillars of pillar_radius = {radius:g} at min_gap = {min_gap:g} cannot fit in the "
            f"{region} region of region_size = {region_size:g} (they would cover {covered / container:.3g} of "
            f"it; no layout exceeds {HEXAGONAL_PACKING_DENSITY:.3f} and a random one stops near 0.55): "
            "reduce pillar_count, pillar_radius or min_gap, or enlarge region_size",
        )
    cell = spacing / math.sqrt(2.0)
    cells = math.floor(2.0 * half / cell) + 1
    if cells > 4096:
        raise StructureError(
            "pillar_radius", radius,
            f"too small for the region (region_size = {region_size:g}): more than 4096 pillar spacings per side",
        )
    pad = 2  # a centre closer than D lies at most 2 cells away
    width = cells + 2 * pad
    # Coordinates of the centre in each cell (nan: empty), flat, row-major.
    cell_y = np.full(width * width, np.nan)
    cell_x = np.full(width * width, np.nan)
    around = (np.arange(-pad, pad + 1)[:, None] * width + np.arange(-pad, pad + 1)[None, :]).ravel()
    distance2 = spacing**2
    placed = np.empty((count, 2))
    n = 0
    drawn = 0
    budget = min(max_attempts_per_pillar * count, MAX_RANDOM_DRAWS)
    while n < count:
        if drawn >= budget:
            raise StructureError(
                "pillar_count", count,
                f"only {n} pillars of pillar_radius = {radius:g} at min_gap = {min_gap:g} fit at random in the "
                f"{region} region (region_size = {region_size:g}) after {drawn} draws; reduce pillar_count, "
                "pillar_radius or min_gap, or enlarge region_size",
            )
        batch = rng.uniform(-half, half, size=(256, 2))
        drawn += len(batch)
        if region == "circle":
            batch = batch[np.einsum("ij,ij->i", batch, batch) <= half * half]
        index = np.minimum(((batch + half) / cell).astype(np.int64), cells - 1) + pad
        flat = index[:, 0] * width + index[:, 1]
        # Conflicts with the centres accepted before this batch, all candidates at once
        # (an empty cell's nan compares false).
        near = flat[:, None] + around[None, :]
        dy = cell_y[near] - batch[:, 0, None]
        dx = cell_x[near] - batch[:, 1, None]
        free = np.flatnonzero(~np.any(dy * dy + dx * dx < distance2, axis=1))
        # Among the free candidates, in order: accepted unless too close to one
        # accepted before; only those close to an earlier free one need the loop.
        close = np.tril(np.sum((batch[free, None, :] - batch[None, free, :]) ** 2, axis=2) < distance2, -1)
        accepted = ~close.any(axis=1)
        for j in np.flatnonzero(~accepted):
            accepted[j] = not np.any(close[j] & accepted)
        take = free[accepted][: count - n]
        placed[n:n + len(take)] = batch[take]
        cell_y[flat[take]] = batch[take, 0]
        cell_x[flat[take]] = batch[take, 1]
        n += len(take)
    return placed


def rasterise_pillars(grid: Grid, centres: np.ndarray, radius: float) -> np.ndarray:
    """Label every element whose centre lies inside a pillar's circle (-1 elsewhere).

    Raises StructureError if a pillar is under ``MIN_PILLAR_RADIUS_ELEMENTS`` in
    radius, reaches outside the domain, or shares an element with another.
    """
    h = grid.element_size
    _check_pillar_radius(grid, radius)
    half = 0.5 * grid.size
    if np.any(np.abs(centres) + radius > half * (1 + 1e-12)):
        raise StructureError("pillar_radius", radius, "pillars reach outside the domain (grid.size)")
    n = grid.elements
    x = grid.centres()
    labels = np.full((n, n), -1, dtype=np.int64)
    reach = math.ceil(radius / h) + 1
    for k, (cy, cx) in enumerate(centres):
        i0 = max(math.floor((cy + half) / h) - reach, 0)
        j0 = max(math.floor((cx + half) / h) - reach, 0)
        rows = slice(i0, min(i0 + 2 * reach + 1, n))
        cols = slice(j0, min(j0 + 2 * reach + 1, n))
        inside = (x[rows, None] - cy) ** 2 + (x[None, cols] - cx) ** 2 <= radius * radius
        block = labels[rows, cols]
        if np.any(block[inside] >= 0):
            raise StructureError("pillar_radius", radius, "pillars overlap; reduce pillar_radius or increase spacing")
        block[inside] = k
    return labels


def _check_pillar_radius(grid: Grid, radius: float, key: str = "pillar_radius", value: object = None,
                         origin: str = "") -> None:
    """StructureError if a pillar of ``radius`` is under `MIN_PILLAR_RADIUS_ELEMENTS` elements.

    A derived radius names the key it comes from (``key``, ``value``) and
    says how it follows from it (``origin``).
    """
    h = grid.element_size
    if not radius >= MIN_PILLAR_RADIUS_ELEMENTS * h:
        raise StructureError(
            key, radius if value is None else value,
            f"{origin}is under {MIN_PILLAR_RADIUS_ELEMENTS:g} elements (h = grid.size / grid.elements = {h:g}); a "
            f"pillar needs at least {MIN_PILLAR_RADIUS_ELEMENTS:g} elements in radius (refine grid.elements)",
        )


def hierarchy_clusters(index: np.ndarray, pillars_per_side: int, clusters: tuple[int, ...]) -> list[np.ndarray]:
    """Cluster maps of the levels above the pillars for a square lattice.

    Level l groups ``clusters[l] x clusters[l]`` units of level l-1 (level 0:
    the pillars).  ``index`` holds the lattice (row, column) of every pillar.
    The product of the cluster sizes must divide ``pillars_per_side`` so that
    the clusters tile the lattice.
    """
    block = 1
    maps = []
    for level, size in enumerate(clusters, start=2):
        block *= int(size)
        if pillars_per_side % block:
            raise StructureError(
                "levels", list(clusters),
                f"level {level} groups {block} x {block} pillars, which does not tile the "
                f"{pillars_per_side} x {pillars_per_side} lattice (pillars_per_side must be a multiple of "
                f"the product of the cluster sizes)",
            )
        per_side = pillars_per_side // block
        key = (index[:, 0] // block) * per_side + index[:, 1] // block
        maps.append(np.unique(key, return_inverse=True)[1].astype(np.int64))
    return maps


def clustered_filling_factors(grid: Grid, pillar: np.ndarray, lattice: ClusteredLattice) -> tuple[float, ...]:
    """The filling factor of every level of a clustered brush as rasterised, bottom-up (phi1, phi2, ...).

    ``pillar`` is the brush's element labels (`rasterise_pillars`, ``Indenter.pillar``).
    Only the sub-pillars are rasterised: phi1 is the area of their elements
    (count x h^2) over the area (2 r2)^2 of the level-2 squares.  The squares of
    the clusters are no part of the raster (the solver sees the sub-pillars'
    footprints and the cluster each belongs to) and the sub-pillars' centres are
    not snapped to the grid, so the higher factors are the exact area ratios:
    phi_l = the level-l squares over the level-(l+1) squares, the last the top
    level's over the region's area A0.  The product is the rasterised filling
    factor A / A0 of the brush (eq. 6.22 on the raster).

    phi1 converges to its nominal value at first order in h: a disk of radius r
    covers the elements of an area in [pi (r - h / sqrt 2)^2, pi (r + h / sqrt 2)^2]
    (every element whose centre lies inside lies within r + h / sqrt 2 of the
    centre, and every point within r - h / sqrt 2 lies in such an element).
    """
    h2 = grid.element_size**2
    areas = [float(np.count_nonzero(pillar >= 0)) * h2]
    areas += [len(centres) * side * side for centres, side in zip(lattice.square_centres, lattice.sides)]
    areas.append(lattice.region_size**2)
    return tuple(inner / outer for inner, outer in itertools.pairwise(areas))


def brush(
    grid: Grid,
    *,
    layout: str,
    pillar_radius: float | None = None,
    contact_modulus: float,
    work_of_adhesion: float,
    stiffness: float = math.inf,
    stiffness_ratio: float | None = None,
    region: str = "square",
    region_size: float | None = None,
    pillars_per_side: int | None = None,
    spacing: float | None = None,
    pillar_count: int | None = None,
    min_gap: float | None = None,
    seed: int = 0,
    roughness: float = 0.0,
    profile: Profile | None = None,
    lengths: np.ndarray | None = None,
    levels: tuple[Level, ...] = (),
    tip: Tip | Sequence[Tip] | None = None,
    tilt: Tilt | None = None,
    grading: Grading | None = None,
    filling_factors: Sequence[float] | None = None,
) -> Indenter:
    """A brush of flat-ended cylindrical pillars on springs (thesis ch. 3-7).

    Parameters
    ----------
    grid : Grid
    layout : {"square", "random", "clustered"}
        Regular n x n lattice of pitch ``spacing`` centred on the domain,
        ``pillar_count`` random non-overlapping positions (seeded), or the
        ``pillars_per_side`` x ``pillars_per_side`` sub-pillars distributed in
        square clusters of the ``levels`` (thesis Fig. 6-3, `clustered_lattice`).
    pillar_radius : float
        Radius r of every pillar, units of length (>= 2 elements).  Required
        by ``square`` and ``random``; ``clustered`` derives it from
        ``filling_factors`` and refuses it.
    contact_modulus, work_of_adhesion : float
        E* and dgamma: they set the reference stress of the concave profile.
    stiffness : float or array of M floats
        k of every pillar's own spring (level 1), or of each pillar's
        (`graded_stiffness`); inf = rigid.
    stiffness_ratio : float, optional
        The same as the dimensionless k~ = k / (E* L) of the configuration key
        ``indenter.stiffness_ratio`` (thesis eq. 4.13, L = ``grid.size``); give
        this or ``stiffness``, not both.
    region : {"square", "circle"}
        Where pillars are placed: a square of side ``region_size`` or a circle
        of that diameter, centred on the domain.  Its area is the apparent area
        A0 of the brush; for the lattice only the pillars whose centres lie in
        the circle are kept.
    region_size : float, optional
        Default: the domain side L.
    pillars_per_side, spacing : square layout
        Default spacing: region_size / pillars_per_side (the lattice fills the
        region, one pillar per cell).
    pillar_count, min_gap : random layout
        Number of pillars and the smallest edge-to-edge gap (default 2 h).
    filling_factors : sequence of float, clustered layout
        phi1, phi2, ... bottom-up, one per level (len(levels) + 1; eq. 6.22):
        the sub-pillars in a level-2 cluster, each level's clusters in the
        next's, the top level's clusters in the region (square only).
    seed : int
        Seeds the random layout and the roughness through independent child
        streams of ``numpy.random.SeedSequence(seed)``: changing sigma rescales
        the same realisation, and the same seed gives the same roughness for a
        random and a regular layout.
    roughness : float
        Standard deviation sigma of the Gaussian pillar lengths (eq. 5.1).
    profile : Profile, optional
        Concave profile (eq. 7.3) centred on the domain; its radius R is the
        distance of the outermost pillar centre.
    lengths : array of M floats, optional
        Explicit extra pillar lengths (units of length), added to the above.
    levels : tuple of Level
        Hierarchy above the pillars, bottom-up (square or clustered layout;
        the clustered layout needs at least one).
    tip : Tip or sequence of M Tips, optional
        The tip shape of every pillar, or of each (default flat).
    grading : Grading, optional
        Grades the pillars' own springs over the brush (a `Level` takes its
        own, graded over its clusters' centres: the mean of their pillars').
    tilt : Tilt, optional
        A tilted base (default none).  Where the tilt puts an element below
        the lowest pillar's tip, every height is shifted so the lowest is 0.

    Notes
    -----
    The pillar length is the sum of the three contributions; the offsets are
    g_n = max(length) - length_n >= 0, so the longest pillar touches first.

    Why one function: every parameter is one key of the config's `indenter` section (layout, region, counts,
    radius, materials, roughness, profile, levels, seed, tip, tilt, filling factors), and the body is the sequence
    positions, footprints, offsets, springs, description that each of them enters once; the steps are in
    `random_positions`, `clustered_lattice`, `rasterise_pillars`, `hierarchy_clusters`, `Profile`, `_tip_heights`
    and `_level_stiffness`.
    """
    if layout not in ("square", "random", "clustered"):
        raise StructureError("layout", layout, "must be 'square', 'random' or 'clustered'")
    if region not in ("square", "circle"):
        raise StructureError("region", region, "must be 'square' or 'circle'")
    h = grid.element_size
    size = grid.size if region_size is None else float(region_size)
    if not (0 < size <= grid.size * (1 + 1e-12)):
        raise StructureError("region_size", region_size, f"must be in (0, grid.size = {grid.size:g}]")
    lattice = _clustered(grid, layout, pillar_radius, region, size, pillars_per_side, levels, filling_factors)
    if lattice is not None:
        pillar_radius = lattice.pillar_radius
    elif pillar_radius is None:
        raise StructureError("pillar_radius", None, f"required with layout = {layout!r}")
    else:
        _check_pillar_radius(grid, pillar_radius)  # before a random layout is searched for
    if stiffness_ratio is not None:
        if not (isinstance(stiffness, (int, float)) and math.isinf(stiffness)):
            raise StructureError("stiffness_ratio", stiffness_ratio,
                                 "give stiffness (k) or stiffness_ratio (k~ = k / (E* L)), not both")
        if not (isinstance(stiffness_ratio, (int, float)) and stiffness_ratio > 0):
            raise StructureError("stiffness_ratio", stiffness_ratio, "must be a number > 0 (inf: rigid)")
        stiffness = float(stiffness_ratio) * float(contact_modulus) * grid.size
    layout_seed, roughness_seed = np.random.SeedSequence(int(seed)).spawn(2)
    index = None
    if layout == "square":
        if pillars_per_side is None or pillars_per_side < 1:
            raise StructureError("pillars_per_side", pillars_per_side, "must be an integer >= 1")
        pitch = size / pillars_per_side if spacing is None else float(spacing)
        if not pitch > 2 * pillar_radius:
            raise StructureError(
                "spacing" if spacing is not None else "pillar_radius", spacing if spacing is not None else pillar_radius,
                f"pillars overlap: the spacing {pitch:g} must exceed the pillar diameter "
                f"2 pillar_radius = {2 * pillar_radius:g}",
            )
        if pillars_per_side * pitch > size * (1 + 1e-9):
            raise StructureError(
                "spacing", pitch,
                f"{pillars_per_side} pillars at spacing {pitch:g} span {pillars_per_side * pitch:g}, "
                f"more than region_size = {size:g}",
            )
        centres, index = square_lattice(pillars_per_side, pitch)
        if region == "circle":
            keep = np.hypot(centres[:, 0], centres[:, 1]) + pillar_radius <= 0.5 * size * (1 + 1e-12)
            if not keep.any():
                raise StructureError("pillar_radius", pillar_radius, "no pillar fits inside the circular region")
            centres, index = centres[keep], index[keep]
    elif lattice is not None:
        centres, index = lattice.centres, lattice.index
    else:
        if levels:
            raise StructureError("levels", [lv.cluster for lv in levels],
                                 "a hierarchy needs layout = 'square' or 'clustered'")
        if pillar_count is None or pillar_count < 1:
            raise StructureError("pillar_count", pillar_count, "must be an integer >= 1")
        gap = 2.0 * h if min_gap is None else float(min_gap)
        if gap < 0:
            raise StructureError("min_gap", min_gap, "must be >= 0")
        centres = random_positions(pillar_count, pillar_radius, gap, region, size, np.random.default_rng(layout_seed))
    labels = rasterise_pillars(grid, centres, pillar_radius)
    n_pillars = len(centres)
    counts = np.bincount(labels[labels >= 0], minlength=n_pillars)

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
        from . import theory

        reference_stress = profile.reference_stress
        if reference_stress is None:
            if not work_of_adhesion > 0:
                raise StructureError(
                    "profile.amplification", profile.amplification,
                    "the default reference stress needs halfspace.work_of_adhesion > 0 "
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
    if grading is not None:
        stiffness = grading.apply(_level_stiffness(stiffness, n_pillars, "stiffness"), centres, "grading")
    spring_levels = [SpringLevel(_level_stiffness(stiffness, n_pillars, "stiffness"),
                                 np.arange(n_pillars, dtype=np.int64))]
    if levels:
        maps = hierarchy_clusters(index, int(pillars_per_side), tuple(lv.cluster for lv in levels))
        for i, (lv, cluster) in enumerate(zip(levels, maps)):
            n_clusters = int(cluster.max()) + 1
            k = lv.stiffness
            if lv.grading is not None:
                counts_c = np.bincount(cluster, minlength=n_clusters)
                cluster_centres = np.stack([np.bincount(cluster, weights=centres[:, axis], minlength=n_clusters)
                                            for axis in (0, 1)], axis=1) / counts_c[:, None]
                k = lv.grading.apply(_level_stiffness(k, n_clusters, f"levels.{i}.stiffness"), cluster_centres,
                                     f"levels.{i}.grading")
            spring_levels.append(SpringLevel(_level_stiffness(k, n_clusters, f"levels.{i}.stiffness"), cluster))
    apparent_area = size * size if region == "square" else math.pi * size * size / 4.0
    real_area = float(counts.sum()) * h * h
    description = BrushGeometry(
        layout=layout,
        region=region,
        region_size=size,
        n_pillars=n_pillars,
        pillar_radius=float(pillar_radius),
        apparent_area=apparent_area,
        real_area=real_area,
        filling_factor=real_area / apparent_area,
        nominal_filling_factor=n_pillars * math.pi * pillar_radius**2 / apparent_area,
        pillar_elements=counts,
        centres=centres,
        offsets=offsets,
        roughness=float(roughness),
        seed=int(seed),
        profile_amplification=float(profile.amplification) if profile is not None else 0.0,
        profile_reference_stress=reference_stress,
        profile_radius=profile_radius,
        level_clusters=[lv.cluster for lv in levels],
        tip=tip_record,
        tilt_angle=float(tilt.angle) if tilt is not None else 0.0,
        tilt_azimuth=float(tilt.azimuth) if tilt is not None else 0.0,
        graded=any(not level.uniform for level in spring_levels),
        contact_modulus=float(contact_modulus),
        work_of_adhesion=float(work_of_adhesion),
        **({} if lattice is None else {
            "nominal_level_filling_factors": lattice.filling_factors,
            "level_filling_factors": clustered_filling_factors(grid, labels, lattice),
            "cluster_sides": lattice.sides,
        }),
    )
    return Indenter(height=height, pillar=labels, levels=tuple(spring_levels), description=description)


def _clustered(grid: Grid, layout: str, pillar_radius: float | None, region: str, size: float,
               pillars_per_side: int | None, levels: tuple[Level, ...],
               filling_factors: Sequence[float] | None) -> ClusteredLattice | None:
    """The `ClusteredLattice` of a clustered brush (None for another layout), the keys it reads checked."""
    if layout != "clustered":
        if filling_factors is not None:
            raise StructureError("filling_factors", list(filling_factors), "only used with layout = 'clustered'")
        return None
    if pillar_radius is not None:
        raise StructureError("pillar_radius", pillar_radius,
                             "layout = 'clustered' derives it from filling_factors and pillars_per_side; remove it")
    if region != "square":
        raise StructureError("region", region, "layout = 'clustered' tiles a square region")
    if filling_factors is None:
        raise StructureError("filling_factors", None, "required with layout = 'clustered' (one per level)")
    if pillars_per_side is None:
        raise StructureError("pillars_per_side", None, "required with layout = 'clustered'")
    lattice = clustered_lattice(pillars_per_side, [lv.cluster for lv in levels], filling_factors, size)
    _check_pillar_radius(
        grid, lattice.pillar_radius, "filling_factors", list(lattice.filling_factors),
        f"the sub-pillar radius r1 = (region_size / pillars_per_side) sqrt(phi1 phi2 ... / pi) = "
        f"{lattice.pillar_radius:.4g} ",
    )
    return lattice


def _level_stiffness(stiffness, n_springs: int, key: str) -> float | np.ndarray:
    """One level's stiffness as given: a number for every spring, or n_springs values (StructureError names ``key``)."""
    if np.ndim(stiffness) == 0:
        value = float(stiffness)
        if not value > 0:
            raise StructureError(key, value, "must be > 0 (inf = rigid)")
        return value
    values = np.asarray(stiffness, dtype=np.float64).ravel()
    if values.shape != (n_springs,):
        raise StructureError(key, f"{values.size} values", f"must hold one stiffness per spring ({n_springs})")
    if not np.all(values > 0):
        raise StructureError(key, float(values.min()), "every spring's stiffness must be > 0 (inf = rigid)")
    infinite = np.isinf(values)
    if infinite.any() and not infinite.all():
        raise StructureError(key, "inf and finite values", "a level is rigid (all inf) or elastic (all finite)")
    return float(values[0]) if infinite.all() else values


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
