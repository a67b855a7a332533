"""Shared helpers of the chapter 5-7 studies (rough, hierarchical and concave brushes)."""

from __future__ import annotations

import hashlib
import math
from collections import OrderedDict
from collections.abc import Mapping
from pathlib import Path

import numpy as np
import pandas as pd
from matplotlib.figure import Figure

from brushbem.studies._common import case_path as common_case_path
from brushbem.studies._common import finished, new_figure  # noqa: F401 (finished: re-exported)
from brushbem.studies._common import save as save_figure
from brushbem.results.columns import summary_column

FA = summary_column("normalized.force_by_rigid_brush")
FP = summary_column("normalized.preload_by_rigid_brush")
SIG = summary_column("normalized.roughness_by_rigid_brush")
K = "indenter.stiffness_ratio"
SIGMA = "indenter.roughness.sigma"
PRELOAD = "protocol.preload_force"
FIS = summary_column("normalized.force_by_ideal_sharing")
H = "indenter.profile.amplification"
REGION = "indenter.region"
RADIUS = "indenter.pillar_radius"

#: Mathtext of the chapters' normalised quantities (eq. 5.3-5.5, 7.4).
K_TEXT = r"$\tilde k$"
K_DEFINED = r"$\tilde k = k/(E^* L)$"
SIGMA_TEXT = r"$\tilde\sigma$"
FA_TEXT = r"$\tilde F_\mathrm{A}$"
FP_TEXT = r"$\tilde F_\mathrm{P}$"


def figure(ncols: int = 1, nrows: int = 1, size=(4.2, 3.4)):
    """``new_figure`` with the chapter 5–7 panel size."""
    return new_figure(ncols, nrows, *size)


def save(fig: Figure, path: Path, written: list[Path]) -> None:
    """Write the figure atomically (``_common.save``) and append its path to ``written``."""
    written.append(save_figure(fig, path))


def key_below(fig: Figure, ax) -> None:
    """The legend of ``ax`` under the figure, where long entries cover no point and no tick label."""
    fig.legend(*ax.get_legend_handles_labels(), loc="outside lower center", frameon=False, fontsize="small")


def empty_note(ax, text: str = "no finished cases") -> None:
    ax.text(0.5, 0.5, text, transform=ax.transAxes, ha="center", va="center", color="0.4")


def has(frame: pd.DataFrame, *columns: str) -> bool:
    return len(frame) > 0 and all(c in frame.columns for c in columns)


def mean_std(frame: pd.DataFrame, keys: list[str], value: str, x: str | None = None) -> pd.DataFrame:
    """Mean and standard deviation of ``value`` (and the mean of ``x``) over realizations."""
    agg = {"mean": (value, "mean"), "std": (value, "std"), "count": (value, "size")}
    if x is not None:
        agg["x"] = (x, "mean")
    out = frame.groupby(keys, dropna=False).agg(**agg).reset_index()
    out["std"] = out["std"].fillna(0.0)
    return out


#: F~_A at the smallest preload of a group at this fraction of the group's largest mean F~_A or
#: more is saturated: the group samples no linear region, and its c is undefined (NaN).
SATURATED = 0.9


#: Results of `adhesion_coefficients` by the content of the columns they read (least recently used last out).
_COEFFICIENTS: OrderedDict[tuple, pd.DataFrame] = OrderedDict()
_COEFFICIENTS_KEPT = 64


def adhesion_coefficients(frame: pd.DataFrame, keys: list[str]) -> pd.DataFrame:
    """c = F~_A / F~_P in the linear region: at the smallest preload of each group (eq. 5.6).

    Returns one row per group with ``c`` (mean over realizations), ``sigma`` (sigma~),
    ``plateau`` (each realization's largest F~_A over the preloads, averaged over the
    realizations: a realization sampled at fewer preloads, the plateau's largest only,
    counts alike, and the mean is that of the per-seed values whose spread is the
    standard error) and ``largest_preload`` (the largest mean F~_P, which tells
    whether ``plateau`` is one).  ``c`` is NaN where the
    group's smallest preload already gives `SATURATED` of its largest force: a group
    sampled only at plateau preloads (the sampled sweep ships such groups
    for the plateaus) has no linear region to read c from.
    """
    columns = [*keys, "c", "sigma", "plateau", "largest_preload"]
    if not has(frame, FA, FP, PRELOAD):
        return pd.DataFrame(columns=columns)
    # The comparison and the row planning read one table's coefficients for many numbers and
    # realisation subsets: a result is kept by the content of the columns it reads, rows in order
    # (a mean's last bits depend on it), so a repeated call returns a copy of the same frame.
    read = [c for c in dict.fromkeys([*keys, FA, FP, PRELOAD, SIG, "realization"]) if c in frame.columns]
    rows = pd.util.hash_pandas_object(frame[read], index=False).to_numpy()
    key = (tuple(keys), tuple(read), tuple(str(frame[c].dtype) for c in read),
           hashlib.blake2b(rows.tobytes(), digest_size=16).digest())
    if key in _COEFFICIENTS:
        _COEFFICIENTS.move_to_end(key)
        return _COEFFICIENTS[key].copy()
    out = _coefficients(frame, keys, columns)
    _COEFFICIENTS[key] = out.copy()
    if len(_COEFFICIENTS) > _COEFFICIENTS_KEPT:
        _COEFFICIENTS.popitem(last=False)
    return out


