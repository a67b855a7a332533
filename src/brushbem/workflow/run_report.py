"""The report of one run: ``brushbem report DIR`` on a folder written by ``brushbem run --out DIR``.

`write_run_report` writes ``DIR/report.html``, one self-contained file (the
figures are PNG data URIs, the style sheet is inline, nothing is fetched):

* the outcome (converged or not, the reason, the warnings, the stages the
  path did not pass through);
* the pull-off curve: the run's ``pulloff.png``, or, where it is missing (or
  with ``redraw``), `brushbem.workflow.plot.pull_off_figure` drawn from
  ``result.nc``;
* the snapshots: the pressure on the contact set at every stage of thesis
  Fig. 4-3 that the path passed through;
* the summary numbers with their units (the configuration's ``[units]``,
  or the units of the inputs), a brush's normalised numbers, the
  refinement of ``--refine``;
* the comparison with the closed forms (``summary.json``'s ``theory``):
  closed-form value, computed value and their ratio per quantity, and the
  quantities whose closed form does not apply named as such, with the
  reason;
* the provenance: brushbem version, commit, creation time, backend, run id
  and the resolved configuration.

Every text taken from the files is escaped (`html.escape`).  Nothing is
computed: the numbers are those of ``summary.json`` and ``result.nc``.
"""

from __future__ import annotations

import base64
import datetime as _dt
import html
import io
import json
import numbers
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from brushbem import __version__
from brushbem.workflow.units import Units

__all__ = ["GENERATOR", "REPORT_FILE", "RunReportError", "is_run_folder", "is_run_report", "write_run_report"]

REPORT_FILE = "report.html"
#: The ``generator`` of the report's ``<meta>``: a ``report.html`` that carries it is brushbem's run report.
GENERATOR = "brushbem run report"
_SUMMARY = "summary.json"
_DATASET = "result.nc"
_FIGURE = "pulloff.png"

_CSS = """
body{font-family:system-ui,sans-serif;margin:1.5em;color:#222;max-width:1200px}
h1{font-size:1.5em}h2{font-size:1.2em;margin-top:1.6em;border-bottom:1px solid #ccc}
table{border-collapse:collapse;font-size:.9em;margin:.5em 0}
th,td{border:1px solid #ccc;padding:.2em .6em;text-align:left;vertical-align:top}
th{background:#f0f0f0}td.num{text-align:right;font-variant-numeric:tabular-nums}
.ok{color:#070}.bad{color:#a00}.na{color:#666;font-style:italic}
.warnings{border:1px solid #b60;background:#fffaf0;padding:.5em 1em}
figure{margin:.5em 0}figure img{max-width:100%;border:1px solid #ddd}
figcaption{font-size:.85em;color:#555}
pre{white-space:pre-wrap;font-size:.8em;background:#fafafa;padding:.5em;border:1px solid #eee}
"""


class RunReportError(ValueError):
    """A run folder whose files cannot be read (missing, corrupt, or from two different runs)."""


def is_run_report(path: str | Path) -> bool:
    """Whether the file ``path`` is a report that `write_run_report` wrote (its ``generator`` meta)."""
    try:
        with open(path, encoding="utf-8", errors="replace") as handle:
            head = handle.read(2048)
    except OSError:
        return False
    return f'<meta name="generator" content="{GENERATOR}">' in head


def is_run_folder(folder: str | Path) -> bool:
    """Whether ``folder`` is one run's output (``summary.json`` and ``result.nc``, no sweep or study record)."""
    folder = Path(folder)
    if (folder / "sweep.json").exists() or (folder / "study.json").exists():
        return False
    return (folder / _SUMMARY).is_file() and (folder / _DATASET).is_file()


def _e(value: Any) -> str:
    return html.escape(str(value), quote=True)


def _number(value: Any) -> str:
    if value is None:
        return "—"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, numbers.Integral):
        return str(int(value))
    if isinstance(value, numbers.Real):
        return f"{float(value):.6g}"
    return str(value)


