"""The elastic half-space as a linear operator: pressure -> surface deflection.

Convention (the one used everywhere in brushbem): the normal pressure ``p`` is
positive when compressive; the surface deflection ``u`` is positive into the
half-space.  A square domain of N x N square elements of size h carries a
pressure that is uniform on each element (thesis sec. 3.1).  The deflection at
the centre of element (i, j) is

    u[i, j] = sum_{i', j'} K[i - i', j - j'] * p[i', j'],

with K the Love influence coefficient of a uniformly loaded square (thesis
eq. 3.5), evaluated here in the equivalent ``asinh`` form.  Far from the
element the four terms nearly cancel; the asinh form loses about eps (r/h)^2
relative accuracy there (8e-11 at r = 1000 h), 3-10 times less than the
literal logarithm form (tests/test_halfspace.py holds it to that bound).

The convolution is non-periodic: kernel and pressure are zero-padded to
2m x 2m (m the side of the window being convolved), the kernel in wrap-around
order (offsets 0..m-1, then -(m-1)..-1; index m unused), multiplied in the
real-FFT domain and the first m x m block of the inverse transform is kept.
Because the convolution is translation invariant, the same operator serves any
sub-window of the domain: a window of m1 x m2 elements needs only the kernel
spectrum of size 2m1 x 2m2, which is computed once and cached.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg

from brushbem import backend

__all__ = ["BLOCK_CACHE_BYTES", "HalfSpace", "influence_coefficients"]

#: Host memory kept for the inverses of small K blocks (``HalfSpace.block_inverse``).
BLOCK_CACHE_BYTES = 256 * 2**20


def _x_asinh_y_over_abs_x(x, y, xp):
    """``x * asinh(y / |x|)`` with its limit 0 at ``x = 0``."""
    safe = xp.where(x == 0, 1.0, xp.abs(x))
    return xp.where(x == 0, 0.0, x * xp.asinh(y / safe))


def influence_coefficients(x, y, element_size: float, contact_modulus: float, xp=np):
    """Deflection at (x, y) due to unit pressure on a square element centred at the origin.

    Parameters
    ----------
    x, y : array_like
        Position of the observation point relative to the element centre,
        in units of length (broadcastable).
    element_size : float
        Side h of the square element, in units of length.
    contact_modulus : float
        E*, in units of stress.
    xp : namespace
        Array namespace of the result.

    Returns
    -------
    ndarray
        Deflection per unit pressure, in units of length / stress
        (thesis eq. 3.5; Johnson, Contact Mechanics, eq. 3.25).
    """
    half = 0.5 * element_size

    def primitive(a, b):
        # Double primitive of 1/sqrt(a^2 + b^2), valid in all four quadrants:
        # d^2/(da db) [a asinh(b/|a|) + b asinh(a/|b|)] = 1/sqrt(a^2 + b^2).
        return _x_asinh_y_over_abs_x(a, b, xp) + _x_asinh_y_over_abs_x(b, a, xp)

    # K is even in x and in y; evaluating at |x|, |y| makes that exact in floating point.
    x = xp.abs(xp.asarray(x, dtype=xp.float64))
    y = xp.abs(xp.asarray(y, dtype=xp.float64))
    total = (
        primitive(x + half, y + half)
        - primitive(x + half, y - half)
        - primitive(x - half, y + half)
        + primitive(x - half, y - half)
    )
    return total / (math.pi * contact_modulus)


@dataclass(eq=False)
class HalfSpace:
    """Non-periodic FFT convolution with the Love kernel on an N x N grid.

    Parameters
    ----------
    elements : int
        N, elements per side of the domain.
    element_size : float
        h = L / N, in units of length.
    contact_modulus : float
        E*, in units of stress.
    xp : namespace, optional
        Array namespace of the operator (NumPy by default; CuPy for the GPU).
    """

    elements: int
    element_size: float
    contact_modulus: float
    xp: object = np
    _spectra: dict = field(default_factory=dict, repr=False)
    _blocks: dict = field(default_factory=dict, repr=False)
    _block_bytes: int = field(default=0, repr=False)
    _host_table: np.ndarray | None = field(default=None, repr=False)

    def __post_init__(self):
        if self.elements < 1:
            raise ValueError(f"elements = {self.elements} must be a positive integer")
        for name in ("element_size", "contact_modulus"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise ValueError(f"{name} = {value} must be finite and > 0")

    @property
    def shape(self) -> tuple[int, int]:
        return (self.elements, self.elements)

    def diagonal(self) -> float:
        """Self-influence K[0, 0] (deflection of an element under its own unit pressure)."""
        value = influence_coefficients(0.0, 0.0, self.element_size, self.contact_modulus, np)
        return float(value)

    def kernel(self, rows: int, cols: int):
        """Influence coefficients for offsets 0..rows-1 by 0..cols-1, shape (rows, cols)."""
        xp = self.xp
        h = self.element_size
        i = xp.arange(rows, dtype=xp.float64)[:, None] * h
        j = xp.arange(cols, dtype=xp.float64)[None, :] * h
        return influence_coefficients(i, j, h, self.contact_modulus, xp)

    def padded_kernel(self, rows: int, cols: int):
        """Kernel on the 2rows x 2cols grid in wrap-around order (index rows/cols unused)."""
        xp = self.xp
        base = self.kernel(rows, cols)
        # Offsets 0..m-1 at indices 0..m-1, zero at m and -(m-1)..-1 at indices
        # m+1..2m-1; K is even in both offsets, so the negative half is the
        # mirror image.
        padded = xp.concat([base, xp.zeros((1, cols), dtype=base.dtype), xp.flip(base[1:, :], axis=0)], axis=0)
        zero_column = xp.zeros((2 * rows, 1), dtype=base.dtype)
        return xp.concat([padded, zero_column, xp.flip(padded[:, 1:], axis=1)], axis=1)

    def spectrum(self, rows: int, cols: int):
        """Real spectrum of the padded kernel for a rows x cols window (cached).

        The padded kernel is even, so its DFT is real: only the real part is
        stored and the product with the pressure spectrum costs half as much.
        """
        key = (rows, cols)
        cached = self._spectra.get(key)
        if cached is None:
            if rows > self.elements or cols > self.elements:
                raise ValueError(f"window {rows}x{cols} exceeds the {self.elements}x{self.elements} domain")
            transformed = backend.rfft2(self.xp, self.padded_kernel(rows, cols), (2 * rows, 2 * cols))
            cached = self.xp.asarray(self.xp.real(transformed), copy=True)
            self._spectra[key] = cached
        return cached

    def wrapped_spectrum(self, long_rows: int, long_cols: int):
        """Real half spectrum of the kernel wrapped onto an L1 x L2 torus (cached).

        Offset o sits at o mod L for |o| <= L // 2, so the circular
        convolution of a pressure on [b0, b1) is the non-periodic one on the
        outputs [0, m) as long as L >= m and L >= 2 max(b1 - 1, m - 1 - b0):
        a pressure in the middle of the window needs a period of only about
        m plus its own extent, not 2m (``apply(..., support=...)``).
        """
        key = ("wrapped", long_rows, long_cols)
        cached = self._spectra.get(key)
        if cached is None:
            xp = self.xp
            base = self.kernel(long_rows // 2 + 1, long_cols // 2 + 1)
            row_offset = xp.minimum(xp.arange(long_rows), long_rows - xp.arange(long_rows))
            col_offset = xp.minimum(xp.arange(long_cols), long_cols - xp.arange(long_cols))
            wrapped = base[row_offset[:, None], col_offset[None, :]]
            cached = xp.asarray(xp.real(backend.rfft2(xp, wrapped, (long_rows, long_cols))), copy=True)
            self._spectra[key] = cached
        return cached

    def mirrored_kernel(self, rows: int, cols: int):
        """K for offsets -(rows-1)..rows-1 by -(cols-1)..cols-1, shape (2rows-1, 2cols-1) (cached).

        The deflection on a rows x cols window of a unit pressure on element
        (r, c) of the window is the view ``[rows-1-r : 2rows-1-r, cols-1-c :
        2cols-1-c]``: a direct sum for a few loaded elements, without a
        transform.
        """
        key = ("mirrored", rows, cols)
        cached = self._spectra.get(key)
        if cached is None:
            xp = self.xp
            base = self.kernel(rows, cols)
            cached = xp.concat([xp.flip(base[1:, :], axis=0), base], axis=0)
            cached = xp.concat([xp.flip(cached[:, 1:], axis=1), cached], axis=1)
            self._spectra[key] = cached
        return cached

    def apply(self, pressure, spectrum=None, support: tuple[int, int, int, int] | None = None):
        """Surface deflection in the window of ``pressure``.

        Parameters
        ----------
        pressure : ndarray, shape (m1, m2), m1, m2 <= N
            Normal pressure on the elements of a window of the domain,
            compressive positive, in units of stress.  Outside the window the
            pressure is zero.
        spectrum : ndarray, optional
            A precomputed spectrum to use instead of the kernel's (for the
            discriminant-matrix operator that adds spring terms to it).
        support : (r0, r1, c0, c1), optional
            A box of the window outside which the pressure vanishes.  When it
            lies well inside the window the transforms use the shorter period
            of ``wrapped_spectrum`` (same result, up to round-off).

        Returns
        -------
        ndarray, shape (m1, m2)
            Deflection into the half-space, in units of length.
        """
        rows, cols = pressure.shape[-2:]
        if spectrum is None and support is not None:
            r0, r1, c0, c1 = support
            long_rows = backend.smooth_length(max(rows, 2 * max(r1 - 1, rows - 1 - r0)))
            long_cols = backend.smooth_length(max(cols, 2 * max(c1 - 1, cols - 1 - c0)))
            if long_rows * long_cols < 0.9 * (4 * rows * cols):
                return backend.padded_convolution(
                    self.xp, pressure, self.wrapped_spectrum(long_rows, long_cols), (long_rows, long_cols)
                )
        if spectrum is None:
            spectrum = self.spectrum(rows, cols)
        return backend.padded_convolution(self.xp, pressure, spectrum)

    def block_inverse(self, offsets: np.ndarray, parent: tuple | None = None) -> np.ndarray:
        """Inverse of K restricted to the elements at ``offsets`` (k x 2 ints, row-major order); cached.

        K between two elements depends only on their offset, so every set of
        elements of the same shape has the same block: the pillars of a
        regular brush share one inverse, and detaching the same edge elements
        from many pillars adds only a few.  ``parent`` = (offsets P, inverse
        of K_P), in the same frame as ``offsets``, with ``offsets`` a subset of
        P: the inverse is then the Schur complement of the elements that left,
        K_E^-1 = B_EE - B_ED B_DD^-1 B_DE with B = K_P^-1, which costs
        O(|P|^2 |D|) instead of a fresh O(|E|^3) inversion (a pillar that loses
        a few edge elements).  The cache keeps at most ``BLOCK_CACHE_BYTES`` of
        inverses (host memory, float64).
        """
        offsets = np.ascontiguousarray(offsets, dtype=np.int64)
        key = (offsets - offsets.min(axis=0)).tobytes()
        cached = self._blocks.get(key)
        if cached is not None:
            return cached
        inverse = None
        if parent is not None:
            parent_offsets, parent_inverse = parent
            width = int(max(parent_offsets[:, 1].max(), offsets[:, 1].max())) + 1
            parent_flat = parent_offsets[:, 0] * width + parent_offsets[:, 1]
            flat = offsets[:, 0] * width + offsets[:, 1]
            if bool(np.all(np.isin(flat, parent_flat))):
                position = np.searchsorted(parent_flat, flat)  # both in row-major order
                gone = np.setdiff1d(np.arange(parent_flat.size), position, assume_unique=True)
                kept = parent_inverse[np.ix_(position, position)]
                if gone.size == 0:
                    inverse = kept
                elif gone.size < position.size:
                    cross = parent_inverse[np.ix_(position, gone)]
                    inverse = kept - cross @ np.linalg.solve(parent_inverse[np.ix_(gone, gone)], cross.T)
                    inverse = 0.5 * (inverse + inverse.T)
        if inverse is None:
            # K is symmetric positive definite, so is every principal block.
            factor = np.linalg.cholesky(self.block_matrix(offsets))
            inverse_factor = scipy.linalg.solve_triangular(factor, np.eye(factor.shape[0]), lower=True)
            inverse = inverse_factor.T @ inverse_factor
        if self._block_bytes + inverse.nbytes > BLOCK_CACHE_BYTES:
            self._blocks.clear()
            self._block_bytes = 0
        self._blocks[key] = inverse
        self._block_bytes += inverse.nbytes
        return inverse

    def block_matrix(self, offsets: np.ndarray) -> np.ndarray:
        """K restricted to the elements at ``offsets`` (k x 2 ints): the dense k x k block (host, float64)."""
        offsets = np.asarray(offsets, dtype=np.int64)
        span = offsets.max(axis=0) - offsets.min(axis=0) + 1
        table = self._host_table
        if table is None or table.shape[0] < span[0] or table.shape[1] < span[1]:
            # Each coefficient is evaluated on its own, so a larger table holds the same values.
            side = max(int(span.max()), 32, 0 if table is None else max(table.shape))
            table = np.asarray(backend.to_numpy(self.kernel(side, side)))
            self._host_table = table
        di = np.abs(offsets[:, None, 0] - offsets[None, :, 0])
        dj = np.abs(offsets[:, None, 1] - offsets[None, :, 1])
        return table[di, dj]

    def dense_matrix(self, rows: int, cols: int) -> np.ndarray:
        """The dense (rows*cols)^2 influence matrix, for tests on small grids."""
        h = self.element_size
        ii, jj = np.meshgrid(np.arange(rows), np.arange(cols), indexing="ij")
        di = (ii.ravel()[:, None] - ii.ravel()[None, :]) * h
        dj = (jj.ravel()[:, None] - jj.ravel()[None, :]) * h
        return influence_coefficients(di, dj, h, self.contact_modulus, np)
