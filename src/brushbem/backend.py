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

__all__ = ["namespace", "rfft2", "irfft2", "segment_sum", "to_numpy", "backend_name", "fft_workers"]


def fft_workers() -> int:
    """Number of threads scipy.fft may use (``BRUSHBEM_FFT_WORKERS``, default: all cores)."""
    value = os.environ.get("BRUSHBEM_FFT_WORKERS")
    if value:
        return max(1, int(value))
    return os.cpu_count() or 1


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
    return xp.fft.rfft2(array, s=shape)


def irfft2(xp, spectrum, shape: tuple[int, int]):
    """Inverse of :func:`rfft2` to real arrays of ``shape`` (last two axes)."""
    if is_numpy_namespace(xp):
        return scipy.fft.irfft2(spectrum, s=shape, workers=fft_workers())
    return xp.fft.irfft2(spectrum, s=shape)


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
    return xp.bincount(labels, weights=weights, minlength=count)


def to_numpy(array) -> np.ndarray:
    """Copy ``array`` to host memory as a NumPy array (for I/O and plotting only)."""
    if isinstance(array, np.ndarray):
        return array
    get = getattr(array, "get", None)
    if get is not None:
        return np.asarray(get())
    return np.asarray(array)