def _read(folder: Path) -> tuple[dict[str, Any], Any]:
    """``summary.json`` (decoded) and the run's `CaseResult` (from ``result.nc``), or `RunReportError`."""
    from brushbem.io import InconsistentCaseError, from_dataset, from_json_safe, read_case

    try:
        summary = json.loads((folder / _SUMMARY).read_text(encoding="utf-8"))
    except (OSError, ValueError) as exc:
        raise RunReportError(f"{folder / _SUMMARY}: cannot be read ({exc})") from None
    if not isinstance(summary, dict):
        raise RunReportError(f"{folder / _SUMMARY}: not a run's summary (a JSON object)")
    try:
        result = from_dataset(read_case(folder))
    except InconsistentCaseError as exc:
        raise RunReportError(str(exc)) from None
    except (OSError, ValueError, KeyError) as exc:
        raise RunReportError(f"{folder / _DATASET}: cannot be read ({exc})") from None
    return from_json_safe(summary), result


# ------------------------------------------------------------------ units


def _units(summary: Mapping[str, Any], result: Any) -> Units:
    provenance = summary.get("provenance") or {}
    config = provenance.get("config") if isinstance(provenance, Mapping) else None
    try:
        if isinstance(config, Mapping):
            return Units.from_config(dict(config))
        return Units.of_record(result.attributes)
    except ValueError:
        return Units()


#: A dimensionless run's quantities are in the units of its inputs: E* (stress) and grid.size (length).
_INPUT_UNITS = {
    "length": "length of the inputs",
    "stress": "stress of the inputs",
    "force": "stress × length² of the inputs",
    "energy": "stress × length³ of the inputs",
    "force / length": "stress × length of the inputs",
    "length^2": "length² of the inputs",
}


def _unit(units: Units, dimension: str | None) -> str:
    """The unit of ``dimension`` for the tables: the configuration's, or that of the inputs; "1" for a ratio."""
    if dimension is None:
        return "1 (dimensionless)"
    if dimension == "s":
        return "s"
    if dimension == "count":
        return "—"
    if units.dimensionless:
        return _INPUT_UNITS[dimension]
    return units.label(dimension)


#: summary.json's numbers and their dimensions, in the order shown.
_SUMMARY_ROWS = (
    ("adhesive_force", "adhesive force F_A", "force"),
    ("pull_off_displacement", "pull-off displacement d_A", "length"),
    ("separation_displacement", "separation displacement", "length"),
    ("work_of_separation", "work of separation W", "energy"),
    ("preload_force", "preload force", "force"),
    ("max_displacement", "preload displacement", "length"),
    ("critical_stress", "critical stress σ_c of the mesh (eq. 2.14)", "stress"),
    ("attached_pillars_at_pull_off", "pillars attached at F_A", "count"),
    ("n_states", "recorded states", "count"),
    ("n_solves", "solves", "count"),
    ("n_cg_iterations", "CG iterations", "count"),
    ("mean_cg_iterations_per_solve", "CG iterations per solve", "count"),
    ("wall_time_s", "wall time of the computation", "s"),
)


def _dimension_of(key: str) -> str | None:
    """The dimension of a theory entry, from its name (None: a ratio or a normalised number)."""
    if key.endswith("_enhancement") or key.startswith("normalized") or key in ("ratio", "order"):
        return None
    if key.endswith("force"):
        return "force"
    if key.endswith(("displacement", "radius")):
        return "length"
    if key.startswith("work"):
        return "energy"
    if key.endswith("stiffness"):
        return "force / length"
    return None


def _table(header: Sequence[str], rows: Sequence[Sequence[str]], numeric: Sequence[int] = (), css: str = "") -> str:
    """An HTML table; the cells are HTML already (escaped by the caller)."""
    head = "".join(f"<th>{_e(cell)}</th>" for cell in header)
    body = "".join(
        "<tr>" + "".join(f'<td class="num">{cell}</td>' if k in numeric else f"<td>{cell}</td>"
                         for k, cell in enumerate(row)) + "</tr>"
        for row in rows)
    return f'<table class="{_e(css)}"><tr>{head}</tr>{body}</table>'


