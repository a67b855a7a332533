"""The pillar model's far field on a lattice by FFT: `Lattice` (``LoadPath.method = "pillars"``).

On a brush whose pillars sit on a rectangular lattice, the far-field
coupling of `brushbem.protocol.pillar_basis` - the multipole expansion of
1/r between two tips' modes - depends on the pillars only through their
moments, once every tip's moments are taken about its lattice point instead
of its centroid, and on the pair through the lattice offset alone.  The sum
over all far pillars is then a handful of discrete convolutions over the
lattice, done by FFT in O(M log M) instead of the dense O(M^2) product.

Here: the far field of the uniform modes (the sources, with ``coupling =
"local"`` the only ones that radiate) on the higher modes (tilt and
quadratic; the uniform mode's own field stays an exact dense product, the
one that its solver factorises).  To second order in the moments, with R
the offset between lattice points, f = 1/r, t the target mode's moments and
q the source's (both about their lattice points; a higher mode carries no
net force, t0 = 0):

    field_k = scale * sum_q x_q [q0 (t1 . grad f + t2 : hess f / 2) - t1 . hess f . q1]

the same terms as `PillarModel._far` for t0 = 0.  Pairs closer than
``near`` are left to the exact blocks (their kernel entries are zero here).
"""

from __future__ import annotations

import math

import numpy as np
import scipy.fft

__all__ = ["Lattice"]


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
        ny, nx = shape
        self.padded = (2 * ny, 2 * nx)
        di = np.fft.fftfreq(2 * ny, 1.0 / (2 * ny))  # offsets 0, 1, ..., ny, -ny + 1, ..., -1 (wrapped)
        dj = np.fft.fftfreq(2 * nx, 1.0 / (2 * nx))
        ry = (di * spacing[0])[:, None] * np.ones((1, 2 * nx))
        rx = np.ones((2 * ny, 1)) * (dj * spacing[1])[None, :]
        r2 = ry * ry + rx * rx
        far = r2 >= near * near
        far &= (np.abs(di) < ny)[:, None] & (np.abs(dj) < nx)[None, :]
        r2 = np.where(far, r2, 1.0)
        f3 = np.where(far, r2 ** -1.5, 0.0)
        f5 = f3 / r2
        kernels = [-ry * f3, -rx * f3, 3.0 * ry * ry * f5 - f3, 3.0 * ry * rx * f5, 3.0 * rx * rx * f5 - f3]
        #: Spectra of grad f (y, x) and hess f (yy, xy, xx) over the lattice offsets, near ones zero.
        self.spectra = scipy.fft.rfft2(np.stack(kernels), s=self.padded)
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

    def far_field(self, x0: np.ndarray, q0: np.ndarray, q1: np.ndarray, t1: np.ndarray,
                  t2: np.ndarray) -> np.ndarray:
        """The far field of the uniform amplitudes ``x0`` (M, c) on the higher modes: (m - 1, M, c).

        ``q0`` (M,), ``q1`` (M, 2): the uniform modes' force and first moment,
        ``t1`` (M, m - 1, 2), ``t2`` (M, m - 1, 2, 2): the higher modes'
        first and second moments, all about the lattice points.
        """
        ny, nx = self.shape
        iy, ix = self.index[:, 0], self.index[:, 1]
        c = x0.shape[1]
        sources = np.zeros((3, c, ny, nx))
        sources[0][:, iy, ix] = (q0[:, None] * x0).T
        sources[1][:, iy, ix] = (q1[:, 0:1] * x0).T
        sources[2][:, iy, ix] = (q1[:, 1:2] * x0).T
        s = scipy.fft.rfft2(sources, s=self.padded)
        gy, gx, hyy, hxy, hxx = self.spectra[:, None]
        products = np.stack([gy * s[0], gx * s[0], hyy * s[0], hxy * s[0], hxx * s[0],
                             hyy * s[1] + hxy * s[2], hxy * s[1] + hxx * s[2]])
        a_y, a_x, b_yy, b_xy, b_xx, c_y, c_x = scipy.fft.irfft2(products, s=self.padded)[..., :ny, :nx][..., iy, ix]
        # Each (c, M); the targets' moments (M, m - 1, ...).
        t1y, t1x = t1[..., 0].T[:, None], t1[..., 1].T[:, None]  # (m - 1, 1, M)
        field = (t1y * (a_y - c_y) + t1x * (a_x - c_x)
                 + 0.5 * (t2[..., 0, 0].T[:, None] * b_yy + 2.0 * t2[..., 0, 1].T[:, None] * b_xy
                          + t2[..., 1, 1].T[:, None] * b_xx))
        return self.scale * field.transpose(0, 2, 1)
