"""Array-namespace helpers: one code path for NumPy (CPU) and CuPy (GPU).

The numerics take their array namespace from their inputs
(``array_api_compat.array_namespace``) and call the few operations that the
array API standard does not cover (real FFTs with padding, segment sums)
through the functions here.  NumPy arrays use ``scipy.fft`` with worker
threads; any other namespace uses its own ``fft`` module.
"""

from __future__ import annotations

import os
from typing import Any

import numpy as np
import scipy.fft
from array_api_compat import array_namespace, is_numpy_namespace

from brushbem import settings

__all__ = [
    "backend_name",
    "bounding_box",
    "fft_workers",
    "irfft2",
    "namespace",
    "padded_convolution",
    "padded_convolution_rows",
    "rfft2",
    "segment_sum",
    "smooth_length",
    "to_numpy",
]

#: Padded transforms with fewer points than this run on one thread: below it the
#: thread hand-off costs about as much as it saves (measured on a 2-core machine,
#: where two workers were no faster than one for 80 x 80 - 300 x 300 transforms).
_THREADED_MIN_POINTS = 512 * 512

_cpu_count = os.cpu_count() or 1


def fft_workers(points: int | None = None) -> int:
    """Number of threads scipy.fft may use (``BRUSHBEM_FFT_WORKERS``, default: all cores).

    With ``points`` (the size of the transform), the default is one thread for
    transforms smaller than 512 x 512, where threading does not pay; an
    explicit ``BRUSHBEM_FFT_WORKERS`` always wins.
    """
    value = os.environ.get("BRUSHBEM_FFT_WORKERS")
    if value:
        return max(1, int(value))
    if points is not None and points < _THREADED_MIN_POINTS:
        return 1
    return _cpu_count


def namespace(*arrays: Any):
    """Array namespace of the given arrays (NumPy when none are arrays)."""
    arrays = [a for a in arrays if a is not None and not isinstance(a, (int, float))]
    if not arrays:
        return array_namespace(np.empty(0))
    return array_namespace(*arrays)


def backend_name(xp) -> str:
    """Short name of the backend of namespace ``xp`` (``"numpy"`` or the module name)."""
    if is_numpy_namespace(xp):
        return "numpy"
    return getattr(xp, "__name__", str(xp)).split(".")[-1]


def rfft2(xp, array, shape: tuple[int, int]):
    """2-D real FFT of ``array`` zero-padded to ``shape`` (last two axes)."""
    if is_numpy_namespace(xp):
        return scipy.fft.rfft2(array, s=shape, workers=fft_workers())
    return xp.fft.rfftn(array, s=shape, axes=(-2, -1))


def irfft2(xp, spectrum, shape: tuple[int, int]):
    """Inverse of :func:`rfft2` to real arrays of ``shape`` (last two axes)."""
    if is_numpy_namespace(xp):
        return scipy.fft.irfft2(spectrum, s=shape, workers=fft_workers())
    return xp.fft.irfftn(spectrum, s=shape, axes=(-2, -1))


