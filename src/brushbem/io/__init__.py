"""Result files of one case: ``summary.json`` and ``result.nc``.

``summary.json``
    The `CaseResult.summary` mapping, indented JSON.  JSON has no infinity or
    NaN; such values are written as the strings ``"inf"``, ``"-inf"``,
    ``"nan"`` (never ``null``, which would read as "missing").

``result.nc`` (NetCDF-4 through h5netcdf)
    The load path along dimension ``step`` (``displacement``, ``force``,
    ``contact_area``, ``cg_iterations``, ``converged``, ``loading``,
    ``attached_pillars``) and the snapshots along dimension ``stage``, whose
    coordinate holds the stage names (``max_preload``, ``zero_force``,
    ``adhesive_force``, ``half_detached``, ``before_separation``: those the
    path passed through), with the base displacement and the force of each
    moment as the coordinates ``stage_displacement`` and ``stage_force``:
    ``pressure`` (float) and ``contact`` (int8, 1 = in contact) on dimensions
    ``(stage, y, x)``, and ``pillar_force`` on ``(stage, pillar)``;
    coordinates ``x``, ``y`` are element centres in units of length, centred
    on the domain: x_i = (i + 1/2) h - L/2.  Per pillar (dimension
    ``pillar``): ``pillar_x``, ``pillar_y``, ``pillar_offset``,
    ``pillar_elements``, ``pillar_stiffness`` (pillars on springs),
    ``pillar_separation_displacement``, ``pillar_max_tension``,
    ``pillar_max_tension_displacement``; ``cross_section_adhesive_force`` is
    the pressure along the element row through the centre at the
    adhesive-force moment (thesis Fig. 7-4).  Global attributes record
    provenance: ``brushbem_version``, ``config`` (the resolved configuration
    as JSON), ``seeds``, ``backend``, ``summary`` (JSON), and every entry of
    `CaseResult.attributes`.  Files written before the ``stage`` dimension
    (one variable per stage, ``pressure_<name>``) are read as well
    (`stage_field`, `from_dataset`).

Every file is written to a temporary file in the output folder and moved into
place with `os.replace`, so a reader never sees a half-written file.  The two
files form one result: both carry the same ``run_id``; ``result.nc`` is moved
into place first and ``summary.json`` last, so that a run killed between the
two leaves a pair whose ids differ, which `read_case` refuses
(`InconsistentCaseError`) instead of pairing an old dataset with a new
summary.  A NetCDF file is rendered in memory and written by Python (up to
`IN_MEMORY_LIMIT` bytes); a larger one, after a free-space check, is streamed
by HDF5 through a Python file object that never passes a failed write on to
HDF5 (`_GuardedFile`).  Either way a full disk or a quota is an ``OSError``
with its errno, never a crash inside the HDF5 library.

Sign convention: d > 0 presses into the half-space; pressure and force are
positive when compressive.
"""

from __future__ import annotations

import contextlib
import dataclasses
import datetime
import errno
import io
import json
import os
import re
import shutil
import stat
import tempfile
import uuid
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from brushbem import __version__
from brushbem.config import RunConfig, config_to_dict, to_json_safe
from brushbem.results import CaseResult
from brushbem.units import DIMENSIONS, Units

__all__ = [
    "DATASET_FILE",
    "IN_MEMORY_LIMIT",
    "SUMMARY_FILE",
    "FolderBusyError",
    "InconsistentCaseError",
    "UnsafeLockError",
    "atomic_path",
    "check_writable",
    "exclusive_folder",
    "from_dataset",
    "load_result",
    "netcdf_attributes",
    "read_case",
    "remove_stale_temporaries",
    "stage_field",
    "stages",
    "temporary_of",
    "to_dataset",
    "write_case",
    "write_dataset",
]

SUMMARY_FILE = "summary.json"
DATASET_FILE = "result.nc"

#: Largest NetCDF file rendered in memory before it is written (bytes).
IN_MEMORY_LIMIT = 512 * 2**20

#: Free space kept beyond a file's own size when writing it (bytes).
_FREE_SPACE_MARGIN = 2**20


class InconsistentCaseError(ValueError):
    """A case folder whose ``summary.json`` and ``result.nc`` are not one result."""


#: A temporary of `atomic_path` (``.<final name>.<random>.tmp``; `tempfile.mkstemp`'s random part is
#: lower-case letters, digits and underscores) or of `check_writable` (``.write-check.<random>.tmp``).
_TEMPORARY = re.compile(r"\.(?P<final>.+)\.[a-z0-9_]+\.tmp")
_WRITE_CHECK = "write-check"


def temporary_of(name: str) -> str | None:
    """The final name whose temporary ``name`` is (``".summary.json.x1y2.tmp"`` -> ``"summary.json"``), or None."""
    match = _TEMPORARY.fullmatch(name)
    return match["final"] if match else None


