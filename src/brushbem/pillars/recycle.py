"""Recycled deflation of the pillar-level CG (`brushbem.pillars.cg.LatticeCG`): Ritz vectors kept from solve to solve.

With the near-field preconditioner N (`LatticeCG.near_factor`, the
scattered sets of a rough brush) the preconditioned system's spectrum is a
cluster and a few tens of outliers above it (99 % of the eigenvalues in
[0.85, 1.49], about 20 up to 11 at 10^4 pillars): the far field's
long-range modes, which the near field leaves out.  They cost about half of
the iterations, and they change little from one solve to the next (a few
pillars leave or peel at an event).  So a solve by the near field alone
keeps its Krylov directions p and their products A p (which the CG computes
anyway), and after it the Ritz vectors of the largest Ritz values of
(A, N) over their span (Rayleigh-Ritz) become the kept vectors W, with Y =
A W from the same products: no product more.

The next solves use them in a two-level (balancing) preconditioner

    B = (I - W E^-1 Y^T) N^-1 (I - Y E^-1 W^T) + W E^-1 W^T,   E = sym(W^T Y)

on the attached set, W restricted to it.  With Y = A W this is the
balancing Neumann-Neumann preconditioner, and the outliers on span W are
gone.  B is symmetric and positive definite whatever W and Y (E positive
definite, which `Recycler.space` ensures by keeping its positive part):
v^T B v = |N^-1/2 (v - Y E^-1 W^T v)|^2 + |E^-1/2 W^T v|^2 is zero only
where W^T v = 0, and then it is v^T N^-1 v.  So the CG converges to the
same solution, to the same residual tolerance, whether or not Y is still
A W on the current set: a pillar that leaves or peels after W was made
leaves Y stale (its column of A is gone or changed), which costs
iterations, never accuracy.  Once more than ``Switches.recycled_stale`` of
the attached pillars have changed since, Y is made afresh before the next
solve (`Recycler.refresh`: k columns of products) and that solve's
directions join W in the Rayleigh-Ritz step (`Recycler.absorb`), so that
what the earlier sets taught is kept.  Between refreshes W and Y
stay as they are (a Rayleigh-Ritz step over stale products let the
iterations grow without bound: 12 to 1603 a solve within 20 solves of a
32 x 32 pull-off).  At most ``Switches.recycled_vectors`` are kept.  Ours:
the thesis states no solver.

Measured on the ``size`` study's sigma~ = 0.1 brush (``benchmarks/large_brush.py``,
before and after in one run): see `brushbem.pillars`.  How many to keep
(separate runs, so within the machine's load): at 10^4 pillars (CG
throughout, first 700 states) 80 vectors took 10.7 iterations a solve as 40
did, and the loading more CPU time; at 10^5 (the pull-off's first 195
states) 100 took 12.0 against 13.9 with 40, 108 CPU-s against 118.  Kept
vectors given up at a refresh (W from the new solve's directions alone, on
N alone) took 14.8 iterations a solve in the pull-off at 10^4 against
10.9, and given up only beyond 20 % of the set changed 13.2.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg

__all__ = ["Recycler", "Space"]

#: Directions whose Gram eigenvalue is below this share of the largest are dropped (nearly dependent ones:
#: rounding would make the Rayleigh-Ritz pencil indefinite); so are the kept vectors' on a set (`Recycler.space`).
_INDEPENDENT = 1e-10


class Space:
    """The two-level preconditioner's coarse part on one attached set: W (n, k), Y (n, k) on it and E^-1 (k, k)."""

    def __init__(self, W: np.ndarray, Y: np.ndarray, inverse: np.ndarray):
        self.W = W
        self.Y = Y
        self.inverse = inverse

    def apply(self, r: np.ndarray, near) -> np.ndarray:
        """B r for r (n, c) on the set (module docstring); ``near``: the near-field factor (its ``solve``)."""
        a = self.inverse @ (self.W.T @ r)
        u = near.solve(np.ascontiguousarray(r - self.Y @ a))
        b = self.inverse @ (self.Y.T @ u)
        return u + self.W @ (a - b)


