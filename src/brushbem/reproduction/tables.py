"""The compact study tables: exporting a study run folder, loading them back, their recorded cases.

A study run folder (``brushbem study NAME --out DIR``) holds NetCDF case files
and parquet summaries: too large to commit, and tied to one machine.
`export_tables` writes what the comparison needs as compact text instead:

    TABLES/<study>/<part>.csv        one row per case: swept values, seed,
                                     status, the summary numbers (full precision)
    TABLES/<study>/provenance.json   brushbem version, commit, quick or full,
                                     per part: sweep file, cases, seeds, grid,
                                     wall time

`load_tables` reads one study's folder back, and `recorded_cases` gives the
hashes of its finished cases (what ``brushbem study --skip-recorded`` leaves out).
"""

from __future__ import annotations

import json
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import pandas as pd

from brushbem import __version__
from brushbem.io import atomic_path
from brushbem.sweep.spec import case_hash

__all__ = ["NOTES_FILE", "PROVENANCE_FILE", "case_hash", "export_tables", "load_tables", "recorded_cases"]

PROVENANCE_FILE = "provenance.json"
NOTES_FILE = "notes.md"


def _commit() -> str | None:
    """The git commit of the working tree this package runs from, if it is a checkout (`io.source_commit`)."""
    from brushbem.io import source_commit

    return source_commit()


def _grid(record: Mapping[str, Any], frame: pd.DataFrame) -> str:
    """The grid of a part: elements per side and the pillars, from its sweep record."""
    base = record.get("base", {})

    def values(key: str, default: Any) -> list:
        if key in frame.columns:
            return sorted(set(frame[key].dropna().tolist()))
        return [default] if default is not None else []

    grid = base.get("grid", {})
    indenter = base.get("indenter", {})
    elements = values("grid.elements", grid.get("elements"))
    text = "N = " + ", ".join(str(int(n)) for n in elements) if elements else "N = ?"
    shape = indenter.get("shape")
    if shape == "brush":
        if indenter.get("layout", "square") == "random":
            counts = values("indenter.pillar_count", indenter.get("pillar_count"))
            text += "; " + ", ".join(str(int(c)) for c in counts) + " random pillars"
        else:
            sides = values("indenter.pillars_per_side", indenter.get("pillars_per_side"))
            text += "; " + ", ".join(f"{int(n)} x {int(n)}" for n in sides) + " pillars"
    elif shape:
        text += f"; {shape}"
    return text


