"""Figures of a pull-off.

Figures are drawn on a `matplotlib.figure.Figure` with an explicit Agg canvas,
never through pyplot: importing this module selects no backend and opens no
window, so it is safe in scripts, workers and tests.  They take brushbem's one
look (`brushbem.figures.figstyle`) and are written as a PNG at 300 dpi with a PDF
beside it.

Sign convention: d > 0 presses into the half-space, F > 0 is compressive; the
adhesive force is the magnitude of the most tensile (minimum) force.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Circle, Patch, Rectangle
from matplotlib.ticker import MaxNLocator
from matplotlib.transforms import Bbox

from brushbem.figures import figstyle
from brushbem.figures.curve_axes import CurveScales, reference_limits
from brushbem.results import CaseResult
from brushbem.results.units import Units

__all__ = ["STAGES", "as_case_result", "draw_with_jumps", "plot_pull_off", "pull_off_figure"]

#: The snapshot stages of a pull-off (thesis Fig. 4-3), numbered on the figure in this order.
STAGES = ("max_preload", "zero_force", "adhesive_force", "half_detached", "before_separation")
#: How the stages are named in the figure's key.
STAGE_NAMES = {
    "max_preload": "maximum preload",
    "zero_force": "zero force",
    "adhesive_force": "adhesive force",
    "half_detached": "half of the pillars detached",
    "before_separation": "last contact before separation",
}
#: The ``gid`` of the stage numbers on the curve (and of the detached pillars' outlines on the map).
STAGE_GID = "stage-label"
DETACHED_GID = "detached-pillars"

_LOADING_COLOUR = figstyle.COLOURS[0]
_UNLOADING_COLOUR = figstyle.COLOURS[1]
_REFERENCE_COLOUR = "0.2"
_STAGE_COLOUR = "0.2"
_DETACHED_COLOUR = figstyle.COLOURS[1]
_MARKER_SIZE = 6.0  # points, the adhesive-force marker
#: The least diameter (points) at which the pressure map outlines each pillar: below it the outlines' ink
#: (0.5 to 0.7 points wide) would cover the pressure they enclose.
_LEAST_OUTLINED = 2.5


def plot_pull_off(
    result: Any,
    path: str | Path,
    reference: Mapping[str, Any] | None = None,
    *,
    units: Units | None = None,
    normalized: bool = False,
) -> Path:
    """Draw `pull_off_figure` and write it at ``path`` (a PNG at 300 dpi) with a PDF beside it.

    ``pulloff.png`` writes ``pulloff.png`` and ``pulloff.pdf``, each replaced
    atomically (`brushbem.figures.figstyle.save`).  Returns ``path``.
    """
    return figstyle.save(pull_off_figure(result, reference, units=units, normalized=normalized), path)


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


@figstyle.styled
def pull_off_figure(
    result: Any,
    reference: Mapping[str, Any] | None = None,
    *,
    ax: Axes | None = None,
    units: Units | None = None,
    normalized: bool = False,
) -> Figure:
    """Force against base displacement, as a `matplotlib.figure.Figure` (no pyplot, no window).

    The loading branch and the unloading (pull-off) branch are drawn in
    different colours, the adhesive-force point (the minimum force) and the
    five stages of thesis Fig. 4-3 are marked, numbered where no number
    covers another or the adhesive-force marker; a jump to separation (or
    into contact) is drawn as a vertical step, not a slope.  Where the
    detachment is a sliver of the curve an inset shows it enlarged (a box on
    the curve marks the region; no connectors).  Without ``ax``, the
    pressure on the contact set at the adhesive-force moment is drawn beside
    the curve, with every pillar of a brush outlined: solid and filled by the
    pressure where it is attached, dashed and hollow where it is not.

    The closed-form limits that ``summary.json`` records are drawn as dashed
    horizontal lines where they exist: a brush's F_c (rigid brush, eq. 4.5)
    and N_p F_K (every pillar at its Kendall force, eq. 7.4), a punch's or a
    sphere's closed-form adhesive force (Kendall, JKR) where no closed-form
    curve is given.  Numbers and axes take the SI prefix that reads
    (62.08 mN, not 6.208e+04 µN) where the configuration names units; without
    ``[units]`` the axes carry no unit and the title says once that the
    numbers are dimensionless.

    With ``normalized`` the axes are the thesis's: F/(N_p F_K) against
    d/|d_c| for a brush (eq. 7.4, 4.12), F/F_A and d/|d_A| of the closed form
    (Kendall, JKR) for a punch or a sphere.

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
    units : brushbem.results.units.Units, optional
        The unit system of the axis labels; by default the run's
        configuration's ``[units]`` (dimensionless without it).
    normalized : bool
        Draw the curve on normalised axes (above).

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    ValueError
        With ``normalized``, for a run whose summary records no closed form
        to normalise by.
    """
    if reference is None:
        reference = getattr(result, "reference", None)  # a PullOff's closed-form curve, as its figure() draws
    result = as_case_result(result)
    units = units if units is not None else Units.of_record(result.attributes)
    curve = result.curve
    summary = result.summary if isinstance(result.summary, Mapping) else {}
    theory = summary.get("theory") if isinstance(summary.get("theory"), Mapping) else {}
    displacement = np.asarray(curve.displacement, dtype=float)
    force = np.asarray(curve.force, dtype=float)
    loading = np.asarray(curve.loading, dtype=bool)
    scales = CurveScales.of(theory, units, displacement, force, normalized)
    displacement, force = displacement * scales.x, force * scales.y

    pattern = next((snap for snap in result.snapshots if snap.name == "adhesive_force"), None)
    map_axes = None
    if ax is not None:
        axes, figure = ax, ax.figure
    else:
        figure = Figure(figsize=(7.2, 3.9) if pattern is not None else (4.6, 3.9), layout="constrained")
        FigureCanvasAgg(figure)
        if pattern is not None:
            axes, map_axes = figure.subplots(1, 2, width_ratios=[1.3, 1.0])
        else:
            axes = figure.add_subplot()
    axes.axhline(0.0, color="0.7", linewidth=0.8)

    if reference is not None and not normalized:
        axes.plot(
            np.asarray(reference["displacement"], dtype=float) * scales.x,
            np.asarray(reference["force"], dtype=float) * scales.y,
            linestyle="--",
            color=_REFERENCE_COLOUR,
            linewidth=1.0,
            label=str(reference.get("label", "reference")),
        )
    # Lines across the curve's span (not axhline): the numbers and the inset see them as lines to keep off.
    span = (float(np.min(displacement)), float(np.max(displacement))) if displacement.size else (0.0, 1.0)
    for value, label, style in reference_limits(theory, reference is not None and not normalized):
        axes.plot(span, [-value * scales.y] * 2, color=_REFERENCE_COLOUR, linewidth=0.9, linestyle=style,
                  zorder=1, label=label)
    unloading = np.flatnonzero(~loading)
    if unloading.size:
        # Start the unloading line at the turning point so the branches join.
        start = max(int(unloading[0]) - 1, 0)
        rows = np.concatenate([[start], unloading]) if start < unloading[0] else unloading
        axes.plot(displacement[rows], force[rows], color=_UNLOADING_COLOUR, linewidth=1.2, label="unloading",
                  zorder=2)
    if np.any(loading):
        # Dashed on top of the unloading line: where the branches coincide both show.
        axes.plot(displacement[loading], force[loading], color=_LOADING_COLOUR, linewidth=1.4,
                  linestyle=(0, (3.0, 2.0)), label="loading", zorder=2.5)
    weakest = None
    if force.size:
        weakest = int(np.argmin(force))
        axes.plot(displacement[weakest], force[weakest], marker="o", markersize=_MARKER_SIZE, linestyle="none",
                  markerfacecolor="none", markeredgecolor="black", markeredgewidth=1.2, zorder=4,
                  label=rf"adhesive force $F_\mathrm{{A}}$ = {scales.force_text(-force[weakest] / scales.y, physical=True)}")

    stages = [(number, name, next((s for s in result.snapshots if s.name == name), None))
              for number, name in enumerate(STAGES, start=1)]
    reached = [(number, snapshot) for number, _, snapshot in stages if snapshot is not None]
    points = {number: (snapshot.displacement * scales.x, snapshot.force * scales.y) for number, snapshot in reached}
    for number, _ in reached:
        axes.plot(*points[number], marker=".", markersize=4, color=_STAGE_COLOUR, linestyle="none", zorder=3)
    # A stage the path does not pass through is said so; one that does not apply (half of the pillars of
    # a single body) is left out.
    missing = summary.get("stages_not_reached") or {}
    stage_key = [Line2D([], [], linestyle="none", marker=f"${number}$", markersize=6, color=_STAGE_COLOUR,
                        label=STAGE_NAMES[name] + (" (not reached)" if snapshot is None else ""))
                 for number, name, snapshot in stages if snapshot is not None or name in missing]

    axes.set_title(rf"$F_\mathrm{{A}}$ = {scales.force_text(summary.get('adhesive_force'), physical=True)},  "
                   rf"$W$ = {scales.energy_text(summary.get('work_of_separation'))}"
                   + ("  (dimensionless)" if units.dimensionless and not normalized else ""))
    axes.set_xlabel(scales.x_label)
    axes.set_ylabel(scales.y_label)
    curve_key = axes.get_legend_handles_labels()[0]
    pillar_key = _draw_pattern(map_axes, pattern, result, units) if map_axes is not None else []
    if ax is None:
        axes.xaxis.set_major_locator(MaxNLocator(nbins=6))  # tick labels apart at the figure's width
        # One key under the figure, a column each: the curves, the pillars, the stages.
        handles, columns = _columns([curve_key, pillar_key, stage_key])
        figure.legend(handles=handles, loc="outside lower center", ncols=columns, frameon=False,
                      handletextpad=0.5, columnspacing=1.5)
        engine = figure.get_layout_engine()
        if engine is not None:
            engine.execute(figure)  # the final positions, in which the numbers are placed
    elif curve_key:
        axes.legend(handles=curve_key + stage_key, loc="best")
    curve_pixels = _curve_pixels(axes)
    inset = _detachment_inset(axes, displacement, force, loading, curve_pixels)
    blocked = [inset.get_tightbbox(_renderer(axes))] if inset is not None else []
    if weakest is not None:
        blocked.append(_marker_box(axes, displacement[weakest], force[weakest], _MARKER_SIZE + 2.0))
    for number, _ in reached:
        blocked.append(_marker_box(axes, *points[number], 3.0))
    _place_labels(axes, [(str(number), *points[number]) for number, _ in reached], blocked, curve_pixels)
    return figure


def _columns(groups: Sequence[list[Any]]) -> tuple[list[Any], int]:
    """Legend handles that a legend of as many columns as non-empty ``groups`` shows one group a column.

    A legend fills its columns top to bottom: each group is padded with blank
    entries to the longest.
    """
    groups = [group for group in groups if group]
    rows = max((len(group) for group in groups), default=0)
    handles: list[Any] = []
    for group in groups:
        handles += group + [Line2D([], [], linestyle="none", label=" ") for _ in range(rows - len(group))]
    return handles, max(len(groups), 1)


def _number(value: Any) -> str:
    try:
        return f"{float(value):.4g}"
    except (TypeError, ValueError):
        return "nan"


def _unit(units: Units, dimension: str) -> str:
    """`` mm`` after a number where the units are known, else nothing (the numbers are dimensionless)."""
    return "" if units.dimensionless else f" {units.label(dimension)}"


def _root(axes: Axes) -> Figure:
    """The figure that holds ``axes``, through any subfigures (``SubFigure.figure`` is the root)."""
    return axes.figure.figure


def _renderer(axes: Axes):
    root = _root(axes)
    get = getattr(root.canvas, "get_renderer", None)
    return get() if callable(get) else root._get_renderer()


def _marker_box(axes: Axes, x: float, y: float, size_points: float) -> Bbox:
    """The display box of a marker of ``size_points`` at data (x, y)."""
    cx, cy = axes.transData.transform((x, y))
    half = 0.5 * size_points * _root(axes).dpi / 72.0
    return Bbox.from_extents(cx - half, cy - half, cx + half, cy + half)


def _curve_pixels(axes: Axes) -> np.ndarray:
    """Points along every line of ``axes`` (its data lines), every 3 pixels or closer, in display coordinates."""
    axes.get_xlim(), axes.get_ylim()  # the view limits are final
    samples = []
    for line in axes.get_lines():
        xy = np.column_stack([np.asarray(line.get_xdata(), float), np.asarray(line.get_ydata(), float)])
        if line.get_transform() != axes.transData or len(xy) < 2:
            continue
        xy = xy[np.all(np.isfinite(xy), axis=1)]
        if len(xy) < 2:
            continue
        pixels = axes.transData.transform(xy)
        lengths = np.hypot(*np.diff(pixels, axis=0).T)
        counts = np.clip(np.ceil(lengths / 3.0).astype(int), 1, 2000)
        starts = np.repeat(pixels[:-1], counts, axis=0)
        steps = np.repeat(np.diff(pixels, axis=0) / counts[:, None], counts, axis=0)
        fractions = np.concatenate([np.arange(c) for c in counts])[:, None]
        samples.append(np.vstack([starts + fractions * steps, pixels[-1:]]))
    return np.vstack(samples) if samples else np.empty((0, 2))


def _inside(points: np.ndarray, box: Bbox) -> int:
    if not len(points):
        return 0
    x, y = points[:, 0], points[:, 1]
    return int(np.count_nonzero((x >= box.x0) & (x <= box.x1) & (y >= box.y0) & (y <= box.y1)))


#: Where a stage number may sit around its point: distances (points) and directions, nearest first.
_OFFSETS = tuple((radius * math.cos(angle), radius * math.sin(angle))
                 for radius in (8.0, 13.0, 19.0, 27.0, 37.0)
                 for angle in np.radians((45, 135, -45, -135, 90, -90, 0, 180, 22.5, 157.5, -22.5, -157.5,
                                          67.5, 112.5, -67.5, -112.5)))


def _place_labels(axes: Axes, labels: Sequence[tuple[str, float, float]], blocked: list[Bbox],
                  curve_pixels: np.ndarray) -> None:
    """Number each point, each number where it covers no other number, no marker and, if it can, no line.

    Around its point the first free place wins (nearest first; a number set
    off further gets a leader line): covering another number or a marker
    is ruled out, the lines crossed count next, then the distance.  Every
    number stays inside the axes.
    """
    renderer = _renderer(axes)
    frame = axes.get_window_extent(renderer)
    taken = list(blocked)
    scale = _root(axes).dpi / 72.0
    for text, x, y in labels:
        label = axes.annotate(text, (x, y), xytext=(0.0, 0.0), textcoords="offset points", ha="center",
                              va="center", fontsize="small", color=_STAGE_COLOUR, zorder=6, gid=STAGE_GID,
                              annotation_clip=False)
        label.set_in_layout(False)
        best, best_score = _OFFSETS[0], None
        for dx, dy in _OFFSETS:
            label.xyann = (dx, dy)
            box = label.get_window_extent(renderer).padded(1.5 * scale)
            outside = not (frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1)
            covered = sum(box.overlaps(other) for other in taken) + int(outside)
            score = (covered, _inside(curve_pixels, box), math.hypot(dx, dy))
            if best_score is None or score < best_score:
                best, best_score = (dx, dy), score
            if score[:2] == (0, 0):
                break
        label.xyann = best
        taken.append(label.get_window_extent(renderer).padded(1.0 * scale))
        if math.hypot(*best) > 10.0:
            # Set off further than the nearest ring, a number gets a leader line to its point.
            leader = axes.annotate("", (x, y), xytext=best, textcoords="offset points", annotation_clip=False,
                                   arrowprops={"arrowstyle": "-", "color": "0.55", "linewidth": 0.5,
                                               "shrinkA": 5.0, "shrinkB": 2.5})
            leader.set_in_layout(False)


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


#: The detachment inset's sizes (axes fraction: width, height), the larger first.
_INSET_SIZES = ((0.34, 0.32), (0.27, 0.25))


def _inset_places(width: float, height: float) -> list[tuple[float, float, float, float]]:
    """Places (left, bottom, width, height in axes fraction) for an inset, the corners first."""
    lefts = np.arange(0.03, 0.97 - width + 1e-9, 0.04)
    bottoms = np.arange(0.03, 0.97 - height + 1e-9, 0.04)
    places = [(float(left), float(bottom), width, height) for left in lefts for bottom in bottoms]
    corners = [(lefts[0], bottoms[0]), (lefts[0], bottoms[-1]), (lefts[-1], bottoms[0]), (lefts[-1], bottoms[-1])]
    return sorted(places, key=lambda p: (min(math.hypot(p[0] - x, p[1] - y) for x, y in corners), -p[1], p[0]))


def _draw_inset(axes: Axes, place: Sequence[float], displacement: np.ndarray, force: np.ndarray,
                limits: tuple[float, float, float, float]) -> Axes:
    """The detachment's states ``displacement``, ``force`` on an inset at ``place`` within ``limits``."""
    inset = axes.inset_axes(list(place))
    inset.set_in_layout(False)
    inset.plot(displacement, force, color=_UNLOADING_COLOUR, linewidth=1.0)
    inset.set_xlim(limits[0], limits[1])
    inset.set_ylim(limits[2], limits[3])
    inset.set_title("detachment, enlarged", fontsize="x-small")
    inset.tick_params(labelsize="x-small")
    inset.xaxis.set_major_locator(MaxNLocator(nbins=2))
    inset.yaxis.set_major_locator(MaxNLocator(nbins=3))
    inset.grid(True)
    return inset


