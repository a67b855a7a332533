"""The pillar model's pillar-level solve: `Solver` (the kept inverse) and `full_solve` (``LoadPath.method = "pillars"``).

`Solver` keeps the inverse of the uniform modes' system (G00 + H) over the
attached pillars and updates it by rank-one steps as pillars join and leave
(``coupling = "local"``); on a lattice with more than ``Switches.kept_pillars``
attached it drops the inverse and solves by CG on the lattice's FFT product
(`brushbem.pillars.cg.LatticeCG`), and keeps one again once the
attached set is back under half that.  `full_solve` factorises the system of
every mode at once (``coupling = "full"``).  The model is described in
`brushbem.pillars`.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import scipy.linalg

from brushbem import settings
from brushbem.config.resources import available_memory, format_bytes, kept_partial_count, pillar_kept_bytes
from brushbem.pillars.basis import PillarModel
from brushbem.pillars.cg import LatticeCG

__all__ = ["Solver", "full_solve", "radiate"]

#: Relative residual of the pillar-level solve above which the kept inverse is refactorised.
_RESIDUAL = 1e-10

#: The kept inverse's low-rank updates run over row slabs of about this many numbers, so that the slab and
#: its product stay in cache (one pass over B in memory instead of three: at 1400 attached pillars B is
#: 16 MB; a rank-one update took 7.4 ms whole and 3.6 ms by slabs there).
_SLAB = 2**16


def _update(B: np.ndarray, U: np.ndarray, V: np.ndarray, scratch: np.ndarray) -> None:
    """B += U @ V (U (n, k), V (k, n)), slab by slab; ``scratch`` holds at least max(`_SLAB`, n) numbers."""
    rows, cols = B.shape
    step = max(1, _SLAB // max(cols, 1))
    for start in range(0, rows, step):
        slab = B[start:start + step]
        out = scratch[:slab.size].reshape(slab.shape)
        if U.shape[1] == 1:  # an outer product (a matrix product of one column took twice as long)
            slab += np.multiply.outer(U[start:start + step, 0], V[0], out=out)
        else:
            slab += np.matmul(U[start:start + step], V, out=out)


def _spd_inverse(A: np.ndarray) -> np.ndarray:
    """The inverse of a symmetric positive definite matrix (LAPACK potrf and potri: a third of cho_solve's work)."""
    factor, info = scipy.linalg.lapack.dpotrf(A, lower=True)
    if info == 0:
        inverse, info = scipy.linalg.lapack.dpotri(factor, lower=True)
    if info != 0:
        raise np.linalg.LinAlgError(f"the pillar-level matrix is not positive definite (LAPACK info {info})")
    return np.tril(inverse) + np.tril(inverse, -1).T


class Solver:
    """The uniform modes' system on the attached set, with its inverse kept (``coupling = 'local'``).

    ``B`` is the inverse of (G00 + H) on the attached pillars in the order
    ``order[:n]`` (``position`` maps a pillar to its row, -1 when off); a pillar
    that joins is appended and one that leaves is swapped with the last, each
    a rank-one update of O(n^2).  While ``iterative`` (a lattice with more than
    ``Switches.kept_pillars`` attached) there is no ``B`` (nor ``order``): joins and
    leaves only mark ``attached`` and `solve` runs `LatticeCG`, warm-started
    from the last solution.
    """

    def __init__(self, model: PillarModel, solve: str = "auto"):
        #: ``"auto"`` (`_kept_limit`), ``"kept"`` (the inverse always kept) or ``"cg"`` (CG on a lattice always).
        self.choice = solve
        self.model = model
        self.attached = np.zeros(model.M, dtype=bool)
        self._B = np.zeros((16, 16))
        self.order = np.zeros(model.M, dtype=np.int64)
        self.position = np.full(model.M, -1, dtype=np.int64)
        self.n = 0
        self.updates = 0
        self.solves = 0
        self._work = np.empty(_SLAB)  # the updates' scratch (`_update`): a slab of B
        self.iterative = False
        self._cg: LatticeCG | None = None
        self._last = np.zeros((model.M, 2))  # the last solution (CG's warm start)
        self._cap: float | None = None  # `_memory_cap`
        #: The last `radiate`'s correction of the uniform amplitudes (its first CG's warm start), or None.
        self.correction: np.ndarray | None = None

    @property
    def cg(self) -> LatticeCG:
        """The CG solve (built at its first use: one product for its preconditioner)."""
        if self._cg is None:
            self._cg = LatticeCG(self.model)
        return self._cg

    def _kept_limit(self, attached: int) -> float:
        """The most attached pillars for which the inverse is kept: ``Switches.kept_pillars``, or while they
        are at most half of the lattice as many as ``Switches.kept_partial_bytes`` holds (or
        ``Switches.kept_partial``: `kept_partial_count`), and on a lattice no more than
        fit in memory (`_memory_cap`); no limit off a lattice, with ``kept_pillars = None`` or ``choice =
        "kept"``; none kept with ``"cg"``."""
        switches = settings.switches()
        if switches.kept_pillars is None or self.model.lattice is None or self.choice == "kept":
            return np.inf
        if self.choice == "cg":
            return 0
        if 2 * attached <= self.model.M:
            return min(max(switches.kept_pillars, kept_partial_count(switches)), _memory_cap(self, switches))
        return min(switches.kept_pillars, _memory_cap(self, switches))

    def _drop_inverse_beyond_kept(self, attached: int) -> bool:
        """Drop the kept inverse (and go ``iterative``) when ``attached`` pillars are beyond `_kept_limit`;
        whether it did."""
        if attached <= self._kept_limit(attached):
            return False
        self.iterative = True
        self._B = np.zeros((16, 16))
        self._work = np.empty(_SLAB)
        self.n = attached
        return True

    def _mark(self, pillars, on: bool) -> None:
        """Iterative: pillars join or leave (no inverse to update); under half of `_kept_limit` attached,
        the inverse is kept again."""
        self.attached[pillars] = on
        self.n = int(np.count_nonzero(self.attached))
        self.updates += int(np.size(pillars))
        if 2 * self.n <= self._kept_limit(self.n):
            self.refactor()

    @property
    def B(self) -> np.ndarray:
        if self.iterative:
            raise RuntimeError("no kept inverse while the solve is CG (Solver.iterative); use inverse_product")
        return self._B[:self.n, :self.n]

    def _reserve(self, n: int) -> None:
        if n > self._B.shape[0]:
            grown = np.zeros((max(n, 2 * self._B.shape[0]),) * 2)
            grown[:self.n, :self.n] = self.B
            self._B = grown
            self._work = np.empty(max(_SLAB, grown.shape[0]))

    def refactor(self) -> None:
        model = self.model
        S = np.flatnonzero(self.attached)
        self.updates = 0
        if self._drop_inverse_beyond_kept(S.size):
            return
        self.iterative = False
        self.position[:] = -1
        self.position[S] = np.arange(S.size)
        self.order[:S.size] = S
        self.n = 0
        self._reserve(S.size)
        self.n = S.size
        if S.size:
            self.B[:] = _spd_inverse(model.uniform_block(S, S) + model.spring_matrix(S))

    def remove(self, p: int) -> None:
        if self.iterative:
            self._mark(p, False)
            return
        i = int(self.position[p])
        B = self.B
        column = B[:, i].copy()
        if column[i] > 0:
            _update(B, column[:, None], -(column / column[i])[None], self._work)
        last = self.n - 1
        if i != last:
            B[[i, last], :] = B[[last, i], :]
            B[:, [i, last]] = B[:, [last, i]]
            self.order[i] = self.order[last]
            self.position[self.order[i]] = i
        self.position[p] = -1
        self.n = last
        self.attached[p] = False
        self.updates += 1

    def add(self, p: int) -> None:
        if self.iterative or self._drop_inverse_beyond_kept(self.n + 1):
            self._mark(p, True)
            return
        model = self.model
        cols = self.order[:self.n]
        springs = model.spring_row(p)
        row = model.uniform_block(np.array([p]), cols)[0] + springs[cols]
        diagonal = model.gram[p, 0] + springs[p]
        Br = self.B @ row
        c = diagonal - row @ Br
        if not c > 1e-12 * diagonal:
            self.attached[p] = True
            self.refactor()
            return
        n = self.n
        self._reserve(n + 1)
        B = self._B
        _update(B[:n, :n], Br[:, None], (Br / c)[None], self._work)
        B[n, :n] = B[:n, n] = -Br / c
        B[n, n] = 1.0 / c
        self.order[n] = p
        self.position[p] = n
        self.n = n + 1
        self.attached[p] = True
        self.updates += 1

    def reshape(self, p: int) -> None:
        """Attached pillar p's row of (G00 + H) has changed (a new raster): B follows in place.

        The leave and the join of `remove` and `add` folded into one update at p's own row: with c = B e_p
        (the old inverse) and r the new row without its diagonal a, B - c c^T / c_p is the inverse without
        p, on which r gives b = B r - c (c . r) / c_p and the Schur complement s = a - r . b; then B gets
        b b^T / s besides, and its row and column p read -b / s and 1 / s.  One pass over B instead of the
        four of a leave and a join.
        """
        if self.iterative:
            self.updates += 1
            return
        model = self.model
        i = int(self.position[p])
        cols = self.order[:self.n]
        springs = model.spring_row(p)
        row = model.uniform_block(np.array([p]), cols)[0] + springs[cols]
        diagonal = float(row[i])
        row[i] = 0.0
        B = self.B
        column = B[:, i].copy()
        if not column[i] > 0:
            self.refactor()
            return
        Br = B @ row - column * (float(column @ row) / column[i])
        Br[i] = 0.0
        c = diagonal - float(row @ Br)
        if not c > 1e-12 * diagonal:
            self.refactor()
            return
        _update(B, np.stack([column, Br], axis=1), np.stack([-(column / column[i]), Br / c]), self._work)
        B[i, :] = B[:, i] = -Br / c
        B[i, i] = 1.0 / c
        self.updates += 1

    def remove_many(self, pillars: np.ndarray) -> None:
        """Several pillars leave at once: one block update, B_KK - B_KR B_RR^-1 B_RK (O(n^2 k) in one pass
        over B instead of k), or a refactorisation when most of them leave."""
        pillars = np.asarray(pillars, dtype=np.int64)
        if self.iterative:
            self._mark(pillars, False)
            return
        if pillars.size <= 1:
            for p in pillars:
                self.remove(int(p))
            return
        if 3 * pillars.size >= self.n:
            self.attached[pillars] = False
            self.refactor()
            return
        B = self.B
        n, k = self.n, pillars.size
        leave = self.position[pillars]
        try:
            block = scipy.linalg.cho_factor(B[np.ix_(leave, leave)])
        except np.linalg.LinAlgError:
            self.attached[pillars] = False
            self.refactor()
            return
        # In place: B - B_:R B_RR^-1 B_R: (the rows and columns R become garbage), then the kept pillars
        # beyond n - k move into the places of those that leave.
        coupling = B[:, leave].copy()
        _update(B, coupling, -scipy.linalg.cho_solve(block, coupling.T), self._work)
        last = n - k
        holes = np.sort(leave[leave < last])
        movers = np.setdiff1d(np.arange(last, n), leave)
        B[holes, :] = B[movers, :]
        B[:, holes] = B[:, movers]
        self.order[holes] = self.order[movers]
        self.position[pillars] = -1
        self.position[self.order[holes]] = holes
        self.n = last
        self.attached[pillars] = False
        self.updates += k

    def add_many(self, pillars: np.ndarray) -> None:
        """Several pillars join at once: one block (Schur complement) update, O(n^2 k) in one pass over B."""
        pillars = np.asarray(pillars, dtype=np.int64)
        if self.iterative or self._drop_inverse_beyond_kept(self.n + pillars.size):
            self._mark(pillars, True)
            return
        if pillars.size <= 1 or self.n == 0:
            for p in pillars:
                self.add(int(p))
            return
        model = self.model
        cols = self.order[:self.n]
        # The springs' blocks of the joining pillars only (rows of all M pillars each: 1.6 GB for 2000
        # joining pillars of 10^5).
        rows = model.uniform_block(pillars, cols) + model.spring_matrix(pillars, cols)
        diagonal = model.uniform_block(pillars, pillars) + model.spring_matrix(pillars)
        BR = self.B @ rows.T  # (n, k)
        schur = diagonal - rows @ BR
        try:
            inverse = _spd_inverse(schur)
        except np.linalg.LinAlgError:
            self.attached[pillars] = True
            self.refactor()
            return
        n, k = self.n, pillars.size
        self._reserve(n + k)
        B = self._B
        coupling = BR @ inverse  # (n, k)
        _update(B[:n, :n], coupling, BR.T, self._work)
        B[:n, n:n + k] = -coupling
        B[n:n + k, :n] = -coupling.T
        B[n:n + k, n:n + k] = inverse
        self.order[n:n + k] = pillars
        self.position[pillars] = np.arange(n, n + k)
        self.n = n + k
        self.attached[pillars] = True
        self.updates += k

    def solve(self) -> tuple[np.ndarray, np.ndarray]:
        """(sol, fields): the uniform amplitudes are d sol[:, 0] - sol[:, 1] on the attached set (0 elsewhere);
        ``fields`` = `PillarModel.fields` of ``sol``."""
        model = self.model
        self.solves += 1
        S = self.attached
        rhs = np.stack([np.where(S, model.force, 0.0), np.where(S, model.force * model.g, 0.0)], axis=1)
        if self.iterative:
            heights = model.g[S]
            if heights.size and float(np.ptp(heights)) == 0.0:
                # Level tips: the second right-hand side is the first times their common height.
                sol, fields = self.cg.solve(S, rhs[:, :1], start=self._last[:, :1])
                sol, fields = np.concatenate([sol, heights[0] * sol], axis=1), np.concatenate(
                    [fields, heights[0] * fields], axis=2)
            else:
                sol, fields = self.cg.solve(S, rhs, start=self._last)
            self._last = sol
            return sol, fields
        for attempt in range(2):
            on = self.order[:self.n]
            sol = np.zeros((model.M, 2))
            sol[on] = self.B @ rhs[on]
            fields = model.fields(sol)
            residual = fields[0].copy()
            residual[:, 0] += model.spring_product(sol[:, 0], S)
            residual[:, 1] += model.spring_product(sol[:, 1], S)
            residual = np.where(S[:, None], residual - rhs, 0.0)
            scale = np.linalg.norm(rhs, axis=0) + 1e-300
            if attempt == 0 and np.max(np.linalg.norm(residual, axis=0) / scale) > _RESIDUAL:
                self.refactor()
                continue
            break
        return sol, fields

    def inverse_product(self, v: np.ndarray, start: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """(x, fields of x): x = (G00 + H)_SS^-1 v on the attached set S (0 off it) for v (M, k), and
        `PillarModel.fields` of x; ``start``: the CG's warm start (while ``iterative``)."""
        if self.iterative:
            return self.cg.solve(self.attached, v, start=start)
        out = np.zeros_like(v)
        on = self.order[:self.n]
        out[on] = self.B @ v[on]
        return out, self.model.fields(out)


def _memory_cap(solver: Solver, switches: settings.Switches) -> float:
    """The most attached pillars of ``solver`` whose kept inverse (`brushbem.config.resources.pillar_kept_bytes`)
    takes at most half of the memory a run may use (`available_memory`, read once; inf where unknown or off),
    with a warning the first time the switches ask for more on this lattice (a lattice only: `_kept_limit`)."""
    if solver._cap is None:
        limit, source = available_memory()
        solver._cap = np.inf if limit is None else math.floor(math.sqrt(0.5 * limit / pillar_kept_bytes(1)))
        partial = kept_partial_count(switches)
        asked = min(solver.model.M, max(switches.kept_pillars, min(partial, solver.model.M // 2)))
        if asked > solver._cap:
            budget = (f"kept_partial = {switches.kept_partial}" if switches.kept_partial is not None else
                      f"kept_partial_bytes = {format_bytes(switches.kept_partial_bytes)} ({partial} pillars)")
            warnings.warn(f"Switches.kept_pillars = {switches.kept_pillars}, {budget}: a kept inverse of {asked} "
                          f"attached pillars needs about "
                          f"{format_bytes(pillar_kept_bytes(asked))} at its peak, more than half of the "
                          f"{format_bytes(limit)} of {source}; the pillar model keeps it up to {solver._cap} "
                          "pillars and solves by CG beyond", RuntimeWarning, stacklevel=2)
    return solver._cap


def full_solve(model: PillarModel, attached: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(alpha, beta) of every mode (M, m) by one dense factorisation (``coupling = 'full'``)."""
    S = np.flatnonzero(attached)
    m = model.m
    alpha = np.zeros((model.M, m))
    beta = np.zeros((model.M, m))
    if S.size == 0:
        return alpha, beta
    A = model.Gf[np.ix_(S, S)].transpose(0, 2, 1, 3).reshape(S.size * m, S.size * m).copy()
    A[::m, ::m] += model.spring_matrix(S)
    rhs = np.zeros((S.size * m, 2))
    rhs[::m, 0] = model.force[S]
    rhs[::m, 1] = model.force[S] * model.g[S]
    sol = scipy.linalg.cho_solve(scipy.linalg.cho_factor(A), rhs)
    alpha[S] = sol[:, 0].reshape(S.size, m)
    beta[S] = sol[:, 1].reshape(S.size, m)
    return alpha, beta


#: The higher modes' near field is fed back until their amplitudes change by less than this fraction (three
#: or four rounds: the coupling through a neighbour's higher mode is weak), or for at most this many rounds.
_RADIATION_TOLERANCE = 1e-7
_RADIATION_ROUNDS = 30


def radiate(model: PillarModel, solver: Solver, attached: np.ndarray, sol: np.ndarray,
            fields: np.ndarray) -> tuple[np.ndarray, np.ndarray, int]:
    """The solution and fields with the higher modes' near field fed back (``coupling = 'local'``), and the rounds.

    The higher modes' amplitudes answer the field on them, -field_k / gram_k; their own field on the
    neighbours (`PillarModel.radiation`, near blocks only) shifts the neighbours' higher modes in turn.
    Fixed point, pillar by pillar: xh = -(field + r)_h / gram_h, r = radiation(xh), until the higher
    amplitudes change by less than ``_RADIATION_TOLERANCE`` of their size.  The uniform amplitudes keep
    the uniform modes' solution (``Switches.radiate_uniform``: they answer r_0 too, one global solve a round).
    """
    attached = attached[:, None, None]
    gram = model.gram[:, 1:, None]
    xh = np.where(attached, -fields[1:].transpose(1, 0, 2) / gram, 0.0)
    total_sol, total_fields = sol, fields
    correction = None
    for rounds in range(1, _RADIATION_ROUNDS + 1):
        r = model.radiation(xh)
        if settings.switches().radiate_uniform:
            # The last round's correction is the warm start (the rounds converge: r changes less each time);
            # the first round's is the last call's (a press's next round changes a few pillars).
            last = solver.correction if correction is None else correction
            negative, shift = solver.inverse_product(r[0], start=None if last is None else -last)
            correction, shift = -negative, -shift
            shift[0] -= model.gram[:, :1] * correction
            total_sol, total_fields = sol + correction, fields + shift + r
        else:
            total_fields = fields + r
        updated = np.where(attached, -total_fields[1:].transpose(1, 0, 2) / gram, 0.0)
        change = float(np.max(np.abs(updated - xh)))
        xh = updated
        if change <= _RADIATION_TOLERANCE * (float(np.max(np.abs(xh))) + 1e-300):
            break
    solver.correction = correction
    return total_sol, total_fields, rounds
