"""The thesis's numbers beside ours, from committed tables.

A study run folder (``brushbem study NAME --out DIR``) holds NetCDF case files
and parquet summaries: too large to commit, and tied to one machine.
`export_tables` writes what the comparison needs as compact text instead:

    TABLES/<study>/<part>.csv        one row per case: swept values, seed,
                                     status, the summary numbers (full precision)
    TABLES/<study>/provenance.json   brushbem version, commit, quick or full,
                                     per part: sweep file, cases, seeds, grid,
                                     wall time

`compare` computes every `brushbem.studies.ThesisNumber` of every study found
there from those tables alone, with the standard error over realisations
where a part has several, and `render` writes the comparison as Markdown
(``docs/thesis-comparison.md``), followed by the hand-written notes of
``TABLES/notes.md``.  The document is a function of the tables: the same
tables give the same bytes, which a test checks for the committed ones.

    brushbem export-tables DIR --to docs/reproduction
    brushbem compare-thesis docs/reproduction --out docs/thesis-comparison.md [--check]
"""

from __future__ import annotations

import dataclasses
import json
import math
import re
import statistics
from collections.abc import Collection, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pandas as pd

from . import __version__
from .io import atomic_path
from .studies.verdicts import REPRODUCED, REPRODUCED_WITHIN, STANDARD_ERRORS, VERDICTS, count_by_chapter, judge
from .sweep.spec import case_hash

__all__ = ["ComparisonRow", "compare", "export_tables", "load_tables", "recorded_cases", "render"]

PROVENANCE_FILE = "provenance.json"
NOTES_FILE = "notes.md"
#: Deviations above this need the explanation of a measurement (the notes): relative to the
#: thesis's value, or, where the thesis states 0 ("tends to zero", "vanishes": every such number is
#: a force normalised by the rigid brush's F_c), absolute, in units of that normalising force.
EXPLAIN_ABOVE = 0.05
#: The studies whose grid the thesis states (the section label); every other grid is ours.
THESIS_GRIDS = {"flat_brush": "the thesis's grid, N = 512 (L736)"}


def deviation_of(thesis: float, ours: float, digits: int = 1) -> tuple[float, bool, str]:
    """(deviation, far, text): relative to ``thesis``, absolute where the thesis states 0.

    ``far`` is a deviation above `EXPLAIN_ABOVE`; a number that is not
    computable (NaN) is not far and its text is "—".  ``digits``: of the
    percentage.
    """
    if not math.isfinite(ours):
        return math.nan, False, "—"
    if thesis == 0:
        return ours, abs(ours) > EXPLAIN_ABOVE, f"{ours:+.3g} (absolute; thesis 0)"
    deviation = (ours - thesis) / thesis
    return deviation, abs(deviation) > EXPLAIN_ABOVE, f"{100 * deviation:+.{digits}f} %"


def _commit() -> str | None:
    """The git commit of the working tree this package runs from, if it is a checkout (`io.source_commit`)."""
    from .io import source_commit

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
        The folders are of different studies, or of quick and thesis grids,
        or ``update`` finds tables of another study there.
    """
    from .studies import StudyError, load_results
    from .studies._framework import read_study_record
    from .sweep import SWEEP_FILE

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
                    if values.notna().all() and (values == values.round()).all():
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


@dataclass(frozen=True)
class ComparisonRow:
    """One thesis number beside ours."""

    study: str
    quantity: str
    where: str
    thesis: float
    ours: float
    standard_error: float
    realizations: int
    note: str
    verdict: str | None = None  # None: judged on the numbers alone (`judge` with nothing declared)
    evidence: str = ""
    claim: str | None = None  # ">" or "<": a trend the thesis asserts against ``thesis``

    @property
    def deviation(self) -> float:
        if not (self.thesis and math.isfinite(self.ours)):
            return math.nan
        return (self.ours - self.thesis) / self.thesis


def _compute(number, tables: Mapping[str, pd.DataFrame]) -> tuple[float, str]:
    try:
        value = float(number.compute(tables))
    except Exception as exc:  # noqa: BLE001 - reported in the row, not raised
        return math.nan, f"{type(exc).__name__}: {exc}"
    return value, "" if math.isfinite(value) else "not computable from these cases"


def _swept_keys(provenance: Mapping[str, Any]) -> dict[str, list[str]]:
    """Part -> the swept keys of its shipped sweep file(s): what tells one parameter point from another."""
    import tomllib

    from .studies.base import SWEEPS_DIR

    keys: dict[str, list[str]] = {}
    for part, info in provenance.get("parts", {}).items():
        found: set[str] = set()
        for name in info.get("sweep_files", [info.get("sweep_file", "")]):
            path = SWEEPS_DIR / str(name)
            if name and path.is_file():
                found |= set(tomllib.loads(path.read_text(encoding="utf-8")).get("sweep", {}))
        keys[part] = sorted(found)
    return keys


def _realizations(tables: Mapping[str, pd.DataFrame]) -> list[int]:
    """Every realisation the tables hold (a part without the column has none)."""
    return sorted({int(r) for frame in tables.values() if "realization" in frame.columns
                           for r in frame["realization"].tolist()})


def _of_realizations(tables: Mapping[str, pd.DataFrame], keep: Collection[int]) -> dict[str, pd.DataFrame]:
    """The tables' rows of the realisations ``keep`` (a part without the column whole)."""
    return {part: frame[frame["realization"].isin(list(keep))] if "realization" in frame.columns else frame
            for part, frame in tables.items()}