def _detachment_inset(axes: Axes, displacement: np.ndarray, force: np.ndarray, loading: np.ndarray,
                      curve_pixels: np.ndarray) -> Axes | None:
    """An inset around the detachment (the states near the adhesive force) when it is a sliver of the curve.

    It goes where it, its tick labels and its title cover no line and stay
    inside the axes (the place nearest a corner of those free), and is left
    out where there is no such place; a box on the curve marks the region it
    enlarges (no connectors, which would cross the curve).
    """
    unloading = np.flatnonzero(~loading)
    if unloading.size < 3 or not np.any(force < 0):
        return None
    near = unloading[force[unloading] <= 0.7 * float(force.min())]
    span = float(np.ptp(displacement)) or 1.0
    if near.size < 2:
        return None
    lo, hi = float(displacement[near].min()), float(displacement[near].max())
    if hi - lo > 0.2 * span or hi == lo:
        return None
    rows = np.arange(max(int(near[0]) - 1, 0), min(int(near[-1]) + 2, force.size))
    margin = 0.1 * (hi - lo)
    low, high = float(force[near].min()), float(force[near].max())
    pad = max(0.15 * (high - low), 0.01 * abs(low))
    limits = (lo - margin, hi + margin, low - pad, high + pad)
    renderer = _renderer(axes)
    frame = axes.get_window_extent(renderer)
    for width, height in _INSET_SIZES:
        # What the tick labels and the title add around the inset, measured once for this size.
        probe = _draw_inset(axes, (0.3, 0.3, width, height), displacement[rows], force[rows], limits)
        inner, outer = probe.get_window_extent(renderer), probe.get_tightbbox(renderer).padded(2.0)
        probe.remove()
        for place in _inset_places(width, height):
            box = Bbox(axes.transAxes.transform([place[:2], (place[0] + width, place[1] + height)]))
            box = Bbox.from_extents(box.x0 - (inner.x0 - outer.x0), box.y0 - (inner.y0 - outer.y0),
                                    box.x1 + (outer.x1 - inner.x1), box.y1 + (outer.y1 - inner.y1))
            if (frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1
                    and _inside(curve_pixels, box) == 0):
                inset = _draw_inset(axes, place, displacement[rows], force[rows], limits)
                axes.add_patch(Rectangle((limits[0], limits[2]), limits[1] - limits[0], limits[3] - limits[2],
                                         fill=False, edgecolor="0.4", linewidth=0.6, zorder=5))
                return inset
    return None


