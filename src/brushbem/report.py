"""Figures and a self-contained HTML report of a sweep or a study run folder.

`draw_figures(DIR)` redraws without computing: a study run folder (it has
``study.json``) is drawn by its study, a plain sweep folder (``sweep.json``) by
`draw_sweep_figures` (adhesive force against every swept key, the pull-off
curves overlaid).  `write_report(DIR)` writes ``DIR/report.html``: one file,
figures embedded as PNG data URIs, the summary table with failed,
unconverged, missing and corrupt cases highlighted, what happened to the
folder (`brushbem.sweep.read_incidents`: corrupt case files moved aside, cases
lost with their workers, interrupted runs; a summary rebuilt on reading), the
thesis numbers of a study, and provenance (version, configuration hashes,
seeds, machine, timings).  All text is escaped; nothing is loaded from
outside the file.
"""

from __future__ import annotations

import base64
import datetime as _dt
import hashlib
import html
import json
import math
import os
import platform
import re
import textwrap
import warnings
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from brushbem import __version__, figstyle
from brushbem.io import atomic_path

if TYPE_CHECKING:
    import pandas as pd

    from brushbem.units import Units

__all__ = [
    "MAX_CURVES",
    "REPORT_FILE",
    "config_hash",
    "draw_figures",
    "draw_sweep_figures",
    "machine_info",
    "write_report",
]

REPORT_FILE = "report.html"
#: At most this many pull-off curves are overlaid in one figure.
MAX_CURVES = 30
_FIGURES_DIR = "figures"


# --------------------------------------------------------------------------- figures


def _new_figure(size: tuple[float, float] = (5.0, 3.8)):
    return figstyle.new_figure(*size)


def _save(figure: Any, path: Path) -> Path:
    """``path`` (a PNG at 300 dpi) and a PDF beside it, atomically (`brushbem.figstyle.save`)."""
    return figstyle.save(figure, path)