def _coefficients(frame: pd.DataFrame, keys: list[str], columns: list[str]) -> pd.DataFrame:
    """`adhesion_coefficients` computed."""
    # One pass of groupbys over every group (a loop of per-group aggregations is 100 x slower).
    frame = frame.assign(_ratio=frame[FA] / frame[FP], _sig=frame.get(SIG, math.nan))
    groups = frame.groupby(keys, dropna=False, sort=True)
    smallest = frame[frame[PRELOAD] == groups[PRELOAD].transform("min")].groupby(keys, dropna=False, sort=True)
    means = frame.groupby([*keys, PRELOAD], dropna=False).agg(fa=(FA, "mean"), fp=(FP, "mean"))
    by_group = means.groupby(level=list(range(len(keys))), dropna=False, sort=True)
    if "realization" in frame.columns:
        largest = frame.groupby([*keys, "realization"], dropna=False)[FA].max()
        plateau = largest.groupby(level=list(range(len(keys))), dropna=False, sort=True).mean()
    else:
        plateau = by_group["fa"].max()
    out = pd.DataFrame({
        "c": smallest["_ratio"].mean(),
        "sigma": groups["_sig"].mean(),
        "plateau": plateau,
        "largest_preload": by_group["fp"].max(),
        "_preloads": by_group["fa"].size(),
        "_smallest": smallest[FA].mean(),
    })
    saturated = (out["_preloads"] > 1) & (out["_smallest"] >= SATURATED * out["plateau"])
    out.loc[saturated, "c"] = math.nan
    out = out.drop(columns=["_preloads", "_smallest"]).reset_index()
    return out[columns].astype({"c": float, "sigma": float, "plateau": float, "largest_preload": float})


def fit_eq58(sigma: np.ndarray, c: np.ndarray, weighting: str = "relative") -> tuple[float, float]:
    """alpha, beta of eq. 5.8, c = alpha / sigma~ - beta, by linear least squares.

    The model is linear in (alpha, beta), so the fit is ``numpy.linalg.lstsq``
    on the columns 1/sigma~ and -1 (exact through two points).  Only points
    with sigma~ > 0 and c > 0 (the adhering side) enter; NaN when fewer than
    two distinct sigma~ remain.

    ``weighting = "relative"`` (the default) minimises the relative residuals
    sum((alpha/sigma~ - beta)/c - 1)^2: c spans four decades over sigma~ = 0.01
    to 3 (Fig. 5-5 b draws it, and the fit, in double-logarithmic coordinates),
    and beta, which sets sigma~_c = alpha/beta, is read where c approaches zero.
    ``"absolute"`` minimises sum(alpha/sigma~ - beta - c)^2, in which the
    sigma~ = 0.01 point (c ~ 100) alone sets alpha and beta carries that
    point's residual (the notes compare the two).
    """
    if weighting not in ("relative", "absolute"):
        raise ValueError(f"weighting must be 'relative' or 'absolute', got {weighting!r}")
    sigma, c = np.asarray(sigma, float), np.asarray(c, float)
    ok = np.isfinite(sigma) & np.isfinite(c) & (sigma > 0) & (c > 0)
    if np.unique(sigma[ok]).size < 2:
        return math.nan, math.nan
    design = np.stack([1.0 / sigma[ok], -np.ones(int(ok.sum()))], axis=1)
    target = c[ok]
    if weighting == "relative":
        design, target = design / target[:, None], np.ones_like(target)
    (alpha, beta), *_ = np.linalg.lstsq(design, target, rcond=None)
    return float(alpha), float(beta)


_BOOTSTRAPS: dict[tuple, dict[str, np.ndarray]] = {}


