"""The comparison document: `render` of `compare`'s rows, the notes that explain deviations, deviations.

`render` writes the comparison as Markdown (``docs/thesis-comparison.md``),
followed by the hand-written notes of ``TABLES/notes.md``; `comparison_document`
is the whole document of a tables folder.  The document is a function of the
tables: the same tables give the same bytes, which a test checks for the
committed ones.

    brushbem export-tables DIR --to docs/reproduction
    brushbem compare-thesis docs/reproduction --out docs/thesis-comparison.md [--check]
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

import pandas as pd

from brushbem.studies.verdicts import (
    PRECISE_WITHIN,
    REPRODUCED,
    REPRODUCED_WITHIN,
    STANDARD_ERRORS,
    VANISHES_BELOW,
    VERDICTS,
    count_by_chapter,
    judge,
)
from brushbem.reproduction.comparison import ComparisonRow, compare
from brushbem.reproduction.tables import NOTES_FILE, PROVENANCE_FILE, load_tables

__all__ = ["comparison_document", "deviation_of", "explaining_sections", "identifications", "note_anchor", "notes_sections",
           "render"]

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


def _row_line(row: ComparisonRow, verdict: str, explained: str) -> str:
    """One row of a study's table (Markdown)."""
    ours = _number(row.ours) if math.isfinite(row.ours) else f"n/a ({_cell(row.note)})"
    error = _number(row.standard_error) if math.isfinite(row.standard_error) else "—"
    _, far, deviation = deviation_of(row.thesis, row.ours)
    if row.claim:  # a trend: judged by its side of the threshold, not by its distance
        far, deviation = verdict != REPRODUCED, f"trend ({row.claim} {_number(row.thesis)})"
    # a number the cases cannot give (n/a) is explained like a far one, where the notes explain the study
    unexplained = "**no explanation in the notes**" if far else ""
    where = (explained or unexplained) if far or not math.isfinite(row.ours) else ""
    text = f"**{verdict}**" + (" (qualitative)" if row.qualitative else "")
    details = [part for part in (row.reason, row.evidence) if part]
    text += (": " + "; ".join(_cell(part) for part in details)) if details else ""
    return (f"| {_cell(row.quantity)} | {_cell(row.where)} | {_number(row.thesis)} | {ours} | "
            f"{error} | {deviation} | {text} | {where} |")


