"""The pillar model's basis and coupling: `Basis`, `PillarModel` (``LoadPath.method = "pillars"``).

`PillarModel` holds, for a brush of flat tips, every pillar's modes (the
half-space pressures of the displacement polynomials of `MODES` on its
raster, cached by raster shape), the Galerkin couplings G_ij between the
modes of two pillars (exact within ``near``, by the multipole expansion
beyond), the springs of every level projected on the uniform mode, and the
higher modes' local amplitudes.  The model, its accuracy and its path are
described in `brushbem.pillars`.
"""

from __future__ import annotations

import math

import numpy as np

from brushbem.physics.halfspace import influence_coefficients
from brushbem.pillars.calibration import CRITERIA, install_criterion
from brushbem.pillars.lattice import Lattice
from brushbem.pillars.modes import MODES, SCHUR_ELEMENTS, Bases, Basis
from brushbem.pillars.tips import TipRaster
from brushbem.protocol.problem import ContactProblem

__all__ = ["MODES", "NEAR_RADII", "Basis", "PillarModel"]

#: On a lattice, G00 (M^2 numbers, with the step of each entry's last refresh) is kept up to this many pillars
#: (0.3 GB) and computed where needed beyond.
DENSE_PILLARS = 5000

#: Centres closer than this many pillar radii are coupled exactly (element-pair sums).
NEAR_RADII = 8.0


