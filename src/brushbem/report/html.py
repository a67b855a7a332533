"""The HTML pieces of the sweep and study report (`brushbem.report.sweeps.write_report`).

The inline style sheet, escaping and cell text, the summary table of the cases
(rows classed by status), the list of cases that did not finish, the figures as
PNG data URIs, the thesis-numbers table with the reproduction notes' explanation
beside an amber (more than 5 % off) number, definition tables, the timings of
the cases, the swept keys of a folder and the list of what happened to it.
`brushbem.report.sweeps` assembles them into ``report.html`` and re-exports the names
that are imported from it.
"""

from __future__ import annotations

import base64
import html
import json
import math
import re
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    import pandas as pd

__all__: list[str] = []

_CSS = """
body{font-family:system-ui,sans-serif;margin:1.5em;color:#222;max-width:1400px}
h1{font-size:1.5em}h2{font-size:1.2em;margin-top:1.6em;border-bottom:1px solid #ccc}
table{border-collapse:collapse;font-size:.85em;margin:.5em 0}
th,td{border:1px solid #ccc;padding:.2em .5em;text-align:left;vertical-align:top}
th{background:#f0f0f0}
tr.case-failed td{background:#fdd}tr.case-unconverged td{background:#ffe9bf}
tr.case-missing td{background:#eee;color:#666}tr.case-corrupt td{background:#f4d0f4}
.incidents{border:1px solid #b60;background:#fffaf0;padding:.5em 1em}
.problems{border:2px solid #c00;background:#fff4f4;padding:.5em 1em}
.ok{color:#070}.na{color:#a00}.far{color:#b60}
figure{display:inline-block;margin:.5em}figure img{max-width:640px;border:1px solid #ddd}
figcaption{font-size:.8em;color:#555}code{font-size:.9em}
pre.note{white-space:pre-wrap;max-width:60em;font-size:.8em;background:#fafafa;padding:.5em}
.scroll{overflow-x:auto}table.summary td:first-child{white-space:nowrap}
"""

_TABLE_COLUMNS = ("case_id",)
_TAIL_COLUMNS = ("realization", "seed", "adhesive_force")
_END_COLUMNS = ("converged", "status", "reason", "wall_time_s")


def write_document(path: Path, title: str, sections: Sequence[str], css: str, meta: str = "") -> Path:
    """Write one self-contained HTML page (inline style sheet, ``meta`` tags in its head) atomically to ``path``."""
    from brushbem.io import atomic_path

    document = ("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">" + meta
                + f"<title>{_e(title)}</title><style>{css}</style></head><body>\n"
                + "\n".join(sections) + "\n</body></html>\n")
    with atomic_path(path) as temporary:
        temporary.write_text(document, encoding="utf-8")
    return path