def _summary_html(summary: Mapping[str, Any], units: Units) -> str:
    rows = [[_e(label), _e(_number(summary[key])), _e(_unit(units, dimension))]
            for key, label, dimension in _SUMMARY_ROWS if key in summary]
    text = _table(("quantity", "value", "unit"), rows, numeric=(1,), css="summary")
    units_note = ("The configuration names no units: every quantity is in the units of its inputs (E* sets the "
                  "stress, grid.size the length)." if units.dimensionless else
                  f"Units of the configuration: length {units.label('length')}, stress {units.label('stress')}.")
    text = f"<p>{_e(units_note)}</p>" + text
    normalized = summary.get("normalized")
    if isinstance(normalized, Mapping) and normalized:
        rows = [[_e(key), _e(_number(value) if not isinstance(value, list) else
                             ", ".join(_number(v) for v in value))]
                for key, value in normalized.items()]
        text += ("<h3>Normalised (thesis ch. 4-7; dimensionless)</h3>"
                 + _table(("quantity", "value"), rows, numeric=(1,)))
    refinement = summary.get("refinement")
    if isinstance(refinement, Mapping) and refinement:
        rows = []
        for key, entry in refinement.items():
            if isinstance(entry, Mapping):
                rows.append([_e(key), _e("; ".join(f"{k} = {_number(v) if not isinstance(v, list) else v}"
                                                  for k, v in entry.items()))])
            else:
                rows.append([_e(key), _e(_number(entry) if not isinstance(entry, list) else entry)])
        text += "<h3>Grid refinement (--refine)</h3>" + _table(("quantity", "value"), rows)
    return text


def _theory_html(summary: Mapping[str, Any], units: Units) -> str:
    """The closed forms beside the computed numbers: value, computed, ratio, or why a closed form does not apply."""
    theory = summary.get("theory")
    if not isinstance(theory, Mapping) or not theory:
        return ('<p class="na" id="theory-none">No closed form applies to this run (an indenter without one, '
                "or no adhesion): nothing to compare.</p>")
    ratios = theory.get("ratios") if isinstance(theory.get("ratios"), Mapping) else {}
    not_applicable = theory.get("not_applicable") if isinstance(theory.get("not_applicable"), Mapping) else {}
    parts = [f"<p>Model: <b>{_e(theory.get('model', '—'))}</b></p>"]
    rows = []
    shown: set[str] = set()
    for key, value in theory.items():
        if key in ("model", "ratios", "not_applicable") or isinstance(value, (Mapping, list, str, bool)):
            continue
        if value is None:
            continue
        computed = summary.get(key) if key in summary else None
        if key in not_applicable:
            ratio = f'<span class="na">not applicable: {_e(not_applicable[key])}</span>'
        elif key in ratios:
            ratio = _e(_number(ratios[key]))
        else:
            ratio = "—"
        rows.append([_e(key), _e(_number(value)), _e(_number(computed)) if computed is not None else "—", ratio,
                     _e(_unit(units, _dimension_of(key)))])
        shown.add(key)
    for key, reason in not_applicable.items():
        if key not in shown:
            rows.append([_e(key), "—", _e(_number(summary.get(key))),
                         f'<span class="na">not applicable: {_e(reason)}</span>',
                         _e(_unit(units, _dimension_of(key)))])
            shown.add(key)
    parts.append(_table(("quantity", "closed form", "computed", "computed / closed form", "unit"), rows,
                        numeric=(1, 2), css="theory"))
    others = [(key, value) for key, value in ratios.items() if key not in shown]
    if others:
        parts.append("<p>Ratios (computed / closed form, dimensionless):</p>"
                     + _table(("ratio", "value"), [[_e(k), _e(_number(v))] for k, v in others], numeric=(1,)))
    notes = [(key, value) for key, value in theory.items() if isinstance(value, str) and key != "model"]
    if notes:
        parts.append("<ul>" + "".join(f"<li>{_e(k)}: {_e(v)}</li>" for k, v in notes) + "</ul>")
    return "".join(parts)


# ------------------------------------------------------------------ figures


def _png_uri(data: bytes) -> str:
    return "data:image/png;base64," + base64.b64encode(data).decode("ascii")


def _figure_png(figure: Any, dpi: int = 110) -> bytes:
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png", dpi=dpi)
    return buffer.getvalue()


def _reference(summary: Mapping[str, Any]) -> Any:
    """The closed-form curve of the run's figure, rebuilt from the recorded configuration; None if it cannot be."""
    provenance = summary.get("provenance") or {}
    config = provenance.get("config") if isinstance(provenance, Mapping) else None
    if not isinstance(config, Mapping):
        return None
    try:
        from brushbem.workflow.assembly import parse
        from brushbem.workflow.case import theory_for

        built = parse(dict(config))
        return theory_for(built.problem, summary, built.path)[1]
    except Exception:  # noqa: BLE001 - a configuration that no longer builds (a moved file): no reference curve
        return None