class PillarModel:
    """Bases, couplings, springs of the pillar model; its raster arrays: the path's cache (`state.RasterCache`)."""

    def __init__(self, problem: ContactProblem, modes: str = "quadratic", coupling: str = "local",
                 peel: bool = True, near: float | None = None, lattice: bool = True, tips: int = 1,
                 criterion: str = "raster"):
        if modes not in MODES:
            raise ValueError(f"modes = {modes!r} must be one of {', '.join(map(repr, MODES))}")
        if criterion not in CRITERIA:
            raise ValueError(f"criterion = {criterion!r} must be one of {', '.join(map(repr, CRITERIA))}")
        if coupling not in ("local", "full"):
            raise ValueError(f"coupling = {coupling!r} must be 'local' or 'full'")
        indenter = problem.indenter
        #: The tips' raster (`brushbem.pillars.tips`): the global grid subdivided ``tips`` times.
        self.tips = raster = TipRaster.build(problem, tips)
        self.n = raster.elements
        h = raster.element_size
        self.h2 = h ** 2
        self.powers = MODES[modes]
        self.m = len(self.powers)
        self.coupling = coupling if self.m > 1 else "full"
        self.peel = peel
        flat, owner = raster.flat, raster.owner
        M = self.M = indenter.n_pillars
        bounds = np.searchsorted(owner, np.arange(M + 1))
        sizes = np.diff(bounds)
        width = int(sizes.max())
        #: Flat indices (the tips' raster) of every pillar's footprint (row-major), padded with -1: (M, width).
        self.slots = np.full((M, width), -1, dtype=np.int64)
        within = np.arange(width)[None, :] < sizes[:, None]
        self.slots[within] = flat
        self.rows, self.cols = np.divmod(np.where(within, self.slots, 0), self.n)
        self.sizes, self.foot = sizes, np.stack([self.rows, self.cols], axis=-1)  # (M,), (M, width, 2): rows, cols
        self.full = within
        #: The global element each footprint slot reports to in the states (`TipRaster.reporting`).
        self.reports = np.where(within, raster.reporting(np.where(within, self.slots, flat[0])), -1)
        self.g = raster.heights
        self.levels = [(np.asarray(level.cluster), level.stiffnesses) for level in indenter.elastic_levels]
        radius = math.sqrt(float(sizes.max()) / math.pi)
        #: Centres closer than this (elements of the tips' raster; ``near`` pillar radii) are coupled exactly.
        self.near = (NEAR_RADII if near is None else float(near)) * radius
        extent = int(max(np.ptp(np.where(within, self.rows, self.rows[:, :1]), axis=1).max(),
                         np.ptp(np.where(within, self.cols, self.cols[:, :1]), axis=1).max())) + 1
        span = min(int(math.ceil(self.near)) + 2 * extent + 2, self.n)
        i = np.arange(span, dtype=np.float64) * h
        self.ktab = influence_coefficients(i[:, None], i[None, :], h, problem.contact_modulus)
        self.scale = h / (math.pi * problem.contact_modulus)
        self.bases = Bases(self.ktab, self.powers)
        install_criterion(self, problem, criterion, raster.critical_stress, sizes, h)
        #: Footprints of `SCHUR_ELEMENTS` or more (fine tips): the others' modes' fields across them, kept
        #: (`_exact`), and every pillar's footprint (row-major offsets from its first row and column).
        self.large = int(sizes.max()) >= SCHUR_ELEMENTS
        self._fields: dict[tuple, np.ndarray] = {}
        self._fields_bytes = 0
        self._pairs: dict[tuple, np.ndarray] = {}
        # Current state of every pillar's raster (a sub-set of its footprint) and its basis.
        self.raster = within.copy()
        self.basis: list[Basis] = [None] * M  # type: ignore[list-item]
        self.origin = np.zeros((M, 2), dtype=np.int64)
        self.centre = np.zeros((M, 2))
        m = self.m
        self.force = np.zeros(M)
        self.gram = np.ones((M, m))
        self.m0 = np.zeros((M, m))
        self.m1 = np.zeros((M, m, 2))
        self.m2 = np.zeros((M, m, 2, 2))
        #: Pressure of every mode on every footprint slot (0 off the raster): (M, width, m).
        self.phi = np.zeros((M, width, m))
        #: The surface on every footprint slot from the others' field and the pillar's own modes:
        #: u = surface_map @ [f, a], (M, width, 2 m).  Its first m columns fit a field across the raster
        #: from its projections f on the modes (the polynomial that has them), the last m are the
        #: displacements of the pillar's own modes (amplitudes a).
        self.surface_map = np.zeros((M, width, 2 * m))
        self.fitted = self.surface_map[..., :m]
        #: Of every pillar's fit across its footprint (`fitted`, per mode): the mean over the footprint's
        #: slots and the largest distance of a slot from it, (m, M) each: the bound of `state.touch_candidates`.
        self.fit_centre = np.zeros((m, M))
        self.fit_spread = np.zeros((m, M))
        self._footprints: dict[tuple, np.ndarray] = {}
        #: Pillars of one group share their footprint and raster (and so the rows of `surface_map`).
        self.surface_group = np.zeros(M, dtype=np.int64)
        self._groups: dict[int, np.ndarray] = {}
        self.lattice = None
        for p in range(M):
            _install_basis(self, p)
        _build_couplings(self, self.centre.copy(), lattice)

    # -- bases ---------------------------------------------------------------
    def surface_group_map(self, group: int) -> np.ndarray:
        """The `surface_map` rows (footprint slots, 2 m) that the pillars of ``surface_group`` ``group`` share."""
        return self._groups[group]

    def mask_basis(self, p: int, mask: np.ndarray) -> tuple[Basis, np.ndarray]:
        """(basis, origin) of pillar p on the footprint slots ``mask`` (`brushbem.pillars.modes.Bases`)."""
        size = self.sizes[p]
        foot, on = self.foot[p, :size], mask[:size]
        return self.bases.get(foot, on), foot[on].min(axis=0)

    # -- couplings -------------------------------------------------------------
    def blocks(self, p: int, mask: np.ndarray | None = None, upper: int = -1) -> tuple[np.ndarray, np.ndarray, Basis]:
        """(others, blocks G_pq (len(others), m, m), basis of p) for pillar p on its raster or on ``mask``.

        ``others`` are the pillars q > ``upper`` but p; the other pillars count with their current rasters.
        """
        if mask is None:
            bp, origin, centre, mask = self.basis[p], self.origin[p], self.centre[p], self.raster[p]
        else:
            bp, origin = self.mask_basis(p, mask)
            centre = origin + bp.centroid
        others = np.arange(upper + 1, self.M)
        others = others[others != p]
        blocks = np.zeros((others.size, self.m, self.m))
        if others.size:
            near = np.isin(others, self.neighbours[p])
            far = ~near
            if far.any():
                blocks[far] = _far(self, bp, centre, others[far])
            for k in np.flatnonzero(near):
                blocks[k] = _exact(self, bp, origin, int(others[k]), p, mask)
        return others, blocks, bp

    def lattice_moments(self, pillars: np.ndarray | None = None) -> tuple[tuple[np.ndarray, ...], tuple[np.ndarray, ...]]:
        """(sources, targets) of `Lattice.far_field`: the modes' moments about the lattice points (of ``pillars``).

        Shifted from the centroid by delta = centroid - point: m1 + m0 delta and
        m2 + m1 delta + delta m1 + m0 delta delta; the sources (uniform modes)
        carry the element square's own second moment m0 h^2 / 12 besides.
        """
        if pillars is None:
            return self._moments
        return tuple(tuple(a[pillars] for a in group) for group in self._moments)  # type: ignore[return-value]

    def uniform_block(self, rows: np.ndarray, cols: np.ndarray) -> np.ndarray:
        """G00[rows, cols], the uniform modes' couplings (the diagonal is the modes' gram)."""
        rows, cols = np.asarray(rows), np.asarray(cols)
        if self.G0 is not None:
            if self.lattice is not None:
                # An entry is current when it was computed after the last change of both its pillars'
                # rasters.  The pillars (of rows or of cols) that changed after one of their entries was
                # computed have those entries computed afresh, both ways.
                computed = self._computed_at[np.ix_(rows, cols)]
                for changed, others in ((rows[(computed < self._changed_at[rows][:, None]).any(axis=1)], cols),
                                        (cols[(computed < self._changed_at[cols][None, :]).any(axis=0)], rows)):
                    if changed.size:
                        self._clock += 1
                        block = _lattice_block(self, changed, others)
                        self.G0[np.ix_(changed, others)] = block
                        self.G0[np.ix_(others, changed)] = block.T
                        self._computed_at[np.ix_(changed, others)] = self._clock
                        self._computed_at[np.ix_(others, changed)] = self._clock
            return self.G0[np.ix_(rows, cols)]
        return _lattice_block(self, rows, cols)

    def set_raster(self, p: int, mask: np.ndarray) -> None:
        """Pillar p holds the footprint slots ``mask`` (all of them once it is off): new basis and couplings."""
        if not mask.any():
            mask = self.full[p]
        if np.array_equal(mask, self.raster[p]):
            return
        self.raster[p] = mask
        _install_basis(self, p)
        _install_row(self, p)

    # -- springs -------------------------------------------------------------
    def spring_row(self, p: int) -> np.ndarray:
        """Row p of H = sum_l (h^2 / k_l) s s^T on the clusters of level l (all pillars)."""
        row = np.zeros(self.M)
        for cluster, stiffness in self.levels:
            same = cluster == cluster[p]
            row[same] += self.h2 / stiffness[cluster[p]]
        return row * self.force[p] * self.force

    def spring_product(self, x0: np.ndarray, attached: np.ndarray) -> np.ndarray:
        """H x0 over the attached pillars."""
        out = np.zeros(self.M)
        weights = np.where(attached, self.force * x0, 0.0)
        for cluster, stiffness in self.levels:
            sums = np.bincount(cluster, weights=weights, minlength=stiffness.size)
            out += (self.h2 / stiffness)[cluster] * sums[cluster]
        return out * self.force

    def spring_matrix(self, S: np.ndarray, T: np.ndarray | None = None) -> np.ndarray:
        """H[S, T] (T = S by default): the springs' block of the pillars S and T."""
        T = S if T is None else T
        out = np.zeros((S.size, T.size))
        for cluster, stiffness in self.levels:
            c, d = cluster[S], cluster[T]
            out += np.where(c[:, None] == d[None, :], (self.h2 / stiffness[c])[:, None], 0.0)
        return out * np.outer(self.force[S], self.force[T])

    def tip_deflection(self, x0: np.ndarray, attached: np.ndarray) -> np.ndarray:
        """The springs' stretch sum_l F_cluster / k_l at every pillar (forces of the attached ones)."""
        out = np.zeros(self.M)
        weights = np.where(attached, self.h2 * self.force * x0, 0.0)
        for cluster, stiffness in self.levels:
            sums = np.bincount(cluster, weights=weights, minlength=stiffness.size)
            out += (sums / stiffness)[cluster]
        return out

    # -- higher modes ----------------------------------------------------------
    def radiation(self, xh: np.ndarray) -> np.ndarray:
        """The field of the higher modes' amplitudes ``xh`` (M, m - 1, c) on every mode of their neighbours.

        The exact near blocks only: (m, M, c).  A higher mode carries no net
        force, so its field falls off as 1 / r^2 or faster, and beyond the
        near distance it is left out.
        """
        M, m, width = self._near_uniform.shape
        # One small product per pillar (np.matmul; einsum's generic loop was ten times slower here).
        blocks = self._near_higher.reshape(M, m, width * (m - 1))
        # np.take: a row gather 17 times faster than fancy indexing at 10^4 pillars (the same numbers).
        near = np.take(xh, self.near_index, axis=0).reshape(M, width * (m - 1), -1)
        return np.matmul(blocks, near).transpose(1, 0, 2)

    def fields(self, x0: np.ndarray, uniform: bool = False, single: bool = False, rows=None) -> np.ndarray:
        """Gs x0 for the uniform amplitudes ``x0`` (M, k): (m, M, k), the projection of their field on every mode.

        ``uniform``: on the uniform modes only, (1, M, k) = G00 x0 (the pillar-level system's product,
        `brushbem.pillars.cg`): the near blocks and the far sums' weights of the other modes are
        left out.  ``single``: the far field in single precision; ``rows`` (uniform): these pillars' only, 0 elsewhere.
        """
        modes = slice(0, 1) if uniform else slice(None)
        if self.lattice is None:
            m = 1 if uniform else self.m
            return (self.Gs[modes].reshape(m * self.M, self.M) @ x0).reshape(m, self.M, x0.shape[1])
        # Pillar by pillar (M, m, k) and transposed once: near blocks, the pillar's own uniform mode, far field.
        on = rows if rows is not None and uniform else slice(None)
        out = np.matmul(self._near_uniform[on, modes], np.take(x0, self.near_index[on], axis=0))
        out[:, 0] += self.gram[on, :1] * x0[on]
        far = self.lattice.far_by_pillar(x0, self._weights[0], self._weights[1][:, modes], single=single)
        whole = far if isinstance(on, slice) else np.zeros_like(far)
        whole[on] = far[on] + out
        return _swap_leading(whole)

    def amplitudes(self, x0: np.ndarray, field: np.ndarray, attached: np.ndarray) -> np.ndarray:
        """All modes' amplitudes (M, m) from the uniform ones and their ``fields`` (``coupling = 'local'``)."""
        x = np.zeros((self.M, self.m))
        on = np.flatnonzero(attached)
        x[on, 0] = x0[on]
        if self.m > 1:
            x[on, 1:] = -field[1:, on].T / self.gram[on, 1:]
        return x