def remove_stale_temporaries(folder: str | Path,
                             names: tuple[str, ...] = (SUMMARY_FILE, DATASET_FILE)) -> list[Path]:
    """Delete the temporary files that a killed writer left in ``folder`` (never a complete file).

    Only the names `atomic_path` creates for the files ``names``
    (``.<name>.<random>.tmp``) and those of `check_writable` are removed:
    nothing else in the folder, hidden ``*.tmp`` files of other programs
    included, is touched, nor a link of such a name.

    Returns
    -------
    list of Path
        The files removed.
    """
    removed = []
    finals = {*names, _WRITE_CHECK}
    for stale in Path(folder).glob(".*.tmp"):
        if temporary_of(stale.name) in finals and stale.is_file() and not stale.is_symlink():
            stale.unlink(missing_ok=True)
            removed.append(stale)
    return removed


class FolderBusyError(RuntimeError):
    """Another process holds a folder's lock (`exclusive_folder`)."""


class UnsafeLockError(OSError):
    """A lock file that brushbem will not write: a link, not a regular file, or not a lock it wrote.

    ``filename`` is the lock file, ``strerror`` what is wrong with it.
    """

    def __str__(self) -> str:
        return f"{self.filename}: {self.strerror}"


def _open_lock(path: Path) -> int:
    """Open the lock file ``path`` for reading and writing, creating it; never through a link.

    Raises `UnsafeLockError` (naming ``path``) when it is a symbolic link, not a
    regular file, or a file with other names (a hard link): writing it would
    change a file that the package did not create.
    """
    refusal = "the lock file is {}; brushbem never writes through it (remove it, or choose another folder)"
    try:
        before = os.lstat(path)
    except FileNotFoundError:
        before = None
    if before is not None and stat.S_ISLNK(before.st_mode):
        raise UnsafeLockError(errno.ELOOP, refusal.format("a symbolic link"), str(path))
    if before is not None and not stat.S_ISREG(before.st_mode):
        raise UnsafeLockError(errno.EINVAL, refusal.format("not a regular file"), str(path))
    flags = os.O_RDWR | os.O_CREAT | os.O_NOFOLLOW | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0)
    try:
        handle = os.open(path, flags, 0o644)
    except OSError as exc:  # replaced by a link or a folder since the check
        if exc.errno in (errno.ELOOP, errno.EISDIR, errno.ENXIO):
            raise UnsafeLockError(exc.errno, refusal.format("a symbolic link or not a regular file"),
                                  str(path)) from None
        raise
    opened = os.fstat(handle)
    if not stat.S_ISREG(opened.st_mode) or opened.st_nlink != 1:
        os.close(handle)
        what = "not a regular file" if not stat.S_ISREG(opened.st_mode) else "a hard link (a file with other names)"
        raise UnsafeLockError(errno.EINVAL, refusal.format(what), str(path))
    return handle


@contextlib.contextmanager
def _locked(path: Path, folder: str | Path) -> Iterator[None]:
    """Hold an ``flock`` on the lock file ``path`` (its holder's pid written in it)."""
    import fcntl

    handle = _open_lock(path)
    try:
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            holder = os.pread(handle, 64, 0).decode("ascii", "replace").strip() or "unknown"
            raise FolderBusyError(f"{folder}: another brushbem process (pid {holder}) is writing into "
                                  "this folder") from None
        content = os.pread(handle, 64, 0).strip()
        if content and not content.isdigit():
            # Not a process id: a file of that name that brushbem did not write.
            raise UnsafeLockError(errno.EEXIST, "the lock file holds something other than a process id; "
                                  "brushbem does not overwrite it (remove it, or choose another folder)", str(path))
        os.ftruncate(handle, 0)
        os.pwrite(handle, str(os.getpid()).encode(), 0)
        yield
    finally:
        os.close(handle)


@contextlib.contextmanager
def exclusive_folder(folder: str | Path, lock_name: str = ".brushbem.lock") -> Iterator[None]:
    """Hold an exclusive lock on ``folder`` while writing into it.

    The lock is an ``flock`` on ``folder/lock_name`` (POSIX; elsewhere no
    lock is taken): the kernel releases it when the holder ends, killed or
    not, so a stale lock never blocks a rerun.  The lock file is opened
    without following links (``O_NOFOLLOW``) and written (the holder's pid)
    only if it is a regular file of one name that is empty or holds a pid:
    a lock file that is a link, or any other file, is refused and left as it
    is.

    Raises
    ------
    FolderBusyError
        When another process holds the lock (its pid in the message).
    UnsafeLockError
        When the lock file is a symbolic or hard link, not a regular file, or
        holds something other than a pid (its path in the message).
    """
    try:
        import fcntl  # noqa: F401 - only whether it exists
    except ImportError:  # not on POSIX: no lock
        yield
        return
    with _locked(Path(folder) / lock_name, folder):
        yield


