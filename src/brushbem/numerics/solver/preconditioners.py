"""Preconditioners of A_S: shifted Laplacian, springs by Woodbury, and the two-level pillar blocks of a brush."""

from __future__ import annotations

import math

import numpy as np
import scipy.linalg
from scipy import sparse
from scipy.sparse import linalg as sparse_linalg

from brushbem import backend, settings
from brushbem.numerics.operator import ContactOperator, ContactSystem
from brushbem.numerics.solver.cache import SolverCache

__all__ = [
    "BLOCK_LIMIT",
    "MAX_BLOCK_PILLARS",
    "PRECONDITIONER_SHIFT",
    "contact_preconditioner",
    "laplacian_preconditioner",
    "pillar_block_preconditioner",
    "spring_preconditioner",
]


#: Largest pillar contact (elements) that ``pillar_block_preconditioner`` inverts exactly.
BLOCK_LIMIT = 256

#: Most pillars for the pillar-block path (its coarse matrices are dense: 2 x 8 n^2 bytes, 85 MB at 2304).
MAX_BLOCK_PILLARS = 3000

#: Random odd multipliers and offsets of the shape signature of a pillar's contact (fixed seed).
_HASH_WEIGHTS = np.random.default_rng(20261121).integers(1, 2**63, size=(2, BLOCK_LIMIT + 1), dtype=np.uint64) | np.uint64(1)

#: Shift of the Laplacian preconditioner, in units of 1/h^2 (see laplacian_preconditioner).
PRECONDITIONER_SHIFT = 0.3


def laplacian_preconditioner(mask, shift: float = PRECONDITIONER_SHIFT):
    """M^-1 = P_S (shift I - Delta_h) P_S: a shifted 5-point Laplacian on the contact set.

    The half-space operator has the symbol 1/(E* |xi|), so its inverse behaves
    like |xi|; ``shift + |xi|^2`` (in element units) follows it at the scale
    where the two meet and, restricted to S with zero values outside
    (symmetric positive definite), brings the condition number of K_S from
    O(D/h) down to about O(sqrt(D/h)), D the size of the contact.  It costs a
    few array passes, far less than one FFT pair, and cut the CG iterations
    2-3 fold on contacts 20-160 elements wide (``benchmarks/preconditioner.py``).
    The constant factor of M does not matter to CG.
    """

    # A 0/1 float mask: multiplying by it is twice as fast as by a bool array.
    xp = backend.namespace(mask)
    maskf = xp.astype(mask, xp.float64)

    def apply(residual):
        z = residual * maskf
        out = (4.0 + shift) * z
        out[1:, :] -= z[:-1, :]
        out[:-1, :] -= z[1:, :]
        out[:, 1:] -= z[:, :-1]
        out[:, :-1] -= z[:, 1:]
        return out

    return apply


def _cut_laplacian(labels, shift: float):
    """``z -> (4 + shift) z - sum of the 4 neighbours with the same label``: block diagonal per pillar."""
    # Float weights: multiplying by a bool array would convert it on every call.
    xp = backend.namespace(labels)
    same_rows = xp.astype((labels[1:, :] == labels[:-1, :]) & (labels[1:, :] >= 0), xp.float64)
    same_cols = xp.astype((labels[:, 1:] == labels[:, :-1]) & (labels[:, 1:] >= 0), xp.float64)

    def apply(z):
        out = (4.0 + shift) * z
        out[1:, :] -= z[:-1, :] * same_rows
        out[:-1, :] -= z[1:, :] * same_rows
        out[:, 1:] -= z[:, :-1] * same_cols
        out[:, :-1] -= z[:, 1:] * same_cols
        return out

    return apply


