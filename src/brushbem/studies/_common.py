"""Helpers shared by the chapter 2-4 studies (not a study: no ``STUDY``)."""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr
from matplotlib.figure import Figure

from brushbem.figures import figstyle
from brushbem.studies.base import finished as finished_rows

NAN = float("nan")


def finished(results: Mapping[str, pd.DataFrame], part: str) -> pd.DataFrame:
    """The finished cases of one part (``base.finished``), renumbered from 0.

    An empty frame, without columns, when the part is missing or has no status.
    """
    frame = results.get(part)
    if frame is None or len(frame) == 0 or "status" not in frame:
        return pd.DataFrame()
    return finished_rows(frame).reset_index(drop=True)


def case_path(row: pd.Series, part: str, figures_dir: Path) -> Path:
    """The case file of a summary row: its ``case_file`` column, else DIR/<part>/cases/<id>.nc."""
    if "case_file" in row and isinstance(row["case_file"], str):
        return Path(row["case_file"])
    return Path(figures_dir).parent / part / "cases" / f"{row['case_id']}.nc"


def open_case(row: pd.Series, part: str, figures_dir: Path) -> xr.Dataset | None:
    """The case dataset, fully loaded, or None when the file is not there."""
    path = case_path(row, part, figures_dir)
    if not path.exists():
        return None
    with xr.open_dataset(path) as ds:
        return ds.load()


def case_config(ds: xr.Dataset) -> dict[str, Any]:
    return json.loads(ds.attrs["config"])


def column(frame: pd.DataFrame, key: str) -> np.ndarray:
    """A float column (NaN where absent); "inf" strings become inf."""
    if key not in frame:
        return np.full(len(frame), NAN)
    return pd.to_numeric(frame[key].replace({"inf": math.inf}), errors="coerce").to_numpy(dtype=float)


def new_figure(ncols: int = 1, nrows: int = 1, width: float = 4.2, height: float = 3.4):
    """A figure of ``nrows`` x ``ncols`` panels of ``width`` x ``height`` inches, in brushbem's look.

    Draw inside `brushbem.figures.figstyle.style` (a study's ``draw`` is `styled`) so
    that every line and text takes the look too.
    """
    fig = figstyle.new_figure(width * ncols, height * nrows)
    with figstyle.style():
        axes = fig.subplots(nrows, ncols, squeeze=False)
    return fig, axes


def save(fig: Figure, path: Path) -> Path:
    """Write ``fig`` at ``path`` (a PNG at 300 dpi) with a PDF beside it, atomically; returns ``path``."""
    return figstyle.save(fig, path)


def mark(ax, x: float, y: float, label: str | None) -> None:
    """Mark a number the thesis states: a red star with its label."""
    ax.plot([x], [y], marker="*", color="red", markersize=10, linestyle="none", zorder=5,
            label=label)


def safe(compute):
    """Wrap a ThesisNumber compute so a missing part or column gives NaN instead of raising."""

    def wrapped(results):
        try:
            value = float(compute(results))
        except (KeyError, IndexError, ValueError, TypeError, ZeroDivisionError):
            return NAN
        return value

    return wrapped