def check_writable(folder: str | Path) -> None:
    """Raise ``OSError`` unless a file can be created (and removed) in ``folder``."""
    handle, name = tempfile.mkstemp(dir=folder, prefix=".write-check.", suffix=".tmp")
    os.close(handle)
    os.unlink(name)


def _check_free_space(folder: Path, needed: int) -> None:
    """Raise ``OSError(ENOSPC)`` when ``folder``'s file system has less than ``needed`` bytes free."""
    free = shutil.disk_usage(folder).free
    if free < needed + _FREE_SPACE_MARGIN:
        raise OSError(errno.ENOSPC, f"no space left on device: writing needs {needed / 2**20:.2f} MiB and "
                      f"{_FREE_SPACE_MARGIN / 2**20:g} MiB to spare, {free / 2**20:.2f} MiB free", str(folder))


@contextlib.contextmanager
def atomic_path(target: str | Path) -> Iterator[Path]:
    """Give a temporary path beside ``target``; move it onto ``target`` on success.

    The temporary file lives in the same folder so that `os.replace` is an
    atomic rename on the same file system.  On an exception it is removed and
    ``target`` is left as it was.

    Parameters
    ----------
    target : path
        The file finally written.

    Yields
    ------
    Path
        Where the caller writes the complete content.
    """
    target = Path(target)
    handle, name = tempfile.mkstemp(dir=target.parent, prefix=f".{target.name}.", suffix=".tmp")
    os.close(handle)
    temporary = Path(name)
    try:
        yield temporary
        # mkstemp creates the file private (0600); results are ordinary files.
        os.chmod(temporary, 0o644)
        os.replace(temporary, target)
    except BaseException:
        temporary.unlink(missing_ok=True)
        raise


def _json(value: Any, indent: int | None = None) -> str:
    # allow_nan=False: a non-finite number that slipped through is a bug to see.
    return json.dumps(to_json_safe(value), indent=indent, allow_nan=False)


def _netcdf_attribute(value: Any) -> str | int | float | np.ndarray:
    """A value NetCDF can store as an attribute; structured values become JSON."""
    if isinstance(value, (bool, np.bool_)):
        # NetCDF has no boolean attribute type.
        return int(value)
    if isinstance(value, (str, int, float, np.integer, np.floating)):
        return value
    return _json(value)


_PILLAR_ATTRS: dict[str, dict[str, str]] = {
    "x": {"long_name": "pillar centre x", "units": "length"},
    "y": {"long_name": "pillar centre y", "units": "length"},
    "offset": {"long_name": "pillar length offset g (0: longest pillar)", "units": "length"},
    "elements": {"long_name": "elements in the rasterised pillar footprint"},
    "stiffness": {"long_name": "stiffness of the pillar's own spring (level 1)", "units": "force / length"},
    "separation_displacement": {"long_name": "last base displacement with contact on the pull-off "
                                             "(nan: never in contact)", "units": "length"},
    "max_tension": {"long_name": "largest tensile force carried on the pull-off (>= 0)", "units": "force"},
    "max_tension_displacement": {"long_name": "base displacement at the pillar's largest tension (nan: never in "
                                             "tension)", "units": "length"},
}


def netcdf_attributes(attributes: dict[str, Any]) -> dict[str, Any]:
    """Attributes NetCDF can store: strings and numbers kept, the rest as JSON.

    Parameters
    ----------
    attributes : dict
        Any provenance values (nested dicts and lists become JSON strings,
        booleans integers, since NetCDF has neither).

    Returns
    -------
    dict
    """
    return {str(key): _netcdf_attribute(value) for key, value in attributes.items()}


#: What brushbem's equations and figures refer to (the NetCDF ``references`` attribute).
REFERENCES = (
    "X. He, The Boundary Element Method Simulation of Adhesion of Brush-Structures (doctoral thesis; brushbem's "
    "eq., Fig. and sec. numbers refer to it); X. He, Q. Li, V. L. Popov, Lubricants 8 (2020) 94, "
    "doi:10.3390/lubricants8100094; X. He, Q. Li, V. L. Popov, The Journal of Adhesion (2021), "
    "doi:10.1080/00218464.2021.1939017; R. Pohrt, V. L. Popov, Facta Universitatis, Series: Mechanical "
    "Engineering (2015) (the detachment criterion)"
)

def _units_of(result: CaseResult, config: RunConfig | None) -> Units:
    """The configuration's ``[units]`` (`brushbem.units`): from ``config``, else from the provenance."""
    return Units.from_config(config) if config is not None else Units.of_record(result.attributes)


