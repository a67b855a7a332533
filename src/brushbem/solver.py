"""Solvers: conjugate gradients on a contact set, and the adhesive equilibrium.

``conjugate_gradient`` solves A_S p = rhs on a fixed contact set S (A symmetric
positive definite on S), warm-started, and returns a frozen ``SolveResult``.

``equilibrium`` finds the state at a fixed base displacement d with the
Pohrt-Popov detachment criterion (thesis sec. 2.2.2, 3.4): solve on S; detach
every element whose tension exceeds the critical stress
Sigma_c = sqrt(E* dgamma / (0.473201 h)) (eq. 2.14); attach every footprint
element that the tip penetrates; repeat until S is stable.  Detachment rule:
all violators of one solve leave together (the thesis's rule, "exclude those
elements ... whose tensile stress are larger than Sigma_c"); the rule changes
the post-peak tail of very soft brushes, not the peak.

Without adhesion (dgamma = 0) the problem is a convex linear complementarity
problem with a unique solution; ``polonsky_keer`` solves it in one constrained
CG loop (Polonsky & Keer 1999), which is much cheaper than the active-set
loop.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
import scipy.linalg
from scipy import sparse
from scipy.sparse import linalg as sparse_linalg

from . import backend
from .operator import ContactOperator, ContactSystem

__all__ = [
    "Equilibrium",
    "SolveResult",
    "conjugate_gradient",
    "contact_preconditioner",
    "critical_stress",
    "equilibrium",
    "laplacian_preconditioner",
    "local_cascade",
    "pillar_block_preconditioner",
    "polonsky_keer",
    "solve_on_set",
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

#: Smallest relative residual ||r|| / ||rhs|| that a CG solve is asked to
#: reach: 16 ulps.  A punch on a spring of k / (2 E* a) = 2e-6 needs 2e-14
#: at tolerance 1e-8 and still gives the stiff spring's F_A to 1e-8
#: (`tests/test_reliability_numerics.py`); below that the recursion's
#: residual drifts from the true one.
ROUNDING_FLOOR = 16 * 2.0**-52

#: SolveResult.reason when the warm start already met the tolerance (solution = initial on the mask).
WARM_START_WITHIN_TOLERANCE = "initial guess within tolerance"

#: Elastic energy of a uniformly loaded square element, in units of p^2 h^3 / E* (eq. 2.13).
ELEMENT_ENERGY_COEFFICIENT = 0.473201


def critical_stress(contact_modulus: float, work_of_adhesion: float, element_size: float) -> float:
    """Sigma_c = sqrt(E* dgamma / (0.473201 h)), thesis eq. 2.14, in units of stress."""
    return math.sqrt(contact_modulus * work_of_adhesion / (ELEMENT_ENERGY_COEFFICIENT * element_size))


@dataclass(frozen=True)
class SolveResult:
    """Outcome of one linear solve.

    Attributes
    ----------
    solution : ndarray
        The pressure (zero outside the set), in units of stress.
    converged : bool
    reason : str
        Why the iteration stopped.
    iterations : int
    residual : float
        Final relative residual ||rhs - A x|| / ||rhs|| on the set.
    residual_history : tuple of float
        Relative residual after every iteration (first entry: initial guess).
    """

    solution: object
    converged: bool
    reason: str
    iterations: int
    residual: float
    residual_history: tuple[float, ...]


def _dot(xp, a, b) -> float:
    # Not a matrix product: BLAS threads its dot products of this size, which
    # was 5x slower in total on a busy 2-core machine and not reproducible.
    return float(xp.sum(a * b))


def conjugate_gradient(
    apply,
    rhs,
    mask,
    initial=None,
    tolerance: float = 1e-8,
    max_iterations: int = 10000,
    preconditioner=None,
    xp=None,
    initial_product=None,
    reference=None,
) -> SolveResult:
    """Preconditioned CG for ``apply(x) = rhs`` on the elements where ``mask`` is True.

    Parameters
    ----------
    apply : callable
        ``apply(x) -> A_S x`` for x zero outside the mask; must return zero
        outside the mask.
    rhs : ndarray
        Right-hand side (only the masked entries matter).
    mask : ndarray of bool
        The set S.
    initial : ndarray, optional
        Warm start (restricted to the mask).
    tolerance : float
        Target relative residual.
    max_iterations : int
    preconditioner : callable, optional
        ``preconditioner(r) -> M^-1 r``, symmetric positive definite on S.
    initial_product : ndarray, optional
        The operator applied to ``initial`` (only its masked entries are
        used), when the caller knows it: saves the first ``apply``.
    reference : callable, optional
        ``reference(x) -> float``: the norm the residual must be small
        against, when that is not ||rhs||.  A spring-mounted indenter's rhs
        is mostly the springs' deflection, while the pressure the criterion
        reads is set by the half-space's part, ||rhs - S x|| (S the spring
        sums): a residual of ``tolerance`` x ||rhs|| can leave that part
        unsolved.  Checked (it is cheap: no transform) each time the residual
        passes ``tolerance`` x ||rhs||; the iteration then goes on until
        ||r|| <= ``tolerance`` x ``reference(x)``.  When that is below what
        double precision resolves against ||rhs|| (``ROUNDING_FLOOR`` x
        ||rhs||), the solve stops not converged, saying so.
    """
    if xp is None:
        from .backend import namespace

        xp = namespace(rhs)
    maskf = xp.astype(mask, rhs.dtype)
    rhs = rhs * maskf
    rhs_norm = math.sqrt(_dot(xp, rhs, rhs))
    if rhs_norm == 0.0:
        return SolveResult(xp.zeros_like(rhs), True, "zero right-hand side", 0, 0.0, (0.0,))
    x = xp.zeros_like(rhs) if initial is None else initial * maskf
    if initial is None:
        residual = rhs
    elif initial_product is not None:
        residual = rhs - initial_product * maskf
    else:
        residual = rhs - apply(x)
    relative = math.sqrt(_dot(xp, residual, residual)) / rhs_norm
    history = [relative]
    # The residual ||r|| / ||rhs|| that counts as converged: lowered when the
    # reference norm asks for more (and then never raised again).
    threshold = tolerance

    def accepted(x) -> SolveResult | bool:
        """True when the reference agrees; a not-converged result when it cannot be met."""
        nonlocal threshold
        if reference is None:
            return True
        wanted = tolerance * float(reference(x)) / rhs_norm
        if wanted >= relative:
            return True
        if wanted < ROUNDING_FLOOR:
            return SolveResult(x, False, (
                f"double precision cannot resolve the half-space's part of the solve: it is "
                f"{wanted / tolerance:.2g} of the right-hand side (the springs' deflection carries the rest), "
                f"so a relative residual of {tolerance:g} on it is below rounding; use stiffer springs, a "
                f"larger solver.tolerance, or a load-controlled model"), 0, relative, tuple(history))
        threshold = wanted
        return False

    if relative <= threshold:
        verdict = accepted(x)
        if verdict is True:
            return SolveResult(x, True, WARM_START_WITHIN_TOLERANCE, 0, relative, tuple(history))
        if isinstance(verdict, SolveResult):
            return verdict
    # x, residual and direction are private arrays from here on (residual may
    # be the masked copy of rhs) and are updated in place: fewer temporaries
    # matter on the small blocks the solves run on.
    direction = residual * maskf if preconditioner is None else preconditioner(residual) * maskf
    rz = _dot(xp, residual, direction)
    for iteration in range(1, max_iterations + 1):
        a_direction = apply(direction)
        curvature = _dot(xp, direction, a_direction)
        if not (curvature > 0.0) or not math.isfinite(curvature):
            reason = (
                "the operator is not positive definite on the contact set"
                if math.isfinite(curvature)
                else "non-finite values in the iteration"
            )
            return SolveResult(x, False, reason, iteration, relative, tuple(history))
        step = rz / curvature
        x += step * direction
        residual -= step * a_direction
        relative = math.sqrt(_dot(xp, residual, residual)) / rhs_norm
        history.append(relative)
        if not math.isfinite(relative):
            return SolveResult(x, False, "non-finite residual", iteration, relative, tuple(history))
        if relative <= threshold:
            verdict = accepted(x)
            if verdict is True:
                return SolveResult(x, True, "relative residual below tolerance", iteration, relative,
                                   tuple(history))
            if isinstance(verdict, SolveResult):
                return dataclasses.replace(verdict, iterations=iteration)
        z = residual * maskf if preconditioner is None else preconditioner(residual) * maskf
        rz_next = _dot(xp, residual, z)
        direction *= rz_next / rz
        direction += z
        rz = rz_next
    return SolveResult(
        x, False, f"no convergence in {max_iterations} iterations", max_iterations, relative, tuple(history)
    )


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
        inverse_compliance.append(np.full(n_units, 1.0 / compliance))
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

    def apply(residual):
        z = alpha_elements * laplacian(residual * maskf)
        sums = np.asarray(backend.to_numpy(
            backend.segment_sum(xp, contact_labels, xp.reshape(z, (-1,))[contact_index], n_pillars)))
        y = xp.asarray(np.append(incidence @ coarse_solve(incidence_t @ sums), 0.0))
        spread = xp.take(y, window_labels)  # a gather: zero off S (the dummy pillar)
        return z - alpha_elements * laplacian(xp.reshape(spread, z.shape))

    return apply


def contact_preconditioner(operator: ContactOperator, mask):
    """The preconditioner for A_S: `spring_preconditioner` with springs, else `laplacian_preconditioner`."""
    if operator.has_springs:
        return spring_preconditioner(operator, mask)
    return laplacian_preconditioner(mask)


def pillar_block_preconditioner(system: ContactSystem, max_block: int = BLOCK_LIMIT):
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
    shared = operator._shared
    previous = shared.setdefault("pillar_blocks", {})
    last = shared.setdefault("pillar_signature", np.zeros(operator.indenter.n_pillars, dtype=np.uint64))
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
    coarse = _coarse_factor(operator, active, stiffness)
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
            factor, positions, reference, size = coarse
            scaled = np.zeros(size)
            scaled[positions] = sums / reference
            correction = sums / reference - scipy.linalg.cho_solve(factor, scaled, check_finite=False)[positions] / reference
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


def _coarse_factor(operator: ContactOperator, active, stiffness):
    """Cholesky factor of T^-1 + H on the pillars ``active`` for `pillar_block_preconditioner`.

    Returns (factor, positions of ``active`` in the factored set, T used, size)
    or None.  The factorisation (dense, O(n^3) for n pillars) is reused from
    an earlier contact set (with at least ``_COARSE_REUSE_MIN`` pillars;
    smaller ones are refactorised every time) while the pillars are a subset
    of its pillars and none has become stiffer: the correction X0 = T0^-1 - T0^-1 (T0^-1 + H)^-1
    T0^-1 then still satisfies X0 < T0^-1 <= T^-1 on any subset, which keeps
    M^-1 positive definite, and only its accuracy on the pillars that lost
    contact suffers.  A new one is made when more than ``_COARSE_STALE`` of
    the pillars lost over ``_COARSE_DRIFT`` of their stiffness.
    """
    cached = operator._shared.get("coarse")
    if cached is not None:
        factor, pillars, reference = cached
        positions = np.searchsorted(pillars, active)
        inside = positions < pillars.size
        if pillars.size >= _COARSE_REUSE_MIN and bool(np.all(inside)) and np.array_equal(pillars[positions], active):
            base = reference[positions]
            if bool(np.all(stiffness <= base * (1 + 1e-9))):
                stale = int(np.sum(stiffness < (1 - _COARSE_DRIFT) * base)) + (pillars.size - active.size)
                if stale <= max(2, _COARSE_STALE * pillars.size):
                    return factor, positions, base, pillars.size
    coupling = operator._shared.get("pillar_coupling")
    if coupling is None:
        # H over all pillars (fixed): springs of every level and the point-load coupling.
        halfspace = operator.halfspace
        h = halfspace.element_size
        n = operator.indenter.n_pillars
        springs = np.zeros((n, n))
        for compliance, cluster in operator.spring_levels:
            units = np.asarray(cluster)
            springs += compliance * (units[:, None] == units[None, :])
        centres = operator.pillar_centres()
        distance = np.sqrt(((centres[:, None, :] - centres[None, :, :]) ** 2).sum(axis=-1)) * h
        np.fill_diagonal(distance, np.inf)
        coupling = (springs + h * h / (math.pi * halfspace.contact_modulus * distance), springs)
        operator._shared["pillar_coupling"] = coupling
    selection = np.ix_(active, active)
    matrix, springs_only = coupling[0][selection], coupling[1][selection]
    for candidate in (matrix, springs_only):
        candidate[np.diag_indices(active.size)] += 1.0 / stiffness
        try:
            factor = scipy.linalg.cho_factor(candidate, lower=True, overwrite_a=True)
        except np.linalg.LinAlgError:
            continue
        pillars = np.array(active)
        operator._shared["coarse"] = (factor, pillars, stiffness.copy())
        return factor, np.arange(active.size), stiffness, active.size
    return None


def solve_on_set(operator: ContactOperator, mask, rhs, initial=None, initial_product=None,
                 tolerance: float = 1e-8, max_iterations: int = 10000, preconditioner=None) -> SolveResult:
    """Solve A_S p = rhs on the set ``mask`` of the operator's window by preconditioned CG.

    On a brush of 2 to ``MAX_BLOCK_PILLARS`` pillars whose contacts have at
    most ``BLOCK_LIMIT`` elements each, the CG runs on the |S| values of S
    (`ContactSystem`) with `pillar_block_preconditioner`; otherwise on the
    window's arrays with ``preconditioner`` (M^-1 on window arrays) or, by
    default, `contact_preconditioner`.  A single body (a punch, a sphere)
    always takes the window path: its contact changes shape at every event,
    and a fresh block inverse per event costs more than the extra iterations.
    So does every array namespace other than NumPy (a GPU): the pillar blocks
    are dense host matrices, and the window path keeps every iteration on
    the device.
    ``rhs``, ``initial`` and ``initial_product`` (A applied to ``initial``,
    if known) are window-shaped; so is the solution.
    """
    xp = operator.xp
    if (preconditioner is None and 2 <= operator.indenter.n_pillars <= MAX_BLOCK_PILLARS
            and backend.is_numpy_namespace(xp)):
        system = operator.system(mask)
        blocked = pillar_block_preconditioner(system)
        if blocked is not None:
            rhs_on_set = system.gather(rhs)
            result = conjugate_gradient(
                system.apply,
                rhs_on_set,
                xp.ones(system.size, dtype=xp.bool),
                initial=None if initial is None else system.gather(initial),
                tolerance=tolerance,
                max_iterations=max_iterations,
                preconditioner=blocked,
                xp=xp,
                initial_product=None if initial_product is None else system.gather(initial_product),
                reference=lambda v: _norm(xp, rhs_on_set - system.spring_deflection(v)),
            )
            return dataclasses.replace(result, solution=system.scatter(result.solution))
    weights = xp.astype(mask, xp.float64)  # 0/1: a cheaper mask to multiply by
    return conjugate_gradient(
        lambda x: operator.apply(x, weights),
        rhs,
        mask,
        initial=initial,
        tolerance=tolerance,
        max_iterations=max_iterations,
        preconditioner=contact_preconditioner(operator, mask) if preconditioner is None else preconditioner,
        xp=xp,
        initial_product=initial_product,
        reference=(lambda x: _norm(xp, (rhs - operator.spring_deflection(x)) * weights))
        if operator.has_springs else None,
    )


def _norm(xp, values) -> float:
    return math.sqrt(_dot(xp, values, values))


def local_cascade(operator: ContactOperator, contact, pressure, leaving, critical: float,
                  max_block: int = BLOCK_LIMIT):
    """Detachment rounds on the pillars that lose elements, each pillar solved on its own.

    The state (``pressure`` on ``contact``, window arrays) is an equilibrium
    and ``leaving`` the elements that must leave.  Every pillar P that loses
    one keeps the deflection that the rest of the structure causes on it
    fixed: its new pressure q solves

        A_PP|S' q = (A_PP p_P)|S',   A_PP = K_PP + (sum_l h^2 / k_l) 1 1^T,

    on its remaining contact S' (the springs of every level above P load all
    of P's elements alike), exactly, with the pillar's half-space block
    (``HalfSpace.block_inverse``, shared by pillars of the same contact shape)
    and the Sherman-Morrison formula for the springs.  Elements of P whose
    tension then exceeds ``critical`` leave too, until P is stable.  The rest
    of the structure is not touched; the caller's next global solve adds the
    change of the far field.  A soft pillar that starts to peel thus peels in
    a few dense solves of its own size, instead of one global solve per ring
    of elements.

    Returns (contact, pressure, number of elements that left) or None where
    it does not apply: an element of ``leaving`` off the pillars, or a
    pillar contact of more than ``max_block`` elements.
    """
    xp = operator.xp
    labels = np.asarray(backend.to_numpy(operator.pillar_labels))
    in_contact = np.asarray(backend.to_numpy(contact), dtype=bool)
    leave = np.asarray(backend.to_numpy(leaving), dtype=bool) & in_contact
    hit = np.unique(labels[leave])
    if hit.size == 0 or hit[0] < 0:
        return None
    rows, cols = np.nonzero(in_contact & np.isin(labels, hit))  # row-major
    by_pillar = np.argsort(labels[rows, cols], kind="stable")
    rows, cols = rows[by_pillar], cols[by_pillar]
    counts = np.bincount(np.searchsorted(hit, labels[rows, cols]), minlength=hit.size)
    if int(counts.max()) > max_block:
        return None
    halfspace = operator.halfspace
    compliance = sum(c for c, _ in operator.spring_levels)
    values = np.array(backend.to_numpy(pressure), dtype=np.float64)
    new_contact = in_contact.copy()
    origin = np.array([operator.window.r0, operator.window.c0])
    detached = 0
    for start, count in zip(np.r_[0, np.cumsum(counts)[:-1]].tolist(), counts.tolist()):
        r, c = rows[start : start + count], cols[start : start + count]
        offsets = np.stack([r, c], axis=1) + origin
        p = values[r, c]
        b = halfspace.block_matrix(offsets) @ p + compliance * p.sum()
        keep = ~leave[r, c]
        parent = (offsets, halfspace.block_inverse(offsets))
        q = np.zeros(count)
        while bool(np.any(keep)):
            sub = offsets[keep]
            inverse = halfspace.block_inverse(sub, parent=parent)
            y = inverse @ b[keep]
            z = inverse.sum(axis=1)
            q = np.zeros(count)
            q[keep] = y - z * (compliance * y.sum() / (1.0 + compliance * z.sum()))
            tense = keep & ((q < -critical) if critical > 0 else (q < 0))
            if not bool(np.any(tense)):
                break
            parent = (sub, inverse)
            keep &= ~tense
        values[r, c] = np.where(keep, q, 0.0)
        new_contact[r, c] = keep
        detached += int(count - np.count_nonzero(keep))
    return xp.asarray(new_contact), xp.asarray(values), detached


@dataclass(frozen=True)
class Equilibrium:
    """The state at one base displacement (on the operator's window).

    Attributes
    ----------
    displacement : float
        Base displacement d.
    pressure : ndarray
        Pressure on the window, compressive positive.
    contact : ndarray of bool
        Contact set on the window.
    converged : bool
    reason : str
    cg_iterations : int
        CG iterations spent, all solves together.
    n_solves : int
    trial_force_sum : float
        Sum of the pressure of the first global solve (the fixed-set force
        the path passes through before a cascade; after the local rounds of
        `local_cascade` where the cascade starts on the pillars).
    detached, attached : int
        Elements that left and joined S.
    deflection : ndarray or None
        ``tip_deflection`` (K p + springs) on the window for the returned pressure, when the
        solver computed it anyway (the final join check of ``equilibrium``),
        so that callers need not transform the pressure again.
    trial_pressure : ndarray or None
        The pressure of the first global solve (on the starting contact set,
        before any element left or joined; the sum of it is
        ``trial_force_sum``); None where no solve ran.
    """

    displacement: float
    pressure: object
    contact: object
    converged: bool
    reason: str
    cg_iterations: int
    n_solves: int
    trial_force_sum: float
    detached: int
    attached: int
    deflection: object = None
    trial_pressure: object = None


def tip_deflection(operator: ContactOperator, pressure):
    """Half-space deflection plus spring deflection of ``pressure`` on the window (unmasked)."""
    return operator.tip_deflection(pressure)


def penetration(operator: ContactOperator, height, displacement: float, pressure):
    """How far the tip reaches into the deformed half-space (> 0: penetrates), on the window."""
    return displacement - height - tip_deflection(operator, pressure)


def equilibrium(
    operator: ContactOperator,
    height,
    displacement: float,
    contact,
    pressure,
    critical: float,
    tolerance: float = 1e-8,
    max_iterations: int = 10000,
    max_rounds: int = 100000,
    preconditioner=None,
    force_detach=None,
    force_attach=None,
    deflection=None,
    cascade: str = "local",
    length_scale: float = 0.0,
) -> Equilibrium:
    """Adhesive equilibrium at base displacement ``displacement`` (module docstring).

    Parameters
    ----------
    operator : ContactOperator
    height : ndarray
        Tip heights on the operator's window (inf outside the footprints).
    displacement : float
        d, in units of length.
    contact : ndarray of bool
        Contact set to start from (history).
    pressure : ndarray
        Warm start.
    critical : float
        Sigma_c; 0 means no adhesion (elements leave when p < 0).
    preconditioner : callable, optional
        M^-1 on the window's arrays, instead of the Laplacian preconditioner
        (the solves then run on the whole window rather than on the block
        around S).
    force_detach, force_attach : ndarray of bool, optional
        Elements that leave / join S before the first solve (the event that
        the event-driven path has reached exactly).
    deflection : ndarray, optional
        ``operator.tip_deflection(pressure)``, when the caller knows it (the
        event-driven path does: the state is affine between events).  It is
        kept in step while nothing is solved: the first solve starts without
        applying the operator, and when that solve finds the warm start
        within tolerance (an attachment exactly at the touching point does
        not change the pressure) the join check needs no transform either.
    cascade : {"local", "global"}
        How the detachment rounds of a brush run.  "global": every round is a
        solve on the whole contact set (the thesis's loop).  "local" (on
        structures of two or more pillars; the others always run "global"):
        the pillars that lose elements peel in rounds of their own
        (`local_cascade`), with the rest of the structure held, and a global
        solve then adds the far field and checks every element again.  Both
        end in a state where no element exceeds the criterion and none
        penetrates; they may differ in which elements a cascade takes along
        when one is within the far field's change of the threshold.
    length_scale : float
        The load path's displacement scale (the largest |d| so far), in
        units of length.  An element joins S when it penetrates by more than
        the solve's accuracy in length, ``10 * tolerance`` times the largest
        of this, |d| and the largest |d - height|; near d = 0 (a flat tip
        pulled back to its zero without adhesion) |d| alone would let
        rounding errors of the pressure keep the contact forever.
    """
    if cascade not in ("local", "global"):
        raise ValueError(f"cascade = {cascade!r} must be 'local' or 'global'")
    xp = operator.xp
    footprint = xp.isfinite(height)
    contact = contact & footprint
    detached = attached = 0
    local = cascade == "local" and preconditioner is None and operator.indenter.n_pillars >= 2
    if force_detach is not None and local and bool(xp.any(contact & force_detach)):
        # The caller's state is an equilibrium: the cascade starts on the pillars.
        cascaded = local_cascade(operator, contact, xp.where(contact, pressure, 0.0), force_detach, critical)
        if cascaded is not None:
            contact, pressure, n_left = cascaded
            detached += n_left
            force_detach = None
            deflection = None
    if force_detach is not None:
        detached += int(xp.count_nonzero(contact & force_detach))
        contact = contact & ~force_detach
    if force_attach is not None:
        joining = force_attach & footprint & ~contact
        attached += int(xp.count_nonzero(joining))
        contact = contact | joining
    target = xp.where(footprint, displacement - height, 0.0)
    if deflection is not None:
        # The pressure outside the new set (elements forced to leave) is dropped.
        deflection = deflection - operator.element_deflection(pressure, ~contact)
    pressure = xp.where(contact, pressure, 0.0)
    iterations = solves = 0
    trial = trial_pressure = None
    # Penetration tolerance: the solve's accuracy in units of length.
    scale = float(xp.max(xp.abs(target))) if bool(xp.any(footprint)) else 0.0
    slack = 10.0 * tolerance * max(scale, abs(displacement), length_scale, 1e-300)
    for _ in range(max_rounds):
        if bool(xp.any(contact)):
            # The solve only needs the deflection on S: run it on the block
            # around S (a caller's preconditioner works on the whole window).
            if preconditioner is None:
                block, block_operator = operator.sub_operator(contact)
            else:
                block, block_operator = operator.window.slices_local, operator
            block_contact = contact[block]
            result = solve_on_set(
                block_operator, block_contact, target[block], pressure[block],
                None if deflection is None else deflection[block], tolerance, max_iterations, preconditioner,
            )
            iterations += result.iterations
            solves += 1
            if result.iterations or result.reason != WARM_START_WITHIN_TOLERANCE:
                deflection = None  # the pressure moved
            pressure = xp.zeros_like(target)
            pressure[block] = result.solution
            if not result.converged:
                return Equilibrium(
                    displacement, pressure, contact, False, result.reason, iterations, solves,
                    trial if trial is not None else float(xp.sum(pressure)), detached, attached,
                )
        else:
            pressure = xp.zeros_like(target)
        if trial is None:
            trial = float(xp.sum(pressure))
            trial_pressure = pressure
        leaving = contact & (pressure < -critical) if critical > 0 else contact & (pressure < 0)
        n_leaving = int(xp.count_nonzero(leaving))
        if n_leaving and local:
            cascaded = local_cascade(operator, contact, pressure, leaving, critical)
            if cascaded is not None:
                contact, pressure, n_left = cascaded
                detached += n_left
                deflection = None
                continue
        if n_leaving:
            contact = contact & ~leaving
            if deflection is not None:
                deflection = deflection - operator.element_deflection(pressure, leaving)
            pressure = xp.where(contact, pressure, 0.0)
            detached += n_leaving
            continue
        if deflection is None:
            deflection = tip_deflection(operator, pressure)
        joining = footprint & ~contact & (displacement - height - deflection > slack)
        n_joining = int(xp.count_nonzero(joining))
        if n_joining:
            contact = contact | joining
            attached += n_joining
            continue
        return Equilibrium(
            displacement, pressure, contact, True, "contact set stable", iterations, solves, trial, detached,
            attached, deflection, trial_pressure,
        )
    return Equilibrium(
        displacement, pressure, contact, False, f"contact set did not stabilise in {max_rounds} rounds",
        iterations, solves, trial if trial is not None else 0.0, detached, attached,
    )


def polonsky_keer(
    operator: ContactOperator,
    height,
    displacement: float,
    pressure,
    tolerance: float = 1e-8,
    max_iterations: int = 10000,
) -> Equilibrium:
    """Non-adhesive contact at base displacement d by constrained CG (Polonsky & Keer 1999).

    Minimises 1/2 p.A p - p.(d - height) subject to p >= 0 on the footprint.
    The contact set is the set where p > 0; elements with p = 0 and a negative
    gap join it inside the iteration (the conjugacy is then reset).  The
    stopping test is the relative residual of the gap on the contact set plus
    the absence of penetration outside it.
    """
    xp = operator.xp
    footprint = xp.isfinite(height)
    target = xp.where(footprint, displacement - height, 0.0)
    if not bool(xp.any(target > 0)):
        zeros = xp.zeros_like(target)
        return Equilibrium(displacement, zeros, zeros > 0, True, "no penetration", 0, 1, 0.0, 0, 0)
    # The rigid-punch-like guess: a small uniform pressure where the tip penetrates.
    guess = xp.astype(target > 0, xp.float64) * (float(xp.max(target)) / operator.halfspace.diagonal()) * 0.1
    pressure = xp.where(footprint & (pressure > 0), pressure, 0.0)
    if not bool(xp.any(pressure > 0)):
        pressure = guess
    target_norm = math.sqrt(float(xp.sum(target[target > 0] ** 2)))
    direction = xp.zeros_like(pressure)
    # The deflection is tracked, not recomputed: one FFT pair per iteration for
    # the search direction, and one more only in iterations where the
    # projection (p < 0 -> 0) or the joining of overlapping elements changed p.
    deflection = operator.deflection(pressure)
    g_old = 1.0
    reset = True
    relative = math.inf
    for iteration in range(1, max_iterations + 1):
        contact = pressure > 0
        if not bool(xp.any(contact)):
            # A step projected every pressure to zero (a warm start far too
            # high): start again from the guess, which loads the penetration.
            pressure = guess
            deflection = operator.deflection(pressure)
            reset = True
            contact = pressure > 0
        gap = deflection - target  # > 0: separated, < 0: penetrating
        gap_c = xp.where(contact, gap, 0.0)
        g_norm2 = float(xp.sum(gap_c * gap_c))
        relative = math.sqrt(g_norm2) / target_norm
        outside_penetration = bool(xp.any(footprint & ~contact & (gap < -tolerance * target_norm)))
        if relative <= tolerance and not outside_penetration and iteration > 1:
            return Equilibrium(
                displacement, pressure, contact, True, "relative gap residual below tolerance",
                iteration - 1, 1, float(xp.sum(pressure)), 0, 0,
            )
        if relative <= tolerance and outside_penetration:
            # S is solved but elements outside it penetrate: the gradient on
            # S vanishes, so no search direction would reach them.  They join
            # with the pressure that closes their own gap (the diagonal), and
            # the iteration restarts on the larger set.
            joining = footprint & ~contact & (gap < -tolerance * target_norm)
            change = xp.where(joining, -gap / operator.halfspace.diagonal(), 0.0)
            pressure = pressure + change
            deflection = deflection + operator.deflection(change)
            reset = True
            continue
        # Preconditioned direction (Vollebregt 2014): z = M^-1 gap on S.
        z = laplacian_preconditioner(contact)(gap_c)
        rz = float(xp.sum(gap_c * z))
        direction = z + (0.0 if reset else rz / g_old) * direction
        direction = xp.where(contact, direction, 0.0)
        g_old = rz
        response_full = operator.deflection(direction)
        denominator = float(xp.sum(direction * response_full))
        if not (denominator > 0):
            return Equilibrium(
                displacement, pressure, contact, False, "search direction lost positivity",
                iteration, 1, float(xp.sum(pressure)), 0, 0,
            )
        step = float(xp.sum(gap_c * direction)) / denominator
        moved = pressure - step * direction
        deflection = deflection - step * response_full
        projected = xp.where(moved > 0, moved, 0.0)
        overlap = footprint & (projected <= 0) & (gap < 0)
        reset = bool(xp.any(overlap))
        if reset:
            projected = projected - xp.where(overlap, step * gap, 0.0)
        change = projected - moved
        if bool(xp.any(change != 0)):
            deflection = deflection + operator.deflection(change)
        pressure = projected
    return Equilibrium(
        displacement, pressure, pressure > 0, False, f"no convergence in {max_iterations} iterations",
        max_iterations, 1, float(xp.sum(pressure)), 0, 0,
    )
