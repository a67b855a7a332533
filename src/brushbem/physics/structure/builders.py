"""The indenters built on a grid: the compact punch, sphere and height map, and the `brush` of pillars."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from brushbem.errors import ParameterError
from brushbem.physics.structure.errors import StructureError
from brushbem.physics.structure.grid import Grid, _check_pillar_radius
from brushbem.physics.structure.hierarchy import Level, _spring_levels
from brushbem.physics.structure.layouts import ClusteredLattice, clustered_lattice, random_positions, square_lattice
from brushbem.physics.structure.raster import clustered_filling_factors, rasterise_pillars
from brushbem.physics.structure.records import BrushGeometry, HeightMapGeometry, Indenter, PunchGeometry, SphereGeometry, SpringLevel
from brushbem.physics.structure.tips import Grading, Profile, Tilt, Tip, _brush_heights, _pillar_offsets
from brushbem.physics.scales import stiffness_of_ratio

__all__ = ["brush", "flat_punch", "height_map", "sphere"]


def _single_spring(stiffness: float, owner: str) -> tuple[SpringLevel, ...]:
    if math.isinf(stiffness):
        return ()
    if not (stiffness > 0 and math.isfinite(stiffness)):
        raise ParameterError(owner, "stiffness", f"{owner}(stiffness={stiffness}) must be > 0 (inf = rigid)")
    return (SpringLevel(stiffness=float(stiffness), cluster=np.zeros(1, dtype=np.int64)),)


def flat_punch(grid: Grid, radius: float, stiffness: float = math.inf) -> Indenter:
    """Flat-ended cylindrical punch of ``radius`` centred on the domain.

    The footprint is the set of elements whose centre lies inside the circle.
    """
    h = grid.element_size
    if not (math.isfinite(radius) and radius >= 2 * h):
        raise ParameterError("flat_punch", "radius", f"flat_punch(radius={radius}) must be >= 2 elements (2h = {2 * h})")
    if 2 * radius > grid.size:
        raise ParameterError("flat_punch", "radius", f"flat_punch(radius={radius}) is larger than the domain (L/2 = {grid.size / 2})")
    inside = grid.radius_squared() <= radius**2
    height = np.where(inside, 0.0, np.inf)
    pillar = np.where(inside, 0, -1)
    area = inside.sum() * h * h
    return Indenter(
        height=height,
        pillar=pillar,
        levels=_single_spring(stiffness, "flat_punch"),
        description=PunchGeometry(radius=radius, rasterised_area=float(area)),
    )


def sphere(grid: Grid, radius: float, stiffness: float = math.inf) -> Indenter:
    """Paraboloid tip r^2 / (2R) of curvature radius ``radius``, centred on the domain."""
    if not (math.isfinite(radius) and radius > 0):
        raise ParameterError("sphere", "radius", f"sphere(radius={radius}) must be finite and > 0")
    height = grid.radius_squared() / (2.0 * radius)
    pillar = np.zeros(height.shape, dtype=np.int64)
    return Indenter(
        height=height,
        pillar=pillar,
        levels=_single_spring(stiffness, "sphere"),
        description=SphereGeometry(radius=radius),
    )


def height_map(grid: Grid, heights: np.ndarray, stiffness: float = math.inf) -> Indenter:
    """Arbitrary tip heights (N x N, units of length) on one spring; shifted so min = 0."""
    heights = np.asarray(heights, dtype=np.float64)
    if heights.shape != (grid.elements, grid.elements):
        raise ParameterError("height_map", "heights", f"height_map(heights=...) has shape {heights.shape}, expected {(grid.elements, grid.elements)}")
    if not np.all(np.isfinite(heights)):
        raise ParameterError("height_map", "heights", "height_map(heights=...) holds non-finite heights")
    height = heights - heights.min()
    pillar = np.zeros(height.shape, dtype=np.int64)
    return Indenter(
        height=height,
        pillar=pillar,
        levels=_single_spring(stiffness, "height_map"),
        description=HeightMapGeometry(),
    )


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
        The dimensionless k~ = k / (E* L) (thesis eq. 4.13) with L the brush's
        side, ``region_size`` (the thesis's "square area L x L" the pillars are
        distributed in, L736; by default the domain side, as in every thesis
        study), not the domain padded around it; give this or ``stiffness``,
        not both.
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

    Why these parameters: every parameter is one key of the config's `indenter` section (layout, region, counts,
    radius, materials, roughness, profile, levels, seed, tip, tilt, filling factors).  The body is the sequence of
    named steps that each of them enters once: layout (`_clustered`, `_square_centres`, `_random_centres`),
    footprints (`rasterise_pillars`), lengths (`_pillar_offsets`), tips (`_brush_heights`), springs and levels
    (`_spring_levels`), and the record (`BrushGeometry`).
    """
    if layout not in ("square", "random", "clustered"):
        raise StructureError("layout", layout, "must be 'square', 'random' or 'clustered'")
    if region not in ("square", "circle"):
        raise StructureError("region", region, "must be 'square' or 'circle'")
    h = grid.element_size
    size = grid.size if region_size is None else float(region_size)
    if not (0 < size <= grid.size * (1 + 1e-12)):
        raise StructureError("region_size", region_size, f"must be in (0, Grid.size = {grid.size:g}]")
    lattice = _clustered(grid, layout, pillar_radius, region, size, pillars_per_side, levels, filling_factors)
    if lattice is not None:
        pillar_radius = lattice.pillar_radius
    elif pillar_radius is None:
        raise StructureError("pillar_radius", None, f"required with layout = {layout!r}")
    else:
        _check_pillar_radius(grid, pillar_radius)  # before a random layout is searched for
    stiffness = _pillar_stiffness(size, stiffness, stiffness_ratio, contact_modulus)
    layout_seed, roughness_seed = np.random.SeedSequence(int(seed)).spawn(2)

    # Layout: the pillar centres (and their lattice indices for a hierarchy).
    index = None
    if layout == "square":
        centres, index = _square_centres(pillars_per_side, spacing, pillar_radius, region, size)
    elif lattice is not None:
        centres, index = lattice.centres, lattice.index
    else:
        centres = _random_centres(grid, levels, pillar_count, min_gap, pillar_radius, region, size, layout_seed)
    labels = rasterise_pillars(grid, centres, pillar_radius)
    n_pillars = len(centres)
    counts = np.bincount(labels[labels >= 0], minlength=n_pillars)

    offsets, reference_stress, profile_radius = _pillar_offsets(
        centres, pillar_radius, roughness, roughness_seed, profile, lengths, contact_modulus, work_of_adhesion)
    height, offsets, tip_record = _brush_heights(grid, labels, centres, pillar_radius, offsets, tip, tilt)
    spring_levels = _spring_levels(stiffness, grading, centres, index, pillars_per_side, levels)

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