def _cf_variables(variables: dict[str, xr.Variable], coords: dict[str, xr.Variable], units: Units) -> None:
    """CF-1.10 attributes: parseable units, flags for masks and booleans.

    The quantities are in the units of the configuration's inputs (E* sets the
    stress, grid.size the length): with ``[units]`` their UDUNITS names, without
    it CF's dimensionless ``"1"``; the physical dimension is always kept in the
    attribute ``dimension``.
    """
    for variable in (*variables.values(), *coords.values()):
        attrs = variable.attrs
        unit = attrs.get("units")
        if unit in DIMENSIONS:
            attrs["dimension"] = unit
            attrs["units"] = units.of(unit)
        elif variable.dtype == np.int8 and "contact" in attrs.get("long_name", ""):
            attrs["flag_values"] = np.array([0, 1], dtype=np.int8)
            attrs["flag_meanings"] = "not_in_contact in_contact"
        elif variable.dtype == bool:  # stored as int8 0 / 1 (xarray's encoding of booleans)
            attrs["flag_values"] = np.array([0, 1], dtype=np.int8)
            attrs["flag_meanings"] = "false true"
        elif unit is None and np.issubdtype(variable.dtype, np.number):
            attrs["units"] = "1"


def _stage_variables(result: CaseResult, h: float, n_pillars: int, variables: dict[str, xr.Variable],
                     coords: dict[str, xr.Variable]) -> None:
    """The snapshots along dimension ``stage``: ``pressure``, ``contact`` (and ``pillar_force``), one variable each.

    The ``stage`` coordinate holds the stage names (in the order recorded), and
    ``stage_displacement`` and ``stage_force`` the moment of each along it.
    """
    snapshots = result.snapshots
    coords["stage"] = xr.Variable("stage", np.array([snapshot.name for snapshot in snapshots], dtype=object),
                                  {"long_name": "snapshot stage of the pull-off (thesis Fig. 4-3)"})
    coords["stage_displacement"] = xr.Variable(
        "stage", np.array([float(snapshot.displacement) for snapshot in snapshots]),
        {"long_name": "base displacement d at the stage (presses > 0)", "units": "length"})
    coords["stage_force"] = xr.Variable(
        "stage", np.array([float(snapshot.force) for snapshot in snapshots]),
        {"long_name": "normal force F at the stage (compressive > 0)", "units": "force"})
    variables["pressure"] = xr.Variable(
        ("stage", "y", "x"), np.stack([np.asarray(snapshot.pressure, dtype=float) for snapshot in snapshots]),
        {"long_name": "pressure at the stage (compressive > 0)", "units": "stress"})
    variables["contact"] = xr.Variable(
        ("stage", "y", "x"), np.stack([np.asarray(snapshot.contact, dtype=np.int8) for snapshot in snapshots]),
        {"long_name": "contact set at the stage (1 = in contact)"})
    if n_pillars and any(snapshot.pillar_force is not None for snapshot in snapshots):
        forces = np.full((len(snapshots), n_pillars), np.nan)
        for k, snapshot in enumerate(snapshots):
            if snapshot.pillar_force is not None:
                forces[k] = np.asarray(snapshot.pillar_force, dtype=float)
        variables["pillar_force"] = xr.Variable(
            ("stage", "pillar"), forces,
            {"long_name": "force on every pillar at the stage (compressive > 0; nan: not recorded)",
             "units": "force"})
    pattern = next((snapshot for snapshot in snapshots if snapshot.name == "adhesive_force"), None)
    if pattern is not None:
        # The stress cross-section through the centre at the critical
        # moment (thesis Fig. 7-4): the row of elements just above y = 0.
        row = pattern.pressure.shape[0] // 2
        variables["cross_section_adhesive_force"] = xr.Variable(
            "x", np.asarray(pattern.pressure[row], dtype=float),
            {"long_name": "pressure along the row through the centre at the adhesive-force moment "
                          "(compressive > 0)", "units": "stress",
             "y": float((row + 0.5) * h - pattern.pressure.shape[0] * h / 2),
             "displacement": float(pattern.displacement), "force": float(pattern.force)},
        )


def to_dataset(result: CaseResult, config: RunConfig | None = None) -> xr.Dataset:
    """The ``result.nc`` content of one run as an in-memory `xarray.Dataset`.

    Variables along ``step`` (the curve), ``x``/``y`` (the snapshots' pressure
    and contact) and ``pillar`` (per-pillar arrays), the summary and the
    provenance as attributes; ``config`` (the resolved configuration) is
    recorded when given.
    """
    return _dataset(result, config)