def _swap_leading(a: np.ndarray) -> np.ndarray:
    """a (M, m, c) as a contiguous (m, M, c): the same numbers.  Pairs of a last axis of two moved as one
    complex number each (a strided copy of two-number rows took eight times as long at 10^4 pillars)."""
    if a.shape[-1] == 2 and a.flags.c_contiguous:
        return np.ascontiguousarray(a.view(np.complex128)[..., 0].T).view(np.float64).reshape(
            a.shape[1], a.shape[0], 2)
    return np.ascontiguousarray(a.transpose(1, 0, 2))


# -- the model's bases and couplings, built and kept up to date (module functions of a `PillarModel`) --------

def _build_couplings(model: PillarModel, full_centres: np.ndarray, lattice: bool) -> None:
    """The lattice (if any), the neighbours coupled exactly, and every coupling of the full footprints."""
    M, m = model.M, model.m
    model.alone = [np.unique(cluster).size == cluster.size for cluster, _ in model.levels]  # one pillar a cluster
    #: The lattice of the pillars (`brushbem.pillars.lattice.Lattice`) when they sit on one
    #: (``coupling = "local"``, more than one mode): the far field of the uniform modes by FFT.
    model.lattice = (Lattice.detect(full_centres, model.near, model.scale)
                    if lattice and model.coupling == "local" and m > 1 else None)
    if model.lattice is not None:
        # Neighbours coupled exactly: by the lattice points, as the FFT leaves them out.
        model.neighbours = model.lattice.neighbours
        model._moments = ((np.zeros(M), np.zeros((M, 2)), np.zeros((M, 2, 2))),
                         (np.zeros((M, m)), np.zeros((M, m, 2)), np.zeros((M, m, 2, 2))))
        _shift_moments(model, np.arange(M))
    else:
        # Neighbours coupled exactly: by the footprints' centres (a peeled raster stays inside its footprint).
        model.neighbours = []
        for p in range(M):
            distance = np.hypot(*(full_centres - full_centres[p]).T)
            close = np.flatnonzero(distance < model.near)
            model.neighbours.append(close[close != p])
    model.Gf = np.zeros((M, M, m, m)) if model.coupling == "full" else None
    # On a lattice, when each pillar's raster last changed and each entry of the kept G00 was computed
    # (`uniform_block`).
    model._clock = 0
    model._changed_at = np.zeros(M, dtype=np.int64)
    # No entry is computed before it is read: a brush pressed in part couples only the pillars it attaches.
    model._computed_at = np.full((M, M), -1, dtype=np.int32) if model.lattice is not None and M <= DENSE_PILLARS \
        else None
    if model.lattice is None:
        # Couplings: Gs[0] = G00 (M, M) and Gs[k] = G_ij[k, 0] (M, M) for the higher modes k, in one array
        # (one pass over memory gives every mode's field); the full blocks for coupling = "full".
        model.Gs = np.zeros((m, M, M))
        model.G0 = model.Gs[0]
        model.Gh = model.Gs[1:]
    else:
        # No dense couplings: the near blocks G_pq[k, 0] per neighbour (every mode k, exact), the far ones by
        # the lattice's FFT (fields) or pair by pair (`uniform_block`).
        model.G0 = np.zeros((M, M)) if M <= DENSE_PILLARS else None
    # Every mode's exact near blocks G_pq (m, m) per neighbour, both ways: on a lattice the near part of
    # the fields; everywhere the higher modes' own field on their neighbours (`radiation`).
    width = max(1, max(len(close) for close in model.neighbours))
    model.near_index = np.zeros((M, width), dtype=np.int64)
    model.near_valid = np.zeros((M, width), dtype=bool)
    model.near_full = np.zeros((M, width, m, m))
    model.near_blocks = model.near_full[..., 0]
    # The same blocks laid out for the products of `fields` and `radiation` (one contiguous matrix per
    # pillar): G_pq[k, 0] as (M, m, width) and G_pq[k, l > 0] as (M, m, width (m - 1)).
    model._near_uniform = np.zeros((M, m, width))
    model._near_higher = np.zeros((M, m, width, m - 1))
    model.near_slot = np.zeros((M, width), dtype=np.int64)
    slot_of = [{int(q): j for j, q in enumerate(close)} for close in model.neighbours]
    for p, close in enumerate(model.neighbours):
        model.near_index[p, :close.size] = close
        model.near_valid[p, :close.size] = True
        model.near_slot[p, :close.size] = [slot_of[int(q)][p] for q in close]
    for p in range(M):
        _install_row(model, p, upper=p)


