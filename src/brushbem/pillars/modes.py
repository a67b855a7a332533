"""The modes of one tip raster: `Basis`, `Bases` (``LoadPath.method = "pillars"``).

For a raster of elements (offsets) the full BEM on it alone gives the
pressures F = K^-1 P of the displacement polynomials P of `MODES`, made
K-orthogonal to the uniform mode (`brushbem.pillars`).  A tip that peels
holds a raster R inside its footprint F, one after another as elements
leave.  On a footprint of `SCHUR_ELEMENTS` elements or more (fine tips,
`brushbem.pillars.tips`), whose own factorisation costs n^3, R's solves
come from the footprint's inverse A = K_FF^-1, kept once per footprint
shape, by the Schur complement over the elements E that left:

    K_RR^-1 v = (A v~)_R - A_RE A_EE^-1 (A v~)_E,   v~ = v on R, 0 on E,

and K F = P gives the K inner products of the Gram-Schmidt without K.  The
polynomials of R (about its own centroid) span those of F, P_R = Q_R T
(Q the footprint's, T a small m x m change of basis), and A v~ = A_F Q T -
A_FE Q_E T with A_F Q kept with the inverse: a peeled raster costs
O(n |E| m + |E|^3), n = |F|, m modes, instead of the raster's own
factorisation's |R|^3 (used while more than half of the footprint has
left).  Smaller footprints factorise every raster directly.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
from dataclasses import dataclass

import numpy as np
import scipy.linalg

__all__ = ["MODES", "SCHUR_ELEMENTS", "Bases", "Basis"]

#: The displacement polynomials (powers of x, y) of each choice of modes.
MODES = {
    "uniform": ((0, 0),),
    "tilt": ((0, 0), (1, 0), (0, 1)),
    "quadratic": ((0, 0), (1, 0), (0, 1), (2, 0), (1, 1), (0, 2)),
}

#: The powers of each choice of modes by its number of modes.
_POWERS = {len(powers): powers for powers in MODES.values()}

#: Footprints of at least this many elements (about 7 elements' radius) give their rasters' modes through
#: the Schur complement of their kept inverse; below, a raster's own factorisation costs as little (one
#: thread: 0.7 against 0.8 ms at 113 elements, 1.0 against 1.3 ms at 153, 1.0 against 2.2 ms at 202, 1.3
#: against 23 ms at 806).  Ours (a cost switch: both give the modes to round-off).
SCHUR_ELEMENTS = 150

#: The kept footprint inverses and bases (bytes) beyond which they are dropped and computed afresh.
_KEPT_BYTES = 2**30

_SERIALS = itertools.count()


@dataclass(frozen=True)
class Basis:
    """The modes of one raster shape (offsets relative to the raster's first row and column).

    phi : (n, m) pressure of each mode per unit amplitude; force : s = sum phi_0
    (the uniform mode's force / h^2 per unit displacement); gram : (m,) the
    diagonal of Phi^T K Phi (1 for a mode the raster cannot carry, whose
    column is zero); centroid : (2,) in elements; m0, m1, m2 : the modes'
    moments about the centroid, for the far field; size : the length (in
    elements) that scales the polynomials; fit : (m, m) the pseudo-inverse of
    Phi^T P, which turns the projections f = Phi^T u of a displacement field
    on the modes into the coefficients of the polynomial that has them (the
    field's fit across the raster, `PillarModel.fitted`).
    """

    offsets: np.ndarray
    phi: np.ndarray
    force: float
    gram: np.ndarray
    centroid: np.ndarray
    m0: np.ndarray
    m1: np.ndarray
    m2: np.ndarray
    size: float
    fit: np.ndarray
    #: A number of its own (the key of the couplings' caches: an id() may be reused once a basis is dropped).
    serial: int = dataclasses.field(default_factory=lambda: next(_SERIALS))

    def polynomials(self, offsets: np.ndarray) -> np.ndarray:
        """The displacement polynomials at element ``offsets`` (relative to the raster's origin): (len, m)."""
        xi = (np.asarray(offsets, dtype=np.float64) - self.centroid) / self.size
        return np.stack([xi[:, 0] ** a * xi[:, 1] ** b for a, b in _POWERS[self.phi.shape[1]]], axis=1)


class Bases:
    """The `Basis` of every raster met, cached by its shape, and the kept inverses of the footprints."""

    def __init__(self, ktab: np.ndarray, powers: tuple[tuple[int, int], ...]):
        self.ktab = ktab
        self.powers = powers
        self._bases: dict[bytes, Basis] = {}
        #: Per footprint shape: its inverse A = K_FF^-1, its polynomials Q and A Q (`_schur`).
        self._inverses: dict[bytes, tuple[np.ndarray, np.ndarray, np.ndarray]] = {}
        self._bytes = 0

    def get(self, footprint: np.ndarray, mask: np.ndarray | None = None) -> Basis:
        """The basis of the raster ``footprint[mask]`` (element offsets, row-major; all of it by default),
        with offsets relative to the raster's first row and column."""
        rc = footprint if mask is None else footprint[mask]
        offsets = rc - rc.min(axis=0)
        key = offsets.tobytes()
        basis = self._bases.get(key)
        if basis is None:
            if self._bytes > _KEPT_BYTES:
                # The model keeps the bases it uses; the others are computed again if met again.
                self._bases.clear()
                self._inverses.clear()
                self._bytes = 0
            n = footprint.shape[0]
            if mask is None or mask.all() or n < SCHUR_ELEMENTS or 2 * np.count_nonzero(~mask) > n \
                    or 8 * n * n > _KEPT_BYTES // 4:
                basis = self._direct(offsets)
            else:
                basis = self._schur(footprint - footprint.min(axis=0), mask, offsets)
            self._bases[key] = basis
            self._bytes += basis.phi.nbytes + offsets.nbytes
        return basis

    def _kernel(self, offsets: np.ndarray) -> np.ndarray:
        rows, cols = offsets[:, 0], offsets[:, 1]
        # ktab[|dy|, |dx|] as one flat gather.
        flat = np.abs(rows[:, None] - rows[None, :]) * self.ktab.shape[1] + np.abs(cols[:, None] - cols[None, :])
        return np.take(self.ktab, flat)

    def _polynomials(self, offsets: np.ndarray) -> tuple[np.ndarray, np.ndarray, float, np.ndarray]:
        centroid = offsets.mean(axis=0)
        xi = offsets - centroid
        size = max(math.sqrt(float(np.mean(np.sum(xi ** 2, axis=1)))), 1.0)
        # x^a y^b of the scaled offsets; the powers 0, 1 and 2 as 1, x and x * x (what numpy's ** computes
        # for them), without a power call each: a new raster's basis is made at every step of a peel.
        y, x = xi[:, 0] / size, xi[:, 1] / size
        P = np.empty((xi.shape[0], len(self.powers)))
        for k, (a, b) in enumerate(self.powers):
            P[:, k] = _power(y, a) * _power(x, b)
        return centroid, xi, size, P

    def _direct(self, offsets: np.ndarray) -> Basis:
        K = self._kernel(offsets)
        # scipy.linalg.cho_factor and cho_solve's LAPACK calls (the same numbers) without their checks.
        factor, info = scipy.linalg.lapack.dpotrf(K, lower=False, clean=False)
        if info != 0:
            raise np.linalg.LinAlgError(f"a tip raster's influence matrix is not positive definite (LAPACK info "
                                        f"{info})")
        centroid, xi, size, P = self._polynomials(offsets)
        F, info = scipy.linalg.lapack.dpotrs(factor, P, lower=False)
        # K-orthogonal modes (Gram-Schmidt in the K inner product, phi_0 = K^-1 1 kept); a mode the raster
        # cannot carry (too few elements, all in a line) is dropped: zero column, unit gram.
        phi = np.zeros_like(F)
        gram = np.ones(F.shape[1])
        kept = []  # the modes kept so far (a kept mode's column is not zero: its norm is positive)
        for k in range(F.shape[1]):
            v = F[:, k].copy()
            for j in kept:
                v -= (phi[:, j] @ P[:, k]) / gram[j] * phi[:, j]
            norm = float(v @ (K @ v))
            if k == 0 or norm > 1e-9 * float(F[:, k] @ P[:, k]):
                phi[:, k] = v
                gram[k] = norm
                kept.append(k)
        return _basis(offsets, phi, gram, centroid, xi, size, P)

    def _schur(self, footprint: np.ndarray, mask: np.ndarray, offsets: np.ndarray) -> Basis:
        """The modes of ``footprint[mask]`` from the footprint's kept inverse (module docstring)."""
        key = footprint.tobytes()
        kept = self._inverses.get(key)
        if kept is None:
            A = _spd_inverse(self._kernel(footprint))
            Q = self._polynomials(footprint)[3]
            kept = self._inverses[key] = (A, Q, A @ Q)
            self._bytes += A.nbytes + 2 * Q.nbytes
        A, Q, AQ = kept
        R, E = np.flatnonzero(mask), np.flatnonzero(~mask)
        centroid, xi, size, P = self._polynomials(offsets)
        # P = Q_R T exactly (the same polynomial space; R holds more than half of F, so Q_R has full rank).
        T = np.linalg.lstsq(Q[R], P, rcond=None)[0]
        rows = A[E]  # A_EF (A is symmetric): every product below is O(n |E| m).
        Y = (AQ - rows.T @ Q[E]) @ T
        Z = scipy.linalg.cho_solve(scipy.linalg.cho_factor(rows[:, E]), Y[E])
        F = (Y - rows.T @ Z)[R]
        # Gram-Schmidt on the coefficients C of phi = F C: K F = P, so phi_j . K F_k = phi_j . P_k and
        # v . K v = (F c) . (P c).
        m = F.shape[1]
        C = np.zeros((m, m))
        gram = np.ones(m)
        for k in range(m):
            c = np.zeros(m)
            c[k] = 1.0
            for j in range(k):
                if C[:, j].any():
                    c -= ((F @ C[:, j]) @ P[:, k]) / gram[j] * C[:, j]
            norm = float((F @ c) @ (P @ c))
            if k == 0 or norm > 1e-9 * float(F[:, k] @ P[:, k]):
                C[:, k] = c
                gram[k] = norm
        return _basis(offsets, F @ C, gram, centroid, xi, size, P)


def _power(values: np.ndarray, exponent: int) -> np.ndarray | float:
    """values ** exponent, the exponents 0, 1 and 2 without a power call (1.0, values, values * values: the
    same numbers as numpy's ** gives)."""
    if exponent == 0:
        return 1.0
    if exponent == 1:
        return values
    if exponent == 2:
        return values * values
    return values ** exponent


def _basis(offsets: np.ndarray, phi: np.ndarray, gram: np.ndarray, centroid: np.ndarray, xi: np.ndarray,
           size: float, P: np.ndarray) -> Basis:
    """The `Basis` of K-orthogonal modes ``phi``: their moments about the centroid and the fit."""
    m0 = phi.sum(axis=0)
    m1 = phi.T @ xi
    m2 = (phi.T @ (xi[:, :, None] * xi[:, None, :]).reshape(-1, 4)).reshape(-1, 2, 2)
    fit = np.linalg.pinv(phi.T @ P, rcond=1e-10)
    return Basis(offsets, phi, float(m0[0]), gram, centroid, m0, m1, m2, size, fit)


def _spd_inverse(K: np.ndarray) -> np.ndarray:
    """K^-1 of a symmetric positive definite K (LAPACK potrf and potri), both triangles."""
    factor, info = scipy.linalg.lapack.dpotrf(K, lower=True)
    inverse, info = scipy.linalg.lapack.dpotri(factor, lower=True) if info == 0 else (None, info)
    if info != 0:
        raise np.linalg.LinAlgError(f"a tip's influence matrix is not positive definite (LAPACK info {info})")
    return np.tril(inverse) + np.tril(inverse, -1).T