def _dataset(result: CaseResult, config: RunConfig | None) -> xr.Dataset:
    curve = result.curve
    h = float(result.element_size)
    variables: dict[str, xr.Variable] = {
        "displacement": xr.Variable(
            "step", np.asarray(curve.displacement, dtype=float),
            {"long_name": "base displacement d (presses > 0)", "units": "length"},
        ),
        "force": xr.Variable(
            "step", np.asarray(curve.force, dtype=float),
            {"long_name": "normal force F (compressive > 0)", "units": "force"},
        ),
        "contact_area": xr.Variable(
            "step", np.asarray(curve.contact_area, dtype=float),
            {"long_name": "contact area h^2 x elements in contact", "units": "length^2"},
        ),
        "cg_iterations": xr.Variable(
            "step", np.asarray(curve.cg_iterations, dtype=np.int64),
            {"long_name": "conjugate-gradient iterations spent on this row"},
        ),
        "converged": xr.Variable(
            "step", np.asarray(curve.converged, dtype=bool),
            {"long_name": "every solve behind this row converged"},
        ),
        "loading": xr.Variable(
            "step", np.asarray(curve.loading, dtype=bool),
            {"long_name": "row belongs to the loading branch (False: unloading)"},
        ),
        "attached_pillars": xr.Variable(
            "step", np.asarray(curve.attached_pillars, dtype=np.int64),
            {"long_name": "pillars with at least one element in contact"},
        ),
    }
    coords: dict[str, xr.Variable] = {}
    if result.snapshots:
        n = result.snapshots[0].pressure.shape[0]
        length = n * h
        centres = (np.arange(n) + 0.5) * h - length / 2
        coords = {
            "x": xr.Variable("x", centres, {"long_name": "element centre x", "units": "length"}),
            "y": xr.Variable("y", centres, {"long_name": "element centre y", "units": "length"}),
        }
    n_pillars = 0
    for snapshot in result.snapshots:
        if snapshot.pillar_force is not None:
            n_pillars = len(snapshot.pillar_force)
    for name, values in result.pillars.items():
        n_pillars = len(values)
    if n_pillars:
        coords["pillar"] = xr.Variable("pillar", np.arange(n_pillars), {"long_name": "pillar index"})
        for name, values in result.pillars.items():
            variables[f"pillar_{name}"] = xr.Variable("pillar", np.asarray(values), _PILLAR_ATTRS.get(name, {}))
    if result.snapshots:
        _stage_variables(result, h, n_pillars, variables, coords)
    coords["step"] = xr.Variable("step", np.arange(len(curve.displacement), dtype=np.int64),
                                 {"long_name": "index of the recorded state along the load path", "units": "1"})
    _cf_variables(variables, coords, _units_of(result, config))
    attributes: dict[str, Any] = {
        "Conventions": "CF-1.10",
        "title": "brushbem pull-off: force-displacement curve, contact snapshots and per-pillar results",
        "source": f"brushbem {__version__}",
        "references": REFERENCES,
        "brushbem_version": __version__,
        # JSON null: not recorded by the caller (not "no seeds" or "no config").
        "config": "null",
        "seeds": "null",
        "backend": "unknown",
        "summary": result.summary,
    }
    attributes.update(result.attributes)
    if config is not None:
        attributes["config"] = config_to_dict(config)
    return xr.Dataset(variables, coords=coords, attrs=netcdf_attributes(attributes))


def write_dataset(
    result: CaseResult, target: str | Path, *, config: RunConfig | None = None
) -> None:
    """Write the ``result.nc`` content of one case to the file ``target``, atomically.

    The same layout as `write_case`'s ``result.nc``, under any file name: a
    parameter sweep keeps one such file per case (``cases/<case-id>.nc``).

    Parameters
    ----------
    result : CaseResult
        The run to record; its ``attributes`` become global attributes.
    target : path
        The file written; its folder must exist.
    config : RunConfig, optional
        The resolved configuration, recorded in the ``config`` attribute.
    """
    dataset = _dataset(result, config)
    target = Path(target)
    size = int(sum(variable.nbytes for variable in dataset.variables.values())) + 2**16
    _check_free_space(target.parent, size)  # uncompressed: an upper bound
    encoding = _field_compression(dataset)
    with atomic_path(target) as temporary:
        if size <= IN_MEMORY_LIMIT:
            # HDF5 writes to memory; Python writes the bytes, so that a full
            # disk raises here instead of failing inside the library (which
            # then crashes the interpreter when it closes the file).
            buffer = io.BytesIO()
            dataset.to_netcdf(buffer, engine="h5netcdf", encoding=encoding)
            with open(temporary, "wb") as handle:
                handle.write(buffer.getbuffer())
                handle.flush()
                os.fsync(handle.fileno())
        else:
            _stream_netcdf(dataset, temporary, encoding, target)