@dataclass(frozen=True)
class _Points:
    """Each table row's parameter point, and the points each realisation has finished."""

    point: dict[str, pd.Series]
    have: dict[int, dict[str, set]]


def _points(tables: Mapping[str, pd.DataFrame], keys: Mapping[str, list[str]]) -> _Points:
    realizations = _realizations(tables)
    point, have = {}, {r: {} for r in realizations}
    for part, frame in tables.items():
        columns = [key for key in keys.get(part, []) if key in frame.columns]
        values = zip(*(frame[c].map(_plain) for c in columns)) if columns else ((None,) for _ in range(len(frame)))
        point[part] = pd.Series(list(values), index=frame.index, dtype=object)
        finished_rows = frame["status"] == "finished" if "status" in frame.columns else pd.Series(True, frame.index)
        for r in realizations:
            rows = finished_rows & (frame["realization"] == r) if "realization" in frame.columns else finished_rows
            have[r][part] = set(point[part][rows])
    return _Points(point, have)


def _counted_realizations(number, tables: Mapping[str, pd.DataFrame], points: _Points | None = None) -> list[int]:
    """The realisations that have finished every point the number reads.

    A run in progress goes seed by seed, so its last seed has some points
    only; read alone, a number would there come from other points (c read at
    a plateau preload, say) and its spread would not be a standard error.
    The reference is the realisation with the most finished points: a
    realisation lacking some of them counts when the reference, without those
    points, gives the same number (the number does not read them).  Without
    ``points`` (the tables' swept keys unknown) every realisation counts.
    """
    realizations = _realizations(tables)
    if len(realizations) < 2 or points is None:
        return realizations
    have = points.have
    reference = max(realizations, key=lambda r: (sum(len(v) for v in have[r].values()), -r))
    subset = _of_realizations(tables, [reference])
    full, _ = _compute(number, subset)
    counted = []
    for r in realizations:
        lacking = {part: have[reference][part] - have[r][part] for part in tables}
        if any(lacking.values()):
            # (not Series.isin: it reads a set of tuples as a 2-D array)
            without = {part: frame[~points.point[part].loc[frame.index].map(lacking[part].__contains__).astype(bool)]
                       if lacking[part] else frame for part, frame in subset.items()}
            value, _ = _compute(number, without)
            if not _same(value, full):
                continue
        counted.append(r)
    return counted


def _standard_error(number, tables: Mapping[str, pd.DataFrame],
                    counted: list[int] | None = None) -> tuple[float, int]:
    """Standard error of the number over the ``counted`` realisations of its tables (nan below two)."""
    realizations = counted if counted is not None else _realizations(tables)
    if len(realizations) < 2:
        return math.nan, len(realizations)
    values = []
    for r in realizations:
        value, _ = _compute(number, _of_realizations(tables, [r]))
        if math.isfinite(value):
            values.append(value)
    if len(values) < 2:
        return math.nan, len(realizations)
    return statistics.stdev(values) / math.sqrt(len(values)), len(realizations)


