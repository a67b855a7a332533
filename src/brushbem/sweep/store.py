"""The sweep folder on disk.

Its file names; the case files ``cases/<case-id>.nc`` (written atomically
by the driver, read back only as far as their attributes, told apart from
corrupt ones, which are moved to ``corrupt/``); ``incidents.jsonl``
(`read_incidents`); ``sweep.json`` (written atomically, read back, and
checked against the sweep run into the folder: `SweepFolderError`); the
lock that keeps a second driver out; and the removal of a killed driver's
temporaries.  The summary of a folder is `brushbem.sweep.summary`'s.
"""

from __future__ import annotations

import contextlib
import dataclasses
import json
import os
import sys
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from brushbem import __version__
from brushbem.config import config_to_dict
from brushbem.results.plain import to_json_safe
from brushbem.sweep.errors import SweepFolderError, _brief, _show
from brushbem.sweep.spec import Sweep, SweepCase
from brushbem.sweep.worker import _RECORDED, CaseOutcome

SWEEP_FILE = "sweep.json"
SUMMARY_FILE = "summary.parquet"
CASES_DIR = "cases"
#: Where a rerun moves case files it cannot read (nothing is deleted).
CORRUPT_DIR = "corrupt"
#: What happened to a sweep folder, one JSON object per line (`read_incidents`).
INCIDENTS_FILE = "incidents.jsonl"
_LOCK_FILE = ".sweep.lock"


def _case_path(out_dir: Path, case_id: str) -> Path:
    return out_dir / CASES_DIR / f"{case_id}.nc"


def _local_files() -> contextlib.AbstractContextManager[Any]:
    """Read and write files with local locks, whatever dask scheduler is the default.

    With a `dask.distributed.Client` as the default scheduler, xarray guards
    NetCDF files with the cluster's distributed locks: the driver's files
    would then depend on the cluster's health (a restarted worker has lost
    such a lock: "Semaphore or Lock ... not known").  The driver's files are
    its own; dask's synchronous scheduler gives xarray ordinary locks.
    """
    dask = sys.modules.get("dask")
    if dask is None or not hasattr(dask, "config"):
        return contextlib.nullcontext()
    return dask.config.set(scheduler="synchronous")


def _write_case_file(out_dir: Path, case: SweepCase, outcome: CaseOutcome) -> None:
    """Record one case in ``cases/<case-id>.nc``, atomically (a failed one as attributes only)."""
    with _local_files():
        _write_case_dataset(out_dir, case, outcome)


def _write_case_dataset(out_dir: Path, case: SweepCase, outcome: CaseOutcome) -> None:
    import xarray as xr

    from brushbem.io import atomic_path, netcdf_attributes, write_dataset

    attributes: dict[str, Any] = {
        "case_id": case.case_id,
        "index": case.index,
        "realization": case.realization,
        "seed": case.seed,
        "seed_applied": case.seed_applied,
        "seeds": [case.seed],
        "swept": case.values,
        "status": outcome.status,
        "reason": outcome.reason,
        "wall_time_s": outcome.wall_time_s,
    }
    path = _case_path(out_dir, case.case_id)
    if outcome.result is not None:
        result = dataclasses.replace(
            outcome.result, attributes={**outcome.result.attributes, **attributes}
        )
        write_dataset(result, path, config=case.config)
        return
    attributes.update({
        "brushbem_version": __version__,
        "config": config_to_dict(case.config),
        "backend": "unknown",
        "traceback": outcome.traceback,
    })
    with atomic_path(path) as temporary:
        xr.Dataset(attrs=netcdf_attributes(attributes)).to_netcdf(temporary, engine="h5netcdf")


def _case_attributes(path: Path) -> dict[str, Any]:
    """The global attributes of a case file (no data is read)."""
    return _metadata(path)[0]