def _stream_netcdf(dataset: xr.Dataset, temporary: Path, encoding: dict[str, Any], target: Path) -> None:
    """Write ``dataset`` to ``temporary`` through `_GuardedFile` (too large to render in memory first).

    HDF5 writes through Python's file calls, and a failed write (a full disk,
    a quota, a file-size limit) never reaches HDF5, which would crash the
    interpreter on it: the file keeps its content in memory from the failure
    on, HDF5 finishes its file, and the failure is raised here as ``OSError``
    with its errno, naming ``target``.
    """
    guarded = _GuardedFile(temporary)
    try:
        dataset.to_netcdf(guarded, engine="h5netcdf", encoding=encoding)
        if guarded.error is None:
            try:
                os.fsync(guarded.fileno())
            except OSError as exc:
                guarded.error = exc
    finally:
        guarded.close()
    if guarded.error is not None:
        error = guarded.error
        raise OSError(error.errno or errno.EIO,
                      f"{error.strerror or error} (writing {target.name}; nothing was left half-written)",
                      str(target)) from None


class _GuardedFile(io.RawIOBase):
    """A file for HDF5 (h5py's file-object driver) whose operations never fail.

    Until a write, read or truncation of the file fails, every operation goes
    to the file; at the first failure the error is kept in ``error``, the
    content written so far is read into memory, and the rest of the writing
    goes there, so that HDF5 completes its file instead of meeting the
    failure (on which the HDF5 library crashes the process when it closes
    the file).  The caller raises ``error`` once HDF5 is done, and discards
    the file.
    """

    def __init__(self, path: Path) -> None:
        super().__init__()
        self._file = open(path, "r+b", buffering=0)  # noqa: SIM115 - closed by close()
        self._position = 0
        self._memory: io.BytesIO | None = None
        self.error: OSError | None = None

    def readable(self) -> bool:
        return True

    def writable(self) -> bool:
        return True

    def seekable(self) -> bool:
        return True

    def fileno(self) -> int:
        return self._file.fileno()

    def tell(self) -> int:
        return self._position

    def seek(self, offset: int, whence: int = os.SEEK_SET) -> int:
        if whence == os.SEEK_SET:
            self._position = offset
        elif whence == os.SEEK_CUR:
            self._position += offset
        else:
            self._position = self._size() + offset
        return self._position

    def _size(self) -> int:
        if self._memory is not None:
            return len(self._memory.getbuffer())
        try:
            return os.fstat(self._file.fileno()).st_size
        except OSError as exc:
            self._fail(exc)
            return self._size()

    def _fail(self, exc: OSError) -> None:
        """Keep ``exc`` and continue in memory, from the content the file holds."""
        self.error = self.error or exc
        memory = io.BytesIO()
        try:
            self._file.seek(0)
            while chunk := self._file.read(1 << 24):
                memory.write(chunk)
        except OSError:
            pass  # what could be read; the file is discarded anyway
        self._memory = memory

    def write(self, data: Any) -> int:
        view = memoryview(data).cast("B")
        if self._memory is None:
            try:
                self._file.seek(self._position)
                done = 0
                while done < len(view):
                    done += self._file.write(view[done:]) or 0
            except OSError as exc:
                self._fail(exc)
        if self._memory is not None:
            self._memory.seek(self._position)
            self._memory.write(view)
        self._position += len(view)
        return len(view)

    def readinto(self, buffer: Any) -> int:
        view = memoryview(buffer).cast("B")
        count = 0
        if self._memory is None:
            try:
                self._file.seek(self._position)
                count = self._file.readinto(view) or 0
            except OSError as exc:
                self._fail(exc)
        if self._memory is not None:
            self._memory.seek(self._position)
            count = self._memory.readinto(view)
        self._position += count
        return count

    def truncate(self, size: int | None = None) -> int:
        size = self._position if size is None else size
        if self._memory is None:
            try:
                self._file.truncate(size)
                return size
            except OSError as exc:
                self._fail(exc)
        assert self._memory is not None
        length = len(self._memory.getbuffer())
        if size <= length:
            self._memory.truncate(size)
        else:  # extend with zeros, as a file's truncation does
            self._memory.seek(length)
            self._memory.write(bytes(size - length))
        return size

    def flush(self) -> None:
        pass  # unbuffered: every write went to the file (or to memory)

    def close(self) -> None:
        try:
            self._file.close()
        finally:
            self._memory = None
            super().close()


def _field_compression(dataset: Any) -> dict[str, dict[str, Any]]:
    """Lossless gzip (with byte shuffling) for the fields on the grid (``y``, ``x``) of a result: the
    pressure and contact snapshots are mostly zeros outside the pillars, so a brush's file shrinks many
    times; one chunk per stage, so that reading one stage reads only its field.  Curves and per-pillar
    arrays stay uncompressed (small, and read whole)."""
    encoding = {}
    for name, variable in dataset.data_vars.items():
        if "x" in variable.dims and "y" in variable.dims and variable.ndim >= 2:
            chunks = tuple(1 if dim == "stage" else int(size) for dim, size in zip(variable.dims, variable.shape))
            encoding[str(name)] = {"zlib": True, "complevel": 4, "shuffle": True, "chunksizes": chunks}
    return encoding