def compare(tables_root: str | Path) -> tuple[list[ComparisonRow], dict[str, dict[str, Any]]]:
    """Every thesis number of every study with tables under ``tables_root`` (studies in name order)."""
    from .studies import get_study

    rows: list[ComparisonRow] = []
    provenances: dict[str, dict[str, Any]] = {}
    for folder in sorted(p for p in Path(tables_root).iterdir() if (p / PROVENANCE_FILE).is_file()):
        provenance, tables = load_tables(folder)
        study = get_study(provenance["study"])
        provenances[study.name] = provenance
        keys = _swept_keys(provenance)
        points = _points(tables, keys) if any(keys.values()) else None
        for number in study.numbers:
            ours, note = _compute(number, tables)
            error, realizations = math.nan, 0
            if math.isfinite(ours):
                counted = _counted_realizations(number, tables, points)
                if set(_realizations(tables)) - set(counted):  # the number of the seeds with all its points
                    ours, note = _compute(number, _of_realizations(tables, counted))
                error, realizations = _standard_error(number, tables, counted)
            verdict = judge(float(number.thesis), ours, error, number.verdict, number.claim)
            rows.append(ComparisonRow(study.name, number.quantity, number.where, float(number.thesis), ours,
                                      error, realizations, note, verdict,
                                      number.evidence if number.verdict in (None, verdict) else "", number.claim))
    return rows, provenances


def _number(value: float) -> str:
    return f"{value:.4g}" if math.isfinite(value) else "n/a"


def _cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def notes_sections(notes: str) -> list[tuple[str, str]]:
    """The ``## `` sections of the notes: (heading, body) in order."""
    sections: list[tuple[str, str]] = []
    for block in re.split(r"^## ", notes, flags=re.MULTILINE)[1:]:
        heading, _, body = block.partition("\n")
        sections.append((heading.strip(), body.strip()))
    return sections


def note_anchor(heading: str) -> str:
    """The HTML id written before a notes heading (the same on GitHub and on the docs site)."""
    return "notes-" + re.sub(r"[^a-z0-9]+", "-", heading.lower()).strip("-")


def explaining_sections(study: str, notes: str) -> list[tuple[str, str]]:
    """The notes sections that explain ``study``'s deviations: those whose heading names it in
    backticks, or with a line ``Explains: `study`, ...``."""
    tag = f"`{study}`"
    found = []
    for heading, body in notes_sections(notes):
        explains = any(line.startswith("Explains:") and tag in line for line in body.splitlines())
        if tag in heading or explains:
            found.append((heading, body))
    return found


def _anchored(notes: str) -> str:
    """The notes with an ``<a id>`` before every ``## `` heading, the targets of the rows' links."""
    return re.sub(r"^## (.+)$", lambda m: f'<a id="{note_anchor(m.group(1))}"></a>\n\n## {m.group(1)}', notes,
                  flags=re.MULTILINE)


