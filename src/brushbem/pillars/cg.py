"""The pillar-level solve without a kept inverse: preconditioned CG on the lattice's FFT product (`LatticeCG`).

A level brush attaches every pillar, so its uniform modes' system (G00 + H)
on the attached set is as large as the brush: at 10^5 pillars its kept
inverse (`brushbem.pillars.solver.Solver`) would take 80 GB.  On a
lattice the product with G00 is `PillarModel.fields` (near blocks and the
far field's FFT, O(M log M)), so the system is solved by conjugate
gradients instead, in O(M) memory.

Preconditioner: the couplings of full rasters depend on the pillars' lattice
offset only, so G00 of the full lattice is a two-level Toeplitz matrix; its
kernel, taken from one column of the product, embedded in a period of at
least 2 n - 1 lattice points per side (the far sums' own period) gives a
circulant C that the FFT inverts.  The springs enter as their mean diagonal.
On the attached set S the preconditioner is P_S (C + h I)^-1 P_S.  On the
full lattice it is nearly exact: 8-9 iterations from a cold start to 1e-10
at 10^4 and 10^5 pillars against 28-47 with the diagonal, and 7-20 where
pillars are off (a disk of them attached, or one in ten missing at random),
measured on the ``size`` study's level lattices (phi = 0.12, k~ = 10);
`tests/test_pillar_cg.py` holds a 16 x 16 lattice to at most 10.

Where the attached set is scattered (a rough brush's contact: most attached
pillars have a detached neighbour, whatever their share of the lattice) the
circulant fits poorly: 21 iterations a solve on average, 42 at most, in the
loading of the 64 x 64 chapter-5 brush at sigma~ = 0.5 by CG throughout.
There the preconditioner is the near field itself: A_S, the exact near
couplings G00 between attached pillars closer than ``near`` (a sparse matrix
of the lattice's few neighbours), the diagonal and the springs' diagonal,
factorised by sparse LU (symmetric ordering, diagonal pivots: in effect a
Cholesky factorisation) and kept while the set and its rasters stand.  The
same loading took 10 iterations a solve on average, 18 at most, and 9.1 CPU s
instead of 16.6 (the 32 x 32 brush at sigma~ = 1: 6.9 against 13.1).  Where
A_S is not positive definite (a pivot <= 0) the circulant serves.

Which of the two serves is decided by the set's boundary share (`boundary_share`:
the attached pillars with a detached neighbour within ``near``, over all
attached), not by its share of the lattice: measured on the same systems
(the ``size`` study's brushes, phi = 0.12, k~ = 1e-2, warm starts as the
path gives them), the circulant took 5-6 iterations where the near field took
9-13 on a level 48 x 48 brush peeling from its edges (boundary shares 0.02-0.23,
332 to 2264 of 2304 attached), and 19-52 where the near field took 12-25 on
the sigma~ = 0.1 brush at 100 x 100 (boundary shares 0.93-1.0, 915 to 5693 of
10^4 attached: more than half of the lattice at 5693, 52 against 25); at
316 x 316 (11606 attached, share 1.0) 47 against 22.  The near field serves
above `BOUNDARY_SHARE`.

Single-precision products: nearly all of a solve's time is its products'
far field (at 316 x 316 pillars, the pull-off's first 100 states: 74 % of
the CPU time, its transforms 46 %).  A warm-started solve starts at a
relative residual of about 3e-4 and falls about fivefold an iteration; the
products of its late iterations only refine what the early ones found, so
they may be inexact in proportion to how small the residual already is
(relaxed inexact Krylov methods: Simoncini and Szyld, SIAM J. Sci. Comput.
25, 2003, 454-477).  An iteration takes the far field in single precision
(`brushbem.pillars.lattice.Lattice.far_by_pillar`, of relative error at
most `SINGLE_ERROR`) when the error that adds to the recursive residual,
predicted as 2 `SINGLE_ERROR` ||r||, keeps the error of all its single
products within `SINGLE_SHARE` of the tolerance; the true residual, from
the solution's fields (which the solve returns anyway), is checked at the
end, and a solve that misses goes on from it in double precision
(``Switches.single_pillar_products``).  The products also take the near
blocks of the attached pillars only.  Profile of that pull-off (cProfile,
before both): the solves 96 % of the time, their products 82 %, the far
field 74 % (its transforms 46 %, its spectral products and copies 28 %),
the two-level preconditioner 4 %, the near factor 1.5 %.  Measured, before
and after in one run (``benchmarks/large_brush.py --sizes 316 --brush size
--sigma 0.1 --seed 0 --exact-max 0 --solves 40 --before 7791b03 --repeat
3``, load about 3): the loading's first 40 solves at 316 x 316, the model's
build included, 46.1 CPU-s against 59.8 (1.30x; 508 iterations against
507); a solve on a random 18 % of that lattice that loses 3 pillars a solve
1.28 against 1.56 CPU-s with two thirds of its products single
(`benchmarks/pillar_cg_single.py`); at 10^4 by CG throughout (``--sizes
100 ... --pillar-solve cg``) the whole run 132 against 165 CPU-s (pull-off
1.24x), F_A and the work the same to 4e-13 and 5e-12.  With the far field
by slabs of the spectrum (`brushbem.pillars.lattice`) and the iteration's
vectors on the attached rows, the same 100 states (``large_brush.py
--pull-off 100 --profile``): 0.405 CPU-s a state under the profiler, the
solves 94 % of it, their products 74 %, the far field 71 % (its transforms
46 %, its spectral products 11 %), the near blocks and gathers 9 %, the
preconditioner 5 %.
"""