def render(rows: list[ComparisonRow], provenances: Mapping[str, Mapping[str, Any]], notes: str = "",
           figures: Mapping[str, list[str]] | None = None,
           identifications: Mapping[str, str] | None = None) -> str:
    """The comparison document (Markdown) of `compare`'s rows, then ``notes``.

    ``figures``: study -> figure paths (relative to the document) linked in its section.
    ``identifications``: study -> the Markdown of its chapter's identification (the candidates
    tried and their score, `brushbem.studies.base.Study.identification`), after its rows.
    """
    figures = figures or {}
    identifications = identifications or {}
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
        "Every row has a verdict, by one rule that no row's declaration bends (`brushbem.studies.verdicts`):",
        f"*reproduced* (within {100 * REPRODUCED_WITHIN:.0f} %, or a standard error within "
        f"{100 * PRECISE_WITHIN:.0f} % of the value and a gap within",
        f"{STANDARD_ERRORS:g} of them; a larger standard error within reach of the thesis's number makes the row *open*,",
        "imprecise), *reproduced with a stated choice* (meets the same rule with a parameter the thesis leaves",
        "open, fixed once per chapter by its identification and named in the row; a choice that does not meet",
        "the rule leaves the row *open*), *contradicted* (the row names the closed form, limit",
        "or run that shows the thesis's number cannot hold for the model it states), *open* (the row names what",
        "was tried), or *used to identify* (the row decided a parameter of its chapter's one identification, so",
        "it does not also test it).  A held-out row of a chapter whose identification ties candidates is",
        "checked at each of them (`brushbem.studies.verdicts.held_out`): it stays *reproduced* (with or without a",
        "stated choice) only if its verdict is the same at every tied candidate whose value exists, else it is",
        "*open*; the check applies to reproduced rows only (no identification ties candidates now).  "
        "Qualitative claims (a trend the text asserts, and a thesis 0 read as",
        f"|ours| < {VANISHES_BELOW:g}) are judged both ways alike: reproduced or contradicted when ours lies on",
        f"one side of the threshold by more than {STANDARD_ERRORS:g} standard errors, open in between, and open (a tie)",
        "within the resolution a row states, the model's measured error on the compared numbers.  Fitted quantities",
        "(alpha, beta, sigma~_c of eq. 5.8) take their standard error from a bootstrap over seeds of the same fit.",
        "Rows outside the counts (a sensitivity to a choice the identification did not make, or a duplicate of a",
        "counted row) follow each study's counted rows.",
        "",
        "| chapter | " + " | ".join(VERDICTS) + " | rows | of which qualitative | outside the counts |",
        "| --- | " + " | ".join("---" for _ in VERDICTS) + " | --- | --- | --- |",
    ]
    verdicts = {id(row): row.verdict or judge(row.thesis, row.ours, row.standard_error, None, row.claim)
                for row in rows}
    counted = [row for row in rows if not row.outside]
    qualitative = count_by_chapter((row.study, REPRODUCED) for row in counted if row.qualitative)
    outside = count_by_chapter((row.study, REPRODUCED) for row in rows if row.outside)
    chapters = count_by_chapter((row.study, verdicts[id(row)]) for row in counted)
    for chapter in sorted(set(chapters) | set(outside)):
        counts = chapters.get(chapter, dict.fromkeys(VERDICTS, 0))
        lines.append(f"| {chapter or 'other'} | " + " | ".join(str(counts[v]) for v in VERDICTS)
                     + f" | {sum(counts.values())} | {qualitative.get(chapter, {}).get(REPRODUCED, 0)}"
                     + f" | {outside.get(chapter, {}).get(REPRODUCED, 0)} |")
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
        if any(info.get("sweep_file") for info in provenance["parts"].values()):
            one_row = [
                f"One row: `brushbem reproduce {name} \"QUANTITY\" --out out/row` runs only the cases that row reads",
                "and those closest to changing it (`--dry-run` lists them with their recorded time;",
                "`--realizations 1` checks the row as its first seed gives it, for a row that reads ten).",
            ]
        else:  # a study without a sweep: its one run computes every row's table
            one_row = ["One row: the study has no sweep; its one run above computes the table every row reads."]
        lines += [
            f"Recompute: {command}, then `brushbem export-tables {folders} --to docs/reproduction`.",
            *one_row,
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
        explained = "; ".join(f"[{_cell(heading)}](#{note_anchor(heading)})"
                              for heading, _ in explaining_sections(name, notes))
        counted_rows = [row for row in by_study[name] if not row.outside]
        outside_rows = [row for row in by_study[name] if row.outside]
        for title, chosen, extra in (("", counted_rows, False),
                                     ("Outside the counts (sensitivities and duplicates):", outside_rows, True)):
            if not chosen:
                continue
            lines += ["", title, ""] if title else [""]
            lines += [
                ("| quantity outside the counts" if extra else "| quantity")
                + " | where | thesis | ours | standard error | deviation | verdict | explained in |"
                + (" outside the counts because |" if extra else ""),
                "| --- | --- | --- | --- | --- | --- | --- | --- |" + (" --- |" if extra else ""),
            ]
            for row in chosen:
                lines.append(_row_line(row, verdicts[id(row)], explained) + (f" {_cell(row.outside)} |" if extra else ""))
        lines.append("")
        if identifications.get(name):
            lines += [identifications[name].strip(), ""]
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
    return render(rows, provenances, notes, figures or {}, identifications(root, provenances))


def identifications(tables_root: str | Path, studies: Iterable[str]) -> dict[str, str]:
    """Study -> the Markdown of its chapter's identification (`Study.identification`) from its tables."""
    from brushbem.studies import get_study

    root, found = Path(tables_root), {}
    for name in studies:
        study = get_study(name)
        if study.identification is not None and (root / name / PROVENANCE_FILE).is_file():
            tables = load_tables(root / name)[1]
            tables.update({Path(probe).stem: pd.read_csv(root / probe) for probe in study.probes
                           if (root / probe).is_file()})
            found[name] = study.identification(tables)
    return found