def bootstrap_eq58(frame: pd.DataFrame, points: int, span: float, resamples: int) -> dict[str, np.ndarray]:
    """eq. 5.8 fitted per k~ over ``resamples`` resamples of the seeds of ``frame`` (finished cases),
    by the estimator of `rough_brush.table_1`.

    Each resample draws the realisations with replacement (numpy's generator, seed 0) and computes,
    as `adhesion_coefficients` does, every group's c (the mean over the drawn seeds of F~_A / F~_P at
    its smallest preload, NaN where saturated), then the fit of eq. 5.8 (`fit_eq58`) per k~ where c > 0
    at ``points`` roughnesses or more spanning a factor ``span``.  Returns ``stiffness_ratio`` (k~ per
    column) and ``alpha``, ``beta``, ``critical_roughness`` arrays of shape (resamples, k~); {} without
    the columns it reads.
    """
    if not has(frame, FA, FP, PRELOAD, SIG, K, SIGMA, "realization"):
        return {}
    read = frame[[K, SIGMA, PRELOAD, FA, FP, SIG, "realization"]]
    key = (points, span, resamples, pd.util.hash_pandas_object(read, index=False).to_numpy().tobytes())
    if key in _BOOTSTRAPS:
        return _BOOTSTRAPS[key]
    seeds = np.array(sorted(read["realization"].unique()))
    draws = np.random.default_rng(0).integers(0, len(seeds), size=(resamples, len(seeds)))
    weights = np.stack([np.bincount(d, minlength=len(seeds)) for d in draws]).astype(float)  # (B, seeds)
    groups = []
    for (k, sigma), g in read.groupby([K, SIGMA], sort=True):
        smallest = g[g[PRELOAD] == g[PRELOAD].min()]
        per_seed = pd.DataFrame({
            "ratio": (smallest[FA] / smallest[FP]).groupby(smallest["realization"]).mean(),
            "small": smallest.groupby("realization")[FA].mean(),
            "largest": g.groupby("realization")[FA].max(),
        }).reindex(seeds)

        def mean(column, per_seed=per_seed):
            values = per_seed[column].to_numpy(float)
            present = np.isfinite(values)
            with np.errstate(invalid="ignore", divide="ignore"):
                return (weights @ np.where(present, values, 0.0)) / (weights @ present)
        c = mean("ratio")
        if g[PRELOAD].nunique() > 1:
            c = np.where(mean("small") >= SATURATED * mean("largest"), np.nan, c)
        groups.append((float(k), float(g[SIG].mean()), c))
    ks = sorted({k for k, _, _ in groups})
    out = {name: np.full((resamples, len(ks)), np.nan) for name in ("alpha", "beta", "critical_roughness")}
    for j, k in enumerate(ks):
        sig = np.array([sigma for kk, sigma, _ in groups if kk == k])
        cs = np.stack([c for kk, _, c in groups if kk == k], axis=1)  # (B, roughnesses)
        for b in range(resamples):
            usable = np.isfinite(cs[b]) & (cs[b] > 0) & (sig > 0)
            if usable.sum() < points or sig[usable].max() < span * sig[usable].min():
                continue
            alpha, beta = fit_eq58(sig[usable], cs[b][usable])
            out["alpha"][b, j], out["beta"][b, j] = alpha, beta
            out["critical_roughness"][b, j] = alpha / beta if beta > 0 else np.nan
    out["stiffness_ratio"] = np.array(ks)
    _BOOTSTRAPS[key] = out
    if len(_BOOTSTRAPS) > 16:
        _BOOTSTRAPS.pop(next(iter(_BOOTSTRAPS)))
    return out


def case_path(figures_dir: Path, part: str, case_id: str, row: pd.Series | None = None) -> Path:
    """``_common.case_path`` by case id: the row's ``case_file``, else ``DIR/<part>/cases/<case_id>.nc``."""
    if row is None or not isinstance(row.get("case_file"), str):
        row = pd.Series({"case_id": case_id})
    return common_case_path(row, part, figures_dir)


def read_curve(path: Path):
    """(displacement, force, contact_area, cross-section x, cross-section pressure) or None."""
    try:
        import xarray as xr

        with xr.open_dataset(path) as ds:
            ds.load()
            d = np.asarray(ds["displacement"].values, float)
            f = np.asarray(ds["force"].values, float)
            a = np.asarray(ds["contact_area"].values, float) if "contact_area" in ds else None
            cs = np.asarray(ds["cross_section_adhesive_force"].values, float) if "cross_section_adhesive_force" in ds else None
            x = np.asarray(ds["x"].values, float) if "x" in ds.coords or "x" in ds else None
        return d, f, a, x, cs
    except (OSError, KeyError, ValueError):  # missing, unreadable or incomplete case file
        return None


def value(frame: pd.DataFrame, column: str, where: Mapping[str, object], how: str = "mean") -> float:
    """Mean (or max) of ``column`` over the rows matching ``where`` (floats compared relatively); NaN if none."""
    if not has(frame, column):
        return math.nan
    mask = np.ones(len(frame), bool)
    for key, want in where.items():
        if key not in frame:
            return math.nan
        col = frame[key]
        if isinstance(want, str):
            mask &= (col == want).to_numpy()
        else:
            mask &= np.isclose(col.astype(float).to_numpy(), float(want), rtol=1e-3, atol=0.0)
    sel = frame.loc[mask, column]
    if len(sel) == 0:
        return math.nan
    return float(sel.max() if how == "max" else sel.mean())