from __future__ import annotations

import numpy as np
import scipy.fft
import scipy.sparse
import scipy.sparse.linalg

from brushbem import settings
from brushbem.pillars.recycle import Recycler

__all__ = ["LatticeCG", "NotConverged", "SINGLE_ERROR", "TOLERANCE", "boundary_share"]

#: The near-field preconditioner (`LatticeCG.near_factor`) serves attached sets whose `boundary_share` is above
#: this; the circulant the others (compact sets, which it fits; the measurements in the module docstring fall
#: at 0.23 or below and 0.93 or above).
BOUNDARY_SHARE = 0.5

#: Relative residual ||b - A x|| / ||b|| of every right-hand side at which the CG stops (the kept inverse's
#: own check, `brushbem.pillars.solver`, refactorises above 1e-10).
TOLERANCE = 1e-11

#: Bound on the relative error of a product (G00 + H) p whose far field is in single precision (against the
#: double one; 2-norms).  Measured: 1.4e-8 - 8.3e-8 for scattered, smooth and positive p on a random 18 % of
#: a 100 x 100 lattice, 1.3e-8 - 4.5e-8 on 40 % of 32 x 32 with peeled rasters; the far field alone 1.5e-7 of
#: its norm at 100 x 100 and 316 x 316.  The bound leaves a factor 3.6 (`tests/test_pillar_cg.py` checks it).
SINGLE_ERROR = 3e-7

#: Share of the tolerance that the single-precision products of a solve may add to its residual, together
#: (the relaxed inexact CG, `LatticeCG.solve`; the true residual is checked at the end).
SINGLE_SHARE = 0.5


class NotConverged(RuntimeError):
    """The pillar-level CG did not reach its tolerance (the message says how far it got)."""