def export_tables(study_dir: str | Path | Sequence[str | Path], tables_root: str | Path, *,
                  update: bool = False) -> Path:
    """Write the compact tables of the study run folder(s) ``study_dir`` under ``tables_root/<study>``.

    Several folders of one study (e.g. its sampled run and a named sampled
    set's, `brushbem.studies.sampled_sets`) merge into one table per part: a
    case in two of them (the same hash) is kept once, finished before
    anything else, at the place of its first record.  Returns the folder
    written.  Existing tables of the study are replaced, unless ``update``:
    then they are merged as one more folder, recorded first, so a case that
    an earlier run (of another machine or session, whose folder is gone)
    recorded stays, and the folders add what they finished.

    Raises
    ------
    StudyError
        The folders are of different studies, or of quick and full grids,
        or ``update`` finds tables of another study there.
    """
    from brushbem.studies import StudyError, get_study, load_results
    from brushbem.studies._framework import read_study_record
    from brushbem.sweep import SWEEP_FILE

    dirs = [Path(study_dir)] if isinstance(study_dir, (str, Path)) else [Path(d) for d in study_dir]
    if not dirs:
        raise StudyError("export-tables: no study folder given")
    records = [read_study_record(folder) for folder in dirs]
    name = records[0]["study"]
    quick = bool(records[0].get("quick", False))
    for folder, record in zip(dirs, records):
        if record["study"] != name or bool(record.get("quick", False)) != quick:
            raise StudyError(f"export-tables: {folder} holds study {record['study']!r}"
                             f"{' (quick)' if record.get('quick') else ''}, not {name!r}"
                             f"{' (quick)' if quick else ''} of {dirs[0]}: export one study's folders together")
    frames: dict[str, list[pd.DataFrame]] = {}
    sources: dict[str, list[tuple[Path, dict[str, Any]]]] = {}
    folder_out = Path(tables_root) / name
    recorded: dict[str, Any] = {}
    if update and (folder_out / PROVENANCE_FILE).is_file():
        recorded = json.loads((folder_out / PROVENANCE_FILE).read_text(encoding="utf-8"))
        if recorded.get("study") != name or bool(recorded.get("quick", False)) != quick:
            raise StudyError(f"export-tables --update: {folder_out} holds study {recorded.get('study')!r}"
                             f"{' (quick)' if recorded.get('quick') else ''}, not {name!r}"
                             f"{' (quick)' if quick else ''}")
        for part in recorded["parts"]:
            # (pandas reads back the digits it wrote: the recorded rows are rewritten unchanged)
            frames[part] = [pd.read_csv(folder_out / f"{part}.csv")]
            sources[part] = []
    for folder, record in zip(dirs, records):
        for part, frame in load_results(folder, tuple(record["parts"])).items():
            table = frame.drop(columns=[c for c in ("case_file",) if c in frame.columns])
            if "index" in table.columns:
                table = table.sort_values("index", kind="stable")
            frames.setdefault(part, []).append(table)
            sources.setdefault(part, []).append((folder, record))
    study = get_study(name)
    for folder, record in zip(dirs, records):
        # the tables a study computes without a sweep: the latest folder's replace the recorded ones
        for part, table in (study.tables(folder) if study.tables is not None else {}).items():
            frames[part], sources[part] = [table], [(folder, record)]
    folder_out.mkdir(parents=True, exist_ok=True)
    parts: dict[str, Any] = {}
    for part, tables in frames.items():
        table = pd.concat(tables, ignore_index=True) if len(tables) > 1 else tables[0]
        if len(tables) > 1 and "case_id" in table.columns:
            # One row per case: a finished one before any other record of the same case, at the
            # place of the case's first record.
            order = (table["status"] != "finished") if "status" in table.columns else pd.Series(False, table.index)
            hashes = table["case_id"].map(case_hash)
            first_place = dict(zip(hashes[::-1], hashes.index[::-1]))  # reversed: the first record wins
            table = table.assign(_rank=order.astype(int), _hash=hashes, _place=hashes.map(first_place))
            table = (table.sort_values("_rank", kind="stable").drop_duplicates("_hash")
                     .sort_values("_place", kind="stable").drop(columns=["_hash", "_rank", "_place"]))
            # A run's rows of cases it left to the tables ("missing", NaN) make integer columns
            # float in the concatenation; where the kept rows are whole again, they are integers
            # again, so an update rewrites the recorded rows unchanged.
            for column, dtype in tables[0].dtypes.items():
                if pd.api.types.is_integer_dtype(dtype) and column in table.columns:
                    values = table[column]
                    # A column another run wrote as text (object) is left as it reads.
                    if (pd.api.types.is_numeric_dtype(values) and values.notna().all()
                            and (values == values.round()).all()):
                        table[column] = values.astype(dtype)
        with atomic_path(folder_out / f"{part}.csv") as temporary:
            table.to_csv(temporary, index=False)
        earlier = recorded.get("parts", {}).get(part, {})
        first = sources[part][0][0] / part / SWEEP_FILE if sources[part] else None
        sweep_record = json.loads(first.read_text(encoding="utf-8")) if first and first.is_file() else {}
        statuses = table["status"].value_counts().to_dict() if "status" in table.columns else {}
        wall = pd.to_numeric(table.get("wall_time_s", pd.Series(dtype=float)), errors="coerce")
        files = list(earlier.get("sweep_files", [earlier["sweep_file"]] if "sweep_file" in earlier else []))
        files += [Path(record.get("sweep_files", {}).get(part, "")).name for _, record in sources[part]]
        files = list(dict.fromkeys(files))
        parts[part] = {
            "sweep_file": files[0],
            "cases": len(table),
            "statuses": {str(k): int(v) for k, v in sorted(statuses.items())},
            "seeds": sorted({int(s) for s in table["seed"].tolist()}) if "seed" in table.columns else [],
            "realizations": int(table["realization"].nunique()) if "realization" in table.columns else 1,
            # the realisations with at least one finished case (a run in progress goes seed by seed)
            "finished_realizations": (int(table.loc[table["status"] == "finished", "realization"].nunique())
                                      if {"realization", "status"} <= set(table.columns) else 1),
            "grid": _grid(sweep_record, table) if sweep_record or not earlier else earlier.get("grid", ""),
            "wall_time_s": float(wall.sum()) if len(wall) else 0.0,
        }
        if len(files) > 1:
            parts[part]["sweep_files"] = files
        # what the earlier record states beyond the computed keys (where it was computed, ...)
        parts[part] |= {key: v for key, v in earlier.items() if key not in parts[part]}
    provenance = {
        "study": name,
        "quick": quick,
        "brushbem_version": records[0].get("brushbem_version", __version__),
        "commit": _commit(),
        "parts": parts,
    }
    earlier_commits = [*recorded.get("earlier_commits", []), recorded.get("commit")] if recorded else []
    if earlier_commits := [c for c in dict.fromkeys(earlier_commits) if c and c != provenance["commit"]]:
        provenance["earlier_commits"] = earlier_commits
    with atomic_path(folder_out / PROVENANCE_FILE) as temporary:
        temporary.write_text(json.dumps(provenance, indent=2, sort_keys=True) + "\n", encoding="utf-8")
    return folder_out


def recorded_cases(tables_root: str | Path, study: str) -> dict[str, set[str]]:
    """Part -> the hashes of the cases finished in the committed tables of ``study``.

    What `brushbem.sweep.run_sweep` leaves out as ``recorded`` (``brushbem
    study --skip-recorded``), so that a sampled run goes on across sessions and
    machines from its committed tables instead of from zero; empty where the
    study has no tables under ``tables_root``.
    """
    folder = Path(tables_root) / study
    if not (folder / PROVENANCE_FILE).is_file():
        return {}
    _, tables = load_tables(folder)
    return {part: {case_hash(case_id) for case_id in frame.loc[frame["status"] == "finished", "case_id"]}
            for part, frame in tables.items() if {"status", "case_id"} <= set(frame.columns)}


def load_tables(folder: str | Path) -> tuple[dict[str, Any], dict[str, pd.DataFrame]]:
    """The provenance and the part tables (part -> DataFrame) of one study's table folder."""
    folder = Path(folder)
    provenance = json.loads((folder / PROVENANCE_FILE).read_text(encoding="utf-8"))
    tables = {part: pd.read_csv(folder / f"{part}.csv") for part in provenance["parts"]}
    return provenance, tables