def _attached(snapshot, pillars: Mapping[str, np.ndarray], element_size: float) -> np.ndarray:
    """Whether every pillar has an element in contact in ``snapshot`` (its footprint: the disc of its area)."""
    contact = np.asarray(snapshot.contact, dtype=bool)
    n = contact.shape[0]
    half = 0.5 * n * element_size
    centres = -half + (np.arange(n) + 0.5) * element_size
    radius = np.sqrt(np.asarray(pillars["elements"], float) * element_size**2 / math.pi)
    attached = np.zeros(len(radius), dtype=bool)
    for i, (x, y, r) in enumerate(zip(pillars["x"], pillars["y"], radius)):
        reach = r + 0.5 * element_size
        columns = np.flatnonzero(np.abs(centres - x) <= reach)
        rows = np.flatnonzero(np.abs(centres - y) <= reach)
        if not (columns.size and rows.size):
            continue
        inside = np.hypot(*np.meshgrid(centres[columns] - x, centres[rows] - y)) <= reach
        attached[i] = bool(np.any(contact[np.ix_(rows, columns)] & inside))
    return attached


def _draw_pattern(axes: Axes, snapshot, result: CaseResult, units: Units) -> list[Any]:
    """The pressure on the contact set at the adhesive-force moment (grey: not in contact), every pillar outlined.

    Returns the legend entries of the pillars (none for a single body).
    """
    from matplotlib.collections import PatchCollection

    element_size = float(result.element_size)
    pressure = np.asarray(snapshot.pressure, dtype=float)
    contact = np.asarray(snapshot.contact, dtype=bool)
    n = pressure.shape[0]
    half = 0.5 * n * element_size
    shown = np.ma.masked_where(~contact, pressure)
    limit = float(np.max(np.abs(pressure[contact]))) if contact.any() else 1.0
    limit = limit or 1.0
    axes.set_facecolor("0.88")
    axes.grid(False)
    image = axes.imshow(
        shown, origin="lower", extent=(-half, half, -half, half), cmap="RdBu_r",
        vmin=-limit, vmax=limit, interpolation="nearest",
    )
    axes.figure.colorbar(
        image, ax=axes, shrink=0.85, label=figstyle.axis_label(r"pressure $p$", "stress", units))
    axes.set_title(rf"contact at $F_\mathrm{{A}}$: $d$ = {snapshot.displacement:.4g}{_unit(units, 'length')}")
    axes.set_xlabel(figstyle.axis_label("$x$", "length", units))
    axes.set_ylabel(figstyle.axis_label("$y$", "length", units))
    pillars = result.pillars or {}
    if not all(key in pillars for key in ("x", "y", "elements")) or len(pillars["x"]) < 2:
        return [Patch(facecolor="0.88", edgecolor="0.6", label="not in contact")]
    radius = np.sqrt(np.asarray(pillars["elements"], float) * element_size**2 / math.pi)
    # Outlines denser than their own ink hide what they enclose: at 10^4-10^5 pillars the map would be
    # black.  They are drawn only where a pillar, and the spacing of the pillars (the side over sqrt(N_p)),
    # span at least `_LEAST_OUTLINED` points on the map.
    figure = _root(axes)
    points_per_length = axes.get_position().width * figure.get_figwidth() * 72.0 / (2.0 * half)
    spacing = 2.0 * half / math.sqrt(len(radius))
    if min(2.0 * float(np.median(radius)), spacing) * points_per_length < _LEAST_OUTLINED:
        axes.set_xlim(-half, half)
        axes.set_ylim(-half, half)
        return [Patch(facecolor="0.88", edgecolor="none", label="not in contact"),
                Patch(facecolor="none", edgecolor="none",
                      label=f"{len(radius)} pillars (too small to outline)")]
    attached = _attached(snapshot, pillars, element_size)
    circles = [Circle((float(x), float(y)), float(r)) for x, y, r in zip(pillars["x"], pillars["y"], radius)]
    entries = []
    if attached.any():
        axes.add_collection(PatchCollection([c for c, on in zip(circles, attached) if on], facecolors="none",
                                            edgecolors="0.1", linewidths=0.5, label="attached pillars",
                                            zorder=3))
    entries.append(Patch(facecolor=image.cmap(0.3), edgecolor="0.1", linewidth=0.5,
                         label="attached pillar (colour: pressure)"))
    if not attached.all():
        detached = PatchCollection([c for c, on in zip(circles, attached) if not on], facecolors="none",
                                   edgecolors=_DETACHED_COLOUR, linewidths=0.7, linestyles="--",
                                   label="detached pillars", zorder=3)
        detached.set_gid(DETACHED_GID)
        axes.add_collection(detached)
    entries.append(Patch(facecolor="none", edgecolor=_DETACHED_COLOUR, linestyle="--", linewidth=0.7,
                         label="detached pillar (not in contact)"))
    axes.set_xlim(-half, half)
    axes.set_ylim(-half, half)
    return entries