def spring_preconditioner(operator: ContactOperator, mask, shift: float = PRECONDITIONER_SHIFT):
    """Preconditioner for A_S = K_S + Z C Z^T that stays good for arbitrarily soft springs.

    Z is the element-to-unit incidence on S over every elastic level (a unit is
    a pillar or a cluster), C = diag(h^2 / k).  The soft springs put eigenvalues
    of order h^2 n / k on the span of Z; a Laplacian preconditioner alone
    leaves them there and CG needs thousands of iterations at k~ = 1e-5.  Here
    K_S^-1 is approximated by B = alpha P_S (shift I - Delta_cut) P_S, the
    shifted 5-point Laplacian with its couplings cut between different
    pillars (so B is block diagonal per pillar), and the spring term is added
    exactly through the Woodbury identity:

        M^-1 = (B^-1 + Z C Z^T)^-1 = B - B Z G^-1 Z^T B,   G = C^-1 + Z^T B Z.

    Because B is block diagonal per pillar, Z^T B Z = Q^T diag(T) Q with Q the
    pillar-to-unit incidence and T_n = 1^T B_n 1, so G is a small sparse
    matrix (diagonal for one level) factorised once per contact set.  The
    scale alpha_n of every pillar block is chosen so that T_n equals the
    stiffness of a rigid circular punch of the pillar's contact area,
    2 E* sqrt(A_n / pi) / h^2 (the mean-mode response of K_n^-1), so the
    preconditioner and A agree on the pillar-mean modes whatever k is.  M^-1
    is symmetric positive definite; each application costs two stencil passes,
    two segment sums and one sparse triangular solve on the units.

    Why one function: it builds one M^-1 (the stencil, the unit graph and its sparse factor) and returns the
    closure that applies it; the pieces only make sense together.
    """
    xp = operator.xp
    labels_np = np.asarray(operator.pillar_labels)
    mask_np = np.asarray(backend.to_numpy(mask), dtype=bool) & (labels_np >= 0)
    n_pillars = operator.indenter.n_pillars
    h = operator.halfspace.element_size
    laplacian = _cut_laplacian(xp.asarray(labels_np), shift)
    maskf = xp.asarray(mask_np.astype(float))
    flat_labels = np.where(mask_np, labels_np, n_pillars).ravel()
    # Sums over the pillars only need the elements of S.
    in_contact = np.flatnonzero(mask_np.ravel())
    contact_index = xp.asarray(in_contact)
    contact_labels = xp.asarray(flat_labels[in_contact])
    window_labels = xp.asarray(flat_labels)
    counts = np.bincount(flat_labels, minlength=n_pillars + 1)[:n_pillars]
    diag_l = np.bincount(flat_labels, weights=np.asarray(backend.to_numpy(laplacian(maskf))).ravel(),
                         minlength=n_pillars + 1)[:n_pillars]
    target = 2.0 * operator.halfspace.contact_modulus * np.sqrt(counts / math.pi) / h
    alpha = np.where(counts > 0, target / np.where(diag_l > 0, diag_l, 1.0), 0.0)
    alpha_elements = xp.asarray(np.append(alpha, 0.0)[np.where(labels_np >= 0, labels_np, n_pillars)])

    # Pillar-to-unit incidence Q over the elastic levels and G = C^-1 + Q^T diag(T) Q.
    rows, cols, inverse_compliance = [], [], []
    offset = 0
    for compliance, cluster in operator.spring_levels:
        n_units = int(cluster.max()) + 1
        rows.append(np.arange(n_pillars))
        cols.append(offset + cluster)
        inverse_compliance.append(1.0 / np.broadcast_to(compliance, (n_units,)))
        offset += n_units
    incidence = sparse.csr_matrix(
        (np.ones(sum(len(r) for r in rows)), (np.concatenate(rows), np.concatenate(cols))),
        shape=(n_pillars, offset),
    )
    coarse = sparse.diags(np.concatenate(inverse_compliance)) + incidence.T @ sparse.diags(target) @ incidence
    coarse = sparse.csc_matrix(coarse)
    if coarse.nnz == offset:  # one level of one-pillar units: G is diagonal
        diagonal = coarse.diagonal()

        def coarse_solve(b):
            return b / diagonal
    else:
        coarse_solve = sparse_linalg.factorized(coarse)
    incidence_t = incidence.T.tocsr()

    if backend.is_numpy_namespace(xp):
        # On the CPU, B restricted to S as a sparse matrix: each application
        # touches the |S| contact elements only, not every window element.
        size = mask_np.size
        labels_c = flat_labels[in_contact]
        local = np.full(size, -1, dtype=np.int64)
        local[in_contact] = np.arange(in_contact.size)
        grid_local = local.reshape(mask_np.shape)
        pairs = []
        for a, b in ((grid_local[:, :-1], grid_local[:, 1:]), (grid_local[:-1, :], grid_local[1:, :])):
            both = (a >= 0) & (b >= 0)
            ia, ib = a[both], b[both]
            same = labels_c[ia] == labels_c[ib]
            pairs.append((ia[same], ib[same]))
        i_nb = np.concatenate([p[0] for p in pairs] + [p[1] for p in pairs])
        j_nb = np.concatenate([p[1] for p in pairs] + [p[0] for p in pairs])
        scale_c = np.append(alpha, 0.0)[labels_c]
        n_c = in_contact.size
        blocked = sparse.csr_matrix(
            (np.concatenate([scale_c * (4.0 + shift), -scale_c[i_nb]]),
             (np.concatenate([np.arange(n_c), i_nb]), np.concatenate([np.arange(n_c), j_nb]))),
            shape=(n_c, n_c),
        )

        def apply(residual):
            z = blocked @ residual.reshape(-1)[in_contact]
            sums = np.bincount(labels_c, weights=z, minlength=n_pillars + 1)[:n_pillars]
            y = np.append(incidence @ coarse_solve(incidence_t @ sums), 0.0)
            out = np.zeros(size)
            out[in_contact] = z - blocked @ y[labels_c]
            return out.reshape(mask_np.shape)

        return apply

    # On a device: the pillar-to-unit sums, the coarse solve and the spread all stay there (no host copy
    # inside a CG iteration).  G is small and dense there: factorised once on the host (`backend.spd_solver`).
    unit_solve = (lambda b: b / xp.asarray(coarse.diagonal())) if coarse.nnz == offset else \
        backend.spd_solver(xp, coarse.toarray())
    levels = []  # (cluster of every pillar, number of clusters, first unit) per level, as G orders its units
    first = 0
    for _, cluster in operator.spring_levels:
        count = int(np.asarray(cluster).max()) + 1
        levels.append((xp.asarray(np.asarray(cluster)), count, first))
        first += count
    zero = xp.zeros(1, dtype=xp.float64)

    def apply(residual):
        z = alpha_elements * laplacian(residual * maskf)
        sums = backend.segment_sum(xp, contact_labels, xp.reshape(z, (-1,))[contact_index], n_pillars)
        on_units = [backend.segment_sum(xp, cluster, sums, count) for cluster, count, _ in levels]  # Q^T sums
        solved = unit_solve(on_units[0] if len(on_units) == 1 else xp.concat(on_units))
        y = sum(xp.take(solved[start:start + count], cluster) for cluster, count, start in levels)  # Q w
        spread = xp.take(xp.concat([y, zero]), window_labels)  # a gather: zero off S (the dummy pillar)
        return z - alpha_elements * laplacian(xp.reshape(spread, z.shape))

    return apply


