"""The report of one run: ``brushbem report DIR`` on a folder written by ``brushbem run --out DIR``.

`write_run_report` writes ``DIR/report.html``, one self-contained file (the
figures are PNG data URIs, the style sheet is inline, nothing is fetched):

* the outcome (converged or not, the reason, the warnings, the stages the
  path did not pass through);
* the pull-off curve: the run's ``pulloff.png`` (only a regular PNG file of
  the folder, never a link), or, where it is missing (or with ``redraw``),
  `brushbem.figures.plot.pull_off_figure` drawn from ``result.nc`` with the
  closed-form limits that ``summary.json`` records;
* the snapshots: the pressure on the contact set at every stage of thesis
  Fig. 4-3 that the path passed through, on one colour scale for every
  panel (none where every pressure is zero);
* the summary numbers with their units (the configuration's ``[units]``,
  or the units of the inputs), a brush's normalised numbers with their
  symbols and definitions, the refinement of ``--refine``;
* the comparison with the closed forms (``summary.json``'s ``theory``), one
  table: per closed form its value, the computed value it is read against
  and their ratio, or why it does not apply; the parameters the closed forms
  were evaluated at below it;
* the provenance: brushbem version, commit, creation time, backend, run id
  and the resolved configuration.

Every text taken from the files is escaped (`html.escape`).  Nothing is
computed: the numbers are those of ``summary.json`` and ``result.nc`` (the
ratios are their quotients); the stored configuration is shown, never
validated or rasterised again.  The report is written under the folder's
lock (`brushbem.io.exclusive_folder`), so a ``brushbem run --out`` writing
the same folder at once is refused rather than left with another run's
report.
"""

from __future__ import annotations

import datetime as _dt
import html
import json
import numbers
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from brushbem import __version__
from brushbem.report.html import write_document
from brushbem.report.run_figures import figure_png, own_png, png_uri, snapshots_figure
from brushbem.results.units import Units

__all__ = ["GENERATOR", "REPORT_FILE", "RunReportError", "is_run_folder", "is_run_report", "not_a_results_folder",
           "write_run_report"]

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


def not_a_results_folder(folder: str | Path) -> str:
    """Why ``folder`` is neither a run folder nor a sweep or study folder, in words for the command line."""
    folder = Path(folder)
    takes = ("`brushbem report` takes a run folder (`brushbem run --out DIR`: summary.json and result.nc), a "
             "sweep folder (sweep.json) or a study folder (study.json)")
    try:
        names = {entry.name for entry in folder.iterdir()}
    except OSError as exc:
        return f"{folder}: cannot be read ({exc.strerror or exc}); {takes}"
    if not names - {".brushbem.lock"}:
        return f"{folder} is empty: {takes}"
    if "design.json" in names:
        return (f"{folder} is a design folder (`brushbem design --out`): its figure is design.png and its numbers "
                f"design.json and design.csv; {takes}")
    halves = [name for name in (_SUMMARY, _DATASET) if name in names]
    if len(halves) == 1:
        missing = _DATASET if halves == [_SUMMARY] else _SUMMARY
        return (f"{folder} holds {halves[0]} but no {missing}: a run that did not finish writing (interrupted or "
                f"killed); run it again with --overwrite. {takes}")
    return f"{folder} is not a run, sweep or study output folder: {takes}"


def _mapping(value: Any) -> Mapping[str, Any]:
    """``value`` where it is a mapping, else an empty one (a file edited by hand: a list where a table belongs)."""
    return value if isinstance(value, Mapping) else {}


def _config(summary: Mapping[str, Any]) -> Mapping[str, Any]:
    """The resolved configuration recorded in ``summary.json`` (empty where it is absent or not a table)."""
    return _mapping(_mapping(summary.get("provenance")).get("config"))


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
    except (OSError, ValueError, KeyError, TypeError, AttributeError, IndexError) as exc:
        raise RunReportError(f"{folder / _DATASET}: cannot be read as a run's result ({exc})") from None
    return from_json_safe(summary), result


# ------------------------------------------------------------------ units


def _units(summary: Mapping[str, Any], result: Any) -> Units:
    config = _config(summary)
    try:
        if config:
            return Units.from_config(dict(config))
        return Units.of_record(result.attributes)
    except (ValueError, TypeError, AttributeError):
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
        rows = []
        for key, value in normalized.items():
            symbol, definition = NORMALISED.get(key, (key, "—"))
            shown = ", ".join(_number(v) for v in value) if isinstance(value, list) else _number(value)
            rows.append([_e(symbol), _e(definition), _e(shown)])
        text += ("<h3>Normalised (thesis ch. 4-7; dimensionless)</h3>"
                 + _table(("symbol", "definition", "value"), rows, numeric=(2,), css="normalised"))
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