def _curve_html(folder: Path, summary: Mapping[str, Any], result: Any, redraw: bool) -> str:
    written = folder / _FIGURE
    caption = "the run's pulloff.png"
    data = None
    if not redraw and written.is_file():
        try:
            data = written.read_bytes()
        except OSError:
            data = None
    if data is None:
        from brushbem.workflow.plot import pull_off_figure

        try:
            data = _figure_png(pull_off_figure(result, _reference(summary)))
            caption = "drawn from result.nc"
        except Exception as exc:  # noqa: BLE001 - the report still shows the numbers
            return f'<p class="bad" id="curve">The curve could not be drawn: {_e(type(exc).__name__)}: {_e(exc)}</p>'
    return (f'<figure id="curve"><img alt="force against base displacement" src="{_png_uri(data)}">'
            f"<figcaption>Force against base displacement ({_e(caption)}): loading and unloading branches, the "
            "adhesive force marked, the stages numbered.</figcaption></figure>")


def _axis(units: Units, name: str, dimension: str) -> str:
    return f"{name} ({'dimensionless' if units.dimensionless else units.label(dimension)})"


def _snapshots_html(summary: Mapping[str, Any], result: Any, units: Units) -> str:
    """The pressure on the contact set at every stage reached (grey: no contact), one panel each."""
    import numpy as np
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    from brushbem.workflow.plot import STAGES

    recorded = {snapshot.name: snapshot for snapshot in result.snapshots}
    order = [name for name in STAGES if name in recorded] + [n for n in recorded if n not in STAGES]
    missing = summary.get("stages_not_reached") or {}
    items = []
    if order:
        figure = Figure(figsize=(3.2 * len(order), 3.3), layout="constrained")
        FigureCanvasAgg(figure)
        axes = figure.subplots(1, len(order), squeeze=False)[0]
        h = float(result.element_size)
        for ax, name in zip(axes, order):
            snapshot = recorded[name]
            pressure = np.asarray(snapshot.pressure, dtype=float)
            contact = np.asarray(snapshot.contact, dtype=bool)
            half = 0.5 * pressure.shape[0] * h
            limit = float(np.max(np.abs(pressure[contact]))) if contact.any() else 1.0
            ax.set_facecolor("0.85")
            image = ax.imshow(np.ma.masked_where(~contact, pressure), origin="lower", cmap="RdBu_r",
                              vmin=-limit or -1.0, vmax=limit or 1.0, interpolation="nearest",
                              extent=(-half, half, -half, half))
            bar = figure.colorbar(image, ax=ax, shrink=0.75)
            bar.set_label(_axis(units, "p, compressive > 0", "stress"), fontsize="small")
            bar.ax.tick_params(labelsize="x-small")
            number = STAGES.index(name) + 1 if name in STAGES else "-"
            ax.set_title(f"{number}: {name.replace('_', ' ')}", fontsize="small")
            ax.set_xlabel(_axis(units, "x", "length"), fontsize="small")
            ax.set_ylabel(_axis(units, "y", "length"), fontsize="small")
            ax.tick_params(labelsize="x-small")
        items.append(f'<figure id="snapshots"><img alt="contact pressure at every stage" '
                     f'src="{_png_uri(_figure_png(figure))}"><figcaption>Pressure on the contact set (grey: no '
                     "contact) at the stages of thesis Fig. 4-3.</figcaption></figure>")
        rows = [[_e(STAGES.index(name) + 1 if name in STAGES else "—"), _e(name),
                 _e(_number(recorded[name].displacement)), _e(_number(recorded[name].force)),
                 _e(int(np.count_nonzero(recorded[name].contact)))] for name in order]
        items.append(_table(("", "stage", f"d ({_unit(units, 'length')})", f"F ({_unit(units, 'force')})",
                             "elements in contact"), rows, numeric=(2, 3, 4)))
    else:
        items.append('<p class="na">The result holds no snapshots.</p>')
    if isinstance(missing, Mapping) and missing:
        items.append("<p>Stages the path did not pass through:</p><ul>" + "".join(
            f"<li>{_e(name)}: {_e(reason)}</li>" for name, reason in missing.items()) + "</ul>")
    return "".join(items)


# ------------------------------------------------------------------ the page