def render(rows: list[ComparisonRow], provenances: Mapping[str, Mapping[str, Any]], notes: str = "",
           figures: Mapping[str, list[str]] | None = None) -> str:
    """The comparison document (Markdown) of `compare`'s rows, then ``notes``.

    ``figures``: study -> figure paths (relative to the document) linked in its section.
    """
    figures = figures or {}
    lines = [
        "# Thesis comparison: the thesis's numbers beside ours",
        "",
        "Generated by `brushbem compare-thesis docs/reproduction` from the tables in",
        "`docs/reproduction/` (do not edit by hand: edit `docs/reproduction/notes.md`, or",
        "recompute a study and export its tables).  Each study's section names its",
        "grids and the command that recomputes it; \"quick\" studies ran the coarse",
        "`*.quick.toml` sweeps, which test the machinery, not the thesis's numbers;",
        "\"sampled\" studies ran the `*.sampled.toml` subsets of the full sweeps that carry",
        "the stated numbers (`docs/reproduction/plan.md`).  The thesis states a grid for",
        "chapter 4 only (512 x 512, L736); every other grid, pillar count and step is ours",
        "(the thesis states none), and the notes show how much the choice matters.",
        f"Deviations above {100 * EXPLAIN_ABOVE:.0f} % are explained in the notes below (where the thesis states",
        f"0, an absolute {EXPLAIN_ABOVE:g} of the normalising force).",
        "",
        "Every row has a verdict: *reproduced* (within "
        f"{100 * REPRODUCED_WITHIN:.0f} % or {STANDARD_ERRORS:g} standard errors;",
        "a thesis 0 only within the standard errors), *reproduced with a stated choice* (of a",
        "parameter the thesis leaves open, named in the row), *contradicted* (the row names the",
        "closed form, limit or run that shows the thesis's number cannot hold for the model it",
        "states), or *open* (the row names what was tried).",
        "",
        "| chapter | " + " | ".join(VERDICTS) + " | rows |",
        "| --- | " + " | ".join("---" for _ in VERDICTS) + " | --- |",
    ]
    verdicts = {id(row): row.verdict or judge(row.thesis, row.ours, row.standard_error, None, row.claim)
                for row in rows}
    for chapter, counts in count_by_chapter((row.study, verdicts[id(row)]) for row in rows).items():
        lines.append(f"| {chapter or 'other'} | " + " | ".join(str(counts[v]) for v in VERDICTS)
                     + f" | {sum(counts.values())} |")
    lines.append("")
    by_study: dict[str, list[ComparisonRow]] = {}
    for row in rows:
        by_study.setdefault(row.study, []).append(row)
    for name in sorted(by_study):
        provenance = provenances[name]
        quick = bool(provenance.get("quick"))
        sampled = any(str(info.get("sweep_file", "")).endswith(".sampled.toml")
                      for info in provenance["parts"].values())
        grid = THESIS_GRIDS.get(name, "grid ours: the thesis states none")
        label = "quick" if quick else f"{grid}, sampled" if sampled else grid
        cases = sum(int(info.get("cases", 0)) for info in provenance["parts"].values())
        done = sum(int(info.get("statuses", {}).get("finished", 0)) for info in provenance["parts"].values())
        missing = sum(int(info.get("statuses", {}).get("missing", 0)) for info in provenance["parts"].values())
        if missing:
            label += f"; in progress, {done} of {cases} cases"
        lines += [f"## `{name}` ({label})", ""]
        flags = " --quick" if quick else " --sampled" if sampled else ""
        command = f"`brushbem study {name} --out out/{name}{flags}`"
        folders = f"out/{name}"
        named_sets = sorted({file.split(".")[2] for info in provenance["parts"].values()
                             for file in info.get("sweep_files", [])[1:] if file.count(".") == 4})
        for subset in named_sets:
            command += f" and `brushbem study {name} --sampled-set {subset} --out out/{name}-{subset}`"
            folders += f" out/{name}-{subset}"
        lines += [
            f"Recompute: {command}, then `brushbem export-tables {folders} --to docs/reproduction`.",
            f"One row: `brushbem reproduce {name} \"QUANTITY\" --out out/row` runs only the cases that row reads",
            "and those closest to changing it (`--dry-run` lists them with their recorded time;",
            "`--realizations 1` checks the row as its first seed gives it, for a row that reads ten).",
            f"brushbem {provenance.get('brushbem_version')}, commit {provenance.get('commit') or 'unknown'}.",
            "",
        ]
        if missing:
            lines += [
                f"The run is in progress: {missing} cases are missing (not yet computed, not failed).  On any",
                "machine, the commands above with `--skip-recorded docs/reproduction` compute only those, and",
                "`export-tables ... --update` merges them into these tables.  A sweep runs seed by seed, so the",
                "rows below are of the realisations that have finished; a number whose points are not yet",
                "computed is n/a.",
                "",
            ]
        lines += [
            "| part | sweep file | grid | cases | realisations | seeds | wall time |",
            "| --- | --- | --- | --- | --- | --- | --- |",
        ]
        for part, info in provenance["parts"].items():
            statuses = ", ".join(f"{n} {s}" for s, n in info.get("statuses", {}).items())
            seeds = info.get("seeds", [])
            seed_text = ", ".join(str(s) for s in seeds[:4]) + (" ..." if len(seeds) > 4 else "")
            realizations = str(info.get("realizations", 1))
            if info.get("finished_realizations", info.get("realizations", 1)) != info.get("realizations", 1):
                realizations = f"{info['finished_realizations']} of {realizations} begun"
            lines.append(
                f"| {part} | {', '.join(info.get('sweep_files', [info.get('sweep_file', '')]))} | "
                f"{_cell(info.get('grid', ''))} | "
                f"{info.get('cases', 0)} ({statuses}) | {realizations} | {seed_text} | "
                f"{info.get('wall_time_s', 0.0):.0f} s |"
            )
        lines += [
            "",
            "| quantity | where | thesis | ours | standard error | deviation | verdict | explained in |",
            "| --- | --- | --- | --- | --- | --- | --- | --- |",
        ]
        explained = "; ".join(f"[{_cell(heading)}](#{note_anchor(heading)})"
                              for heading, _ in explaining_sections(name, notes))
        for row in by_study[name]:
            ours = _number(row.ours) if math.isfinite(row.ours) else f"n/a ({_cell(row.note)})"
            error = _number(row.standard_error) if math.isfinite(row.standard_error) else "—"
            _, far, deviation = deviation_of(row.thesis, row.ours)
            if row.claim:  # a trend: judged by its side of the threshold, not by its distance
                far, deviation = verdicts[id(row)] != REPRODUCED, f"trend ({row.claim} {_number(row.thesis)})"
            # a number the cases cannot give (n/a) is explained like a far one, where the notes explain the study
            unexplained = "**no explanation in the notes**" if far else ""
            where = (explained or unexplained) if far or not math.isfinite(row.ours) else ""
            verdict = f"**{verdicts[id(row)]}**" + (f": {_cell(row.evidence)}" if row.evidence else "")
            lines.append(f"| {_cell(row.quantity)} | {_cell(row.where)} | {_number(row.thesis)} | {ours} | "
                         f"{error} | {deviation} | {verdict} | {where} |")
        lines.append("")
        if figures.get(name):
            lines += ["Figures drawn from these tables (`brushbem compare-thesis ... --figures DIR`):", ""]
            lines += [f"![{Path(path).stem}]({path})" for path in figures[name]]
            lines.append("")
    if notes.strip():
        lines += [_anchored(notes.strip()), ""]
    return "\n".join(lines)