#: Every normalised number of ``summary.json`` (``normalized``): its symbol and its definition.
NORMALISED: dict[str, tuple[str, str]] = {
    "force_by_compact_punch": ("F_A / F_K", "adhesive force over Kendall's force of one punch of the brush's "
                               "real area (eq. 4.11)"),
    "force_by_rigid_brush": ("F_A / F_c", "adhesive force over the rigid brush's force F_c (eq. 4.5, 5.3)"),
    "force_by_ideal_sharing": ("F_A / (N_p F_K)", "adhesive force over the sum of the pillars' Kendall forces, "
                               "every pillar at its own (eq. 7.4)"),
    "displacement_by_rigid_brush": ("d_A / |d_c|", "pull-off displacement over the rigid brush's critical "
                                    "displacement (eq. 4.12); negative in tension"),
    "separation_displacement_by_rigid_brush": ("d_s / |d_c|", "displacement of the last contact before "
                                               "separation over |d_c|"),
    "max_displacement_by_rigid_brush": ("d_P / |d_c|", "preload (largest) displacement over |d_c|"),
    "preload_by_rigid_brush": ("F_P / F_c", "preload force over F_c"),
    "preload_by_compact_punch": ("F_P / F_K", "preload force over Kendall's force of the compact punch"),
    "roughness_by_rigid_brush": ("σ / |d_c|", "roughness (standard deviation of the pillars' length offsets) "
                                 "over |d_c|"),
    "stiffness_ratio": ("k~ = k / (E* L)", "pillar stiffness over E* times the brush's side L "
                        "(indenter.region_size, by default grid.size; eq. 4.13); a graded level's mean stiffness"),
    "level_stiffness_ratios": ("k~_l", "k~ of every spring level, the pillars' first (eq. 6.24)"),
    "equivalent_single_level_stiffness_ratio": ("k~_eq", "the single level of the same stiffness as the "
                                                "hierarchy (eq. 6.28)"),
    "filling_factor": ("φ = A / A_0", "real area of the rasterised footprints over the apparent area of their "
                       "region"),
    "pillars": ("N_p", "number of pillars"),
    "attached_pillars_at_pull_off": ("N_att", "pillars in contact at the adhesive force"),
    "profile_amplification": ("h~", "amplification of the concave profile (eq. 7.2)"),
}

#: The closed forms of ``summary.json``'s ``theory``: what each is and which computed number it is read against
#: (a key of the summary, or ``normalized.<key>``), with that number's symbol.
CLOSED_FORMS: dict[str, tuple[str, str, str]] = {
    "adhesive_force": ("adhesive force", "adhesive_force", "F_A"),
    "pull_off_displacement": ("base displacement at the adhesive force", "pull_off_displacement", "d_A"),
    "work_of_separation": ("work of separation", "work_of_separation", "W"),
    "compact_punch_force": ("F_K: Kendall's force of one punch of the brush's real area (eq. 4.11)",
                            "adhesive_force", "F_A"),
    "rigid_brush_force": ("F_c: the rigid brush's force (eq. 4.5, 5.3)", "adhesive_force", "F_A"),
    "ideal_sharing_force": ("N_p F_K: every pillar at its Kendall force (eq. 7.4)", "adhesive_force", "F_A"),
    "rigid_brush_displacement": ("−|d_c|: the rigid brush's critical displacement (eq. 4.12)",
                                 "pull_off_displacement", "d_A"),
    "rigid_brush_enhancement": ("φ^−1/4: the rigid brush's F_c / F_K (eq. 4.9)",
                                "normalized.force_by_compact_punch", "F_A / F_K"),
    "soft_brush_enhancement": ("N_p^1/4: the soft brush's limit of F_A / F_K (eq. 4.18)",
                               "normalized.force_by_compact_punch", "F_A / F_K"),
}

#: Closed-form entries that are the parameters of the closed forms, not values to compare.
_PARAMETERS = {
    "equivalent_radius": "radius sqrt(A/π) of the rasterised footprint's area A, at which Kendall is evaluated",
    "normalized_stiffness": "the spring's normalised stiffness of the closed form (punch: k / (2 E* a))",
    "preload_contact_radius": "Hertz contact radius of the preload",
    "zero_force_radius": "JKR's a_o, the contact radius at zero force (eq. 2.27)",
}


def _computed(summary: Mapping[str, Any], key: str) -> Any:
    if key.startswith("normalized."):
        return _mapping(summary.get("normalized")).get(key.split(".", 1)[1])
    return summary.get(key)