def _pillar_stiffness(side: float, stiffness, stiffness_ratio: float | None, contact_modulus: float):
    """The pillars' own stiffness k, from ``stiffness`` or from k~ = ``stiffness_ratio`` (k = k~ E* L, L = ``side``,
    the brush's side: eq. 4.13)."""
    if stiffness_ratio is not None:
        if not (isinstance(stiffness, (int, float)) and math.isinf(stiffness)):
            raise StructureError("stiffness_ratio", stiffness_ratio,
                                 "give stiffness (k) or stiffness_ratio (k~ = k / (E* L)), not both")
        if not (isinstance(stiffness_ratio, (int, float)) and stiffness_ratio > 0):
            raise StructureError("stiffness_ratio", stiffness_ratio, "must be a number > 0 (inf: rigid)")
        stiffness = stiffness_of_ratio(float(stiffness_ratio), float(contact_modulus), float(side))
    return stiffness


def _square_centres(pillars_per_side: int | None, spacing: float | None, pillar_radius: float, region: str,
                    size: float) -> tuple[np.ndarray, np.ndarray]:
    """The brush step "layout" of ``layout = "square"``: the lattice's centres and indices (those in the region)."""
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
    return centres, index


def _random_centres(grid: Grid, levels: tuple[Level, ...], pillar_count: int | None, min_gap: float | None,
                    pillar_radius: float, region: str, size: float, layout_seed: np.random.SeedSequence) -> np.ndarray:
    """The brush step "layout" of ``layout = "random"``: `random_positions` seeded by ``layout_seed``."""
    h = grid.element_size
    if levels:
        raise StructureError("levels", [lv.cluster for lv in levels],
                             "a hierarchy needs layout = 'square' or 'clustered'")
    if pillar_count is None or pillar_count < 1:
        raise StructureError("pillar_count", pillar_count, "must be an integer >= 1")
    gap = 2.0 * h if min_gap is None else float(min_gap)
    if gap < 0:
        raise StructureError("min_gap", min_gap, "must be >= 0")
    return random_positions(pillar_count, pillar_radius, gap, region, size, np.random.default_rng(layout_seed))


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
