"""One look for every brushbem figure: the style, the axis labels, and how a figure is written.

The run figure (`brushbem.figures.plot`), the study figures (`brushbem.studies`), the
sweep figures (`brushbem.report.sweeps`) and the design figure (`brushbem.design`)
are drawn inside `style` (or a function decorated with `styled`) and written
with `save`: a PNG at 300 dpi and a PDF (vector) beside it, each replaced
atomically.

Labels are matplotlib mathtext (``r"$\\tilde F = F/F_\\mathrm{K}$"``).  A
dimensional quantity is labelled with its unit when the configuration names
one (``[units]``, `brushbem.results.units.Units`) and without a unit when it does
not (the numbers are then in the units of the inputs); a normalised quantity needs none.  `KEY_LABELS` names the
configuration keys and summary columns that sweeps vary and report;
`key_label` and `key_symbol` read it and fall back to the key itself.

Importing this module loads no plotting library: matplotlib is imported when
a style is entered or a figure written.
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from brushbem.results.units import Units

__all__ = [
    "COLOURS",
    "DPI",
    "KEY_LABELS",
    "STYLE",
    "Quantity",
    "axis_label",
    "key_label",
    "key_name",
    "key_symbol",
    "new_figure",
    "save",
    "style",
    "styled",
    "unit_text",
]

#: Raster resolution of every PNG written.
DPI = 300

#: The colour cycle: Okabe and Ito's palette, told apart with the common forms of colour blindness
#: (its yellow, unreadable on white, left out).
COLOURS = ("#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#000000")

#: The rcParams of every figure: sizes for a journal column (7-9 pt text), thin grid, fonts embedded
#: as TrueType in PDF (editable text, accepted by publishers), mathtext in the text font.
STYLE: dict[str, Any] = {
    "font.size": 9.0,
    "axes.titlesize": 9.0,
    "axes.labelsize": 9.0,
    "axes.titlelocation": "center",
    "figure.titlesize": 10.0,
    "legend.fontsize": 7.5,
    "legend.title_fontsize": 7.5,
    "legend.framealpha": 0.9,
    "legend.edgecolor": "0.8",
    "xtick.labelsize": 8.0,
    "ytick.labelsize": 8.0,
    "xtick.direction": "in",
    "ytick.direction": "in",
    "axes.linewidth": 0.8,
    "axes.grid": True,
    "grid.linewidth": 0.4,
    "grid.alpha": 0.5,
    "lines.linewidth": 1.2,
    "lines.markersize": 4.0,
    "errorbar.capsize": 2.0,
    "mathtext.fontset": "dejavusans",
    "image.cmap": "viridis",
    "figure.dpi": 100,
    "savefig.dpi": DPI,
    "pdf.fonttype": 42,
    "ps.fonttype": 42,
    "svg.fonttype": "none",
}


def _rc() -> dict[str, Any]:
    from cycler import cycler

    return {**STYLE, "axes.prop_cycle": cycler(color=list(COLOURS))}


@contextmanager
def style() -> Iterator[None]:
    """Draw (and save) inside this context to give a figure brushbem's look.

    A panel whose curves carry no labels (a quick grid of one series) gets no
    legend: matplotlib's warning that it found none to draw is expected there.
    """
    import warnings

    import matplotlib as mpl

    with mpl.rc_context(_rc()), warnings.catch_warnings():
        warnings.filterwarnings("ignore", message="No artists with labels found to put in legend")
        yield


F = TypeVar("F", bound=Callable[..., Any])


def styled(function: F) -> F:
    """``function`` run inside `style`: every figure it draws and writes has brushbem's look."""

    @functools.wraps(function)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        with style():
            return function(*args, **kwargs)

    return wrapper  # type: ignore[return-value]