def _theory_html(summary: Mapping[str, Any], units: Units) -> str:
    """The closed forms beside the computed numbers, one table: closed form, computed, ratio (or why not)."""
    theory = summary.get("theory")
    if not isinstance(theory, Mapping) or not theory:
        return ('<p class="na" id="theory-none">No closed form applies to this run (an indenter without one, '
                "or no adhesion): nothing to compare.</p>")
    not_applicable = _mapping(theory.get("not_applicable"))
    parts = [f"<p>Model: <b>{_e(theory.get('model', '—'))}</b></p>"]
    rows, parameters = [], []
    for key, value in theory.items():
        if key in ("model", "ratios", "not_applicable") or value is None:
            continue
        if isinstance(value, bool) or not isinstance(value, numbers.Real):
            continue
        if key in _PARAMETERS or (key not in CLOSED_FORMS and key not in summary):
            parameters.append([_e(key), _e(_PARAMETERS.get(key, "—")), _e(_number(value)),
                               _e(_unit(units, _dimension_of(key)))])
            continue
        meaning, against, symbol = CLOSED_FORMS.get(key, (key, key, key))
        computed = _computed(summary, against)
        if key in not_applicable:
            ratio = f'<span class="na">not applicable: {_e(not_applicable[key])}</span>'
        elif isinstance(computed, numbers.Real) and not isinstance(computed, bool) and value:
            ratio = _e(_number(float(computed) / float(value)))
        else:
            ratio = '<span class="na">no computed value</span>'
        dimension = None if against.startswith("normalized.") else _dimension_of(key)
        rows.append([_e(meaning), _e(_number(value)), _e(f"{symbol} = {_number(computed)}"), ratio,
                     _e(_unit(units, dimension))])
    for key, reason in not_applicable.items():
        if key not in theory:
            rows.append([_e(key), "—", _e(_number(summary.get(key))),
                         f'<span class="na">not applicable: {_e(reason)}</span>',
                         _e(_unit(units, _dimension_of(key)))])
    parts.append(_table(("closed form", "value", "computed", "computed / closed form", "unit"), rows,
                        numeric=(1,), css="theory"))
    if parameters:
        parts.append("<p>The closed forms were evaluated at:</p>"
                     + _table(("parameter", "meaning", "value", "unit"), parameters, numeric=(2,),
                              css="theory-parameters"))
    notes = [(key, value) for key, value in theory.items() if isinstance(value, str) and key != "model"]
    if notes:
        parts.append("<ul>" + "".join(f"<li>{_e(k)}: {_e(v)}</li>" for k, v in notes) + "</ul>")
    return "".join(parts)


# ------------------------------------------------------------------ figures


def _curve_html(folder: Path, summary: Mapping[str, Any], result: Any, redraw: bool) -> str:
    caption = "the run's pulloff.png"
    data = None
    if not redraw:
        data, why = own_png(folder / _FIGURE)
        if data is None and why != f"no {_FIGURE}":
            caption = f"drawn from result.nc; {why}, not embedded"
    if data is None:
        from brushbem.figures.plot import pull_off_figure

        try:
            # The closed-form limits the figure draws are those summary.json records: nothing recomputed.
            data = figure_png(pull_off_figure(result))
            caption = caption if caption.startswith("drawn") else "drawn from result.nc"
        except Exception as exc:  # noqa: BLE001 - the report still shows the numbers
            return f'<p class="bad" id="curve">The curve could not be drawn: {_e(type(exc).__name__)}: {_e(exc)}</p>'
    return (f'<figure id="curve"><img alt="force against base displacement" src="{png_uri(data)}">'
            f"<figcaption>Force against base displacement ({_e(caption)}): loading and unloading branches, the "
            "adhesive force marked, the stages numbered.</figcaption></figure>")


def _snapshots_html(summary: Mapping[str, Any], result: Any, units: Units) -> str:
    """The pressure on the contact set at every stage reached (grey: no contact), one panel each."""
    import numpy as np

    from brushbem.figures.plot import STAGES

    recorded = {snapshot.name: snapshot for snapshot in result.snapshots}
    order = [name for name in STAGES if name in recorded] + [n for n in recorded if n not in STAGES]
    missing = _mapping(summary.get("stages_not_reached"))
    items = []
    if order:
        figure, largest = snapshots_figure(result, units, order)
        items.append(f'<figure id="snapshots"><img alt="contact pressure at every stage" '
                     f'src="{png_uri(figure_png(figure))}"><figcaption>Pressure on the contact set (grey: no '
                     "contact) at the stages of thesis Fig. 4-3, every panel on one colour scale"
                     + ("" if largest > 0.0 else " (none: every pressure on the contact is zero)")
                     + ".</figcaption></figure>")
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
    provenance = _mapping(summary.get("provenance"))
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
        unreadable, or from another run than its partner; if another
        brushbem process is writing the folder.
    OSError
        If ``report.html`` cannot be written (it is written atomically:
        nothing half-written is left).
    """
    from brushbem.io import FolderBusyError, exclusive_folder

    folder = Path(folder)
    if not is_run_folder(folder):
        raise RunReportError(not_a_results_folder(folder))
    # Under the folder's lock: a `brushbem run --out` into this folder at the same moment would replace the
    # results under the report (and remove the report it describes before this one is written).
    try:
        with exclusive_folder(folder):
            return _write(folder, redraw)
    except FolderBusyError as exc:
        raise RunReportError(f"{exc}; report it when that run has finished") from None


def _write(folder: Path, redraw: bool) -> Path:
    summary, result = _read(folder)
    units = _units(summary, result)
    shape = _mapping(_config(summary).get("indenter")).get("shape") or "run"
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
    return write_document(folder / REPORT_FILE, title, sections, _CSS,
                          meta=f'<meta name="generator" content="{_e(GENERATOR)}">')
