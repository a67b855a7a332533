"""Writing a case's result files: ``result.nc`` (`write_dataset`) and the pair with ``summary.json`` (`write_case`).

A NetCDF file up to `IN_MEMORY_LIMIT` bytes is rendered in memory and written
by Python; a larger one is streamed by HDF5 through `_GuardedFile`, which
never passes a failed write on to HDF5.  `write_case` gives both files one
``run_id`` and writes the summary last, with its provenance (`source_commit`).
"""

from __future__ import annotations

import dataclasses
import datetime
import errno
import io
import json
import os
import uuid
from pathlib import Path
from collections.abc import Mapping
from typing import Any

import numpy as np
import xarray as xr

from brushbem import __version__
from brushbem.config import RunConfig, config_to_dict
from brushbem.results import CaseResult, Provenance, RunSummary

from brushbem.io.atomic import CURVE_FILE, DATASET_FILE, SUMMARY_FILE, _check_free_space, atomic_path
from brushbem.io.dataset import _dataset, _field_compression, _units_of
from brushbem.io.encoding import _json

#: Largest NetCDF file rendered in memory before it is written (bytes).
IN_MEMORY_LIMIT = 512 * 2**20


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
            # then crashes the interpreter when it closes the file).  By
            # netCDF4-python: h5netcdf's variable by variable creation costs
            # 0.1-0.2 s for a case's 26 variables, netCDF4's 0.02 s (a sweep
            # of quick cases spent most of its time writing them).
            content = dataset.to_netcdf(engine="netcdf4", encoding=encoding)
            with open(temporary, "wb") as handle:
                handle.write(content)
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


def saved_summary(summary: Mapping[str, Any], run_id: str, provenance: Provenance) -> Mapping[str, Any]:
    """The summary as ``summary.json`` holds it: ``summary`` with the files' ``run_id`` and the ``provenance``."""
    if isinstance(summary, RunSummary):
        return dataclasses.replace(summary, run_id=run_id, provenance=provenance)
    return {**summary, "run_id": run_id, "provenance": provenance}


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
    summary = _json(saved_summary(result.summary, run_id, Provenance.from_mapping(
        _provenance(result, config, created, commit))), indent=2) + "\n"
    _check_free_space(out_dir, len(summary))
    # The dataset and the curve first, the summary last: the summary is the files' commit.
    write_dataset(result, out_dir / DATASET_FILE, config=config)
    write_curve(result, out_dir / CURVE_FILE, config=config)
    with atomic_path(out_dir / SUMMARY_FILE) as temporary, open(temporary, "w", encoding="utf-8") as handle:
        handle.write(summary)
        handle.flush()
        os.fsync(handle.fileno())


#: The columns of ``curve.csv``: the `Curve` field, and its physical dimension (None: a count or a flag).
CURVE_COLUMNS = (("displacement", "length"), ("force", "force"), ("contact_area", "length^2"),
                 ("attached_pillars", None), ("loading", None), ("converged", None))


def write_curve(result: CaseResult, path: str | Path, *, config: RunConfig | None = None) -> None:
    """Write the force-displacement curve as ``curve.csv`` (atomically: a reader sees the old file or the new).

    One row per recorded equilibrium, in the order of the path; the columns are `CURVE_COLUMNS`, named
    ``displacement [um]`` with the configuration's ``[units]`` (`brushbem.results.units.Units.of`) and
    plainly without; ``loading`` and ``converged`` are 1 or 0.  Numbers are written as the shortest
    text that reads back as the same double (those of ``result.nc``, exactly).
    """
    import csv

    from brushbem.results.units import Units

    units = Units.from_config(config if config is not None else result.attributes.get("config"))
    header = [name if dimension is None or units.dimensionless else f"{name} [{units.of(dimension)}]"
              for name, dimension in CURVE_COLUMNS]
    columns = [np.asarray(getattr(result.curve, name)) for name, _ in CURVE_COLUMNS]
    text = io.StringIO()
    writer = csv.writer(text, lineterminator="\n")
    writer.writerow(header)
    for row in zip(*columns, strict=True):
        writer.writerow([int(v) if v.dtype.kind in "bi" else repr(float(v)) for v in row])
    content = text.getvalue()
    path = Path(path)
    _check_free_space(path.parent, len(content))
    with atomic_path(path) as temporary, open(temporary, "w", encoding="utf-8", newline="") as handle:
        handle.write(content)
        handle.flush()
        os.fsync(handle.fileno())
