"""The summary of a sweep folder: one row per case, from its case files.

`build_summary` builds it (and writes ``summary.parquet`` atomically);
`load_summary` reads ``summary.parquet``, rebuilt when it is missing, stale
or unreadable.
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import warnings
from pathlib import Path
from typing import TYPE_CHECKING, Any

from brushbem.results.plain import to_json_safe
from brushbem.sweep.errors import SweepWarning, _brief
from brushbem.sweep.store import (
    CASES_DIR,
    CORRUPT_DIR,
    SUMMARY_FILE,
    SWEEP_FILE,
    _case_path,
    _read_case_record,
    _read_record,
    read_incidents,
)

if TYPE_CHECKING:  # pandas is imported where needed: loading a sweep file does not need it
    import pandas as pd


_NON_FINITE = {"inf": math.inf, "-inf": -math.inf, "nan": math.nan}


def _arrow_safe(frame: pd.DataFrame) -> pd.DataFrame:
    """Make object columns storable in Parquet.

    JSON wrote non-finite floats as ``"inf"``/``"-inf"``/``"nan"``; a column of
    numbers and such strings becomes float again.  A column still mixing types
    (or holding tables/arrays) is stored as JSON text, one value per cell.
    """
    import pandas as pd

    for name in frame.columns:
        column = frame[name]
        if not (column.dtype == object or pd.api.types.is_string_dtype(column)):
            continue
        values = [v for v in column if not (v is None or (isinstance(v, float) and math.isnan(v)))]
        restored = [_NON_FINITE.get(v, v) if isinstance(v, str) else v for v in values]
        if values and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in restored):
            frame[name] = pd.to_numeric(
                column.map(lambda v: _NON_FINITE.get(v, v) if isinstance(v, str) else v)
            )
        elif len({type(v) for v in values}) > 1 or any(isinstance(v, (dict, list)) for v in values):
            frame[name] = column.map(
                lambda v: None if v is None or (isinstance(v, float) and math.isnan(v))
                else json.dumps(to_json_safe(v), sort_keys=True)
            )
    return frame


def build_summary(out_dir: str | Path, *, write: bool = True) -> pd.DataFrame:
    """One row per case of the sweep in ``out_dir``, from its case files.

    Columns: ``case_id``, ``index``, ``realization``, ``seed``,
    ``seed_applied``, the swept values under their dotted keys, ``status``,
    ``reason``, ``wall_time_s`` (of the whole case, in its worker), then the
    ``summary.json`` fields flattened with dots (``theory.ratios.adhesive_force``;
    its own ``reason`` and ``wall_time_s`` give way to the case's), and
    ``brushbem_version``, ``backend``.  A case without a file has status
    ``missing`` (its reason says so when its worker was lost), a case whose
    file cannot be read as a result has status ``corrupt`` (nothing of it is
    read).  Case files of other sweeps in the folder are ignored.

    Parameters
    ----------
    out_dir : path
        A folder written by `run_sweep` (it needs ``sweep.json``).
    write : bool
        Also write ``summary.parquet`` (atomically).

    Returns
    -------
    pandas.DataFrame

    Raises
    ------
    FileNotFoundError
        If ``out_dir`` has no ``sweep.json``.
    SweepFolderError
        If its ``sweep.json`` cannot be read.
    """
    import pandas as pd

    from brushbem.io import atomic_path

    out_dir = Path(out_dir)
    record = _read_record(out_dir)
    lost = {entry.get("case_id"): entry.get("detail", "") for entry in read_incidents(out_dir)
            if entry["event"] == "lost"}
    rows, summaries = [], []
    for entry in record["cases"]:
        row: dict[str, Any] = {
            key: entry[key] for key in ("case_id", "index", "realization", "seed", "seed_applied")
        }
        row.update(entry["values"])
        path = _case_path(out_dir, entry["case_id"])
        summary: dict[str, Any] = {}
        provenance: dict[str, Any] = {"brushbem_version": None, "backend": None}
        attributes, problem = _read_case_record(path, entry["case_id"]) if path.exists() else (None, "")
        if attributes is not None:
            row["status"] = attributes.get("status")
            row["reason"] = attributes.get("reason")
            row["wall_time_s"] = attributes.get("wall_time_s")
            try:
                summary = json.loads(attributes.get("summary", "null")) or {}
            except (TypeError, ValueError):
                summary = {}
            provenance = {key: attributes.get(key) for key in ("brushbem_version", "backend")}
        elif problem:
            row.update(status="corrupt", wall_time_s=math.nan,
                       reason=f"case file {problem}; a rerun moves it to {CORRUPT_DIR}/ and recomputes it")
        elif entry["case_id"] in lost:
            row.update(status="missing", wall_time_s=math.nan,
                       reason=f"its worker was lost ({lost[entry['case_id']]})")
        else:
            row.update(status="missing", reason="not computed yet", wall_time_s=math.nan)
        rows.append(row)
        summaries.append((summary, provenance))
    frame = pd.DataFrame(rows, columns=[
        "case_id", "index", "realization", "seed", "seed_applied", *record["sweep"],
        "status", "reason", "wall_time_s",
    ])
    flat = pd.json_normalize([s for s, _ in summaries], sep=".")
    flat = flat.drop(columns=[c for c in flat.columns if c in frame.columns])
    provenance = pd.DataFrame([p for _, p in summaries], columns=["brushbem_version", "backend"])
    frame = _arrow_safe(pd.concat([frame, flat, provenance], axis=1))
    if write:
        with atomic_path(out_dir / SUMMARY_FILE) as temporary:
            frame.to_parquet(temporary, engine="pyarrow", index=False)
    return frame


def load_summary(out_dir: str | Path, *, rebuild: bool = False) -> pd.DataFrame:
    """The summary of the sweep in ``out_dir`` (one row per case).

    ``summary.parquet`` is read as it is unless it is missing, older than a
    case file, the ``cases/`` folder or ``sweep.json`` (a killed or extended
    sweep, a case file replaced or damaged since), or ``rebuild``
    is set; then it is rebuilt with `build_summary` (and written where the
    folder is writable).  A ``summary.parquet`` that cannot be read (corrupt,
    or written by a newer format) is rebuilt too, with a `SweepWarning`.

    Returns
    -------
    pandas.DataFrame

    Raises
    ------
    FileNotFoundError
        If ``out_dir`` has no ``sweep.json``.
    SweepFolderError
        If its ``sweep.json`` cannot be read.
    """
    import pandas as pd

    out_dir = Path(out_dir)
    path = out_dir / SUMMARY_FILE
    if not rebuild and path.exists():
        written = path.stat().st_mtime_ns
        newest = max(
            (out_dir / name).stat().st_mtime_ns
            for name in (SWEEP_FILE, CASES_DIR) if (out_dir / name).exists()
        )
        with contextlib.suppress(FileNotFoundError), os.scandir(out_dir / CASES_DIR) as entries:
            for entry in entries:
                with contextlib.suppress(FileNotFoundError):
                    newest = max(newest, entry.stat().st_mtime_ns)
        if newest <= written:
            try:
                return pd.read_parquet(path, engine="pyarrow")
            except Exception as exc:  # noqa: BLE001 - a derived file: rebuilt, whatever the reader says
                warnings.warn(f"{path} cannot be read ({_brief(exc)}); "
                              "rebuilt from the case files", SweepWarning, stacklevel=2)
    try:
        return build_summary(out_dir)
    except OSError:  # a read-only results folder: summarise without writing
        return build_summary(out_dir, write=False)