class LatticeCG:
    """(G00 + H)_SS x = b on the attached set S of a lattice brush, by CG with a circulant preconditioner."""

    def __init__(self, model):
        if model.lattice is None:
            raise ValueError("LatticeCG needs the pillars on a lattice (PillarModel.lattice)")
        self.model = model
        lattice = model.lattice
        self.index = lattice.index
        ny, nx = lattice.shape
        self.period = (scipy.fft.next_fast_len(2 * ny), scipy.fft.next_fast_len(2 * nx, real=True))
        kernel = self._kernel()
        diagonal = np.zeros(model.M)
        for cluster, stiffness in model.levels:
            diagonal += (model.h2 / stiffness)[cluster]
        diagonal *= model.force**2
        spectrum = scipy.fft.rfft2(kernel).real + float(np.mean(diagonal))
        # The circulant of a positive kernel's even extension is positive for 1 / r couplings; a period
        # whose embedding is not (a coarse lattice of few pillars) is clipped to keep P positive definite.
        floor = 1e-3 * float(np.min(model.gram[:, 0]) + np.min(diagonal))
        self.inverse_spectrum = 1.0 / np.maximum(spectrum, floor)
        self.iterations = 0  # all solves together
        self._near_key: tuple | None = None
        self._near_lu = None
        self._near_matrix = None  # the near-field matrix that ``_near_lu`` factorises (`Recycler.absorb`)
        self.recycler: Recycler | None = None  # the kept Ritz vectors (`brushbem.pillars.recycle`)
        self._set_key: bytes | None = None  # the set whose `boundary_share` ``_scattered`` holds
        self._scattered = False
        self.products = 0
        self.single_products = 0  # of ``products``, those with the far field in single precision
        self.single_error = SINGLE_ERROR  # the bound `solve` takes for their relative error
        self.restarts = 0  # solves whose true residual missed the tolerance after single products (`solve`)

    def _kernel(self) -> np.ndarray:
        """G00 of full rasters against the lattice offset, as a periodic array of ``period``."""
        model = self.model
        index = self.index
        source = int(np.lexsort((index[:, 1], index[:, 0]))[0])  # the first lattice point held
        unit = np.zeros((model.M, 1))
        unit[source, 0] = 1.0
        column = model.fields(unit)[0][:, 0]
        offset = index - index[source]
        py, px = self.period
        kernel = np.zeros((py, px))
        ahead = np.all(offset >= 0, axis=1)
        values = np.zeros(model.lattice.shape)
        values[offset[ahead, 0], offset[ahead, 1]] = column[ahead]
        # Offsets no pillar holds (a lattice with holes): the monopole of the farthest one held.
        held = np.zeros(model.lattice.shape, dtype=bool)
        held[offset[ahead, 0], offset[ahead, 1]] = True
        if not held.all():
            oy, ox = np.nonzero(held)
            r = np.hypot(oy, ox)
            far = int(np.argmax(r))
            gy, gx = np.indices(held.shape)
            distance = np.maximum(np.hypot(gy, gx), 1.0)
            values = np.where(held, values, values[oy[far], ox[far]] * max(r[far], 1.0) / distance)
        ny, nx = values.shape
        kernel[:ny, :nx] = values
        kernel[py - ny + 1:, :nx] = values[1:][::-1]
        kernel[:ny, px - nx + 1:] = values[:, 1:][:, ::-1]
        kernel[py - ny + 1:, px - nx + 1:] = values[1:, 1:][::-1, ::-1]
        return kernel

    def near_factor(self, attached: np.ndarray):
        """The preconditioner on a scattered set (`boundary_share` above ``BOUNDARY_SHARE``): the sparse LU of
        the near-field part A_S of (G00 + H)_SS (`_near_factor`), kept while S and its rasters stand; None on
        a compact set (the circulant's) or where A_S is not positive definite."""
        model = self.model
        if not settings.switches().near_preconditioner:
            return None
        S = np.flatnonzero(attached)
        if S.tobytes() != self._set_key:
            self._set_key, self._scattered = S.tobytes(), boundary_share(model, attached) > BOUNDARY_SHARE
        if not self._scattered:
            return None
        serials = self.serials(attached)[S]
        key = (S.tobytes(), serials.tobytes(), model.origin[S].tobytes())
        if self._near_key != key:
            self._near_key = key
            self._near_lu, self._near_matrix = _near_factor(model, S)
        return self._near_lu

    def precondition(self, r: np.ndarray, attached: np.ndarray, near=None, space=None) -> np.ndarray:
        """z for the residual r (M, k): A_S^-1 r on S by ``near`` (`near_factor`), with the recycled vectors'
        coarse part where ``space`` (`brushbem.pillars.recycle.Space`) is given, or without ``near`` the
        circulant's P_S (C + h I)^-1 P_S r."""
        if near is None:
            return self.circulant_precondition(r, attached)
        out = np.zeros_like(r)
        S = np.flatnonzero(attached)
        part = np.ascontiguousarray(r[S])
        out[S] = near.solve(part) if space is None else space.apply(part, near)
        return out

    def circulant_precondition(self, r: np.ndarray, attached: np.ndarray) -> np.ndarray:
        """P_S (C + h I)^-1 P_S r for r (M, k)."""
        iy, ix = self.index[:, 0], self.index[:, 1]
        py, px = self.period
        grid = np.zeros((r.shape[1], py, px))
        grid[:, iy, ix] = np.where(attached[:, None], r, 0.0).T
        z = scipy.fft.irfft2(scipy.fft.rfft2(grid) * self.inverse_spectrum, s=(py, px))
        return np.where(attached[:, None], z[:, iy, ix].T, 0.0)

    def serials(self, attached: np.ndarray) -> np.ndarray:
        """Every pillar's raster (`PillarModel.basis` serial) where ``attached``, -1 elsewhere (M,)."""
        model = self.model
        S = np.flatnonzero(attached)
        out = np.full(model.M, -1, dtype=np.int64)
        out[S] = np.fromiter((model.basis[p].serial for p in S), dtype=np.int64, count=S.size)
        return out

    def _recycler(self) -> Recycler | None:
        """The kept Ritz vectors (``Switches.recycled_vectors`` of them at most; None when that is 0).  A new
        count keeps the vectors kept so far (the next Rayleigh-Ritz step keeps the new count)."""
        most = settings.switches().recycled_vectors
        if most <= 0:
            return None
        if self.recycler is None:
            self.recycler = Recycler(self.model.M, most)
        self.recycler.most = most
        return self.recycler

    def _on_set(self, V: np.ndarray, S: np.ndarray, attached: np.ndarray) -> np.ndarray:
        """A_S V for V (n, k) on the attached pillars S (indices): (n, k), two columns a product (per column,
        one of 40 took 7.8 ms at 10^4 pillars against 2.9 for one of two: the far field's arrays leave the
        cache)."""
        out = np.empty_like(V)
        for start in range(0, V.shape[1], 2):
            part = V[:, start:start + 2]
            out[:, start:start + 2] = self._product_on(part, S, attached, np.ones(part.shape[1], dtype=bool),
                                                       single=self._single_allowed())
        return out

    def _product(self, x: np.ndarray, attached: np.ndarray, columns: np.ndarray, single: bool = False) -> np.ndarray:
        """(G00 + H) x on S for x (M, k) zero off S: the uniform modes' field of the ``columns`` only;
        ``single``: its far field in single precision (`brushbem.pillars.lattice.Lattice.far_by_pillar`)."""
        S = np.flatnonzero(attached)
        out = np.zeros_like(x)
        out[S] = self._product_on(np.ascontiguousarray(x[S]), S, attached, columns, single=single)
        return out

    def _product_on(self, V: np.ndarray, S: np.ndarray, attached: np.ndarray, columns: np.ndarray,
                    single: bool = False) -> np.ndarray:
        """`_product` on the attached pillars' rows: (G00 + H)_SS V for V (n, k) on S (indices), the ``columns``
        only (0 in the others)."""
        model = self.model
        self.products += 1
        self.single_products += bool(single)
        out = np.zeros_like(V)
        if not columns.any():
            return out
        full = np.zeros((model.M, int(np.count_nonzero(columns))))
        full[S] = V[:, columns]
        rows = None if S.size == model.M else S  # the near blocks of the set only
        product = model.fields(full, uniform=True, single=single, rows=rows)[0][S]
        for c in range(full.shape[1]):
            product[:, c] += _springs_on(model, full[S, c], S)
        out[:, columns] = product
        return out

    def _precondition_on(self, r: np.ndarray, S: np.ndarray, attached: np.ndarray, near, space) -> np.ndarray:
        """`precondition` on the attached pillars' rows: z (n, k) for r (n, k) on S (indices)."""
        if near is not None:
            r = np.ascontiguousarray(r)
            return near.solve(r) if space is None else space.apply(r, near)
        full = np.zeros((self.model.M, r.shape[1]))
        full[S] = r
        return self.circulant_precondition(full, attached)[S]

    def solve(self, attached: np.ndarray, rhs: np.ndarray, start: np.ndarray | None = None,
              tolerance: float = TOLERANCE) -> tuple[np.ndarray, np.ndarray]:
        """(x, fields of x) with (G00 + H)_SS x = rhs on S (``attached``), x = 0 off S; rhs (M, k).

        Every column runs its own CG (its own steps) and the columns still short of ``tolerance`` (relative
        residual) share the product of each iteration: the uniform modes' field only
        (`PillarModel.fields` with ``uniform``); the fields of every mode are those of the solution, one
        product more.  ``start``: a warm start (restricted to S here).  The late products take the far field in
        single precision while their error fits the budget of `SINGLE_SHARE` (module docstring).  The
        iteration's vectors hold the attached pillars' rows only (at 316 x 316 pillars, 18 % attached: their
        norms and inner products over all M rows had taken 7 % of a pull-off state's time).

        Why one function: the iteration, the single products' budget and the check of the true residual at the
        end share x, r, z, p and every column's residual norms; split, each piece would take and return them all.
        """
        rhs = np.where(attached[:, None], rhs, 0.0)
        k = rhs.shape[1]
        S = np.flatnonzero(attached)
        b = rhs[S]
        norms = np.linalg.norm(b, axis=0)
        # A column of zeros has the solution zero, whatever the start.
        x = np.zeros_like(b) if start is None else np.where(norms > 0, start[S], 0.0)
        r = b - self._product_on(x, S, attached, np.ones(k, dtype=bool))
        residual = np.linalg.norm(r, axis=0)
        active = residual > tolerance * norms
        if not active.any():
            solution = self._whole(x, S)
            return solution, self.model.fields(solution)
        near = self.near_factor(attached)
        recycler = self._recycler() if near is not None else None
        space, fresh, serials = None, False, None
        if recycler is not None:
            serials = self.serials(attached)
            changed = recycler.changed(serials)
            fresh = changed > settings.switches().recycled_stale
            if fresh and recycler.W is not None:
                recycler.refresh(S, serials, lambda V: self._on_set(V, S, attached))
            space = recycler.space(S)
        directions: list[np.ndarray] = []
        products: list[np.ndarray] = []
        z = self._precondition_on(r, S, attached, near, space)
        p = z.copy()
        rz = np.sum(r * z, axis=0)
        most = settings.switches().pillar_cg_iterations
        # The error the single-precision products have added to each column's recursive residual (at most
        # SINGLE_ERROR |step| ||A p|| a product), and the most it may add: SINGLE_SHARE of the tolerance.
        inexact = self._single_allowed()
        carried = np.zeros(k)
        took_single = False
        budget = SINGLE_SHARE * tolerance * norms
        for iteration in range(1, most + 1):
            # A single product adds about 2 SINGLE_ERROR ||r|| (the residual's fall is ||step A p||, at most
            # about twice ||r||); it is taken when that fits every active column's budget.
            single = inexact and bool(np.all((carried + 2.0 * self.single_error * residual <= budget)[active]))
            ap = self._product_on(p, S, attached, active, single=single)
            took_single |= single
            if fresh:
                directions.append(p[:, active])
                products.append(ap[:, active])
            curvature = np.sum(p * ap, axis=0)
            if bool(np.any(active & ~(curvature > 0))):
                raise NotConverged("the pillar-level system is not positive definite on the attached set "
                                   f"(CG curvature {curvature.min():.3g} at iteration {iteration})")
            step = np.where(active, rz / np.where(active, curvature, 1.0), 0.0)
            x += step * p
            r -= step * ap
            if single:
                carried += self.single_error * np.abs(step) * np.linalg.norm(ap, axis=0)
            self.iterations += 1
            residual = np.linalg.norm(r, axis=0)
            active = residual > tolerance * norms
            if not active.any():
                solution = self._whole(x, S)
                fields = self.model.fields(solution)
                if not took_single:
                    break
                r = self._true_residual(rhs, solution, fields, attached)[S]
                residual = np.linalg.norm(r, axis=0)
                active = residual > tolerance * norms
                if not active.any():
                    break
                # Missed (rare): on from the true residual, in double precision, CG restarted.
                self.restarts += 1
                inexact = took_single = False
                z = self._precondition_on(r, S, attached, near, space)
                p = z.copy()
                rz = np.sum(r * z, axis=0)
                continue
            z = self._precondition_on(r, S, attached, near, space)
            rz_next = np.sum(r * z, axis=0)
            p = z + np.where(active, rz_next / np.where(active, rz, 1.0), 0.0) * p
            rz = rz_next
        else:
            worst = float(np.max(residual / np.where(norms > 0, norms, 1.0)))
            raise NotConverged(f"the pillar-level CG reached a relative residual of {worst:.3g}, not "
                               f"{tolerance:g}, in {most} iterations ({int(attached.sum())} pillars attached, "
                               f"{k} right-hand sides)")
        if fresh:
            recycler.absorb(S, serials, space, directions, products, self._near_matrix)
        return solution, fields

    def _whole(self, x: np.ndarray, S: np.ndarray) -> np.ndarray:
        """x (n, k) on the attached pillars S (indices) as (M, k), 0 off S."""
        out = np.zeros((self.model.M, x.shape[1]))
        out[S] = x
        return out

    def _true_residual(self, rhs: np.ndarray, x: np.ndarray, fields: np.ndarray, attached: np.ndarray) -> np.ndarray:
        """rhs - (G00 + H) x on S from the fields of x (`PillarModel.fields`, in double precision): the residual
        that single-precision products leave unchecked, at no product more."""
        r = rhs - fields[0]
        for c in range(rhs.shape[1]):
            r[:, c] -= self.model.spring_product(x[:, c], attached)
        return np.where(attached[:, None], r, 0.0)

    def _single_allowed(self) -> bool:
        """Whether products may take the far field in single precision (``Switches.single_pillar_products``,
        on a lattice)."""
        return settings.switches().single_pillar_products and self.model.lattice is not None