def comparison_document(tables_root: str | Path, figures: Mapping[str, list[str]] | None = None) -> str:
    """`render` of `compare` of ``tables_root`` with its notes: the whole document.

    ``figures`` (study -> paths relative to the document) are linked under
    their study's section.
    """
    root = Path(tables_root)
    rows, provenances = compare(root)
    notes_path = root / NOTES_FILE
    notes = notes_path.read_text(encoding="utf-8") if notes_path.is_file() else ""
    return render(rows, provenances, notes, figures or {})


def draw_table_figures(tables_root: str | Path, figures_root: str | Path) -> dict[str, list[Path]]:
    """Draw, for every thesis-grid study in ``tables_root`` with ``draw_tables``, its figures from the tables.

    The figures go to ``figures_root/<study>/``; they carry the thesis's
    axes, normalisations and closed-form lines, and are drawn from the
    same tables as the comparison rows.

    Returns
    -------
    dict
        Study name -> the figures written.
    """
    from .studies import STUDIES

    drawn: dict[str, list[Path]] = {}
    for folder in sorted(Path(tables_root).iterdir()):
        study = STUDIES.get(folder.name)
        if study is None or study.draw_tables is None or not (folder / PROVENANCE_FILE).is_file():
            continue
        provenance, tables = load_tables(folder)
        if provenance.get("quick"):
            continue  # quick grids test the machinery: no figure beside the thesis's
        drawn[study.name] = study.draw_tables(tables, Path(figures_root) / study.name)
    return drawn


class ReproduceError(ValueError):
    """A row that cannot be recomputed: unknown study or quantity, or no finished case it reads."""