def _install_basis(model: PillarModel, p: int) -> None:
    mask = model.raster[p]
    basis, origin = model.mask_basis(p, mask)
    model.basis[p] = basis
    model.origin[p] = origin
    model.centre[p] = origin + basis.centroid
    model.force[p] = basis.force
    model.gram[p] = basis.gram
    model.m0[p], model.m1[p], model.m2[p] = basis.m0, basis.m1, basis.m2
    model.phi[p] = 0.0
    model.phi[p, mask] = basis.phi
    within = model.full[p]
    foot = model.foot[p, :model.sizes[p]] - origin
    key = (basis.serial, foot.tobytes())
    cached = model._footprints.get(key)
    if cached is None:
        cached = np.concatenate([basis.polynomials(foot) @ basis.fit, _own_field(model, basis, foot, mask)],
                                axis=1)
        if len(model._footprints) > 20_000:
            model._footprints.clear()
            used = set(model.surface_group.tolist())
            model._groups = {group: array for group, array in model._groups.items() if group in used}
        model._footprints[key] = cached
        model._groups[id(cached)] = cached
    model.surface_map[p, within] = cached
    model.surface_group[p] = id(cached)
    model.fit_centre[:, p] = centre = cached[:, :model.m].mean(axis=0)
    model.fit_spread[:, p] = np.max(np.abs(cached[:, :model.m] - centre), axis=0)
    if model.lattice is not None:
        _shift_moments(model, np.array([p]))


