"""What an indenter is: its springs (`SpringLevel`), the rasterised `Indenter` and the `Geometry` records.

The records of `Geometry` say, for the record, what shape an indenter has and
the parameters it was built from (`PunchGeometry`, `SphereGeometry`,
`HeightMapGeometry`, `BrushGeometry`); the builders are in
`brushbem.physics.structure.builders`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from brushbem.errors import ParameterProblem, raise_first
from brushbem.results.mapping import MappingRecord

__all__ = [
    "BrushGeometry",
    "Geometry",
    "HeightMapGeometry",
    "Indenter",
    "PunchGeometry",
    "SphereGeometry",
    "SpringLevel",
]


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


def elastic_connection_problems(stiffness: float, *, viscoelastic: bool, pillar_law: object) -> list[ParameterProblem]:
    """The rigid-pillar rule, stated once: viscoelastic pillars and a nonlinear pillar law need elastic
    connections of the pillars (level 1) of finite stiffness.

    A viscoelastic connection's ``stiffness`` is its relaxed one, a law's slopes are factors of it: a rigid
    connection (inf) has neither.  ``stiffness``: the pillars' own (the softest of level 1; inf: rigid or
    no springs), as given where it is known before the indenter is built; ``viscoelastic``: whether the
    pillars are (`Indenter.viscoelastic`); ``pillar_law``: the law or None.  `Indenter` raises the first
    problem; the rules of the paths (`brushbem.physics.viscoelastic.time_stepping_problems`,
    `brushbem.physics.pillar_laws.law_path_problems`) return them for the configuration to name by key.
    """
    if math.isfinite(stiffness):
        return []
    problems = []
    if viscoelastic:
        problems.append(ParameterProblem("Indenter", "levels", stiffness,
                                         "must be finite with Indenter.viscoelastic (it is the relaxed stiffness)"))
    if pillar_law is not None:
        problems.append(ParameterProblem("Indenter", "levels", stiffness,
                                         "must be finite with Indenter.pillar_law (its slopes are factors of it)"))
    return problems


@dataclass(frozen=True)
class Indenter:
    """A rasterised indenter (see `brushbem.physics.structure`).

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
    viscoelastic : brushbem.physics.viscoelastic.Viscoelastic or None
        The rheology of the pillars' own connections (level 1), whose
        ``stiffness`` is then the relaxed one; None: elastic springs.
    pillar_law : brushbem.physics.pillar_laws.PiecewiseLinear or None
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
        own = math.inf if not self.levels else self.levels[0].softest
        raise_first(elastic_connection_problems(own, viscoelastic=self.viscoelastic is not None,
                                                pillar_law=self.pillar_law))

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

    def preload_reaches(self, displacement: float) -> bool:
        """The preload rule, stated once: a base displacement presses the indenter only beyond
        `lowest_height`; at or below it nothing touches and there is nothing to pull off.

        The load paths (`brushbem.protocol.problem.check_preload`), the pillar model and the
        configuration's rules on the rasterised structure (`brushbem.runs.assembly`) all ask this.
        """
        return displacement > self.lowest_height

    @property
    def elastic_levels(self) -> tuple[SpringLevel, ...]:
        """The levels with finite stiffness (the rigid ones add nothing to the operator)."""
        return tuple(level for level in self.levels if not level.rigid)

    def element_clusters(self, level: SpringLevel) -> np.ndarray:
        """Cluster index of every element for ``level``, -1 outside the footprints."""
        return np.where(self.pillar >= 0, level.cluster[np.maximum(self.pillar, 0)], -1)
