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

import json
import math
import re
import statistics
import subprocess
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pandas as pd

from . import __version__

__all__ = ["ComparisonRow", "compare", "export_tables", "load_tables", "render"]

PROVENANCE_FILE = "provenance.json"
NOTES_FILE = "notes.md"
#: Deviations above this need the explanation of a measurement (the notes).
EXPLAIN_ABOVE = 0.05


def _commit() -> str | None:
    """The git commit of the working tree this package runs from, if it is a checkout."""
    try:
        result = subprocess.run(["git", "rev-parse", "HEAD"], cwd=Path(__file__).resolve().parent,
                                capture_output=True, text=True, timeout=10, check=False)
    except (OSError, subprocess.SubprocessError):
        return None
    return result.stdout.strip() or None if result.returncode == 0 else None


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


def export_tables(study_dir: str | Path, tables_root: str | Path) -> Path:
    """Write the compact tables of the study run folder ``study_dir`` under ``tables_root/<study>``.

    Returns the folder written.  Existing tables of the study are replaced.
    """
    from .studies import load_results
    from .studies._framework import read_study_record
    from .sweep import SWEEP_FILE

    study_dir = Path(study_dir)
    record = read_study_record(study_dir)
    name = record["study"]
    results = load_results(study_dir, tuple(record["parts"]))
    folder = Path(tables_root) / name
    folder.mkdir(parents=True, exist_ok=True)
    parts: dict[str, Any] = {}
    for part, frame in results.items():
        table = frame.drop(columns=[c for c in ("case_file",) if c in frame.columns])
        if "index" in table.columns:
            table = table.sort_values("index", kind="stable")
        table.to_csv(folder / f"{part}.csv", index=False)
        sweep_record = {}
        if (study_dir / part / SWEEP_FILE).is_file():
            sweep_record = json.loads((study_dir / part / SWEEP_FILE).read_text(encoding="utf-8"))
        statuses = table["status"].value_counts().to_dict() if "status" in table.columns else {}
        wall = pd.to_numeric(table.get("wall_time_s", pd.Series(dtype=float)), errors="coerce")
        parts[part] = {
            "sweep_file": Path(record.get("sweep_files", {}).get(part, "")).name,
            "cases": len(table),
            "statuses": {str(k): int(v) for k, v in sorted(statuses.items())},
            "seeds": sorted({int(s) for s in table["seed"].tolist()}) if "seed" in table.columns else [],
            "realizations": int(table["realization"].nunique()) if "realization" in table.columns else 1,
            "grid": _grid(sweep_record, table),
            "wall_time_s": float(wall.sum()) if len(wall) else 0.0,
        }
    provenance = {
        "study": name,
        "quick": bool(record.get("quick", False)),
        "brushbem_version": record.get("brushbem_version", __version__),
        "commit": _commit(),
        "parts": parts,
    }
    (folder / PROVENANCE_FILE).write_text(json.dumps(provenance, indent=2, sort_keys=True) + "\n", encoding="utf-8")
    return folder


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


def _standard_error(number, tables: Mapping[str, pd.DataFrame]) -> tuple[float, int]:
    """Standard error of the number over the realisations of its tables (nan below two)."""
    realizations = sorted({int(r) for frame in tables.values() if "realization" in frame.columns
                           for r in frame["realization"].tolist()})
    if len(realizations) < 2:
        return math.nan, len(realizations)
    values = []
    for r in realizations:
        subset = {part: frame[frame["realization"] == r] if "realization" in frame.columns else frame
                  for part, frame in tables.items()}
        value, _ = _compute(number, subset)
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
        for number in study.numbers:
            ours, note = _compute(number, tables)
            error, realizations = _standard_error(number, tables) if math.isfinite(ours) else (math.nan, 0)
            rows.append(ComparisonRow(study.name, number.quantity, number.where, float(number.thesis), ours,
                                      error, realizations, note))
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
        "\"sampled\" studies ran, at the thesis's grid, the `*.sampled.toml` subsets of the",
        "full sweeps that carry the stated numbers (`docs/reproduction/plan.md`).",
        f"Deviations above {100 * EXPLAIN_ABOVE:.0f} % are explained in the notes below.",
        "",
    ]
    by_study: dict[str, list[ComparisonRow]] = {}
    for row in rows:
        by_study.setdefault(row.study, []).append(row)
    for name in sorted(by_study):
        provenance = provenances[name]
        quick = bool(provenance.get("quick"))
        sampled = any(str(info.get("sweep_file", "")).endswith(".sampled.toml")
                      for info in provenance["parts"].values())
        label = "quick" if quick else "thesis grid, sampled" if sampled else "thesis grid"
        lines += [f"## `{name}` ({label})", ""]
        flags = " --quick" if quick else " --sampled" if sampled else ""
        command = f"brushbem study {name} --out out/{name}{flags}"
        lines += [
            f"Recompute: `{command}`, then `brushbem export-tables out/{name} --to docs/reproduction`.",
            f"brushbem {provenance.get('brushbem_version')}, commit {provenance.get('commit') or 'unknown'}.",
            "",
            "| part | sweep file | grid | cases | realisations | seeds | wall time |",
            "| --- | --- | --- | --- | --- | --- | --- |",
        ]
        for part, info in provenance["parts"].items():
            statuses = ", ".join(f"{n} {s}" for s, n in info.get("statuses", {}).items())
            seeds = info.get("seeds", [])
            seed_text = ", ".join(str(s) for s in seeds[:4]) + (" ..." if len(seeds) > 4 else "")
            lines.append(
                f"| {part} | {info.get('sweep_file', '')} | {_cell(info.get('grid', ''))} | "
                f"{info.get('cases', 0)} ({statuses}) | {info.get('realizations', 1)} | {seed_text} | "
                f"{info.get('wall_time_s', 0.0):.0f} s |"
            )
        lines += [
            "",
            "| quantity | where | thesis | ours | standard error | deviation | explained in |",
            "| --- | --- | --- | --- | --- | --- | --- |",
        ]
        explained = "; ".join(f"[{_cell(heading)}](#{note_anchor(heading)})"
                              for heading, _ in explaining_sections(name, notes))
        for row in by_study[name]:
            ours = _number(row.ours) if math.isfinite(row.ours) else f"n/a ({_cell(row.note)})"
            error = _number(row.standard_error) if math.isfinite(row.standard_error) else "—"
            deviation = f"{100 * row.deviation:+.1f} %" if math.isfinite(row.deviation) else "—"
            far = math.isfinite(row.deviation) and abs(row.deviation) > EXPLAIN_ABOVE
            where = (explained or "**no explanation in the notes**") if far else ""
            lines.append(f"| {_cell(row.quantity)} | {_cell(row.where)} | {_number(row.thesis)} | {ours} | "
                         f"{error} | {deviation} | {where} |")
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