def source_commit() -> str | None:
    """The git commit of the checkout brushbem runs from, or None (an installed package, no git)."""
    import subprocess

    try:
        done = subprocess.run(["git", "rev-parse", "HEAD"], cwd=Path(__file__).resolve().parent,
                              capture_output=True, text=True, timeout=10, check=False)
    except (OSError, subprocess.SubprocessError):
        return None
    return (done.stdout.strip() or None) if done.returncode == 0 else None


def _provenance(result: CaseResult, config: RunConfig | None, created: str, commit: str | None) -> dict[str, Any]:
    """What ``summary.json`` records of where its numbers come from: version, commit, time, units, configuration."""
    units = _units_of(result, config)
    configuration = config_to_dict(config) if config is not None else result.attributes.get("config")
    if isinstance(configuration, str):
        try:
            configuration = json.loads(configuration)
        except ValueError:
            pass
    return {
        "brushbem_version": result.attributes.get("brushbem_version", __version__),
        "commit": commit,
        "created": created,
        "backend": result.attributes.get("backend"),
        "units": ("dimensionless: the units of the inputs" if units.dimensionless else
                  {dimension: units.of(dimension) for dimension in ("length", "stress", "force", "energy")}),
        "config": configuration,
    }


def write_case(result: CaseResult, out_dir: str | Path, *, config: RunConfig | None = None) -> None:
    """Write ``summary.json`` and ``result.nc`` of one case into ``out_dir``.

    Parameters
    ----------
    result : CaseResult
        The run to record.
    out_dir : path
        Output folder; created if absent.  Existing files of the same names are
        replaced atomically.
    config : RunConfig, optional
        The resolved configuration, recorded in the ``config`` attribute.  If
        not given, ``result.attributes["config"]`` is used when present.
    """
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    run_id = uuid.uuid4().hex
    created = datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds")
    commit = source_commit()
    result = dataclasses.replace(result, attributes={**result.attributes, "run_id": run_id, "date_created": created,
                                                     **({"commit": commit} if commit else {})})
    summary = _json({**result.summary, "run_id": run_id,
                     "provenance": _provenance(result, config, created, commit)}, indent=2) + "\n"
    _check_free_space(out_dir, len(summary))
    # The dataset first, the summary last: the summary is the pair's commit.
    write_dataset(result, out_dir / DATASET_FILE, config=config)
    with atomic_path(out_dir / SUMMARY_FILE) as temporary, open(temporary, "w", encoding="utf-8") as handle:
        handle.write(summary)
        handle.flush()
        os.fsync(handle.fileno())


def read_case(out_dir: str | Path) -> xr.Dataset:
    """Read the ``result.nc`` of a case folder into memory.

    Parameters
    ----------
    out_dir : path
        A folder written by `write_case`.

    Returns
    -------
    xarray.Dataset
        Fully loaded; the file is closed on return.

    Raises
    ------
    InconsistentCaseError
        When ``summary.json`` is missing, unreadable, or from another run than
        ``result.nc`` (a run killed while writing its files).
    """
    out_dir = Path(out_dir)
    dataset = xr.load_dataset(out_dir / DATASET_FILE, engine="h5netcdf")
    run_id = dataset.attrs.get("run_id")
    if run_id is not None:
        try:
            summary = json.loads((out_dir / SUMMARY_FILE).read_text(encoding="utf-8"))
        except (OSError, ValueError) as exc:
            raise InconsistentCaseError(
                f"{out_dir}: {SUMMARY_FILE} is missing or unreadable beside {DATASET_FILE} "
                f"(a run stopped while writing?): {exc}") from None
        if not isinstance(summary, dict) or summary.get("run_id") != run_id:
            raise InconsistentCaseError(
                f"{out_dir}: {SUMMARY_FILE} and {DATASET_FILE} come from different runs (a run stopped "
                "between writing them); rerun the case")
    return dataset


#: How `to_json_safe` writes the non-finite numbers JSON has no literal for.
_NON_FINITE = {"nan": float("nan"), "inf": float("inf"), "-inf": float("-inf")}


def from_json_safe(node: Any) -> Any:
    """A decoded summary with its non-finite numbers ("nan", "inf") numbers again (`to_json_safe`'s inverse)."""
    if isinstance(node, dict):
        return {key: from_json_safe(value) for key, value in node.items()}
    if isinstance(node, list):
        return [from_json_safe(value) for value in node]
    return _NON_FINITE.get(node, node) if isinstance(node, str) else node