def padded_convolution(xp, array, spectrum, padded_shape: tuple[int, int] | None = None):
    """Non-periodic convolution of ``array`` (..., m1, m2) by a real L1 x (L2 // 2 + 1) half spectrum.

    ``padded_shape`` = (L1, L2), at least (m1, m2); (2m1, 2m2) by default.
    Equal to ``irfft2(rfft2(array, (L1, L2)) * spectrum)[..., :m1, :m2]``,
    but done axis by axis so that the zero padding is never transformed: the
    real transform along the rows runs on the m1 non-zero rows only, and the
    inverse real transform along the rows only on the m1 rows that are kept.
    That skips a quarter of the butterflies and the padded copy; it measured
    1.2-2x faster than the two-dimensional calls for windows of 40-256
    elements (scipy's pocketfft, 2-core machine).  A 2-D array with rows of
    zeros goes by `padded_convolution_rows` (its forward transforms along the
    rows skip them; same result, bit for bit).
    """
    rows, cols = array.shape[-2:]
    long_rows, long_cols = (2 * rows, 2 * cols) if padded_shape is None else padded_shape
    if is_numpy_namespace(xp):
        if settings.switches().skip_empty_rows and array.ndim == 2:
            # A pressure on a few pillars, or on a contact that fills part of its window: the
            # transforms along the rows skip the rows that hold nothing (the same numbers).
            occupied = np.flatnonzero(array.any(axis=1))
            if occupied.size == 0:
                return np.zeros((rows, cols), dtype=np.result_type(array.dtype, np.float64))
            if occupied.size < rows:
                return padded_convolution_rows(xp, array[occupied], occupied, spectrum, (long_rows, long_cols),
                                               out_rows=rows)
        workers = fft_workers(long_rows * long_cols)
        product = scipy.fft.rfft(array, n=long_cols, axis=-1, workers=workers)
        product = scipy.fft.fft(product, n=long_rows, axis=-2, workers=workers, overwrite_x=True)
        product *= spectrum
        product = scipy.fft.ifft(product, axis=-2, workers=workers, overwrite_x=True)[..., :rows, :]
        return scipy.fft.irfft(product, n=long_cols, axis=-1, workers=workers)[..., :cols]
    product = xp.fft.rfftn(array, s=(long_rows, long_cols), axes=(-2, -1))
    product *= spectrum
    return xp.fft.irfftn(product, s=(long_rows, long_cols), axes=(-2, -1))[..., :rows, :cols]


def padded_convolution_rows(xp, rows_values, row_index, spectrum, padded_shape: tuple[int, int],
                            out_rows: int | None = None):
    """`padded_convolution` of an array that vanishes outside the rows ``row_index``, kept on those rows.

    ``rows_values`` (k, m2) holds rows ``row_index`` (k sorted indices into the
    window's m1 rows) of the pressure; the rest of the window is zero.  Returns
    the deflection on the same rows, (k, m2).  The real transforms along the
    rows run on the k rows only, forward and back; only the transforms along
    the columns see every padded row.  For a brush, whose pillars cover a
    third of the rows of their window, that skips about two thirds of the
    real-transform work of ``padded_convolution`` and the padded copies.
    With ``out_rows`` = m1 it returns the deflection on the whole window
    instead, (m1, m2): only the forward transforms skip the empty rows.
    """
    long_rows, long_cols = padded_shape
    cols = rows_values.shape[-1]
    kept = row_index if out_rows is None else slice(0, out_rows)
    if is_numpy_namespace(xp):
        workers = fft_workers(long_rows * long_cols)
        rows_spectrum = scipy.fft.rfft(rows_values, n=long_cols, axis=-1, workers=workers)
        product = np.zeros((long_rows, rows_spectrum.shape[-1]), dtype=rows_spectrum.dtype)
        product[row_index] = rows_spectrum
        product = scipy.fft.fft(product, axis=-2, workers=workers, overwrite_x=True)
        product *= spectrum
        product = scipy.fft.ifft(product, axis=-2, workers=workers, overwrite_x=True)
        return scipy.fft.irfft(product[kept], n=long_cols, axis=-1, workers=workers)[..., :cols]
    rows_spectrum = xp.fft.rfft(rows_values, n=long_cols, axis=-1)
    product = xp.zeros((long_rows, rows_spectrum.shape[-1]), dtype=rows_spectrum.dtype)
    product[row_index, :] = rows_spectrum
    product = xp.fft.fft(product, axis=-2) * spectrum
    product = xp.fft.ifft(product, axis=-2)
    return xp.fft.irfft(product[kept, :], n=long_cols, axis=-1)[..., :cols]


def smooth_length(size: int) -> int:
    """Smallest n >= size with no prime factor above 5 (a fast FFT length)."""
    n = max(int(size), 1)
    while True:
        rest = n
        for factor in (2, 3, 5):
            while rest % factor == 0:
                rest //= factor
        if rest == 1:
            return n
        n += 1