@dataclass(frozen=True)
class RowPlan:
    """What recomputing one row runs: per part, the parameter points the row reads.

    Attributes
    ----------
    study, quantity : str
    committed : float
        The row's value from the committed tables' first ``realizations`` seeds: what the run must give.
    points : dict
        Part -> list of swept-value mappings (one per parameter point the row reads).
    sweep_files : dict
        Part -> the shipped sweep file those points come from.
    realizations : int
        How many realisations (the first ones, with the sweep's own seeds) are run.
    cases : int
        The cases that makes.
    recorded_seconds : float
        Their wall time as recorded in the tables (an estimate of the run's).
    case_hashes : dict
        Part -> the committed cases' hashes (their ids after the index) that the run must give again.
    every_seed : float
        The row's value from every seed of the tables (the one the comparison prints).
    rivals : dict
        Part -> those of ``points`` that the number does not read but would
        if their results changed by a little (the runners-up of a maximum).
    """

    study: str
    quantity: str
    committed: float
    points: dict[str, list[dict[str, Any]]]
    sweep_files: dict[str, Path]
    realizations: int
    cases: int
    recorded_seconds: float
    case_hashes: dict[str, list[str]] = dataclasses.field(default_factory=dict)
    every_seed: float = math.nan
    rivals: dict[str, list[dict[str, Any]]] = dataclasses.field(default_factory=dict)


def _same(a: float, b: float) -> bool:
    if math.isnan(a) or math.isnan(b):
        return math.isnan(a) and math.isnan(b)
    return math.isclose(a, b, rel_tol=1e-12, abs_tol=1e-300)


def _plain(value: Any) -> Any:
    """A table cell as the sweep file writes it (numpy scalars as Python numbers)."""
    return value.item() if hasattr(value, "item") else value


RIVALS = 2
"""Points a row's plan adds beyond those its number reads: the ones closest to changing it."""

RIVAL_STEPS = (0.0025, 0.005, 0.01, 0.02)
"""Relative changes of a point's results tried, smallest first, to rank the points that could change a number.

The largest, 2 %, is above the spread of neighbouring points around the
thesis's maxima (chapter 7's refined ĥ points differ by under 1 %), and
below the 5 % at which a deviation needs explaining.
"""

_NOT_RESULTS = {"index", "realization", "seed", "wall_time_s"}


def _rivals(number, tables: Mapping[str, pd.DataFrame], point_of: Mapping[str, Mapping[str, tuple]],
            candidates: set, committed: float, limit: int) -> set:
    """The (at most ``limit``) points left out of a plan whose results, changed least, change the number.

    Each candidate's float results (every float column but its swept values
    and bookkeeping) are scaled by ``1 ± step`` for the steps of
    :data:`RIVAL_STEPS`, smallest first, in the full tables; the step at which
    the number first moves ranks it.  A point that no step moves is no rival.
    For a number that reads every point (a mean, a fit) there are none left to
    add; for the position of a maximum they are the points whose value is
    within a step of the maximum's.
    """
    if limit <= 0 or not candidates:
        return set()

    ranked = []
    for candidate in sorted(candidates, key=repr):
        part, point = candidate
        frame = tables[part]
        rows = frame["case_id"].map(lambda i, part=part, point=point: point_of[part].get(i) == point).to_numpy()
        keys = {key for key, _ in point}
        columns = [c for c in frame.columns if c not in keys and c not in _NOT_RESULTS
                   and pd.api.types.is_float_dtype(frame[c])]

        def moves(step: float, frame=frame, rows=rows, columns=columns, part=part) -> bool:
            for factor in (1 + step, 1 - step):
                changed = frame.copy()
                changed.loc[rows, columns] = frame.loc[rows, columns] * factor
                if not _same(_compute(number, {**tables, part: changed})[0], committed):
                    return True
            return False

        if moves(RIVAL_STEPS[-1]):  # then the smallest step that moves it ranks it
            ranked.append((next(s for s in RIVAL_STEPS if s == RIVAL_STEPS[-1] or moves(s)), repr(candidate),
                           candidate))
    return {candidate for _, _, candidate in sorted(ranked)[:limit]}


def _find_number(study, quantity: str):
    exact = [n for n in study.numbers if n.quantity == quantity]
    found = exact or [n for n in study.numbers if quantity.lower() in n.quantity.lower()]
    if len(found) != 1:
        known = "; ".join(repr(n.quantity) for n in study.numbers)
        what = "no" if not found else f"{len(found)}"
        raise ReproduceError(f"study {study.name!r}: {what} quantities match {quantity!r}; its quantities: {known}")
    return found[0]


