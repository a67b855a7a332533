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

This module holds the figures, the provenance and the assembly of the
report; the HTML pieces (style sheet, tables, figure embedding, the thesis
numbers and their explanations) are in `brushbem.report.html`.
"""

from __future__ import annotations

import datetime as _dt
import hashlib
import json
import os
import platform
import textwrap
import warnings
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from brushbem import __version__
from brushbem.figures import figstyle
from brushbem.report.html import (
    _CSS,
    _cell,
    _definition_list,
    _e,
    _explanation,  # noqa: F401 - re-exported (imported from here)
    _figures_html,
    _incidents_html,
    write_document,
    _notes_text,  # noqa: F401 - re-exported (imported from here)
    _numbers_table,
    _problems,
    _slug,
    _summary_table,
    _sweep_keys,
    _timings,
)

if TYPE_CHECKING:
    import pandas as pd

    from brushbem.results.units import Units

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
    """``path`` (a PNG at 300 dpi) and a PDF beside it, atomically (`brushbem.figures.figstyle.save`)."""
    return figstyle.save(figure, path)


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
    (`brushbem.figures.figstyle.key_label`), the lines by the other keys' symbols.
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
    """How the keys are named in a legend: their symbols (`brushbem.figures.figstyle.key_symbol`), or the keys
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
    from brushbem.results.units import Units

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
    return write_document(out_dir / REPORT_FILE, title, sections, _CSS)