def _own_field(model: PillarModel, basis: Basis, foot: np.ndarray, mask: np.ndarray) -> np.ndarray:
    """The displacement of ``basis``'s modes on the footprint slots ``foot`` (offsets from the raster's
    origin; ``mask`` those of the raster): K_FR Phi.  On a large footprint its raster's part is the
    polynomial K_RR Phi = P (Phi^T P)^-1 diag(gram) (K Phi lies in P's span), the rest a product."""
    if not model.large:
        K = model.ktab[np.abs(foot[:, None, 0] - basis.offsets[None, :, 0]),
                      np.abs(foot[:, None, 1] - basis.offsets[None, :, 1])]
        return K @ basis.phi
    on = mask[:foot.shape[0]]
    out = np.empty((foot.shape[0], basis.phi.shape[1]))
    out[on] = basis.polynomials(foot[on]) @ (basis.fit * basis.gram[None, :])
    off = foot[~on]
    K = model.ktab[np.abs(off[:, None, 0] - basis.offsets[None, :, 0]),
                  np.abs(off[:, None, 1] - basis.offsets[None, :, 1])]
    out[~on] = K @ basis.phi
    return out


def _exact(model: PillarModel, bp: Basis, origin: np.ndarray, q: int, p: int, mask: np.ndarray) -> np.ndarray:
    """Phi_p^T K_pq Phi_q, exact, for p's raster ``bp`` on its footprint slots ``mask`` at ``origin``;
    cached by the shapes and their offset.  On a large footprint through q's field across p's whole
    footprint (`_field_across`), kept while q's raster stands: p peeling costs a product of its raster."""
    bq = model.basis[q]
    if model.large:
        return bp.phi.T @ _field_across(model, p, q)[mask[:model.full[p].sum()]]
    dr, dc = model.origin[q] - origin
    key = (bp.serial, bq.serial, int(dr), int(dc))
    block = model._pairs.get(key)
    if block is None:
        a, b = bp.offsets, bq.offsets + (dr, dc)
        K = model.ktab[np.abs(a[:, None, 0] - b[None, :, 0]), np.abs(a[:, None, 1] - b[None, :, 1])]
        block = bp.phi.T @ K @ bq.phi
        if len(model._pairs) > 200_000:
            model._pairs.clear()
        model._pairs[key] = block
    return block