def _attribute(value: Any) -> Any:
    """A NetCDF attribute as `to_dataset` wrote it: JSON strings decoded, the rest as is."""
    if isinstance(value, str) and (value.startswith(("{", "[")) or value == "null"):
        try:
            return json.loads(value)
        except ValueError:
            return value
    return value.item() if isinstance(value, np.generic) else value


def stages(dataset: xr.Dataset) -> list[str]:
    """The snapshot stages a ``result.nc`` holds, in its order (either layout of `stage_field`)."""
    if "stage" in dataset.coords:
        return [str(name) for name in dataset["stage"].to_numpy()]
    return [str(name)[len("pressure_"):] for name in dataset.data_vars if str(name).startswith("pressure_")]


def stage_field(dataset: xr.Dataset, name: str, stage: str) -> xr.DataArray | None:
    """The snapshot ``name`` (``"pressure"``, ``"contact"`` or ``"pillar_force"``) at ``stage``, or None.

    Reads both layouts of ``result.nc``: one variable along ``stage``
    (``pressure(stage, y, x)``, with the moment in the coordinates
    ``stage_displacement`` and ``stage_force``), and one variable per stage
    in files written before it (``pressure_<stage>``, the moment in its
    attributes).  The field returned carries the moment as the attributes
    ``displacement`` and ``force`` either way.
    """
    if "stage" in dataset.coords:
        if name not in dataset.data_vars or stage not in stages(dataset):
            return None
        field = dataset[name].sel(stage=stage)
        moment = {"displacement": float(field["stage_displacement"]), "force": float(field["stage_force"])}
        field = field.drop_vars([coord for coord in ("stage", "stage_displacement", "stage_force")
                                 if coord in field.coords])
        return field.assign_attrs(moment)
    legacy = f"{name}_{stage}"
    return dataset[legacy] if legacy in dataset.data_vars else None


def from_dataset(dataset: xr.Dataset) -> CaseResult:
    """The `CaseResult` of a ``result.nc`` (`to_dataset`'s layout), for figures and analysis.

    The curve, the snapshots (pressure, contact and per-pillar forces with
    their moment), the per-pillar arrays, the summary and the provenance
    attributes are read back; nothing is recomputed.
    """
    from brushbem.results import Curve, Snapshot

    def column(name: str, dtype: Any, default: Any = 0) -> np.ndarray:
        if name in dataset:
            return np.asarray(dataset[name].to_numpy(), dtype=dtype)
        return np.full(dataset.sizes.get("step", 0), default, dtype=dtype)

    curve = Curve(
        displacement=column("displacement", float), force=column("force", float),
        contact_area=column("contact_area", float), cg_iterations=column("cg_iterations", np.int64),
        converged=column("converged", bool, True), loading=column("loading", bool, False),
        attached_pillars=column("attached_pillars", np.int64),
    )
    snapshots = []
    for stage in stages(dataset):
        pressure = stage_field(dataset, "pressure", stage)
        contact = stage_field(dataset, "contact", stage)
        pillar_force = stage_field(dataset, "pillar_force", stage)
        forces = None if pillar_force is None else np.asarray(pillar_force.to_numpy(), dtype=float)
        snapshots.append(Snapshot(
            name=stage, displacement=float(pressure.attrs["displacement"]), force=float(pressure.attrs["force"]),
            pressure=np.asarray(pressure.to_numpy(), dtype=float),
            contact=(np.asarray(contact.to_numpy(), dtype=bool) if contact is not None
                     else np.zeros(pressure.shape, dtype=bool)),
            pillar_force=None if forces is None or np.all(np.isnan(forces)) else forces,
        ))
    pillars = {str(name)[len("pillar_"):]: dataset[name].to_numpy() for name in dataset.data_vars
               if str(name).startswith("pillar_") and not str(name).startswith("pillar_force")}
    x = dataset["x"].to_numpy() if "x" in dataset.coords else np.array([])
    attributes = {str(key): _attribute(value) for key, value in dataset.attrs.items()}
    summary = attributes.pop("summary", {})
    return CaseResult(
        curve=curve, snapshots=tuple(snapshots), summary=from_json_safe(summary) if isinstance(summary, dict) else {},
        attributes=attributes, element_size=float(x[1] - x[0]) if x.size > 1 else 1.0, pillars=pillars,
    )


def load_result(path: str | Path) -> CaseResult:
    """The `CaseResult` of a case folder (``brushbem run --out``) or of one ``.nc`` file (a sweep's case)."""
    path = Path(path)
    if path.is_dir():
        dataset = read_case(path)
    elif path.is_file():
        dataset = xr.load_dataset(path, engine="h5netcdf")
    else:
        raise FileNotFoundError(f"{path}: no such case folder or result file")
    return from_dataset(dataset)