class Recycler:
    """The kept vectors of a `LatticeCG` (module docstring): W and Y over all M pillars, zero off their set, and
    the rasters (`PillarModel.basis` serials, -1 off) of the set on which Y = A W held."""

    def __init__(self, M: int, most: int):
        self.M = M
        self.most = most
        self.W: np.ndarray | None = None
        self.Y: np.ndarray | None = None
        self.serials = np.full(M, -1, dtype=np.int64)

    def space(self, S: np.ndarray) -> Space | None:
        """The kept vectors restricted to the attached pillars ``S`` (indices); None if none.

        E^-1 is the inverse of sym(W^T Y) on the eigenvectors of its eigenvalues above ``_INDEPENDENT`` of the
        largest (a vector that lay mostly on pillars now off leaves a small or negative one): symmetric and
        positive semidefinite, so B stays positive definite (module docstring).
        """
        if self.W is None or S.size == 0:
            return None
        W, Y = self.W[S], self.Y[S]
        E = W.T @ Y
        values, vectors = np.linalg.eigh(0.5 * (E + E.T))
        keep = values > _INDEPENDENT * max(float(values[-1]), 0.0)
        if not keep.any():
            return None
        kept = vectors[:, keep]
        return Space(W, Y, (kept / values[keep]) @ kept.T)

    def changed(self, serials: np.ndarray) -> float:
        """The share of the attached pillars (``serials``: every pillar's raster serial, -1 off) that have left,
        joined or changed their raster since Y = A W held (inf when nothing is kept)."""
        if self.W is None:
            return np.inf
        return np.count_nonzero(serials != self.serials) / max(int(np.count_nonzero(serials >= 0)), 1)

    def refresh(self, S: np.ndarray, serials: np.ndarray, product) -> None:
        """Y = A W on the attached pillars ``S`` afresh (``product``: A_S V for V (n, k) on S), W restricted."""
        W = np.zeros_like(self.W)
        W[S] = self.W[S]
        Y = np.zeros_like(self.Y)
        Y[S] = product(W[S])
        self.W, self.Y, self.serials = W, Y, serials

    def absorb(self, S: np.ndarray, serials: np.ndarray, space: Space | None, directions: list[np.ndarray],
               products: list[np.ndarray], near_matrix) -> None:
        """Keep the Ritz vectors of the largest Ritz values of (A, N) over span(W, a solve's ``directions``).

        ``space``: the kept vectors on ``S`` (indices) with Y = A W there (`refresh`), or None;
        ``directions`` and ``products``: the CG's p and A p on S, (n, c) each; ``near_matrix``: N on S
        (sparse); ``serials``: the rasters on which the products hold (`changed`).
        """
        V = np.concatenate(([space.W] if space is not None else []) + directions, axis=1)
        AV = np.concatenate(([space.Y] if space is not None else []) + products, axis=1)
        basis = _orthonormal(V)
        if basis is None:
            return
        V, AV = V @ basis, AV @ basis
        T = V.T @ AV
        N = V.T @ (near_matrix @ V)
        try:
            values, vectors = scipy.linalg.eigh(0.5 * (T + T.T), 0.5 * (N + N.T))
        except np.linalg.LinAlgError:
            return
        vectors = vectors[:, -min(self.most, values.size):]
        W = np.zeros((self.M, vectors.shape[1]))
        Y = np.zeros((self.M, vectors.shape[1]))
        W[S] = V @ vectors
        Y[S] = AV @ vectors
        self.W, self.Y, self.serials = W, Y, serials


def _orthonormal(V: np.ndarray) -> np.ndarray | None:
    """C (k, r) with V C orthonormal and spanning V's numerically independent part; None if V is zero."""
    gram = V.T @ V
    values, vectors = np.linalg.eigh(0.5 * (gram + gram.T))
    if not values.size or values[-1] <= 0.0:
        return None
    keep = values > _INDEPENDENT * values[-1]
    return vectors[:, keep] / np.sqrt(values[keep])
