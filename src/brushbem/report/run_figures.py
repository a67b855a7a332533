"""The figures of a run's report: the run's own ``pulloff.png`` read safely, and the snapshot panels.

`own_png` embeds only a regular PNG file of the run folder (never a link, a hard link or another kind of
file); `snapshots_figure` draws the pressure on the contact set at every stage on one colour scale.
"""

from __future__ import annotations

import base64
import io
import os
import stat
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from brushbem.results.units import Units

__all__ = ["axis_label", "figure_png", "own_png", "png_uri", "snapshots_figure"]


def png_uri(data: bytes) -> str:
    return "data:image/png;base64," + base64.b64encode(data).decode("ascii")


def figure_png(figure: Any, dpi: int = 110) -> bytes:
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png", dpi=dpi)
    return buffer.getvalue()


#: The PNG signature: the first bytes of every PNG file.
_PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
#: The largest pulloff.png embedded (bytes); the run's own is about 0.3 MB at 300 dpi.
_MAX_FIGURE_BYTES = 32 * 2**20


def own_png(path: Path) -> tuple[bytes | None, str]:
    """The bytes of ``path`` where it is a regular PNG file of its folder (opened without following a link).

    Returns (None, why) for a link, anything but a regular file, a file with other names (a hard link), a
    file that is not a PNG or is too large: a report made to be shared embeds nothing but the run's figure.
    """
    flags = os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0)
    try:
        if stat.S_ISLNK(os.lstat(path).st_mode):
            return None, f"{path.name} is a link"
        handle = os.open(path, flags)
    except FileNotFoundError:
        return None, f"no {path.name}"
    except OSError as exc:
        return None, f"{path.name} cannot be opened ({exc.strerror or exc})"
    try:
        opened = os.fstat(handle)
        if not stat.S_ISREG(opened.st_mode):
            return None, f"{path.name} is not a regular file"
        if opened.st_nlink != 1:
            return None, f"{path.name} is a hard link (a file with other names)"
        if opened.st_size > _MAX_FIGURE_BYTES:
            return None, f"{path.name} is larger than {_MAX_FIGURE_BYTES // 2**20} MiB"
        with os.fdopen(handle, "rb", closefd=False) as stream:
            data = stream.read(_MAX_FIGURE_BYTES + 1)
    except OSError as exc:
        return None, f"{path.name} cannot be read ({exc.strerror or exc})"
    finally:
        os.close(handle)
    if not data.startswith(_PNG_SIGNATURE):
        return None, f"{path.name} is not a PNG file"
    return data, ""


def axis_label(units: Units, name: str, dimension: str) -> str:
    """An axis label with its unit; without one where the configuration names none (the report says so once)."""
    return name if units.dimensionless else f"{name} ({units.label(dimension)})"


def snapshots_figure(result: Any, units: Units, order: Sequence[str]) -> tuple[Any, float]:
    """The pressure on the contact set at the stages ``order``, one panel each, on one colour scale.

    Returns the figure and the largest |p| on a contact (the colour scale's half-width; 0 where every
    pressure on the contact is zero: then the panels show the contact in grey and there is no colour bar).
    """
    import numpy as np
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    from brushbem.figures.plot import STAGES

    recorded = {snapshot.name: snapshot for snapshot in result.snapshots}
    figure = Figure(figsize=(3.0 * len(order) + 0.8, 3.3), layout="constrained")
    FigureCanvasAgg(figure)
    axes = figure.subplots(1, len(order), squeeze=False)[0]
    h = float(result.element_size)
    # One colour scale for every panel, so that the panels compare; none where every pressure on the
    # contact is zero (a colour bar would scale round-off).
    largest = max((float(np.max(np.abs(np.asarray(s.pressure, float)[np.asarray(s.contact, bool)])))
                   for s in recorded.values() if np.any(s.contact)), default=0.0)
    image = None
    for ax, name in zip(axes, order):
        snapshot = recorded[name]
        pressure = np.asarray(snapshot.pressure, dtype=float)
        contact = np.asarray(snapshot.contact, dtype=bool)
        half = 0.5 * pressure.shape[0] * h
        ax.set_facecolor("0.85")
        ax.grid(False)
        if largest > 0.0:
            image = ax.imshow(np.ma.masked_where(~contact, pressure), origin="lower", cmap="RdBu_r",
                              vmin=-largest, vmax=largest, interpolation="nearest",
                              extent=(-half, half, -half, half))
        else:
            ax.imshow(np.ma.masked_where(~contact, np.zeros_like(pressure)), origin="lower", cmap="Greys",
                      vmin=-1.0, vmax=1.0, interpolation="nearest", extent=(-half, half, -half, half))
        number = STAGES.index(name) + 1 if name in STAGES else "-"
        ax.set_title(f"{number}: {name.replace('_', ' ')}", fontsize="small")
        ax.set_xlabel(axis_label(units, "x", "length"), fontsize="small")
        ax.set_ylabel(axis_label(units, "y", "length") if ax is axes[0] else "", fontsize="small")
        ax.tick_params(labelsize="x-small")
    if image is not None:
        bar = figure.colorbar(image, ax=list(axes), shrink=0.75)
        bar.set_label(axis_label(units, "p, compressive > 0", "stress"), fontsize="small")
        bar.ax.tick_params(labelsize="x-small")
    return figure, largest