def _outcome_html(summary: Mapping[str, Any]) -> str:
    converged = bool(summary.get("converged"))
    interrupted = bool(summary.get("interrupted"))
    status = ("interrupted (a partial result)" if interrupted else "converged" if converged else "not converged")
    css = "ok" if converged and not interrupted else "bad"
    text = (f'<p class="{css}" id="outcome"><b>{_e(status)}</b>: {_e(summary.get("reason", "no reason given"))}'
            "</p>")
    warnings = summary.get("warnings") or []
    if warnings:
        text += ('<div class="warnings" id="warnings"><b>Warnings</b><ul>'
                 + "".join(f"<li>{_e(w)}</li>" for w in warnings) + "</ul></div>")
    return text


def _provenance_html(folder: Path, summary: Mapping[str, Any], result: Any) -> str:
    provenance = summary.get("provenance") if isinstance(summary.get("provenance"), Mapping) else {}
    attributes = result.attributes
    units = provenance.get("units")
    items = {
        "brushbem version (run)": provenance.get("brushbem_version") or attributes.get("brushbem_version"),
        "commit": provenance.get("commit") or attributes.get("commit") or "not recorded (not run from a git "
                                                                          "checkout)",
        "created": provenance.get("created") or attributes.get("date_created"),
        "backend": provenance.get("backend") or attributes.get("backend"),
        "units": (", ".join(f"{k}: {v}" for k, v in units.items()) if isinstance(units, Mapping) else units),
        "seeds": ", ".join(map(str, attributes.get("seeds") or [])) or "—",
        "run id": summary.get("run_id") or attributes.get("run_id"),
        "folder": str(folder.resolve()),
        "report written": (_dt.datetime.now(_dt.UTC).isoformat(timespec="seconds")
                           + f" by brushbem {__version__}"),
    }
    listing = "".join(f"<dt>{_e(key)}</dt><dd>{_e(value if value is not None else '—')}</dd>"
                      for key, value in items.items())
    config = provenance.get("config")
    if config is None:
        config = attributes.get("config")
    config_text = json.dumps(config, indent=2, sort_keys=False, default=str) if config is not None else "not recorded"
    return (f'<dl id="provenance">{listing}</dl><h3>Configuration (resolved: defaults filled in)</h3>'
            f'<pre id="configuration">{_e(config_text)}</pre>')


def write_run_report(folder: str | Path, *, redraw: bool = False) -> Path:
    """Write ``folder/report.html`` for the run folder ``folder`` (module docstring); return its path.

    Parameters
    ----------
    folder : path
        A folder written by ``brushbem run --out`` (``summary.json`` and
        ``result.nc`` of one run).
    redraw : bool
        Draw the curve from ``result.nc`` even where ``pulloff.png`` is there.

    Raises
    ------
    RunReportError
        If the folder's ``summary.json`` or ``result.nc`` is missing,
        unreadable, or from another run than its partner.
    OSError
        If ``report.html`` cannot be written (it is written atomically:
        nothing half-written is left).
    """
    from brushbem.io import atomic_path

    folder = Path(folder)
    if not is_run_folder(folder):
        raise RunReportError(f"{folder} holds no summary.json and result.nc of a run (`brushbem run --out`)")
    summary, result = _read(folder)
    units = _units(summary, result)
    config = (summary.get("provenance") or {}).get("config") or {}
    shape = ((config.get("indenter") or {}).get("shape") if isinstance(config, Mapping) else None) or "run"
    title = f"brushbem run {folder.resolve().name}: {shape}"
    headline = (f"F_A = {_number(summary.get('adhesive_force'))}, W = {_number(summary.get('work_of_separation'))}"
                + ("" if units.dimensionless else f" ({units.label('force')}, {units.label('energy')})"))
    sections = [
        f"<h1>{_e(title)}</h1>",
        f"<p>{_e(headline)}</p>",
        _outcome_html(summary),
        "<h2>Pull-off curve</h2>" + _curve_html(folder, summary, result, redraw),
        "<h2>Snapshots</h2>" + _snapshots_html(summary, result, units),
        "<h2>Summary</h2>" + _summary_html(summary, units),
        "<h2>Closed forms</h2>" + _theory_html(summary, units),
        "<h2>Provenance</h2>" + _provenance_html(folder, summary, result),
    ]
    document = ("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
                f'<meta name="generator" content="{_e(GENERATOR)}">'
                f"<title>{_e(title)}</title><style>{_CSS}</style></head><body>\n"
                + "\n".join(sections) + "\n</body></html>\n")
    path = folder / REPORT_FILE
    with atomic_path(path) as temporary:
        temporary.write_text(document, encoding="utf-8")
    return path