def contact_preconditioner(operator: ContactOperator, mask):
    """The preconditioner for A_S: `spring_preconditioner` with springs, else `laplacian_preconditioner`."""
    if operator.has_springs:
        return spring_preconditioner(operator, mask)
    return laplacian_preconditioner(mask)


def pillar_block_preconditioner(system: ContactSystem, max_block: int = BLOCK_LIMIT,
                                cache: SolverCache | None = None):
    """Two-level preconditioner for A_S on the pillars of a brush (vectors on S), or None.

    A_S = K_S + Z H_s Z^T, Z the element-to-pillar incidence on S and H_s the
    spring compliances (h^2/k_l for every pair of pillars under the same unit
    of level l).  It is approximated by

        M = B + Z (H_s + G) Z^T,

    B = blockdiag(K_n) the exact half-space blocks of the pillars' contact
    elements (inverted once per shape, ``HalfSpace.block_inverse``) and G the
    far-field coupling of the pillars as point loads, G_mn = h^2 / (pi E* r_mn)
    between their footprint centroids.  By the Woodbury identity

        M^-1 = B^-1 - B^-1 Z X Z^T B^-1,  X = T^-1 - T^-1 (T^-1 + H)^-1 T^-1,

    with T = Z^T B^-1 Z = diag(1^T K_n^-1 1) (each pillar's exact mean-mode
    stiffness) and H = H_s + G, so a solve with the dense pillar matrix
    T^-1 + H (the brush as interacting punches on springs) is all the
    coarse work.  M^-1 is SPD exactly when T^-1 + H is; where the point-load
    coupling makes it indefinite (pillars much closer than their size) G is
    dropped, which leaves the exact blocks and the springs.  Within a pillar
    the preconditioner is exact, between pillars it keeps the interaction of
    their mean modes, so the CG iterations no longer depend on the pillar
    stiffness nor much on the number of pillars (tests/test_brush.py and
    ``benchmarks/preconditioner.py``).

    Returns None when an element of S lies off the pillars or a pillar's
    contact has more than ``max_block`` elements (a large punch or sphere:
    the blocks would cost more than they save).

    Why one function: it builds one M^-1 from the pillar blocks, the coarse pillar-space matrix and their
    reuse in `PillarCache`, and returns the closure that applies it; the reuse logic needs all three.

    ``cache``: the caller's `SolverCache`, whose `PillarCache` it reads and fills (None: a fresh one, nothing
    reused).
    """
    labels = system.pillars
    if system.size == 0 or bool(np.any(labels < 0)):
        return None
    order = np.argsort(labels, kind="stable")  # by pillar, row-major within each
    sorted_labels = labels[order]
    starts = np.flatnonzero(np.r_[True, sorted_labels[1:] != sorted_labels[:-1]])
    counts = np.diff(np.r_[starts, sorted_labels.size])
    if int(counts.max()) > max_block:
        return None
    operator = system.operator
    halfspace = operator.halfspace
    active = sorted_labels[starts]
    rows = system.element_rows[order]
    cols = system.element_cols[order]
    # Pillars whose contacts have the same shape share one inverse block.  The
    # shapes are told apart by a hash of their element offsets (checked
    # exactly within every group), without a Python loop over the pillars.
    segment = np.repeat(np.arange(active.size), counts)
    rel_rows = rows - np.minimum.reduceat(rows, starts)[segment]
    rel_cols = cols - np.minimum.reduceat(cols, starts)[segment]
    codes = rel_rows * (2 * BLOCK_LIMIT + 1) + rel_cols  # a contact of <= BLOCK_LIMIT elements spans fewer
    rank = np.arange(rows.size) - starts[segment]
    with np.errstate(over="ignore"):
        mixed = codes.astype(np.uint64) * _HASH_WEIGHTS[0][rank] + _HASH_WEIGHTS[1][rank]
        signature = np.add.reduceat(mixed, starts) + counts.astype(np.uint64) * np.uint64(0x9E3779B97F4A7C15)
    _, group_of = np.unique(signature, return_inverse=True)
    by_group = np.argsort(group_of, kind="stable")
    group_starts = np.flatnonzero(np.r_[True, group_of[by_group][1:] != group_of[by_group][:-1]])
    group_members = np.split(by_group, group_starts[1:])
    blocks = []  # (element indices on S (members x k), members, inverse, inverse @ 1)
    stiffness = np.empty(active.size)
    # Each pillar's last block (grid coordinates, inverse) and its signature:
    # a pillar that lost a few elements since is downdated from it
    # (HalfSpace.block_inverse).
    solver_cache = SolverCache() if cache is None else cache
    cache = solver_cache.pillars
    previous = cache.blocks
    if cache.signature is None:
        cache.signature = np.zeros(operator.indenter.n_pillars, dtype=np.uint64)
    last = cache.signature
    r0, c0 = operator.window.r0, operator.window.c0

    def grid_offsets(member: int, k: int):
        start = int(starts[member])
        return np.stack([rows[start : start + k] + r0, cols[start : start + k] + c0], axis=1)

    pending = list(group_members)
    while pending:
        members = pending.pop()
        k = int(counts[members[0]])
        at = starts[members][:, None] + np.arange(k)[None, :] if bool(np.all(counts[members] == k)) else None
        same = None if at is None else np.all(codes[at] == codes[at[0]], axis=1)
        if same is None or not bool(np.all(same)):  # a hash collision: split the group
            exact: dict[bytes, list[int]] = {}
            for member in members.tolist():
                start = int(starts[member])
                exact.setdefault(codes[start : start + int(counts[member])].tobytes(), []).append(member)
            pending.extend(np.asarray(m) for m in exact.values())
            continue
        elements = order[at]
        inverse = halfspace.block_inverse(grid_offsets(members[0], k), parent=previous.get(int(active[members[0]])))
        pillars = active[members]
        for member in members[last[pillars] != signature[members]].tolist():
            previous[int(active[member])] = (grid_offsets(member, k), inverse)
        last[pillars] = signature[members]
        row_sums = inverse.sum(axis=1)
        stiffness[members] = row_sums.sum()
        blocks.append((elements, members, inverse, row_sums))
    coarse = _coarse_factor(operator, solver_cache, active, stiffness)
    xp = system.xp

    def apply(residual):
        r = np.asarray(backend.to_numpy(residual))
        z = np.empty_like(r)
        sums = np.empty(active.size)
        for elements, members, inverse, _ in blocks:
            local = r[elements] @ inverse  # inverse is symmetric
            z[elements] = local
            sums[members] = local.sum(axis=1)
        if coarse is not None:
            solve, positions, reference, size = coarse
            scaled = np.zeros(size)
            scaled[positions] = sums / reference
            correction = sums / reference - solve(scaled)[positions] / reference
            for elements, members, _, row_sums in blocks:
                z[elements] -= correction[members][:, None] * row_sums[None, :]
        return xp.asarray(z)

    return apply