def _file_with(points: list[dict[str, Any]], files: list[Path]) -> Path:
    """The first of a part's sweep files that lists every one of ``points`` (else the first file).

    A part merged from several sampled sets (same base and seed) can run a
    row's points from any of them; the one that holds them names it truthfully.
    """
    import itertools
    import tomllib

    for path in files:
        spec = tomllib.loads(path.read_text(encoding="utf-8"))
        keys, values = list(spec.get("sweep", {})), list(spec.get("sweep", {}).values())
        combine = itertools.product if spec.get("mode", "zip") == "product" else zip
        listed = {tuple(_plain(v) for v in row) for row in combine(*values)}
        if all(tuple(_plain(point.get(key)) for key in keys) in listed for point in points):
            return path
    return files[0]


def plan_row(tables_root: str | Path, study_name: str, quantity: str, realizations: int | None = None,
             rivals: int = RIVALS) -> RowPlan:
    """The cases that recompute one row of the comparison: the parameter points its number reads.

    Starting from every finished point of the committed tables, each point
    whose cases can be left out without changing the number is left out; the
    points that remain give the committed number by themselves.  The number
    is a function of the tables, so this finds what it reads without the
    study declaring it.  To these come up to ``rivals`` points the number
    would read if their results were a little different (see
    :func:`_rivals`): for a maximum or its position, the runners-up, so the
    recomputed number is a check of the ranking and not only of one case.
    The cases
    are the shipped sweep file's (same configurations, seeds and case hashes),
    for the first ``realizations`` seeds (default: as many as the tables have
    finished); with fewer, the plan and its committed number are those of the
    tables' first seeds, so a run of a few seeds is checked too.

    Raises
    ------
    ReproduceError
        Unknown study or quantity, or a number that no finished case determines.
    """
    import tomllib

    from .studies import StudyError, get_study
    from .studies.base import SWEEPS_DIR

    try:
        study = get_study(study_name)
    except StudyError as exc:  # the message lists the known studies
        raise ReproduceError(str(exc)) from None
    folder = Path(tables_root) / study.name
    if not (folder / PROVENANCE_FILE).is_file():
        raise ReproduceError(f"no tables of study {study.name!r} in {tables_root} (no {PROVENANCE_FILE})")
    number = _find_number(study, quantity)
    provenance, tables = load_tables(folder)
    every_seed, _ = _compute(number, tables)
    if realizations is not None:  # the row as the first seeds give it: planned, run and checked on those
        tables = {part: frame[frame["realization"] < realizations] if "realization" in frame.columns else frame
                  for part, frame in tables.items()}
    committed, _ = _compute(number, tables)
    if not math.isfinite(committed):
        seeds = "" if realizations is None else f" of the first {realizations} seed(s)"
        raise ReproduceError(f"{number.quantity!r} is n/a in the committed tables{seeds}: no finished case "
                             "determines it")
    # Every finished case's parameter point, by the shipped sweep's case hashes.
    point_of: dict[str, dict[str, tuple]] = {}
    paths: dict[str, Path] = {}
    finished_realizations = 1
    for part, frame in tables.items():
        if not {"status", "case_id"} <= set(frame.columns):
            continue
        done = frame[frame["status"] == "finished"]
        if not len(done):
            continue
        paths[part] = SWEEPS_DIR / provenance["parts"][part]["sweep_file"]
        keys = sorted(tomllib.loads(paths[part].read_text(encoding="utf-8")).get("sweep", {}))
        missing = [key for key in keys if key not in done.columns]
        if missing:
            raise ReproduceError(f"the table of part {part!r} lacks the swept column(s) {', '.join(missing)}")
        point_of[part] = {case_id: tuple((key, _plain(value)) for key, value in zip(keys, values))
                          for case_id, *values in done[["case_id", *keys]].itertuples(index=False)}
        if "realization" in done.columns:
            finished_realizations = max(finished_realizations, int(done["realization"].nunique()))

    def restricted(keep: set[tuple[str, tuple]]) -> dict[str, pd.DataFrame]:
        return {part: frame[frame["case_id"].map(lambda i, part=part: (part, point_of.get(part, {}).get(i)) in keep)]
                if part in point_of else frame for part, frame in tables.items()}

    # Leave out, one by one, every point whose cases the number does not need: what is left
    # gives the committed value by itself (of equal plateau preloads, one is kept).
    everything = {(part, point) for part, ids in point_of.items() for point in set(ids.values())}
    keep = set(everything)
    for candidate in sorted(keep, key=repr):
        value, _ = _compute(number, restricted(keep - {candidate}))
        if _same(value, committed):
            keep.discard(candidate)
    runners_up = _rivals(number, tables, point_of, everything - keep, committed, rivals)
    keep |= runners_up
    points: dict[str, list[dict[str, Any]]] = {}
    for part, point in sorted(keep, key=repr):
        points.setdefault(part, []).append(dict(point))
    sweep_files = {part: _file_with(part_points, [SWEEPS_DIR / name for name in provenance["parts"][part].get(
        "sweep_files", [])] or [paths[part]]) for part, part_points in points.items()}
    selected = restricted(keep)
    selected_rows = {part: frame[frame["status"] == "finished"] for part, frame in selected.items() if part in points}
    if not points:
        raise ReproduceError(f"{number.quantity!r} depends on no single case of the tables (a closed form): "
                             "there is nothing to recompute")
    realizations = realizations or finished_realizations
    chosen_by_part = {}
    for part, frame in selected_rows.items():
        if "realization" in frame.columns:
            frame = frame[frame["realization"] < realizations]
        chosen_by_part[part] = frame
    chosen = pd.concat(list(chosen_by_part.values()))
    case_hashes = {part: sorted(case_hash(i) for i in frame["case_id"])
                   for part, frame in chosen_by_part.items()}
    seconds = float(pd.to_numeric(chosen.get("wall_time_s", pd.Series(dtype=float)), errors="coerce").sum())
    cases = 0
    for part, part_points in points.items():
        spec_realizations = int(tomllib.loads(sweep_files[part].read_text(encoding="utf-8")).get("realizations", 1))
        cases += len(part_points) * min(realizations, spec_realizations)
    rival_points = {part: [dict(point) for p, point in sorted(runners_up, key=repr) if p == part]
                    for part in points}
    return RowPlan(study.name, number.quantity, committed, points, sweep_files, realizations, cases, seconds,
                   case_hashes, every_seed, rival_points)