def _field_across(model: PillarModel, p: int, q: int) -> np.ndarray:
    """K_Fq Phi_q: the field of q's modes on every slot of p's footprint F; cached by q's raster shape,
    p's footprint shape and their offset."""
    bq = model.basis[q]
    foot = model.foot[p, :model.sizes[p]]
    corner = foot.min(axis=0)
    dr, dc = model.origin[q] - corner
    key = (bq.serial, int(dr), int(dc), (foot - corner).tobytes())
    field = model._fields.get(key)
    if field is None:
        if model._fields_bytes > 2**29:
            model._fields.clear()
            model._fields_bytes = 0
        a, b = foot - corner, bq.offsets + (dr, dc)
        K = model.ktab[np.abs(a[:, None, 0] - b[None, :, 0]), np.abs(a[:, None, 1] - b[None, :, 1])]
        field = model._fields[key] = K @ bq.phi
        model._fields_bytes += field.nbytes
    return field


def _far(model: PillarModel, bp: Basis, centre: np.ndarray, others: np.ndarray) -> np.ndarray:
    """Blocks G_pq (len(others), m, m) by the multipole expansion of 1/r to second order.

    With t the moments of p's modes and q those of the others' (the element square's own second moment
    h^2/12 added to the source), about their centroids R apart:
    G = t0 q0 f + (t1 q0 - t0 q1) . grad f + (t2 q0 - 2 t1 q1 + t0 q2) : hess f / 2, f = 1/r.
    With ``coupling = "local"`` only the uniform mode's row and column are filled.
    """
    ry, rx = centre[0] - model.centre[others, 0], centre[1] - model.centre[others, 1]
    r2 = ry * ry + rx * rx
    f = 1.0 / np.sqrt(r2)
    f3 = f / r2
    f5 = f3 / r2
    gy, gx = -ry * f3, -rx * f3
    hyy, hxy, hxx = 3.0 * ry * ry * f5 - f3, 3.0 * ry * rx * f5, 3.0 * rx * rx * f5 - f3
    t0, t1, t2 = bp.m0, bp.m1, bp.m2  # (m,), (m, 2), (m, 2, 2)
    q0, q1, q2 = model.m0[others], model.m1[others], model.m2[others]  # (J, m), (J, m, 2), (J, m, 2, 2)
    q1y, q1x = q1[..., 0], q1[..., 1]
    spread = q0 / 12.0
    q2h = (q2[..., 0, 0] + spread) * hyy[:, None] + 2.0 * q2[..., 0, 1] * hxy[:, None] \
        + (q2[..., 1, 1] + spread) * hxx[:, None]  # (J, n)
    q1g = q1y * gy[:, None] + q1x * gx[:, None]  # (J, n)
    H = np.stack([hyy, hxy, hxx], axis=1)  # (J, 3)
    t2h = H @ np.stack([t2[:, 0, 0], 2.0 * t2[:, 0, 1], t2[:, 1, 1]])  # (J, m)
    t1g = np.stack([gy, gx], axis=1) @ t1.T  # (J, m)
    # t1^T hess: (J, m, 2) as its y and x components.
    th_y = hyy[:, None] * t1[None, :, 0] + hxy[:, None] * t1[None, :, 1]
    th_x = hxy[:, None] * t1[None, :, 0] + hxx[:, None] * t1[None, :, 1]
    m = model.m
    g = np.zeros((others.size, m, m))
    if model.Gf is not None:
        g = (t0[None, :, None] * q0[:, None, :] * f[:, None, None]
             + t1g[:, :, None] * q0[:, None, :] - t0[None, :, None] * q1g[:, None, :]
             + 0.5 * (t2h[:, :, None] * q0[:, None, :] + t0[None, :, None] * q2h[:, None, :])
             - (th_y[:, :, None] * q1y[:, None, :] + th_x[:, :, None] * q1x[:, None, :]))
        return model.scale * g
    # Column 0 (all of p's modes, the others' uniform mode) and row 0 (p's uniform mode, all of theirs).
    g[:, :, 0] = (t0[None, :] * (q0[:, :1] * f[:, None]) + t1g * q0[:, :1] - t0[None, :] * q1g[:, :1]
                  + 0.5 * (t2h * q0[:, :1] + t0[None, :] * q2h[:, :1])
                  - (th_y * q1y[:, :1] + th_x * q1x[:, :1]))
    g[:, 0, 1:] = (t0[0] * q0[:, 1:] * f[:, None] + t1g[:, :1] * q0[:, 1:] - t0[0] * q1g[:, 1:]
                   + 0.5 * (t2h[:, :1] * q0[:, 1:] + t0[0] * q2h[:, 1:])
                   - (th_y[:, :1] * q1y[:, 1:] + th_x[:, :1] * q1x[:, 1:]))
    return model.scale * g