def boundary_share(model, attached: np.ndarray) -> float:
    """The share of the attached pillars that have a detached neighbour (``model.near_index``: the pillars
    within ``near``); 0 on an empty set."""
    if not attached.any():
        return 0.0
    rows = np.flatnonzero(attached)
    detached = model.near_valid[rows] & ~attached[model.near_index[rows]]
    return float(np.count_nonzero(detached.any(axis=1))) / rows.size


def _springs_on(model, v: np.ndarray, S: np.ndarray) -> np.ndarray:
    """H_SS v for v (n,) on the attached pillars ``S`` (indices): `PillarModel.spring_product` on their rows only
    (the same sums, without the zeros of the pillars off)."""
    out = np.zeros(S.size)
    weights = model.force[S] * v
    for cluster, stiffness in model.levels:
        mine = cluster[S]
        sums = np.bincount(mine, weights=weights, minlength=stiffness.size)
        out += (model.h2 / stiffness)[mine] * sums[mine]
    return out * model.force[S]


def _near_factor(model, S: np.ndarray):
    """The sparse LU of the near-field part of (G00 + H)_SS (`LatticeCG.near_factor`) and that part, or None
    and None where a pivot is not positive (the part is not positive definite, so no CG preconditioner)."""
    n = S.size
    position = np.full(model.M, -1, dtype=np.int64)
    position[S] = np.arange(n)
    where = position[model.near_index[S]]
    hit = model.near_valid[S] & (where >= 0)
    rows = np.nonzero(hit)[0]
    diagonal = model.gram[S, 0].copy()
    for cluster, stiffness in model.levels:
        diagonal += (model.h2 / stiffness)[cluster[S]] * model.force[S] ** 2
    A = scipy.sparse.csc_matrix((np.concatenate([model.near_full[S, :, 0, 0][hit], diagonal]),
                                 (np.concatenate([rows, np.arange(n)]), np.concatenate([where[hit], np.arange(n)]))),
                                shape=(n, n))
    try:
        lu = scipy.sparse.linalg.splu(A, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                                      options={"SymmetricMode": True})
    except RuntimeError:  # exactly singular
        return None, None
    return (lu, A) if bool(np.all(lu.U.diagonal() > 0)) else (None, None)
