"""The data files a configuration names (``indenter.file``, ``indenter.lengths_file``).

A name is resolved against the configuration's folder (`_existing_file`) and
read as ``.npy`` data header first, never unpickled (`_read_numbers`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from pydantic import ValidationInfo

from brushbem.config.limits import MAGNITUDE_RANGE


def _existing_file(value: str, info: ValidationInfo) -> Path:
    """``value`` resolved against the configuration's folder; ValueError if it is not a regular file.

    A relative name is resolved against the folder of the configuration file
    (``base_dir`` of the validation context); an absolute name, or one that
    leads out of that folder, is allowed: the file is only read as ``.npy``
    data (`_read_numbers`), never executed or unpickled.
    """
    base_dir = Path((info.context or {}).get("base_dir") or Path.cwd())
    try:
        path = (base_dir / value).resolve()
        exists, regular, folder = path.exists(), path.is_file(), path.is_dir()
    except (OSError, ValueError) as exc:  # e.g. an embedded NUL or a name too long
        raise ValueError(f"not a usable path ({exc})") from None
    if folder:
        raise ValueError(f"is a folder, not a .npy file ({path})")
    if exists and not regular:
        raise ValueError(f"is not a regular file ({path})")
    if not exists:
        raise ValueError(f"file not found (looked for {path})")
    return path


def _read_numbers(path: Path) -> np.ndarray:
    """The array of real numbers in the ``.npy`` file ``path``, as float64.

    The header is read first, so that a file of Python objects is refused
    without unpickling anything (``allow_pickle`` stays off), and a file of
    another format is named as such.

    Raises
    ------
    ValueError
        With a message saying what is wrong: not ``.npy`` data, an object
        (pickled) array, not real numbers, or values that are not finite or
        lie outside `MAGNITUDE_RANGE`.
    """
    try:
        with path.open("rb") as stream:
            try:
                version = np.lib.format.read_magic(stream)
            except ValueError:
                raise ValueError(
                    f"cannot be read as a .npy array: {path} is not a .npy file (it does not start with "
                    "the NumPy format's magic bytes); save the array with numpy.save"
                ) from None
            if version not in ((1, 0), (2, 0)):  # 3.0 only serves structured arrays with unicode names
                raise ValueError(f"unsupported .npy format version {version[0]}.{version[1]}")
            read_header = np.lib.format.read_array_header_1_0 if version == (1, 0) else np.lib.format.read_array_header_2_0
            shape, _, dtype = read_header(stream)
    except OSError as exc:
        raise ValueError(f"cannot be read ({path}: {exc.strerror or exc})") from None
    except ValueError as exc:
        if str(exc).startswith("cannot be read"):
            raise
        raise ValueError(f"cannot be read as a .npy array ({path}: {exc})") from None
    if dtype.hasobject:
        raise ValueError(
            f"holds Python objects ({path}); brushbem loads numeric .npy arrays only and never unpickles "
            "(allow_pickle is off): save a float array"
        )
    if dtype.kind not in "fiu":
        raise ValueError(f"holds {dtype} values ({path}); must hold real numbers (float or integer)")
    try:
        values = np.load(path, allow_pickle=False)
    except (OSError, ValueError, EOFError) as exc:  # e.g. a truncated file
        raise ValueError(f"cannot be read as a .npy array ({path}: {exc})") from None
    with np.errstate(over="ignore"):  # float128 beyond float64 becomes inf, refused below
        values = np.asarray(values, dtype=np.float64)
    if values.size and not np.all(np.isfinite(values)):
        raise ValueError(f"must hold finite values ({path} holds nan or inf)")
    largest = float(np.max(np.abs(values))) if values.size else 0.0
    if largest > MAGNITUDE_RANGE[1]:
        raise ValueError(f"holds values up to {largest:g} ({path}); must be at most {MAGNITUDE_RANGE[1]:g} in magnitude")
    assert shape == values.shape
    return values


def _check_height_map(path: Path) -> None:
    """Check that ``path`` holds a square 2-D array of finite real numbers.

    Raises
    ------
    ValueError
        With a message saying what is wrong and naming the file.
    """
    heights = _read_numbers(path)
    if heights.ndim != 2 or heights.shape[0] != heights.shape[1]:
        raise ValueError(f"must hold a square N x N array, found shape {heights.shape} ({path})")


def _height_map_shape(path: str) -> tuple[int, ...]:
    """Shape of a validated ``.npy`` file, from its header only (no data read)."""
    return np.load(path, mmap_mode="r", allow_pickle=False).shape