def _install_lattice_row(model: PillarModel, p: int, upper: int) -> None:
    """The exact near blocks of pillar p with its neighbours beyond ``upper`` (lattice storage), both ways."""
    bp, origin = model.basis[p], model.origin[p]
    close = model.neighbours[p]
    slots = np.flatnonzero(close > upper)
    if slots.size:
        _set_near_row(model, p, slots, close[slots],
                      np.stack([_exact(model, bp, origin, int(q), p, model.raster[p]) for q in close[slots]]))
    if model.G0 is not None and upper < 0:
        # The kept G00's entries of p are refreshed when they are next read (`uniform_block`), those
        # read only: a pillar that peels in steps or comes off is not recomputed against every pillar.
        model._clock += 1
        model._changed_at[p] = model._clock


def _set_near(model: PillarModel, p: int, j: int, q: int, block: np.ndarray) -> None:
    """G_pq = ``block`` for p's neighbour number j, q, and G_qp = block^T, in every layout."""
    i = model.near_slot[p, j]
    model.near_full[p, j] = block
    model.near_full[q, i] = block.T
    model._near_uniform[p, :, j] = block[:, 0]
    model._near_uniform[q, :, i] = block[0, :]
    model._near_higher[p, :, j] = block[:, 1:]
    model._near_higher[q, :, i] = block.T[:, 1:]


def _set_near_row(model: PillarModel, p: int, slots: np.ndarray, others: np.ndarray, blocks: np.ndarray) -> None:
    """`_set_near` for p's neighbours number ``slots`` (``others``) at once: G_pq = ``blocks`` (k, m, m)."""
    back = model.near_slot[p, slots]
    model.near_full[p, slots] = blocks
    model.near_full[others, back] = blocks.transpose(0, 2, 1)
    model._near_uniform[p, :, slots] = blocks[:, :, 0]
    model._near_uniform[others, :, back] = blocks[:, 0, :]
    model._near_higher[p, :, slots] = blocks[:, :, 1:]
    model._near_higher[others, :, back] = blocks.transpose(0, 2, 1)[:, :, 1:]