#: A coarse factorisation is kept while at most this fraction of its pillars
#: (and at least 2) have lost more than ``_COARSE_DRIFT`` of their stiffness.
_COARSE_STALE = 0.02
_COARSE_DRIFT = 0.3
#: Fewer pillars than this are refactorised for every contact set (a few ms).
_COARSE_REUSE_MIN = 1024
#: ... and the largest fraction of the factorised pillars that may have left the contact set.
_COARSE_UPDATE_SHRINK = 0.25


class _CoarseBase:
    """The Cholesky factor of M0 = T0^-1 + H on the pillars P0, and solves with the matrices near it.

    Between two solves of a pull-off the coarse matrix changes on a few pillars
    only: a pillar leaves the contact set (its row and column go) or loses
    elements (its entry of T^-1 grows).  The matrix on the pillars S of P0
    with the stiffnesses T is M = (M0 + E diag(delta) E^T)_SS, delta = T^-1 -
    T0^-1 on the pillars that changed and E their columns of the identity.
    With R the pillars of P0 off S, the solution x of M x = b is the x of the
    bordered system

        (M0 + E diag(delta) E^T) x + E_R lambda = b,   x_R = 0,

    and with y = M0^-1 b and W = M0^-1 [E E_R] the corrections z of rank
    k = |changed| + |R| solve one k x k system:  x = y - W z.  The columns of
    W are kept from one solve to the next (they depend on the pillars only,
    not on delta), so a solve with one more pillar changed costs one more
    pair of triangular solves instead of a factorisation; the result is the
    factorised matrix's to rounding.  Used only while T^-1 does not fall
    (every delta >= 0) on a matrix that was factorised with the point-load
    coupling: M is then a principal block of an SPD matrix plus a positive
    diagonal, SPD as a fresh factorisation would find it.
    """

    def __init__(self, factor, pillars: np.ndarray, compliance: np.ndarray):
        self.factor = factor
        self.pillars = pillars
        self.compliance = compliance
        self.columns = np.empty(0, dtype=np.int64)  # positions in P0 with a column of M0^-1
        self.inverse_columns = np.empty((pillars.size, 0))
        self.last: tuple | None = None  # (pillars, stiffness, solve) of the last call

    def solve(self, b):
        return scipy.linalg.cho_solve(self.factor, b, check_finite=False)

    def near(self, active: np.ndarray, stiffness: np.ndarray):
        """``b -> M^-1 b`` on ``active`` (module docstring), or None when M is too far from M0."""
        last = self.last
        if last is not None and np.array_equal(last[0], active) and np.array_equal(last[1], stiffness):
            return last[2]
        n0 = self.pillars.size
        positions = np.searchsorted(self.pillars, active)
        if bool(np.any(positions >= n0)) or not np.array_equal(self.pillars[np.minimum(positions, n0 - 1)], active):
            return None
        delta = 1.0 / stiffness - self.compliance[positions]
        if bool(np.any(delta < 0)):
            return None
        kept = np.zeros(n0, dtype=bool)
        kept[positions] = True
        removed = np.flatnonzero(~kept)
        if removed.size > _COARSE_UPDATE_SHRINK * n0:
            return None
        dirty = np.union1d(positions[delta != 0], removed)
        if dirty.size > settings.switches().coarse_update_rank:
            return None
        if dirty.size == 0:
            solve = self.solve
        else:
            new = np.setdiff1d(dirty, self.columns, assume_unique=True)
            if new.size:
                unit = np.zeros((n0, new.size))
                unit[new, np.arange(new.size)] = 1.0
                self.inverse_columns = np.concatenate([self.inverse_columns, self.solve(unit)], axis=1)
                self.columns = np.concatenate([self.columns, new])
            order = np.argsort(self.columns)
            w = self.inverse_columns[:, order[np.searchsorted(self.columns[order], dirty)]]
            g = w[dirty, :]
            out = ~kept[dirty]
            full_delta = np.zeros(n0)
            full_delta[positions] = delta
            scale = np.where(out, 1.0, full_delta[dirty])
            system = np.where(out[:, None], g, np.eye(dirty.size) + scale[:, None] * g)
            lu = scipy.linalg.lu_factor(system, check_finite=False)
            base = self.solve

            def solve(b):
                full = np.zeros(n0)
                full[positions] = b
                y = base(full)
                z = scipy.linalg.lu_solve(lu, scale * y[dirty], check_finite=False)
                # Not w @ z: BLAS would thread this small product (see `cg._dot`).
                return (y - np.einsum("ij,j->i", w, z))[positions]

        self.last = (active.copy(), stiffness.copy(), solve)
        return solve


