"""Beyond the thesis (its ch. 4 question past 2304 pillars): F~_A and the work against the number of pillars.

The ``size`` study runs square lattices of 64 to 10^4 flat pillars (the
level and rough brushes also 316 x 316, 10^5) at the ch. 4 filling factor
phi = 0.12 (sweep files written by ``docs/studies/make_size_sweeps.py``) by the pillar-level model
(``protocol.method = "pillars"``, validated against the exact event path in
``docs/pillars/validation.md``): stiff (k~ = 10), soft (k~ = 1e-2) and softer
(k~ = 1e-4) brushes of level tips, and soft brushes of Gaussian lengths
sigma~ = 0.1 and 1.  Its figures, in the thesis's normalisations:

* ``size_force.png``: F~_A = F_A / F_K (eq. 4.11, F_K of the compact punch of
  the same real area) against N_p for the level brushes, with the rigid
  limit phi^-1/4 (eq. 4.9) and the soft one N_p^1/4 (eq. 4.10); and F_A / F_c
  (the rigid flat brush's force, eq. 5.3) against N_p for the soft brushes,
  level and rough.
* ``size_work.png``: W~ = W / W_K (eq. 4.15, W_K = 2 dgamma A) against N_p,
  with eq. 4.18 (W~_S = N_p^-1/2 phi^1/2 / k~) for the soft brushes.

The thesis states no numbers beyond 2304 pillars; its own statement (sec.
4.3) is that the plateau follows N^1/4 with an amplitude 1.2-1.3 times below
eq. 4.10, which the ``verdict`` of this study's page reads off the fitted
exponent and amplitude.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

import numpy as np
import pandas as pd
from matplotlib.ticker import FormatStrFormatter, NullFormatter

from brushbem.studies._ch5_7 import empty_note, figure, finished, has, save
from brushbem.studies.base import Study
from brushbem.figures.figstyle import styled
from brushbem.results.columns import summary_column

PARTS = ("stiff", "soft", "softer", "rough_small", "rough_large")
LEVEL = ("stiff", "soft", "softer")
LABELS = {"stiff": r"$\tilde k$ = 10", "soft": r"$\tilde k$ = $10^{-2}$", "softer": r"$\tilde k$ = $10^{-4}$",
          "rough_small": r"$\tilde k$ = $10^{-2}$, $\tilde\sigma$ = 0.1",
          "rough_large": r"$\tilde k$ = $10^{-2}$, $\tilde\sigma$ = 1"}
N_P = summary_column("normalized.pillars")
PHI = summary_column("normalized.filling_factor")
F_COMPACT = summary_column("normalized.force_by_compact_punch")
F_RIGID = summary_column("normalized.force_by_rigid_brush")
K_RATIO = summary_column("normalized.stiffness_ratio")
DGAMMA = "halfspace.work_of_adhesion"


def power_law(frame: pd.DataFrame, column: str) -> tuple[float, float]:
    """(exponent, amplitude) of the least-squares line log column = log amplitude + exponent log N_p."""
    x, y = np.log(frame[N_P].to_numpy(float)), np.log(frame[column].to_numpy(float))
    exponent, intercept = np.polyfit(x, y, 1)
    return float(exponent), float(np.exp(intercept))


def work_tilde(frame: pd.DataFrame) -> np.ndarray:
    """W~ = W / (2 dgamma A), A = phi L^2 the real area (L = 1, the sweeps' unit square)."""
    dgamma = frame[DGAMMA].to_numpy(float) if DGAMMA in frame else np.full(len(frame), 1e-4)
    return frame["work_of_separation"].to_numpy(float) / (2.0 * dgamma * frame[PHI].to_numpy(float))


def _plain_ticks(ax, counts: list[float]) -> None:
    """Log axes labelled with plain numbers instead of powers of ten; the pillar counts as the x ticks."""
    if counts:
        # Every pillar count as a tick, labelled where the labels do not crowd: at least a tenth of the
        # axis's decades apart (a factor 1.7 over 64 to 10^4 pillars, 2.1 up to 10^5), from the largest down.
        counts = sorted(counts)
        apart = max(1.7, (counts[-1] / counts[0]) ** 0.1)
        labelled = [counts[-1]]
        for count in counts[-2::-1]:
            if count * apart <= labelled[-1]:
                labelled.append(count)
        ax.set_xticks(counts, [f"{count:g}" if count in labelled else "" for count in counts])
    if ax.get_yscale() == "log" and ax.lines:
        low, high = ax.get_ylim()
        if high > 100 * low:
            # Several decades: the powers of ten.
            ticks = 10.0 ** np.arange(np.ceil(np.log10(low)), np.floor(np.log10(high)) + 1)
        else:
            ticks = np.unique([float(f"{tick:.2g}") for tick in np.geomspace(low, high, 5)])
        ax.set_yticks(ticks[(ticks >= low) & (ticks <= high)])
    for axis in (ax.xaxis, ax.yaxis):
        if axis.get_scale() == "log":
            if axis is ax.yaxis or not counts:
                axis.set_major_formatter(FormatStrFormatter("%g"))
            axis.set_minor_formatter(NullFormatter())


@styled
def _draw(results: Mapping[str, pd.DataFrame], figures_dir: Path) -> list[Path]:
    written: list[Path] = []
    frames = {part: finished(results, part) for part in PARTS}
    frames = {part: frame.sort_values(N_P) for part, frame in frames.items() if has(frame, N_P, F_COMPACT)}
    counts = sorted({float(n) for frame in frames.values() for n in frame[N_P]})
    fig, ax = figure(2, 1)
    if not frames:
        empty_note(ax[0, 0])
        empty_note(ax[0, 1])
    for part in LEVEL:
        if part in frames:
            frame = frames[part]
            ax[0, 0].plot(frame[N_P], frame[F_COMPACT], "o-", ms=4, label=LABELS[part])
    if frames:
        phi = float(np.mean([frame[PHI].mean() for frame in frames.values()]))
        ax[0, 0].plot(counts, np.asarray(counts)**0.25, "k--", lw=0.9, label=r"$N_\mathrm{p}^{1/4}$ (eq. 4.10)")
        ax[0, 0].axhline(phi**-0.25, ls=":", color="0.4", lw=0.9, label=r"$\varphi^{-1/4}$ (eq. 4.9)")
    ax[0, 0].set(xscale="log", yscale="log", xlabel=r"pillars $N_\mathrm{p}$",
                 ylabel=r"$\tilde F_\mathrm{A} = F_\mathrm{A}/F_\mathrm{K}$ (eq. 4.11)", title="Level tips")
    for part in ("soft", "rough_small", "rough_large"):
        if part in frames and has(frames[part], F_RIGID):
            frame = frames[part]
            ax[0, 1].plot(frame[N_P], frame[F_RIGID], "o-", ms=4, label=LABELS[part])
    # Logarithmic in F_A / F_c too: the sigma~ = 1 brush falls by four decades.
    ax[0, 1].set(xscale="log", yscale="log", xlabel=r"pillars $N_\mathrm{p}$",
                 ylabel=r"$F_\mathrm{A}/F_\mathrm{c}$ (eq. 5.3)", title="Soft brushes, level and rough")
    for a_ in ax[0]:
        _plain_ticks(a_, counts)
        if a_.lines:
            a_.legend(fontsize="small")
    save(fig, Path(figures_dir) / "size_force.png", written)
    fig, ax = figure(1, 1)
    if not frames:
        empty_note(ax[0, 0])
    for part, frame in frames.items():
        line, = ax[0, 0].plot(frame[N_P], work_tilde(frame), "o-", ms=4, label=LABELS[part])
        if part in ("soft", "softer") and has(frame, K_RATIO):
            estimate = frame[N_P] ** -0.5 * frame[PHI] ** 0.5 / frame[K_RATIO]
            ax[0, 0].plot(frame[N_P], estimate, "--", color=line.get_color(), lw=0.9)
    ax[0, 0].set(xscale="log", yscale="log", xlabel=r"pillars $N_\mathrm{p}$",
                 ylabel=r"$\tilde W = W/W_\mathrm{K}$ (eq. 4.15)", title="dashed: eq. 4.18")
    _plain_ticks(ax[0, 0], counts)
    if ax[0, 0].lines:
        ax[0, 0].legend(fontsize="small")
    save(fig, Path(figures_dir) / "size_work.png", written)
    return written


SIZE = Study(
    name="size",
    title="Beyond the thesis: F~_A and the work against the number of pillars (64 to 10^4, rough to 10^5)",
    figures=(),
    parts=PARTS,
    draw=_draw,
    draw_tables=_draw,
    notes="No thesis numbers beyond 2304 pillars; runs the pillar-level model (docs/pillars/validation.md).",
)