def _slug(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", text).strip("_") or "value"


def _numeric(values: Sequence[Any]) -> bool:
    return all(isinstance(v, (int, float, np.integer, np.floating)) and not isinstance(v, bool)
               for v in values)


def _wide(values: Sequence[float]) -> bool:
    """Positive values spanning more than two decades (drawn on a log axis)."""
    finite = [float(v) for v in values if np.isfinite(v)]
    return bool(finite) and min(finite) > 0 and max(finite) / min(finite) > 100.0


def _force_columns(frame: pd.DataFrame) -> list[str]:
    """``adhesive_force`` and the normalised forces, where present."""
    columns = [c for c in ("adhesive_force",) if c in frame.columns]
    columns += [c for c in frame.columns
                if c.startswith("normalized.") and "force" in c and _numeric(frame[c].dropna().tolist())]
    return columns


@figstyle.styled
def _plot_against(frame: pd.DataFrame, key: str, others: list[str], column: str, path: Path,
                  units: Units | None = None) -> Path:
    """``column`` against swept ``key``: one line per combination of the other swept values.

    Axes are labelled by the quantities' names, symbols and units
    (`brushbem.figstyle.key_label`), the lines by the other keys' symbols.
    """
    figure = _new_figure()
    axes = figure.add_subplot()
    xs_all = frame[key].tolist()
    categorical = not _numeric(xs_all)
    categories = list(dict.fromkeys(map(str, xs_all)))
    groups = frame.groupby(others, dropna=False, sort=False) if others else [((), frame)]
    for label, group in groups:
        label = label if isinstance(label, tuple) else (label,)
        xs = ([categories.index(str(v)) for v in group[key]] if categorical
              else group[key].astype(float).to_numpy())
        ys = group[column].astype(float).to_numpy()
        order = np.argsort(xs, kind="stable")
        text = ", ".join(f"{name} = {_cell(v)}" for name, v in zip(_legend_names(others), label)) or None
        xs, ys = np.asarray(xs)[order], ys[order]
        # Every realization as a marker, the mean over realizations as the line.
        line = axes.plot(xs, ys, marker="o", linestyle="none", alpha=0.6, label=text)[0]
        unique = np.unique(xs)
        means = [np.nanmean(ys[xs == x]) if np.any(np.isfinite(ys[xs == x])) else np.nan for x in unique]
        axes.plot(unique, means, color=line.get_color())
    if categorical:
        axes.set_xticks(range(len(categories)), categories, rotation=30, ha="right")
    elif _wide(frame[key].astype(float).tolist()):
        axes.set_xscale("log")
    if _wide(frame[column].astype(float).tolist()):
        axes.set_yscale("log")
    axes.set_xlabel(figstyle.key_label(key, units))
    axes.set_ylabel(figstyle.key_label(column, units))
    title = f"{figstyle.key_name(column)} against {figstyle.key_name(key)}, finished cases"
    axes.set_title("\n".join(textwrap.wrap(title, 60)))
    if axes.get_legend_handles_labels()[0]:
        axes.legend(loc="best")
    return _save(figure, path)


def _legend_names(keys: Sequence[str]) -> list[str]:
    """How the keys are named in a legend: their symbols (`brushbem.figstyle.key_symbol`), or the keys
    themselves where two would share one."""
    short = [figstyle.key_symbol(key) for key in keys]
    return short if len(set(short)) == len(short) else list(keys)


def _case_label(row: pd.Series, keys: Sequence[str], realizations: bool) -> str:
    """A curve's legend entry: its swept values (``$\\tilde k$ = 0.01, $\\sigma$ = 0.002``), not its id."""
    present = [key for key in keys if key in row.index]
    parts = [f"{name} = {_cell(row[key])}" for name, key in zip(_legend_names(present), present)]
    if realizations and "realization" in row.index:
        parts.append(f"realization {int(row['realization'])}")
    return ", ".join(parts) or str(row["case_id"])


@figstyle.styled
def _plot_curves(frame: pd.DataFrame, cases_dir: Path, path: Path, keys: Sequence[str] = (),
                 units: Units | None = None) -> Path | None:
    """The force-displacement curves of (at most `MAX_CURVES`) finished cases, overlaid, labelled by swept value."""
    import xarray as xr

    figure = _new_figure((6.0, 4.2))
    axes = figure.add_subplot()
    axes.axhline(0.0, color="0.7", linewidth=0.8)
    drawn = 0
    rows = frame.head(MAX_CURVES)
    realizations = "realization" in rows and rows["realization"].nunique() > 1
    for _, row in rows.iterrows():
        case_id = row["case_id"]
        file = cases_dir / f"{case_id}.nc"
        if not file.is_file():
            continue
        try:
            with xr.open_dataset(file, engine="h5netcdf") as dataset:
                if "force" not in dataset or "displacement" not in dataset:
                    continue
                displacement, force = dataset["displacement"].to_numpy(), dataset["force"].to_numpy()
        except Exception:  # noqa: BLE001, S112 - a file damaged since the summary was read: not drawn
            continue
        axes.plot(displacement, force, linewidth=1.0, label=_case_label(row, keys, realizations))
        drawn += 1
    if not drawn:
        return None
    axes.set_xlabel(figstyle.axis_label(r"base displacement $d$", "length", units))
    axes.set_ylabel(figstyle.axis_label(r"force $F$", "force", units))
    shown = f"{drawn} of {len(frame)}" if len(frame) > drawn else f"{drawn}"
    axes.set_title(f"pull-off curves ({shown} finished cases)")
    if drawn <= 12:
        axes.legend(loc="best")
    return _save(figure, path)


def draw_sweep_figures(out_dir: str | Path, figures_dir: str | Path | None = None) -> list[Path]:
    """Generic figures of a plain sweep folder, from its stored results (nothing is computed).

    For every swept key: the adhesive force (and each ``normalized.*force*``
    value) of the finished cases against it, one line per combination of the
    other swept values (log axes where the values span more than two
    decades); and the pull-off curves of the finished cases overlaid
    (`MAX_CURVES` at most).

    Axes are labelled by the quantities' names and symbols, in the units the
    sweep's base configuration names (``[units]``), or "dimensionless".
    Every figure is a PNG at 300 dpi with a PDF beside it.

    Returns
    -------
    list of Path
        The PNG files written (in ``out_dir/figures`` by default), each with its PDF.
    """
    from brushbem.studies import finished
    from brushbem.sweep import CASES_DIR, SWEEP_FILE, load_summary

    out_dir = Path(out_dir)
    figures_dir = Path(figures_dir) if figures_dir is not None else out_dir / _FIGURES_DIR
    figures_dir.mkdir(parents=True, exist_ok=True)
    record = json.loads((out_dir / SWEEP_FILE).read_text(encoding="utf-8"))
    keys = list(record.get("sweep", {}))
    frame = finished(load_summary(out_dir))
    written: list[Path] = []
    if frame.empty:
        return written
    units = _sweep_units(record)
    for column in _force_columns(frame):
        for key in keys:
            others = [k for k in keys if k != key]
            name = f"{_slug(column)}_vs_{_slug(key)}.png"
            written.append(_plot_against(frame, key, others, column, figures_dir / name, units))
    curves = _plot_curves(frame, out_dir / CASES_DIR, figures_dir / "pulloff_curves.png", keys, units)
    if curves is not None:
        written.append(curves)
    return written


def _sweep_units(record: Mapping[str, Any]) -> Units:
    """The units the sweep's base configuration names (``sweep.json``'s ``base``); dimensionless without."""
    from brushbem.units import Units

    try:
        return Units.from_config(record.get("base"))
    except (TypeError, ValueError):
        return Units()


def draw_figures(out_dir: str | Path) -> list[Path]:
    """Redraw the figures of a study run folder or of a plain sweep folder.

    Raises
    ------
    FileNotFoundError
        If ``out_dir`` holds neither ``study.json`` nor ``sweep.json``.
    """
    from brushbem.studies import STUDY_FILE, draw_study
    from brushbem.sweep import SWEEP_FILE

    out_dir = Path(out_dir)
    if (out_dir / STUDY_FILE).is_file():
        return draw_study(out_dir)
    if (out_dir / SWEEP_FILE).is_file():
        return draw_sweep_figures(out_dir)
    raise FileNotFoundError(f"{out_dir} holds neither {STUDY_FILE} nor {SWEEP_FILE}: "
                            "not a study or sweep output folder")


# --------------------------------------------------------------------------- provenance


def config_hash(config_json: str) -> str:
    """SHA-256 of a resolved configuration, over its canonical JSON (sorted keys, compact)."""
    canonical = json.dumps(json.loads(config_json), sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(canonical.encode("utf-8")).hexdigest()


def _case_hashes(cases_dir: Path, case_ids: Sequence[str]) -> dict[str, str]:
    """Case id -> `config_hash` of the configuration stored in its case file."""
    import xarray as xr

    hashes: dict[str, str] = {}
    for case_id in case_ids:
        file = cases_dir / f"{case_id}.nc"
        if not file.is_file():
            continue
        try:
            with xr.open_dataset(file, engine="h5netcdf") as dataset:
                config = dataset.attrs.get("config")
            if config:
                hashes[str(case_id)] = config_hash(str(config))
        except Exception as exc:  # noqa: BLE001 - any unreadable file is reported as such
            hashes[str(case_id)] = f"unreadable: {type(exc).__name__}"
    return hashes


def machine_info() -> dict[str, str]:
    """Where the report was written: platform, Python, cores, numeric library versions."""
    import scipy

    return {
        "platform": platform.platform(),
        "machine": platform.machine(),
        "python": platform.python_version(),
        "cpu_count": str(os.cpu_count()),
        "numpy": np.__version__,
        "scipy": scipy.__version__,
    }


# --------------------------------------------------------------------------- HTML

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
    path = Path(__file__).resolve().parents[2] / "docs" / "reproduction" / "notes.md"
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


def write_report(out_dir: str | Path, *, redraw: bool = False) -> Path:
    """Write ``out_dir/report.html`` for a study run folder or a plain sweep folder.

    Figures in ``out_dir/figures`` are drawn first when there are none (or
    ``redraw``); nothing is computed.  The file is self-contained: figures
    are PNG data URIs, the style sheet is inline.  A `SweepWarning` of
    reading the results (an unreadable summary rebuilt) is listed in the
    report and issued again to the caller.

    Returns
    -------
    Path
        The report file (written atomically).

    Raises
    ------
    FileNotFoundError
        If ``out_dir`` is neither a study nor a sweep output folder.
    brushbem.sweep.SweepFolderError
        If a ``sweep.json`` in it cannot be read.
    """
    from brushbem.studies import STUDY_FILE, get_study, load_results
    from brushbem.studies._framework import read_study_record
    from brushbem.sweep import (
        CASES_DIR,
        SWEEP_FILE,
        SweepFolderError,
        SweepWarning,
        load_summary,
        read_incidents,
    )

    out_dir = Path(out_dir)
    is_study = (out_dir / STUDY_FILE).is_file()
    if not is_study and not (out_dir / SWEEP_FILE).is_file():
        raise FileNotFoundError(f"{out_dir} holds neither {STUDY_FILE} nor {SWEEP_FILE}: "
                                "not a study or sweep output folder")
    figures_dir = out_dir / _FIGURES_DIR
    draw_note = ""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", SweepWarning)
        if redraw or not any(figures_dir.glob("*.png")):
            try:
                draw_figures(out_dir)
            except SweepFolderError:
                raise
            except Exception as exc:  # noqa: BLE001 - reported, not raised
                draw_note = f"drawing the figures failed: {type(exc).__name__}: {exc}"
        study = None
        if is_study:
            record = read_study_record(out_dir)
            study = get_study(record["study"])
            frames = load_results(out_dir, tuple(record.get("parts", study.parts)))
            folders = {part: out_dir / part for part in frames}
            title = f"brushbem study {study.name}: {study.title}"
        else:
            frames = {"": load_summary(out_dir)}
            record = json.loads((out_dir / SWEEP_FILE).read_text(encoding="utf-8"))
            folders = {"": out_dir}
            title = f"brushbem sweep {out_dir.name}"
    figures = sorted(figures_dir.glob("*.png"))
    notices = list(dict.fromkeys(str(w.message) for w in caught if issubclass(w.category, SweepWarning)))
    for notice in notices:
        warnings.warn(notice, SweepWarning, stacklevel=2)
    incidents = {part: read_incidents(folder) for part, folder in folders.items()}

    problems: list[str] = []
    tables: list[str] = []
    hashes_all: dict[str, str] = {}
    for part, frame in frames.items():
        problems += _problems(frame, part)
        ids = frame["case_id"].tolist() if "case_id" in frame.columns else []
        hashes = _case_hashes(folders[part] / CASES_DIR, ids)
        hashes_all.update({f"{part}/{k}" if part else k: v for k, v in hashes.items()})
        heading = f"<h3>part {_e(part)}</h3>" if part else ""
        counts = frame["status"].value_counts().to_dict() if "status" in frame.columns else {}
        count_text = ", ".join(f"{n} {s}" for s, n in sorted(counts.items())) or "no cases"
        tables.append(f"{heading}<p>{len(frame)} cases: {_e(count_text)}</p>"
                      + _summary_table(frame, _sweep_keys(folders[part]), hashes))

    seeds = sorted({int(s) for frame in frames.values() if "seed" in frame.columns
                    for s in frame["seed"].dropna()})
    provenance = {
        "brushbem version (report)": __version__,
        "brushbem versions (cases)": ", ".join(sorted({str(v) for f in frames.values()
                                                       if "brushbem_version" in f.columns
                                                       for v in f["brushbem_version"].dropna()})) or "—",
        "backends (cases)": ", ".join(sorted({str(v) for f in frames.values() if "backend" in f.columns
                                              for v in f["backend"].dropna()})) or "—",
        "written": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
        "folder": str(out_dir.resolve()),
        "seeds": ", ".join(map(str, seeds)) or "—",
    }
    if is_study:
        provenance["quick"] = "yes" if record.get("quick") else "no"
        provenance["thesis figures"] = ", ".join(record.get("figures", study.figures))
    else:
        provenance["sweep source"] = str(record.get("source"))
        provenance["mode / realizations / seed"] = (
            f"{record.get('mode')} / {record.get('realizations')} / {record.get('seed')}")

    sections = [f"<h1>{_e(title)}</h1>"]
    if problems:
        sections.append(f'<div class="problems" id="problems"><b>{len(problems)} case(s) did not '
                        f"finish:</b><ul>{''.join(problems)}</ul></div>")
    else:
        sections.append('<p class="ok" id="problems">Every case finished (converged).</p>')
    sections.append("<h2>What happened</h2>" + _incidents_html(incidents, notices))
    if study is not None and study.notes:
        sections.append(f"<p>{_e(study.notes)}</p>")
    if study is not None:
        sections.append("<h2>Thesis numbers</h2>" + _numbers_table(study, frames))
    sections.append("<h2>Figures</h2>" + (f'<p class="na">{_e(draw_note)}</p>' if draw_note else "")
                    + _figures_html(figures))
    sections.append("<h2>Cases</h2>" + "".join(tables))
    sections.append("<h2>Provenance</h2>" + _definition_list(provenance)
                    + "<h3>Machine</h3>" + _definition_list(machine_info())
                    + "<h3>Timings</h3>" + _definition_list(_timings(frames))
                    + "<h3>Configuration hashes (SHA-256 of the resolved configuration)</h3>"
                    + _definition_list(hashes_all))
    document = ("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
                f"<title>{_e(title)}</title><style>{_CSS}</style></head><body>\n"
                + "\n".join(sections) + "\n</body></html>\n")
    path = out_dir / REPORT_FILE
    with atomic_path(path) as temporary:
        temporary.write_text(document, encoding="utf-8")
    return path