def new_figure(width: float = 5.0, height: float = 4.0) -> Figure:
    """A `Figure` with constrained layout and an Agg canvas (no pyplot, no window), in `style`."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    with style():
        figure = Figure(figsize=(width, height), layout="constrained")
    FigureCanvasAgg(figure)
    return figure


_VECTOR = ".pdf"
_RASTER = ".png"
_FORMATS = (".png", ".pdf", ".svg", ".eps", ".ps")
#: Whether `save` leaves out the PDF beside each PNG (`raster_only`).
_RASTER_ONLY: ContextVar[bool] = ContextVar("raster_only", default=False)


@contextmanager
def raster_only() -> Iterator[None]:
    """Inside this block `save` writes the PNG (or the named file) without the PDF beside it.

    For checks that a figure is drawn (the tests of the studies and of the
    committed figures): the PDF is 40 % of a figure's writing time.
    """
    token = _RASTER_ONLY.set(True)
    try:
        yield
    finally:
        _RASTER_ONLY.reset(token)


def save(figure: Figure, path: str | Path) -> Path:
    """Write ``figure`` as a PNG at `DPI` and a PDF beside it (same stem), each atomically.

    ``path`` names the file: ``pulloff.png`` writes ``pulloff.png`` and
    ``pulloff.pdf``; ``fig.svg`` writes ``fig.svg`` too.  A name without one
    of these suffixes gets ``.png`` added (``adhesive_force_vs_indenter.radius``
    writes ``adhesive_force_vs_indenter.radius.png`` and ``.pdf``).  Each file
    is written to a temporary beside it and renamed over it
    (`brushbem.io.atomic_path`): a failed write leaves the old file.

    Returns
    -------
    Path
        ``path`` (with ``.png`` added where it had no figure suffix).
    """
    from brushbem.io import atomic_path

    path = Path(path)
    if path.suffix.lower() not in _FORMATS:
        path = path.with_name(path.name + _RASTER)
    path.parent.mkdir(parents=True, exist_ok=True)
    beside = [] if _RASTER_ONLY.get() else [path.with_suffix(_VECTOR)]
    targets = list(dict.fromkeys([path, path.with_suffix(_RASTER), *beside]))
    with style(), _quiet_font_subsetting():
        for target in targets:
            kind = target.suffix.lower().lstrip(".")
            options: dict[str, Any] = {"format": kind, "dpi": DPI}
            if kind == "pdf":
                options["metadata"] = {"CreationDate": None}  # the same figure gives the same file
            with atomic_path(target) as temporary:
                figure.savefig(temporary, **options)
    return path


@contextmanager
def _quiet_font_subsetting() -> Iterator[None]:
    """fontTools' notes on the embedded fonts' own metadata (a font's creation date) kept off the terminal."""
    import logging

    logger = logging.getLogger("fontTools")
    level = logger.level
    logger.setLevel(max(level, logging.ERROR))
    try:
        yield
    finally:
        logger.setLevel(level)


# --------------------------------------------------------------------------- labels


@dataclass(frozen=True)
class Quantity:
    """How a configuration key or a summary column is labelled.

    Attributes
    ----------
    name : str
        Words, e.g. ``"pillar stiffness"``.
    symbol : str
        Mathtext, e.g. ``r"$\\tilde k$"``; in legends (``symbol = value``).
    dimension : str or None
        One of `brushbem.results.units.DIMENSIONS` (labelled with the unit, or
        "dimensionless"); ``"angle"`` (degrees); None for a normalised or
        counted quantity (no unit).
    definition : str
        Shown after the symbol on an axis, opening with mathtext that continues
        the symbol's, e.g. ``r"$= k/(E^* L)$"`` or ``r"$= F_\\mathrm{A}/F_\\mathrm{c}$ (eq. 5.3)"``.
    """

    name: str
    symbol: str
    dimension: str | None = None
    definition: str = ""


#: Dotted configuration keys and summary columns -> how they are labelled.
KEY_LABELS: dict[str, Quantity] = {
    "halfspace.contact_modulus": Quantity("contact modulus", r"$E^*$", "stress"),
    "halfspace.youngs_modulus": Quantity("Young's modulus", r"$E$", "stress"),
    "halfspace.poisson_ratio": Quantity("Poisson's ratio", r"$\nu$"),
    "halfspace.work_of_adhesion": Quantity("work of adhesion", r"$\Delta\gamma$", "force / length"),
    "grid.size": Quantity("domain side", r"$L$", "length"),
    "grid.elements": Quantity("elements per side", r"$N$"),
    "indenter.radius": Quantity("indenter radius", r"$R$", "length"),
    "indenter.stiffness": Quantity("spring stiffness", r"$k$", "force / length"),
    "indenter.stiffness_ratio": Quantity("pillar stiffness", r"$\tilde k$", None, r"$= k/(E^* L)$"),
    "indenter.pillar_radius": Quantity("pillar radius", r"$r$", "length"),
    "indenter.pillars_per_side": Quantity("pillars per side", r"$n$"),
    "indenter.pillar_count": Quantity("number of pillars", r"$N_\mathrm{p}$"),
    "indenter.spacing": Quantity("pillar spacing", r"$s$", "length"),
    "indenter.region_size": Quantity("region size", r"$L_0$", "length"),
    "indenter.min_gap": Quantity("least gap", r"$g_\mathrm{min}$", "length"),
    "indenter.roughness.sigma": Quantity("roughness", r"$\sigma$", "length"),
    "indenter.profile.amplification": Quantity("profile amplification", r"$\tilde h$"),
    "indenter.tip.radius": Quantity("tip cap radius", r"$R_\mathrm{tip}$", "length"),
    "indenter.tip.depth": Quantity("tip dish depth", r"$\delta$", "length"),
    "indenter.tilt.angle": Quantity("tilt angle", r"$\theta$", "angle"),
    "indenter.tilt.azimuth": Quantity("tilt azimuth", r"$\psi$", "angle"),
    "indenter.grading.amplitude": Quantity("grading amplitude", r"$a$"),
    "indenter.grading.exponent": Quantity("grading exponent", r"$m$"),
    "indenter.viscoelastic.relaxation_time": Quantity("relaxation time", r"$\tau$"),
    "indenter.viscoelastic.instantaneous_factor": Quantity("instantaneous stiffness", r"$k_0/k_\infty$"),
    "indenter.seed": Quantity("seed", r"$s$"),
    "protocol.preload_displacement": Quantity("preload displacement", r"$d_\mathrm{P}$", "length"),
    "protocol.preload_force": Quantity("preload force", r"$F_\mathrm{P}$", "force"),
    "protocol.step": Quantity("displacement step", r"$\Delta d$", "length"),
    "protocol.speed": Quantity("pulling speed", r"$v$"),
    "solver.tolerance": Quantity("solver tolerance", r"$\epsilon$"),
    # Summary columns.
    "adhesive_force": Quantity("adhesive force", r"$F_\mathrm{A}$", "force"),
    "work_of_separation": Quantity("work of separation", r"$W$", "energy"),
    "preload_force": Quantity("preload force", r"$F_\mathrm{P}$", "force"),
    "pull_off_displacement": Quantity("pull-off displacement", r"$d_\mathrm{A}$", "length"),
    "separation_displacement": Quantity("separation displacement", r"$d_\mathrm{s}$", "length"),
    "normalized.force_by_compact_punch": Quantity(
        "adhesive force", r"$\tilde F_\mathrm{A}$", None, r"$= F_\mathrm{A}/F_\mathrm{K}$ (eq. 4.11)"),
    "normalized.force_by_rigid_brush": Quantity(
        "adhesive force", r"$\tilde F_\mathrm{A}$", None, r"$= F_\mathrm{A}/F_\mathrm{c}$ (eq. 5.3)"),
    "normalized.force_by_ideal_sharing": Quantity(
        "adhesive force", r"$\tilde F_\mathrm{A}$", None, r"$= F_\mathrm{A}/(N_\mathrm{p} F_\mathrm{K})$ (eq. 7.4)"),
    "normalized.preload_by_rigid_brush": Quantity(
        "preload", r"$\tilde F_\mathrm{P}$", None, r"$= F_\mathrm{P}/F_\mathrm{c}$"),
    "normalized.roughness_by_rigid_brush": Quantity(
        "roughness", r"$\tilde\sigma$", None, r"$= \sigma/|d_\mathrm{c}|$"),
    "normalized.stiffness_ratio": Quantity("pillar stiffness", r"$\tilde k$", None, r"$= k/(E^* L)$"),
    "normalized.filling_factor": Quantity("filling factor", r"$\phi$"),
    "normalized.pillars": Quantity("number of pillars", r"$N_\mathrm{p}$"),
}


def unit_text(dimension: str | None, units: Units | None = None) -> str:
    """The parenthesised unit of an axis: ``" (mm)"``, ``" (°)"``; ``""`` for None or without ``[units]``.

    Without ``[units]`` the numbers are in the units of the inputs: an axis says nothing rather than
    "(dimensionless)" on every axis; the figure says it once where it matters (the run figure's title).
    """
    if dimension is None:
        return ""
    if dimension == "angle":
        return " (°)"
    if units is None or units.dimensionless:
        return ""
    return f" ({units.label(dimension)})"


def axis_label(name: str, dimension: str | None = None, units: Units | None = None) -> str:
    """``name`` with its unit: ``"force $F$ (N)"``, or ``name`` alone (no unit, or no ``[units]``)."""
    return name + unit_text(dimension, units)


def key_label(key: str, units: Units | None = None) -> str:
    """The axis label of a configuration key or summary column: name, symbol, definition and unit.

    ``key_label("indenter.stiffness_ratio")`` is ``r"pillar stiffness $\\tilde k = k/(E^* L)$"``;
    ``key_label("indenter.radius", Units("mm", "MPa"))`` is ``"indenter radius $R$ (mm)"``, without
    ``[units]`` ``"indenter radius $R$"``.
    A key not in `KEY_LABELS` is its own label.
    """
    quantity = KEY_LABELS.get(key)
    if quantity is None:
        return key
    symbol = quantity.symbol
    if quantity.definition:
        symbol = symbol[:-1] + " " + quantity.definition[1:]  # one mathtext run: "$\tilde k = k/(E^* L)$"
    return axis_label(f"{quantity.name} {symbol}", quantity.dimension, units)


def key_name(key: str) -> str:
    """The words of a key (``"pillar stiffness"``); the key itself where `KEY_LABELS` does not name it."""
    quantity = KEY_LABELS.get(key)
    return quantity.name if quantity is not None else key


def key_symbol(key: str) -> str:
    """The short name of a key in a legend (``symbol = value``): ``r"$\\tilde k$"``; else its last part."""
    quantity = KEY_LABELS.get(key)
    return quantity.symbol if quantity is not None else key.rsplit(".", 1)[-1]