def _metadata(path: Path) -> tuple[dict[str, Any], set[str]]:
    """The global attributes and the variable names of a NetCDF file, as ``xarray.open_dataset`` gives them.

    Read by h5netcdf alone, with the bytes attributes decoded as xarray's
    h5netcdf backend does: xarray's opening also decodes every variable and
    builds the coordinates' indexes, ten times the cost (0.13 s against
    0.012 s for a brush's case file), at every summary and resume.
    """
    import h5netcdf

    with h5netcdf.File(path, "r", phony_dims="access") as file:
        attributes = {key: value.decode("utf-8") if isinstance(value, bytes) else value
                      for key, value in file.attrs.items()}
        return attributes, set(file.variables)


def _read_case_record(path: Path, case_id: str) -> tuple[dict[str, Any] | None, str]:
    """The attributes of the case file of ``case_id``, or None and why it is not a result.

    A case file is a result when it opens, its ``status`` is one a case is
    recorded with, its ``case_id`` is its own, and a finished or unconverged
    case has its load path.  No data is read beyond the file's metadata.
    """
    try:
        with _local_files():
            attributes, variables = _metadata(path)
    except Exception as exc:  # noqa: BLE001 - any unreadable file is corrupt, whatever the library says
        return None, f"cannot be read ({_brief(exc)})"
    status = attributes.get("status")
    if status not in _RECORDED:
        return None, f"no case status (found {_show(status)})"
    if attributes.get("case_id") != case_id:
        return None, f"records case {_show(attributes.get('case_id'))}, not {case_id}"
    if status != "failed" and not {"displacement", "force"} <= variables:
        return None, f"a {status} case without its load path"
    return attributes, ""


def _set_aside(out_dir: Path, path: Path) -> Path:
    """Move an unreadable case file to ``corrupt/`` under a free name; the new path."""
    folder = out_dir / CORRUPT_DIR
    folder.mkdir(exist_ok=True)
    target = folder / path.name
    number = 0
    while target.exists():
        number += 1
        target = folder / f"{path.stem}.{number}{path.suffix}"
    os.replace(path, target)
    return target


def _record_incident(out_dir: Path, event: str, detail: str, **fields: Any) -> None:
    """Append one incident to ``incidents.jsonl`` (a line per incident, flushed at once)."""
    entry = {"time": time.strftime("%Y-%m-%dT%H:%M:%S%z"), "event": event, **fields, "detail": detail}
    line = json.dumps(to_json_safe(entry), allow_nan=False) + "\n"
    with open(out_dir / INCIDENTS_FILE, "a", encoding="utf-8") as handle:
        handle.write(line)
        handle.flush()
        os.fsync(handle.fileno())


def read_incidents(out_dir: str | Path) -> list[dict[str, Any]]:
    """What happened to a sweep folder, oldest first (see the `brushbem.sweep` docstring).

    Every entry has ``time``, ``event`` and ``detail``; ``case_id`` and
    ``moved_to`` where they apply.  Events: ``corrupt`` (a case file moved
    aside and recomputed), ``lost`` (a case lost with its worker, left
    missing), ``interrupted`` (a run stopped by a signal), ``extended`` (a
    sweep grown by new cases), ``unreadable-record`` (``sweep.json``
    unreadable, the folder identified by its case files), ``stale-temporary``
    (half-written files of a killed driver removed).  A line that does not
    parse (a driver killed while appending it) is skipped.

    Returns
    -------
    list of dict
        Empty if the folder has no incidents file.
    """
    path = Path(out_dir) / INCIDENTS_FILE
    try:
        lines = path.read_text(encoding="utf-8", errors="replace").splitlines()
    except FileNotFoundError:
        return []
    incidents = []
    for line in lines:
        try:
            entry = json.loads(line)
        except ValueError:
            continue
        if isinstance(entry, dict) and "event" in entry:
            incidents.append(entry)
    return incidents


def _read_record(out_dir: Path) -> dict[str, Any]:
    """The ``sweep.json`` of ``out_dir``.

    Raises
    ------
    FileNotFoundError
        If there is none.
    SweepFolderError
        If it cannot be read as a sweep record (the file named).
    """
    path = out_dir / SWEEP_FILE
    try:
        record = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise
    except (OSError, UnicodeDecodeError, ValueError) as exc:
        raise SweepFolderError([f"`{path}`: cannot be read as a sweep record ({_brief(exc)})"]) from None
    cases = record.get("cases") if isinstance(record, dict) else None
    if not (isinstance(cases, list) and all(isinstance(c, dict) and "case_id" in c for c in cases)):
        raise SweepFolderError([f"`{path}`: not a sweep record (no list of cases with their ids)"])
    return record


