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
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from brushbem.io import atomic_path
from brushbem.results import CaseResult

__all__ = ["STAGES", "plot_pull_off", "pull_off_figure"]

#: The snapshot stages of a pull-off (thesis Fig. 4-3), numbered on the figure in this order.
STAGES = ("max_preload", "zero_force", "adhesive_force", "half_detached", "before_separation")

_LOADING_COLOUR = "tab:blue"
_UNLOADING_COLOUR = "tab:red"
_REFERENCE_COLOUR = "0.2"


def plot_pull_off(
    result: CaseResult,
    path: str | Path,
    reference: Mapping[str, Any] | None = None,
) -> None:
    """Draw `pull_off_figure` and save it as a PNG at ``path`` (replaced atomically)."""
    figure = pull_off_figure(result, reference)
    with atomic_path(path) as temporary:
        figure.savefig(temporary, format="png", dpi=150)


def pull_off_figure(result: CaseResult, reference: Mapping[str, Any] | None = None) -> Figure:
    """Force against base displacement, as a `matplotlib.figure.Figure` (no pyplot, no window).

    The loading branch and the unloading (pull-off) branch are drawn in
    different colours and the adhesive-force point (the minimum force) is
    marked.  Beside the curve: the pressure on the contact set at the
    adhesive-force moment (the detachment pattern).

    Parameters
    ----------
    result : CaseResult
        The run; its ``curve`` is drawn (displacement in units of length,
        force in units of force, compressive positive).
    reference : mapping, optional
        A closed-form curve drawn dashed: ``displacement`` and ``force``
        (array-like of equal length, same units as the curve) and ``label``
        (str).
    """
    curve = result.curve
    displacement = np.asarray(curve.displacement, dtype=float)
    force = np.asarray(curve.force, dtype=float)
    loading = np.asarray(curve.loading, dtype=bool)

    pattern = next((snap for snap in result.snapshots if snap.name == "adhesive_force"), None)
    figure = Figure(figsize=(11.0, 4.8) if pattern is not None else (6.4, 4.8), layout="constrained")
    FigureCanvasAgg(figure)
    if pattern is not None:
        axes, map_axes = figure.subplots(1, 2, width_ratios=[1.35, 1.0])
        _draw_pattern(map_axes, pattern, float(result.element_size))
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
    axes.set_xlabel("base displacement d (presses > 0; units of the inputs' length)")
    axes.set_ylabel("force F (compressive > 0; units of the inputs)")
    axes.grid(True, linewidth=0.4, alpha=0.5)
    if axes.get_legend_handles_labels()[0]:
        axes.legend(loc="best", fontsize="small")
    return figure


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


def _draw_pattern(axes, snapshot, element_size: float) -> None:
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
    axes.figure.colorbar(image, ax=axes, shrink=0.8, label="p (compressive > 0)")
    axes.set_title(f"contact at the adhesive force (d = {snapshot.displacement:.4g})", fontsize="small")
    axes.set_xlabel("x")
    axes.set_ylabel("y")