def _slug(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", text).strip("_") or "value"


def _e(value: Any) -> str:
    return html.escape(str(value), quote=True)


def _cell(value: Any) -> str:
    if value is None:
        return ""
    if isinstance(value, (float, np.floating)):
        return "" if math.isnan(value) else f"{float(value):.6g}"
    if isinstance(value, (bool, np.bool_)):
        return "yes" if value else "no"
    return str(value)


def _table_columns(frame: pd.DataFrame, swept: Sequence[str]) -> list[str]:
    normalized = [c for c in frame.columns
                  if c.startswith(("normalized.", "theory.ratios."))]
    wanted = [*_TABLE_COLUMNS, *swept, *_TAIL_COLUMNS, *normalized, *_END_COLUMNS]
    return [c for c in dict.fromkeys(wanted) if c in frame.columns]


def _summary_table(frame: pd.DataFrame, swept: Sequence[str], hashes: Mapping[str, str]) -> str:
    columns = _table_columns(frame, swept)
    head = "".join(f"<th>{_e(c)}</th>" for c in columns) + "<th>config SHA-256</th>"
    body = []
    for _, row in frame.iterrows():
        status = str(row.get("status", ""))
        css = f"case case-{_slug(status)}" if status else "case"
        cells = "".join(f"<td>{_e(_cell(row[c]))}</td>" for c in columns)
        digest = hashes.get(str(row.get("case_id")), "")
        cells += f"<td><code title=\"{_e(digest)}\">{_e(digest[:16])}</code></td>"
        body.append(f'<tr class="{_e(css)}" data-case="{_e(row.get("case_id", ""))}">{cells}</tr>')
    return (f'<div class="scroll"><table class="summary"><thead><tr>{head}</tr></thead>'
            f"<tbody>{''.join(body)}</tbody></table></div>")


def _problems(frame: pd.DataFrame, label: str = "") -> list[str]:
    items = []
    if "status" not in frame.columns:
        return items
    for _, row in frame[frame["status"] != "finished"].iterrows():
        where = f"{label}/" if label else ""
        items.append(f"<li><b>{_e(where)}{_e(row.get('case_id', '?'))}</b> "
                     f"({_e(row.get('status'))}): {_e(row.get('reason', ''))}</li>")
    return items


def _figures_html(paths: Sequence[Path]) -> str:
    parts = []
    for path in paths:
        data = base64.b64encode(Path(path).read_bytes()).decode("ascii")
        parts.append(f'<figure><img alt="{_e(path.name)}" src="data:image/png;base64,{data}">'
                     f"<figcaption>{_e(path.name)}</figcaption></figure>")
    return "\n".join(parts) or "<p>No figures (no finished case to draw).</p>"


def _notes_text() -> str:
    """The reproduction notes (``docs/reproduction/notes.md``) when brushbem runs from a clone, else ""."""
    path = Path(__file__).resolve().parents[3] / "docs" / "reproduction" / "notes.md"
    try:
        return path.read_text(encoding="utf-8")
    except OSError:
        return ""


def _explanation(study: str, notes: str) -> str:
    """Where a deviation above 5 % of ``study`` is explained: the notes' sections, as `render` links them.

    With the notes at hand and no section for the study, it says so, as the
    comparison document does; without the notes (an installed package) it
    points to the document.
    """
    from brushbem.reproduction import explaining_sections

    if not notes:
        return (f"see docs/thesis-comparison.md (the notes on <code>{_e(study)}</code>) in brushbem's "
                "repository")
    sections = explaining_sections(study, notes)
    if not sections:
        return "<strong>no explanation in the notes</strong>"
    return "".join(f"<details><summary>explained in docs/thesis-comparison.md: {_e(heading)}</summary>"
                   f"<pre class=\"note\">{_e(body)}</pre></details>" for heading, body in sections)


def _numbers_table(study: Any, results: Mapping[str, pd.DataFrame]) -> str:
    # The comparison document's rule for "far".
    from brushbem.reproduction import deviation_of

    notes = _notes_text()
    far_rows = 0
    rows = []
    for number in study.numbers:
        try:
            ours = float(number.compute(results))
            if not math.isfinite(ours):
                raise ValueError(f"not finite: {ours}")
            ours_text = f"{ours:.6g}"
            # Above 5 % a deviation needs the explanation of docs/thesis-comparison.md (the same rule
            # as the comparison document's; where the thesis states 0, 0.05 of the normalising force).
            _, far, deviation_text = deviation_of(number.thesis, ours, digits=2)
            css = "far" if far else "ok"
        except Exception as exc:  # noqa: BLE001 - reported, not raised
            ours_text, deviation_text, css = f"n/a ({type(exc).__name__}: {exc})", "n/a", "na"
        explanation = _explanation(study.name, notes) if css == "far" else ""
        far_rows += css == "far"
        rows.append(f"<tr><td>{_e(number.quantity)}</td><td>{_e(number.where)}</td>"
                    f"<td>{_e(f'{number.thesis:.6g}')}</td><td class=\"{css}\">{_e(ours_text)}</td>"
                    f"<td class=\"{css}\">{_e(deviation_text)}</td><td>{explanation}</td></tr>")
    if not rows:
        return "<p>This study states no numbers to compare.</p>"
    legend = ("<p>Amber: more than 5 % from the thesis; each such row says where the deviation is measured "
              "and explained (grid, realisations, a fixed step, or a parameter it leaves open).</p>"
              if far_rows else "")
    return (legend + '<table class="numbers"><thead><tr><th>quantity</th><th>where</th><th>thesis</th>'
            "<th>ours</th><th>deviation</th><th>explanation</th></tr></thead>"
            f"<tbody>{''.join(rows)}</tbody></table>")


def _definition_list(items: Mapping[str, Any]) -> str:
    rows = "".join(f"<tr><th>{_e(k)}</th><td>{_e(v)}</td></tr>" for k, v in items.items())
    return f'<table class="provenance">{rows}</table>'


def _timings(frames: Mapping[str, pd.DataFrame]) -> dict[str, str]:
    times = [float(t) for frame in frames.values() if "wall_time_s" in frame.columns
             for t in frame["wall_time_s"] if t is not None and np.isfinite(float(t))]
    if not times:
        return {"cases timed": "0"}
    return {
        "cases timed": str(len(times)),
        "total wall time of the cases (s)": f"{sum(times):.4g}",
        "per case: mean / min / max (s)": f"{np.mean(times):.4g} / {min(times):.4g} / {max(times):.4g}",
    }


def _sweep_keys(folder: Path) -> list[str]:
    from brushbem.sweep import SWEEP_FILE

    try:
        return list(json.loads((folder / SWEEP_FILE).read_text(encoding="utf-8")).get("sweep", {}))
    except (OSError, ValueError, AttributeError):
        return []


def _incidents_html(incidents: Mapping[str, Sequence[Mapping[str, Any]]], notices: Sequence[str]) -> str:
    """What happened to the folder: the incidents of every (part) folder and the notices of this reading."""
    items = [f"<li>{_e(notice)}</li>" for notice in notices]
    for part, entries in incidents.items():
        for entry in entries:
            where = f"{part}/" if part else ""
            case = f" {where}{entry['case_id']}" if entry.get("case_id") else (f" {part}" if part else "")
            moved = f" (moved to {where}{entry['moved_to']})" if entry.get("moved_to") else ""
            items.append(f"<li><code>{_e(entry.get('time', ''))}</code> <b>{_e(entry['event'])}</b>"
                         f"{_e(case)}: {_e(entry.get('detail', ''))}{_e(moved)}</li>")
    if not items:
        return '<p class="ok" id="incidents">Nothing went wrong in this folder.</p>'
    return f'<div class="incidents" id="incidents"><ul>{"".join(items)}</ul></div>'
