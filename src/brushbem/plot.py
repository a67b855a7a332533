"""Figures of a pull-off.

Figures are drawn on a `matplotlib.figure.Figure` with an explicit Agg canvas,
never through pyplot: importing this module selects no backend and opens no
window, so it is safe in scripts, workers and tests.

Sign convention: d > 0 presses into the half-space, F > 0 is compressive; the
adhesive force is the magnitude of the most tensile (minimum) force.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from brushbem.io import atomic_path
from brushbem.results import CaseResult
from brushbem.units import Units

__all__ = ["STAGES", "as_case_result", "draw_with_jumps", "plot_pull_off", "pull_off_figure"]

#: The snapshot stages of a pull-off (thesis Fig. 4-3), numbered on the figure in this order.
STAGES = ("max_preload", "zero_force", "adhesive_force", "half_detached", "before_separation")

_LOADING_COLOUR = "tab:blue"
_UNLOADING_COLOUR = "tab:red"
_REFERENCE_COLOUR = "0.2"


def plot_pull_off(
    result: Any,
    path: str | Path,
    reference: Mapping[str, Any] | None = None,
    *,
    units: Units | None = None,
) -> None:
    """Draw `pull_off_figure` and save it as a PNG at ``path`` (replaced atomically)."""
    figure = pull_off_figure(result, reference, units=units)
    with atomic_path(path) as temporary:
        figure.savefig(temporary, format="png", dpi=150)


def as_case_result(result: Any) -> CaseResult:
    """A `CaseResult` from any form of a run.

    Accepts a `CaseResult`, a `brushbem.PullOff` (``brushbem.run``'s
    result), an `xarray.Dataset` read from a ``result.nc``, or the path of a
    case folder or of a ``.nc`` file (a sweep's ``cases/<case-id>.nc``).
    """
    if isinstance(result, CaseResult):
        return result
    inner = getattr(result, "result", None)
    if isinstance(inner, CaseResult):
        return inner
    import xarray as xr

    from brushbem.io import from_dataset, load_result

    if isinstance(result, xr.Dataset):
        return from_dataset(result)
    if isinstance(result, (str, Path)):
        return load_result(result)
    raise TypeError(f"result: {type(result).__name__} is not a run (a CaseResult, a PullOff, an xarray.Dataset "
                    "of a result.nc, or the path of a case folder or .nc file)")


def pull_off_figure(
    result: Any,
    reference: Mapping[str, Any] | None = None,
    *,
    ax: Axes | None = None,
    units: Units | None = None,
) -> Figure:
    """Force against base displacement, as a `matplotlib.figure.Figure` (no pyplot, no window).

    The loading branch and the unloading (pull-off) branch are drawn in
    different colours, the adhesive-force point (the minimum force) and the
    five stages of thesis Fig. 4-3 are marked; a jump to separation (or into
    contact) is drawn as a vertical step, not a slope.  Without ``ax``, the
    pressure on the contact set at the adhesive-force moment (the detachment
    pattern) is drawn beside the curve.

    Parameters
    ----------
    result : CaseResult, PullOff, xarray.Dataset or path
        The run (see `as_case_result`); its ``curve`` is drawn.
    reference : mapping, optional
        A closed-form curve drawn dashed: ``displacement`` and ``force``
        (array-like of equal length, same units as the curve) and ``label``
        (str).
    ax : matplotlib.axes.Axes, optional
        Draw the curve on these axes (of any figure, pyplot's included) and
        return their figure (``ax.figure``: a `SubFigure` where the axes
        lie in one); the pattern is not drawn then.
    units : brushbem.units.Units, optional
        The unit system of the axis labels; by default the run's
        configuration's ``[units]`` (dimensionless without it).

    Returns
    -------
    matplotlib.figure.Figure
    """
    if reference is None:
        reference = getattr(result, "reference", None)  # a PullOff's closed-form curve, as its figure() draws
    result = as_case_result(result)
    units = units if units is not None else Units.of_record(result.attributes)
    curve = result.curve
    displacement = np.asarray(curve.displacement, dtype=float)
    force = np.asarray(curve.force, dtype=float)
    loading = np.asarray(curve.loading, dtype=bool)

    pattern = next((snap for snap in result.snapshots if snap.name == "adhesive_force"), None)
    if ax is not None:
        axes, figure = ax, ax.figure
    else:
        figure = Figure(figsize=(11.0, 4.8) if pattern is not None else (6.4, 4.8), layout="constrained")
        FigureCanvasAgg(figure)
        if pattern is not None:
            axes, map_axes = figure.subplots(1, 2, width_ratios=[1.35, 1.0])
            _draw_pattern(map_axes, pattern, float(result.element_size), units)
        else:
            axes = figure.add_subplot()
    axes.axhline(0.0, color="0.7", linewidth=0.8)

    if reference is not None:
        axes.plot(
            np.asarray(reference["displacement"], dtype=float),
            np.asarray(reference["force"], dtype=float),
            linestyle="--",
            color=_REFERENCE_COLOUR,
            linewidth=1.2,
            label=str(reference.get("label", "reference")),
        )
    if np.any(loading):
        # Wide and light beneath the unloading line, so both branches show where they coincide.
        axes.plot(displacement[loading], force[loading], color=_LOADING_COLOUR, linewidth=3.0, alpha=0.45,
                  label="loading")
    unloading = np.flatnonzero(~loading)
    if unloading.size:
        # Start the unloading line at the turning point so the branches join.
        start = max(int(unloading[0]) - 1, 0)
        rows = np.concatenate([[start], unloading]) if start < unloading[0] else unloading
        axes.plot(displacement[rows], force[rows], color=_UNLOADING_COLOUR, label="unloading")
    if force.size:
        weakest = int(np.argmin(force))
        axes.plot(
            displacement[weakest],
            force[weakest],
            marker="o",
            linestyle="none",
            color="black",
            label=f"adhesive force $F_A$ = {-force[weakest]:.4g}",
        )

    _detachment_inset(axes, displacement, force, loading)
    for number, name in enumerate(STAGES, start=1):
        snapshot = next((snap for snap in result.snapshots if snap.name == name), None)
        if snapshot is not None:
            axes.annotate(str(number), (snapshot.displacement, snapshot.force), textcoords="offset points",
                          xytext=(4, 4), fontsize="small", color="0.25")
            axes.plot(snapshot.displacement, snapshot.force, marker=".", color="0.25", linestyle="none")
    summary = result.summary if isinstance(result.summary, Mapping) else {}
    missing = summary.get("stages_not_reached") or {}
    stages = ", ".join(f"{n} {name.replace('_', ' ')}" + (" (not reached)" if name in missing else "")
                       for n, name in enumerate(STAGES, start=1))
    axes.set_title(f"pull-off: F_A = {summary.get('adhesive_force', float('nan')):.4g}, "
                   f"W = {summary.get('work_of_separation', float('nan')):.4g}\nstages: {stages}", fontsize="small")
    axes.set_xlabel(units.axis("base displacement d, presses > 0", "length"))
    axes.set_ylabel(units.axis("force F, compressive > 0", "force"))
    axes.grid(True, linewidth=0.4, alpha=0.5)
    if axes.get_legend_handles_labels()[0]:
        axes.legend(loc="best", fontsize="small")
    return figure


def draw_with_jumps(axes: Axes, x: Any, y: Any, displacement: Any, **style: Any) -> None:
    """Draw y against x with the jumps as jumps: a step taken at a fixed base displacement.

    Where two consecutive recorded states share the same displacement d, the
    system jumped between them (a detachment cascade, a jump to separation):
    no state lies between them, so the step is drawn dotted and thin, not as
    part of the solid curve.  Against d itself such a step is vertical; against
    the contact radius (thesis Fig. 2-5, 2-8) it would otherwise read as a
    slope.  ``style`` (matplotlib's line keywords, aliases such as ``c`` and
    ``lw`` included) applies to the solid pieces; the jumps take its colour.
    The ``label`` goes to the first solid piece (to the first jump only when
    the curve is nothing but jumps).
    """
    from matplotlib import cbook
    from matplotlib.lines import Line2D

    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    d = np.asarray(displacement, dtype=float)
    style = cbook.normalize_kwargs(style, Line2D)
    label = style.pop("label", None)
    colour = style.pop("color", None)
    if x.size < 2:
        axes.plot(x, y, color=colour, label=label, **style)
        return
    scale = float(np.max(np.abs(d))) or 1.0
    jump = np.abs(np.diff(d)) <= 1e-12 * scale  # segment i joins states i and i + 1 at the same d
    pieces: list[tuple[int, int, bool]] = []  # (first state, last state, is a jump)
    start = 0
    for i in range(x.size - 1):
        if jump[i]:
            if i > start:
                pieces.append((start, i, False))
            pieces.append((i, i + 1, True))
            start = i + 1
    if start < x.size - 1:
        pieces.append((start, x.size - 1, False))
    labelled = next((n for n, piece in enumerate(pieces) if not piece[2]), 0)
    for n, (first, last, is_jump) in enumerate(pieces):
        rows = slice(first, last + 1)
        text = label if n == labelled else None
        if is_jump:
            line = axes.plot(x[rows], y[rows], color=colour, linestyle=":", linewidth=0.8, label=text)[0]
        else:
            line = axes.plot(x[rows], y[rows], color=colour, label=text, **style)[0]
        colour = line.get_color()  # the axes' next colour, taken once, for every piece


def _detachment_inset(axes, displacement: np.ndarray, force: np.ndarray, loading: np.ndarray) -> None:
    """An inset around the detachment (the states near the adhesive force) when it is a sliver of the curve."""
    unloading = np.flatnonzero(~loading)
    if unloading.size < 3 or not np.any(force < 0):
        return
    near = unloading[force[unloading] <= 0.7 * float(force.min())]
    span = float(np.ptp(displacement)) or 1.0
    if near.size < 2:
        return
    lo, hi = float(displacement[near].min()), float(displacement[near].max())
    if hi - lo > 0.2 * span or hi == lo:
        return
    inset = axes.inset_axes([0.08, 0.42, 0.38, 0.36])
    rows = np.arange(max(int(near[0]) - 1, 0), min(int(near[-1]) + 2, force.size))
    inset.plot(displacement[rows], force[rows], color=_UNLOADING_COLOUR, linewidth=1.0)
    margin = 0.1 * (hi - lo)
    inset.set_xlim(lo - margin, hi + margin)
    low, high = float(force[near].min()), float(force[near].max())
    pad = max(0.15 * (high - low), 0.01 * abs(low))
    inset.set_ylim(low - pad, high + pad)
    inset.set_title("detachment (zoom)", fontsize="x-small")
    inset.tick_params(labelsize="x-small")
    axes.indicate_inset_zoom(inset, edgecolor="0.5")


def _draw_pattern(axes, snapshot, element_size: float, units: Units) -> None:
    """The pressure on the contact set at the adhesive-force moment (grey: not in contact)."""
    pressure = np.asarray(snapshot.pressure, dtype=float)
    contact = np.asarray(snapshot.contact, dtype=bool)
    n = pressure.shape[0]
    half = 0.5 * n * element_size
    shown = np.ma.masked_where(~contact, pressure)
    limit = float(np.max(np.abs(pressure[contact]))) if contact.any() else 1.0
    axes.set_facecolor("0.85")
    image = axes.imshow(
        shown, origin="lower", extent=(-half, half, -half, half), cmap="RdBu_r",
        vmin=-limit, vmax=limit, interpolation="nearest",
    )
    axes.figure.colorbar(image, ax=axes, shrink=0.8, label=units.axis("p, compressive > 0", "stress"))
    axes.set_title(f"contact at the adhesive force (d = {snapshot.displacement:.4g})", fontsize="small")
    axes.set_xlabel(units.axis("x", "length"))
    axes.set_ylabel(units.axis("y", "length"))