def _check_folder(out_dir: Path, sweep: Sweep) -> None:
    """Refuse a folder that holds another sweep; record an extension or a lost record.

    The folder's sweep is what ``sweep.json`` records, or, if that is
    unreadable, the case files in ``cases/``.  ``sweep`` may run there when
    it keeps every one of those cases (the same ids).
    """
    ids = {case.case_id for case in sweep.cases}
    try:
        recorded = [str(case["case_id"]) for case in _read_record(out_dir)["cases"]]
    except FileNotFoundError:
        return
    except SweepFolderError as error:
        found = sorted(path.stem for path in (out_dir / CASES_DIR).glob("*.nc"))
        foreign = [case_id for case_id in found if case_id not in ids]
        if foreign:
            raise SweepFolderError([
                *error.problems,
                (f"`{out_dir}`: holds case files of a different sweep (e.g. {foreign[0]}); "
                 "run this sweep into a new --out folder"),
            ]) from None
        _record_incident(out_dir, "unreadable-record",
                         f"{error.problems[0]}; rewritten: its {len(found)} case files belong to this sweep")
        return
    dropped = [case_id for case_id in recorded if case_id not in ids]
    if dropped:
        raise SweepFolderError([(
            f"`{out_dir}`: holds a different sweep ({len(recorded)} cases in {out_dir / SWEEP_FILE}, "
            f"{len(dropped)} of them not in this sweep, e.g. {dropped[0]}); a folder takes one sweep, "
            "or one that only adds cases (more realizations): run this sweep into a new --out folder"
        )])
    if len(ids) > len(recorded):
        _record_incident(out_dir, "extended",
                         f"the sweep grew from {len(recorded)} to {len(ids)} cases")


@contextlib.contextmanager
def _exclusive(out_dir: Path) -> Iterator[None]:
    """Refuse a second sweep driver on the same folder (the kernel drops the lock if one is killed).

    The lock file is never written through a link (`brushbem.io.exclusive_folder`): one that is a
    link or not a regular file is a `SweepFolderError`, and the file it points to is left as it is.
    """
    from brushbem.io import FolderBusyError, UnsafeLockError, exclusive_folder

    with contextlib.ExitStack() as stack:
        try:
            stack.enter_context(exclusive_folder(out_dir, _LOCK_FILE))
        except FolderBusyError:
            raise RuntimeError(f"another sweep is running in {out_dir}") from None
        except UnsafeLockError as exc:
            raise SweepFolderError([f"`{exc.filename}`: {exc.strerror}"]) from None
        yield


def _write_json(path: Path, value: Any) -> None:
    from brushbem.io import atomic_path

    with atomic_path(path) as temporary:
        temporary.write_text(json.dumps(to_json_safe(value), indent=1, allow_nan=False) + "\n")


def _remove_stale_temporaries(out_dir: Path) -> None:
    """Remove what a driver killed while writing left: temporaries of its files, never complete files."""
    from brushbem.io import temporary_of

    # Only what `brushbem.io.atomic_path` names the temporaries of the driver's files
    # (``.<name>.<random>.tmp``): a case file's, sweep.json's or summary.parquet's.
    stale = [
        *(path for path in (out_dir / CASES_DIR).glob(".*.tmp") if (temporary_of(path.name) or "").endswith(".nc")),
        *(path for path in out_dir.glob(".*.tmp") if temporary_of(path.name) in (SWEEP_FILE, SUMMARY_FILE)),
    ]
    stale = [path for path in stale if path.is_file() and not path.is_symlink()]
    for path in stale:
        path.unlink(missing_ok=True)
    if stale:
        _record_incident(out_dir, "stale-temporary",
                         f"removed {len(stale)} half-written file(s) of a killed run: "
                         + ", ".join(sorted(str(path.relative_to(out_dir)) for path in stale)[:5])
                         + (", ..." if len(stale) > 5 else ""))