def _shift_moments(model: PillarModel, pillars: np.ndarray) -> None:
    """The lattice moments (`PillarModel.lattice_moments`) of ``pillars`` afresh from their bases."""
    if pillars.size == 1 and model.M > 1:
        _shift_one(model, int(pillars[0]))
        return
    delta = model.centre[pillars] - model.lattice.points[pillars]  # (P, 2)
    m0, m1, m2 = model.m0[pillars], model.m1[pillars], model.m2[pillars]
    t1 = m1 + m0[..., None] * delta[:, None, :]
    shift = m1[..., :, None] * delta[:, None, None, :]
    t2 = m2 + shift + shift.swapaxes(-1, -2) + m0[..., None, None] * (delta[:, :, None] * delta[:, None, :])[:, None]
    (q0, q1, q2), (s0, s1, s2) = model._moments
    s0[pillars], s1[pillars], s2[pillars] = m0, t1, t2
    q0[pillars], q1[pillars] = m0[:, 0], t1[:, 0]
    q2[pillars] = t2[:, 0] + (m0[:, 0] / 12.0)[:, None, None] * np.eye(2)
    weights = Lattice.weights((q0[pillars], q1[pillars], q2[pillars]), (s0[pillars], s1[pillars], s2[pillars]))
    if pillars.size == model.M:
        model._weights = weights
    else:
        model._weights[0][:, pillars], model._weights[1][pillars] = weights


def _shift_one(model: PillarModel, p: int) -> None:
    """`_shift_moments` of one pillar (a raster changed): the same sums, without the arrays of a batch."""
    delta = model.centre[p] - model.lattice.points[p]
    m0, m1, m2 = model.m0[p], model.m1[p], model.m2[p]
    t1 = m1 + m0[:, None] * delta[None, :]
    shift = m1[:, :, None] * delta[None, None, :]
    t2 = m2 + shift + shift.swapaxes(-1, -2) + m0[:, None, None] * (delta[:, None] * delta[None, :])[None]
    (q0, q1, q2), (s0, s1, s2) = model._moments
    s0[p], s1[p], s2[p] = m0, t1, t2
    q0[p], q1[p] = m0[0], t1[0]
    q2[p] = t2[0] + (m0[0] / 12.0) * np.eye(2)
    model._weights[0][:, p] = (q0[p], q1[p, 0], q1[p, 1], q2[p, 0, 0], q2[p, 0, 1], q2[p, 1, 1])
    targets = model._weights[1][p]  # (m, 6): `Lattice.weights`'s targets
    targets[:, 0], targets[:, 1], targets[:, 2] = m0, t1[:, 0], t1[:, 1]
    targets[:, 3], targets[:, 4], targets[:, 5] = 0.5 * t2[:, 0, 0], t2[:, 0, 1], 0.5 * t2[:, 1, 1]


def _lattice_block(model: PillarModel, rows: np.ndarray, cols: np.ndarray) -> np.ndarray:
    """G00[rows, cols] on a lattice: the far pairs' multipoles as the FFT sums them, the near ones exact."""
    sources, _ = model.lattice_moments(cols)
    _, targets = model.lattice_moments(rows)
    out = np.empty((rows.size, cols.size))
    # In slabs of rows: the pair arithmetic's temporaries stay near 2^20 numbers each.
    slab = max(1, 2**20 // max(cols.size, 1))
    for start in range(0, rows.size, slab):
        part = slice(start, start + slab)
        out[part] = model.lattice.pair_couplings(rows[part], cols, sources,
                                                tuple(a[part, 0] for a in targets))
    position = np.full(model.M, -1)
    position[cols] = np.arange(cols.size)
    where = position[model.near_index[rows]]
    hit = model.near_valid[rows] & (where >= 0)
    out[np.nonzero(hit)[0], where[hit]] = model.near_blocks[rows][..., 0][hit]
    same = position[rows]
    out[np.flatnonzero(same >= 0), same[same >= 0]] = model.gram[rows[same >= 0], 0]
    return out


def _install_row(model: PillarModel, p: int, upper: int = -1) -> None:
    """Blocks G_pq for every q > ``upper`` (all when -1), written to both triangles."""
    if model.lattice is not None:
        _install_lattice_row(model, p, upper)
        return
    others, blocks, _ = model.blocks(p, upper=upper)
    for j, q in enumerate(model.neighbours[p]):
        if q > upper:
            _set_near(model, p, j, int(q), blocks[np.searchsorted(others, q)])
    model.G0[p, others] = model.G0[others, p] = blocks[:, 0, 0]
    model.G0[p, p] = model.gram[p, 0]
    if model.m > 1:
        model.Gh[:, p, others] = blocks[:, 1:, 0].T
        model.Gh[:, others, p] = blocks[:, 0, 1:].T
        model.Gh[:, p, p] = 0.0
    if model.Gf is not None:
        model.Gf[p, others] = blocks
        model.Gf[others, p] = blocks.transpose(0, 2, 1)
        model.Gf[p, p] = np.diag(model.gram[p])