def segment_sum(xp, labels, weights, count: int):
    """Sum ``weights`` per label: ``out[c] = sum(weights[labels == c])``.

    ``labels`` and ``weights`` are flat arrays of equal length, labels in
    ``[0, count)``.  This is the incidence product ``P @ x`` of the spring
    operator.
    """
    if count == 0:
        return xp.zeros(0, dtype=weights.dtype)
    if is_numpy_namespace(xp):
        return np.bincount(labels, weights=weights, minlength=count)
    if hasattr(xp, "bincount"):  # CuPy, PyTorch
        return xp.bincount(labels, weights=weights, minlength=count)
    # The array API standard has no bincount: differences of the cumulative
    # sum over the labels sorted, at the boundaries of every label's run.
    order = xp.argsort(labels, stable=True)
    sorted_labels = xp.take(labels, order)
    sums = xp.cumulative_sum(xp.take(weights, order), include_initial=True)
    bounds = xp.searchsorted(sorted_labels, xp.arange(count + 1, dtype=sorted_labels.dtype))
    return xp.take(sums, bounds[1:]) - xp.take(sums, bounds[:-1])


def to_numpy(array) -> np.ndarray:
    """Copy ``array`` to host memory as a NumPy array: the one host/device boundary.

    Every host copy of a namespace array goes through here (I/O, plotting and
    the small dense pillar-space steps of the solver), never through an
    implicit ``np.asarray``, which CuPy refuses.  CuPy arrays are copied with
    ``.get()``, PyTorch tensors with ``.cpu()``, any other array API array by
    DLPack.
    """
    if isinstance(array, np.ndarray):
        return array
    if isinstance(array, (bool, int, float, np.generic)):
        return np.asarray(array)
    get = getattr(array, "get", None)
    if get is not None:
        return np.asarray(get())
    cpu = getattr(array, "cpu", None)
    if cpu is not None:
        array = cpu()
    return np.from_dlpack(array)


def bounding_box(xp, mask) -> tuple[int, int, int, int] | None:
    """Bounding box (r0, r1, c0, c1) of the True entries of a 2-D mask of namespace ``xp`` (None: empty).

    Reduces on the device and copies two short vectors (the rows and the
    columns that hold the mask) to the host, not the mask.
    """
    rows = np.flatnonzero(to_numpy(xp.any(mask, axis=1)))
    if rows.size == 0:
        return None
    r0, r1 = int(rows[0]), int(rows[-1]) + 1
    cols = np.flatnonzero(to_numpy(xp.any(mask[r0:r1, :], axis=0)))  # only the rows that hold the mask
    return r0, r1, int(cols[0]), int(cols[-1]) + 1


def spd_solver(xp, matrix: np.ndarray):
    """``b -> matrix^-1 b`` on the device of ``xp`` for a small dense SPD host ``matrix``, or None if it is not SPD.

    The factorisation is made once, on the host (Cholesky, scipy); the solve
    runs where ``b`` lives, so a preconditioner applies it inside a CG
    iteration without a host copy.  On NumPy it is the Cholesky solve; on a
    device namespace the inverse from that factor is copied over once and
    each solve is one matrix-vector product there (the array API has no
    triangular solve).  The two agree to rounding (about ``cond(matrix)``
    times 1e-16 relative).
    """
    import scipy.linalg

    try:
        factor = scipy.linalg.cho_factor(matrix, lower=True, check_finite=False)
    except np.linalg.LinAlgError:
        return None
    if is_numpy_namespace(xp):
        return lambda b: scipy.linalg.cho_solve(factor, b, check_finite=False)
    inverse = xp.asarray(scipy.linalg.cho_solve(factor, np.eye(matrix.shape[0]), check_finite=False))
    return lambda b: inverse @ b
