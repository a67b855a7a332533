"""Where the pillars stand: the square lattice, the clustered lattice of thesis Fig. 6-3, random packing."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from brushbem.physics.structure.errors import StructureError

__all__ = [
    "HEXAGONAL_PACKING_DENSITY",
    "MAX_RANDOM_DRAWS",
    "ClusteredLattice",
    "clustered_lattice",
    "random_positions",
    "square_lattice",
]


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
    The segment sums (``ContactProblem.coupling = "segments"``) need no such gap; the
    discriminant matrix needs a box that covers a cluster's footprint (about
    2 r2 - 2 w) and reaches no other (about 2 D + 2 w away), which the
    thesis's brush misses (`brushbem.numerics.operator.discriminant_half_width`
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