def reproduce_row(plan: RowPlan, out_dir: str | Path, executor: Any = None, *, workers: int | None = None,
                  progress: bool = False) -> float:
    """Run the cases of ``plan`` into ``out_dir/<part>`` (resuming) and return the number from them.

    Each part runs as a sweep of the plan's points with the shipped file's
    base, seed and mode of seeding, so its cases are the committed ones
    (``SeedSequence.spawn`` gives the first seeds alike for any count).
    """
    import tomllib

    from .studies import get_study
    from .sweep import load_summary, run_sweep

    study = get_study(plan.study)
    number = _find_number(study, plan.quantity)
    tables: dict[str, pd.DataFrame] = {}
    for part, path in plan.sweep_files.items():
        spec = tomllib.loads(path.read_text(encoding="utf-8"))
        keys = list(plan.points[part][0])
        subset = {
            "base": spec["base"],
            "mode": "zip",
            "realizations": min(plan.realizations, int(spec.get("realizations", 1))),
            "seed": spec.get("seed", 0),
            "sweep": {key: [point[key] for point in plan.points[part]] for key in keys},
        }
        if "refine" in spec:
            subset["refine"] = spec["refine"]
        run_sweep(subset, Path(out_dir) / part, executor, workers=workers, progress=progress,
                  base_dir=path.parent)
        tables[part] = load_summary(Path(out_dir) / part)
        if plan.case_hashes.get(part) and not set(plan.case_hashes[part]) <= {
                case_hash(case_id) for case_id in tables[part]["case_id"]}:
            raise ReproduceError(f"part {part!r}: the recomputed cases are not the committed ones (their "
                                 "configurations or seeds differ: the sweep file changed since the tables)")
    for part in study.parts:
        tables.setdefault(part, pd.DataFrame(columns=["case_id", "status"]))
    value, note = _compute(number, tables)
    if not math.isfinite(value):
        raise ReproduceError(f"{plan.quantity!r}: the recomputed cases give n/a ({note})")
    return value