def _coarse_factor(operator: ContactOperator, solver_cache: SolverCache, active, stiffness):
    """Solves with T^-1 + H on the pillars ``active`` for `pillar_block_preconditioner`.

    Returns (``b -> (T_0^-1 + H)^-1 b`` on the pillars of the factorised set,
    positions of ``active`` in that set, T_0 used, its size) or None.  The
    factorisation (dense, O(n^3) for n pillars) is reused from an earlier
    contact set (with at least ``_COARSE_REUSE_MIN`` pillars; smaller ones are
    refactorised every time) while the pillars are a subset of its pillars and
    none has become stiffer: the correction X0 = T0^-1 - T0^-1 (T0^-1 + H)^-1
    T0^-1 then still satisfies X0 < T0^-1 <= T^-1 on any subset, which keeps
    M^-1 positive definite, and only its accuracy on the pillars that lost
    contact suffers.  A new one is made when more than ``_COARSE_STALE`` of
    the pillars lost over ``_COARSE_DRIFT`` of their stiffness.  A new one is
    the exact matrix of ``active``: solved through the last Cholesky factor
    and a low-rank correction while the two differ on at most
    ``Switches.coarse_update_rank`` pillars (`_CoarseBase`), else factorised.
    """
    cache = solver_cache.pillars
    cached = cache.coarse
    if cached is not None:
        solve, pillars, reference = cached
        positions = np.searchsorted(pillars, active)
        inside = positions < pillars.size
        if pillars.size >= _COARSE_REUSE_MIN and bool(np.all(inside)) and np.array_equal(pillars[positions], active):
            base = reference[positions]
            if bool(np.all(stiffness <= base * (1 + 1e-9))):
                stale = int(np.sum(stiffness < (1 - _COARSE_DRIFT) * base)) + (pillars.size - active.size)
                if stale <= max(2, _COARSE_STALE * pillars.size):
                    return solve, positions, base, pillars.size
    factored = cache.coarse_base
    solve = None if factored is None or settings.switches().coarse_update_rank <= 0 else factored.near(active, stiffness)
    if solve is not None:
        cache.coarse = (solve, np.array(active), stiffness.copy())
        return solve, np.arange(active.size), stiffness, active.size
    coupling = cache.coupling
    if coupling is None:
        # H over all pillars (fixed): springs of every level and the point-load coupling.
        halfspace = operator.halfspace
        h = halfspace.element_size
        n = operator.indenter.n_pillars
        springs = np.zeros((n, n))
        for compliance, cluster in operator.spring_levels:
            units = np.asarray(cluster)
            springs += np.asarray(compliance)[units][:, None] * (units[:, None] == units[None, :])
        centres = solver_cache.pillar_centres(operator)
        distance = np.sqrt(((centres[:, None, :] - centres[None, :, :]) ** 2).sum(axis=-1)) * h
        np.fill_diagonal(distance, np.inf)
        coupling = (springs + h * h / (math.pi * halfspace.contact_modulus * distance), springs)
        cache.coupling = coupling
    selection = np.ix_(active, active)
    matrix, springs_only = coupling[0][selection], coupling[1][selection]
    cache.coarse_base = None
    for with_coupling, candidate in ((True, matrix), (False, springs_only)):
        candidate[np.diag_indices(active.size)] += 1.0 / stiffness
        try:
            factor = scipy.linalg.cho_factor(candidate, lower=True, overwrite_a=True)
        except np.linalg.LinAlgError:
            continue
        pillars = np.array(active)
        base = _CoarseBase(factor, pillars, 1.0 / stiffness)
        if with_coupling:
            # Only a factor with the point-load coupling is the one a fresh factorisation would find.
            cache.coarse_base = base
        cache.coarse = (base.solve, pillars, stiffness.copy())
        return base.solve, np.arange(active.size), stiffness, active.size
    return None
