"""The pillar model's far field on a lattice by FFT: `Lattice` (``LoadPath.method = "pillars"``).

On a brush whose pillars sit on a rectangular lattice, the far-field
coupling of `brushbem.pillars.basis` - the multipole expansion of
1/r between two tips' modes - depends on the pillars only through their
moments, once every tip's moments are taken about its lattice point instead
of its centroid, and on the pair through the lattice offset alone.  The sum
over all far pillars is then a handful of discrete convolutions over the
lattice, done by FFT in O(M log M) instead of the dense O(M^2) product.

Here: the far field of the uniform modes (the sources: with ``coupling =
"local"`` only their far field is kept; a higher mode carries no net force
and its field, fed back near only, falls off faster) on every mode.  To
second order in the moments, with R the offset between lattice points,
f = 1/r, t the target mode's moments and q the source's (both about their
lattice points):

    field_k = scale * sum_q x_q [t0 (q0 f - q1 . grad f + q2 : hess f / 2)
                                 + q0 (t1 . grad f + t2 : hess f / 2) - t1 . hess f . q1]

the same terms as `brushbem.pillars.basis._far`.  Pairs closer than
``near`` are left to the exact blocks (their kernel entries are zero here).
"""

from __future__ import annotations

import math
import os
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import scipy.fft

__all__ = ["Lattice", "far_workers"]

#: Columns of the half spectrum a slab of `Lattice.far_by_pillar` takes along y in double precision (twice as
#: many in single).  At 316 x 316 pillars, two columns, one thread (CPU time, a loaded machine): 16 or 32
#: took 52 ms in double precision, 8 took 54, 64 took 67 and the whole spectrum at once 76; in single
#: precision 32 or 64 took 26-28 ms against 31.5 at once.
_SLAB = 16

#: Smaller padded transforms take the whole spectrum as one slab (at 100 x 100 and 200 x 200 pillars, padded to
#: 208 x 208 and 400 x 400, slabs of 8-64 columns were no faster than one).
_SLABBED_POINTS = 512 * 512

#: The far fields' thread pool and the process that made it (a forked child makes its own).
_POOLS: dict[int, tuple[int, ThreadPoolExecutor]] = {}


def far_workers() -> int:
    """The threads of a far field: ``BRUSHBEM_FFT_WORKERS`` where set, else one.

    One by default, as the pillar model's BLAS (`brushbem.pillars.path`): on a loaded machine threads lose.
    Measured at 316 x 316 pillars (the ``size`` study's sigma~ = 0.1 brush, 200 pull-off states from the same
    loaded state, ``benchmarks/large_brush.py --pull-off``, two cores shared with two to three other
    processes): two threads 0.429 wall-s and 0.384 CPU-s a state against 0.364 and 0.353 on one, though a
    far field of two columns alone (load 3-4) took 74 ms of wall time on two threads against 98 in double
    precision and 49 against 62 in single, at the same CPU time.
    """
    value = os.environ.get("BRUSHBEM_FFT_WORKERS")
    return max(1, int(value)) if value else 1


def _pool(workers: int) -> ThreadPoolExecutor:
    """A pool of ``workers`` threads, made once in this process."""
    held = _POOLS.get(workers)
    if held is None or held[0] != os.getpid():
        held = _POOLS[workers] = (os.getpid(), ThreadPoolExecutor(workers, thread_name_prefix="far-field"))
    return held[1]


class Lattice:
    """Pillars on a rectangular lattice: their indices, lattice points and the far field's kernels.

    ``index`` (M, 2): every pillar's row and column in the lattice; ``points``
    (M, 2): its lattice point (elements); ``neighbours``: for every pillar the
    others whose lattice points are closer than ``near`` (elements).
    """

    def __init__(self, index: np.ndarray, shape: tuple[int, int], origin: np.ndarray, spacing: np.ndarray,
                 near: float, scale: float):
        self.index = index
        self.shape = shape
        self.points = origin + index * spacing
        self.scale = scale
        self._spacing = np.asarray(spacing, dtype=np.float64)
        self._near2 = near * near
        ny, nx = shape
        # Periods of at least 2 n - 1 (no offset wraps onto another), of fast transform lengths (2 n = 632 at
        # 316 x 316 pillars has the prime factor 79: 2.4 times slower than 640).
        self.padded = (scipy.fft.next_fast_len(2 * ny), scipy.fft.next_fast_len(2 * nx, real=True))
        py, px = self.padded
        di = np.fft.fftfreq(py, 1.0 / py)  # offsets 0, 1, ..., -1 (wrapped); those of |di| >= ny are zero
        dj = np.fft.fftfreq(px, 1.0 / px)
        ry = (di * spacing[0])[:, None] * np.ones((1, px))
        rx = np.ones((py, 1)) * (dj * spacing[1])[None, :]
        r2 = ry * ry + rx * rx
        far = r2 >= near * near
        far &= (np.abs(di) < ny)[:, None] & (np.abs(dj) < nx)[None, :]
        r2 = np.where(far, r2, 1.0)
        f3 = np.where(far, r2 ** -1.5, 0.0)
        f5 = f3 / r2
        f1 = np.where(far, r2 ** -0.5, 0.0)
        kernels = [f1, -ry * f3, -rx * f3, 3.0 * ry * ry * f5 - f3, 3.0 * ry * rx * f5, 3.0 * rx * rx * f5 - f3]
        #: Spectra of f, grad f (y, x) and hess f (yy, xy, xx) over the lattice offsets, near ones zero.
        self.spectra = scipy.fft.rfft2(np.stack(kernels), s=self.padded)
        # `spectra` by slabs of columns (`_slabs`), in single and double precision, once asked for.
        self._single: list | None = None
        self._double: list | None = None
        #: Every pillar's lattice site in row-major order, and whether the pillars are the sites in that order
        #: (a full lattice: its grids are the pillars' values reshaped, no scatter or gather).
        self._site = index[:, 0] * shape[1] + index[:, 1]
        self._in_order = bool(np.array_equal(self._site, np.arange(shape[0] * shape[1])))
        order = np.full(shape, -1, dtype=np.int64)
        order[index[:, 0], index[:, 1]] = np.arange(index.shape[0])
        self.neighbours = []
        reach_i = int(math.ceil(near / spacing[0])) if spacing[0] > 0 else 0
        reach_j = int(math.ceil(near / spacing[1])) if spacing[1] > 0 else 0
        for p, (i, j) in enumerate(index):
            rows = slice(max(i - reach_i, 0), min(i + reach_i + 1, ny))
            cols = slice(max(j - reach_j, 0), min(j + reach_j + 1, nx))
            close = order[rows, cols].ravel()
            close = close[close >= 0]
            distance = np.hypot(*(self.points[close] - self.points[p]).T)
            close = close[(distance < near) & (close != p)]
            self.neighbours.append(np.sort(close))

    @classmethod
    def detect(cls, centres: np.ndarray, near: float, scale: float) -> Lattice | None:
        """The lattice of pillar ``centres`` (elements), or None when they do not sit on one.

        Centres count as one lattice row (column) when they are within an
        element of each other; the rows must be evenly spaced (every centre
        within an element of its lattice point), every lattice site hold at
        most one pillar and at least half of them one.
        """
        M = centres.shape[0]
        if M < 4:
            return None
        index = np.zeros((M, 2), dtype=np.int64)
        origin = np.zeros(2)
        spacing = np.ones(2)
        shape = [1, 1]
        for axis in (0, 1):
            values = np.sort(centres[:, axis])
            levels = int(np.count_nonzero(np.diff(values) > 1.0)) + 1
            origin[axis] = values[0]
            if levels > 1:
                spacing[axis] = (values[-1] - values[0]) / (levels - 1)
                index[:, axis] = np.rint((centres[:, axis] - values[0]) / spacing[axis]).astype(np.int64)
                if np.max(np.abs(centres[:, axis] - values[0] - index[:, axis] * spacing[axis])) > 1.0:
                    return None
            shape[axis] = levels
        sites = index[:, 0] * shape[1] + index[:, 1]
        if np.unique(sites).size != M or 2 * M < shape[0] * shape[1]:
            return None
        # Lattice points about the mean offset of the centres from them (rasterisation shifts them alike).
        origin += np.mean(centres - (origin + index * spacing), axis=0)
        return cls(index, (shape[0], shape[1]), origin, spacing, near, scale)

    def far_field(self, x0: np.ndarray, sources: tuple[np.ndarray, np.ndarray, np.ndarray],
                  targets: tuple[np.ndarray, np.ndarray, np.ndarray]) -> np.ndarray:
        """The far field of the uniform amplitudes ``x0`` (M, c) on every mode: (m, M, c).

        ``sources`` = (q0 (M,), q1 (M, 2), q2 (M, 2, 2)): the uniform modes'
        moments (the element square's own second moment included);
        ``targets`` = (t0 (M, m), t1 (M, m, 2), t2 (M, m, 2, 2)): every mode's;
        all about the lattice points.  With the lattice sums P = sum q0 x f,
        D = sum x q1 . grad f, Q = sum x q2 : hess f, g = sum q0 x grad f,
        H = sum q0 x hess f, h = sum x hess f . q1:

            field_k = scale * [t0 (P - D + Q / 2) + t1 . (g - h) + t2 : H / 2].
        """
        return self.weighted_far_field(x0, *self.weights(sources, targets))

    @staticmethod
    def weights(sources: tuple[np.ndarray, np.ndarray, np.ndarray],
                targets: tuple[np.ndarray, np.ndarray, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
        """The moments as `weighted_far_field` takes them: the sources' (6, M), (q0, q1 (y, x), q2 (yy, xy,
        xx)), and every target mode's weights of the six lattice sums (potential, g - h (y, x), H (yy, xy,
        xx)), (M, m, 6): t0, t1 (y, x), t2 (yy / 2, xy, xx / 2)."""
        q0, q1, q2 = sources
        t0, t1, t2 = targets
        return (np.stack([q0, q1[:, 0], q1[:, 1], q2[:, 0, 0], q2[:, 0, 1], q2[:, 1, 1]]),
                np.stack([t0, t1[..., 0], t1[..., 1], 0.5 * t2[..., 0, 0], t2[..., 0, 1], 0.5 * t2[..., 1, 1]],
                         axis=-1))

    def weighted_far_field(self, x0: np.ndarray, sources: np.ndarray, targets: np.ndarray) -> np.ndarray:
        """`far_field` with the moments as `weights` gives them."""
        return self.far_by_pillar(x0, sources, targets).transpose(1, 0, 2)

    def far_by_pillar(self, x0: np.ndarray, sources: np.ndarray, targets: np.ndarray,
                      single: bool = False, workers: int | None = None) -> np.ndarray:
        """`weighted_far_field` pillar by pillar: (M, m, c), contiguous.

        ``single``: the grids, transforms and spectral products in single precision (float32,
        complex64; the sums weighted and returned in float64): 14.7 ms against 35.5 at 316 x 316
        pillars, 1.0 against 4.0 at 100 x 100 (one column, idle machine), with an error of 1.5e-7 of
        the far field's norm (`brushbem.pillars.cg.SINGLE_ERROR`), for the late iterations of a CG
        whose residual is already small (`brushbem.pillars.cg.LatticeCG.solve`).  ``workers``: the
        threads (default `far_workers`).
        """
        if x0.shape[1] > 1 and not single:
            # Column by column in double precision: the arrays of one stay in the cache (at 316 x 316 pillars
            # two columns together took 1.09-1.23 times the CPU time of each alone, on one thread or two; in
            # single precision 0.94-1.00).
            return np.concatenate([self.far_by_pillar(x0[:, j:j + 1], sources, targets, single, workers)
                                   for j in range(x0.shape[1])], axis=2)
        ny, nx = self.shape
        real = np.float32 if single else np.float64
        M = x0.shape[0]
        c = x0.shape[1]
        m = targets.shape[1]
        # The 2-D transforms of the zero-padded grids axis by axis: the rows of padding need no transform
        # along x, and only the rows of the lattice come back along x.  Along y, the transforms, the spectral
        # products and the inverse transforms go by slabs of ``_SLAB`` columns of the spectrum (`_spectral_slab`),
        # whose arrays stay in the cache: at 316 x 316 pillars, two columns, 55 ms against 78 in double
        # precision, the same numbers.  The slabs are shared among the ``workers`` threads, and the transforms
        # along x are threaded by scipy.
        py, px = self.padded
        # x0 transposed into a contiguous array first: the broadcast product over its strided columns took 40 us
        # of the far field's 450 at 32 x 32 pillars, and 5 us so (the same numbers).
        values = (sources[:, None, :] * np.ascontiguousarray(x0.T)[None]).astype(real, copy=False)
        if self._in_order:
            grid = values.reshape(6, c, ny, nx)
        else:
            grid = np.zeros((6, c, ny * nx), dtype=real)
            grid[:, :, self._site] = values
            grid = grid.reshape(6, c, ny, nx)
        workers = far_workers() if workers is None else workers
        # The transforms pad with zeros themselves (the same numbers as a padded copy, without it).
        half = scipy.fft.rfft(grid, n=px, axis=-1, workers=workers)
        sums = np.empty(half.shape, dtype=half.dtype)  # the six sums' spectra, rows of the lattice only
        slabs = self._slabs(single)
        if workers > 1:
            parts = [slabs[i::workers] for i in range(workers)]
            list(_pool(workers).map(lambda part: [self._spectral_slab(half, sums, *slab) for slab in part], parts))
        else:
            for slab in slabs:
                self._spectral_slab(half, sums, *slab)
        sums = scipy.fft.irfft(sums, n=px, axis=-1, workers=workers)[..., :nx]  # (6, c, ny, nx)
        if single:
            sums = sums.astype(np.float64)
        if m == 1 and self._in_order:
            # The uniform modes (the CG's product): the six sums weighted in place of a gathered copy.
            weights = targets[:, 0].T.reshape(6, 1, ny, nx)
            field = weights[0] * sums[0]
            for k in range(1, 6):
                field += weights[k] * sums[k]
            field = np.ascontiguousarray(field.reshape(c, M).T)[:, None, :]
        else:
            sums = sums.reshape(6, c, ny * nx)
            if not self._in_order:
                sums = sums[..., self._site]
            field = np.matmul(targets, np.ascontiguousarray(sums.transpose(2, 0, 1)))  # (M, m, c)
        field *= self.scale
        return field

    def _slabs(self, single: bool) -> list[tuple[int, int, np.ndarray]]:
        """The slabs of `far_by_pillar`: first and last column of the half spectrum and `spectra` on them as one
        contiguous array, ``_SLAB`` columns in double precision and twice as many in single (the same bytes),
        made once for each precision."""
        if (self._single if single else self._double) is None:
            spectra = self.spectra.astype(np.complex64) if single else self.spectra
            width = (2 * _SLAB if single else _SLAB) if self.padded[0] * self.padded[1] >= _SLABBED_POINTS else \
                spectra.shape[-1]
            slabs = [(a, min(a + width, spectra.shape[-1]), np.ascontiguousarray(spectra[..., a:a + width]))
                     for a in range(0, spectra.shape[-1], width)]
            if single:
                self._single = slabs
            else:
                self._double = slabs
        return self._single if single else self._double

    def _spectral_slab(self, half: np.ndarray, sums: np.ndarray, a: int, b: int, kernels: np.ndarray) -> None:
        """Columns a:b of the six sums' spectra (``sums``, the lattice's rows) from those of the sources'
        transforms along x (``half``): along y forth, the products with the kernels' spectra, back."""
        ny = self.shape[0]
        s0, s1y, s1x, s2yy, s2xy, s2xx = scipy.fft.fft(half[..., a:b], n=self.padded[0], axis=-2)
        f, gy, gx, hyy, hxy, hxx = kernels
        # The six sums' spectra, written in place (the temporaries of the products cost as much as the
        # products): f s0 - gy s1y - gx s1x + (hyy s2yy + hxx s2xx) / 2 + hxy s2xy, gy s0 - hyy s1y - hxy s1x,
        # gx s0 - hxy s1y - hxx s1x, hyy s0, hxy s0, hxx s0.  (The kernels' spectra are real or imaginary, but
        # products of real pairs on numpy's views took 12.4 ms at 316 x 316 pillars against these 4.1.)
        out = np.empty((6,) + s0.shape, dtype=s0.dtype)
        term = np.empty_like(s0)
        potential, along_y, along_x = out[0], out[1], out[2]
        np.multiply(f, s0, out=potential)
        potential -= np.multiply(gy, s1y, out=term)
        potential -= np.multiply(gx, s1x, out=term)
        np.multiply(hyy, s2yy, out=term)
        term += np.multiply(hxx, s2xx, out=along_y)
        term *= 0.5
        potential += term
        potential += np.multiply(hxy, s2xy, out=term)
        np.multiply(gy, s0, out=along_y)
        along_y -= np.multiply(hyy, s1y, out=term)
        along_y -= np.multiply(hxy, s1x, out=term)
        np.multiply(gx, s0, out=along_x)
        along_x -= np.multiply(hxy, s1y, out=term)
        along_x -= np.multiply(hxx, s1x, out=term)
        for k, kernel in ((3, hyy), (4, hxy), (5, hxx)):
            np.multiply(kernel, s0, out=out[k])
        sums[..., a:b] = scipy.fft.ifft(out, axis=-2, overwrite_x=True)[..., :ny, :]

    def pair_couplings(self, rows: np.ndarray, cols: np.ndarray, sources: tuple[np.ndarray, np.ndarray, np.ndarray],
                       targets: tuple[np.ndarray, np.ndarray, np.ndarray]) -> np.ndarray:
        """The far coupling of the uniform modes of ``rows`` and ``cols`` (the terms of `far_field` for one pair
        each, 0 where the pair is near): (len(rows), len(cols)).  ``sources`` are the moments of the ``cols``,
        ``targets`` the uniform modes' moments of the ``rows``."""
        q0, q1, q2 = sources
        t0, t1, t2 = targets
        offset = self.index[rows][:, None, :] - self.index[cols][None, :, :]
        ry = offset[..., 0] * self._spacing[0]
        rx = offset[..., 1] * self._spacing[1]
        r2 = ry * ry + rx * rx
        far = r2 >= self._near2
        r2 = np.where(far, r2, 1.0)
        f = np.where(far, r2 ** -0.5, 0.0)
        f3 = f / r2
        f5 = f3 / r2
        gy, gx = -ry * f3, -rx * f3
        hyy, hxy, hxx = 3.0 * ry * ry * f5 - f3, 3.0 * ry * rx * f5, 3.0 * rx * rx * f5 - f3
        potential = (q0 * f - (q1[:, 0] * gy + q1[:, 1] * gx)
                     + 0.5 * (q2[:, 0, 0] * hyy + 2.0 * q2[:, 0, 1] * hxy + q2[:, 1, 1] * hxx))
        ay = q0 * gy - (hyy * q1[:, 0] + hxy * q1[:, 1])
        ax = q0 * gx - (hxy * q1[:, 0] + hxx * q1[:, 1])
        g = (t0[:, None] * potential + t1[:, None, 0] * ay + t1[:, None, 1] * ax
             + 0.5 * q0 * (t2[:, None, 0, 0] * hyy + 2.0 * t2[:, None, 0, 1] * hxy + t2[:, None, 1, 1] * hxx))
        return self.scale * g
