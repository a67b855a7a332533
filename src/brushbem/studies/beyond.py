"""Beyond the thesis (its sec. 8.2): tip shapes, stiffness gradients, misalignment, viscoelastic pillars.

Four studies, each with its sweep files in ``sweeps/`` (written by
``docs/studies/make_beyond_sweeps.py``) and its figures in the thesis's
normalisations: the adhesive force by the ideal-sharing force N F_K (eq. 7.4,
F~ = 1 is equal load sharing), displacements by |d_c| (eq. 4.12), speeds by
|d_c| / tau.  The thesis states no numbers for them: their checks are the
limits in ``tests/test_tips_grading_tilt.py``, ``tests/test_viscoelastic.py``
and ``tests/test_pillar_laws.py``.

* ``tip_shape``: F~ against the cap curvature r / R (spherical caps) and the
  dish depth delta / |d_c| (concave tips), stiff and soft brushes.
* ``grading``: F~ against a radial stiffness gradient k_n = k (1 + a (r_n /
  R)^2) in the thesis's ch. 7 setting (circle, phi = 0.06): does grading
  reach equal load sharing?
* ``tilt``: F~ against the tilt of the base, stiff and soft brushes.
* ``viscoelastic``: F_A and the work of separation against the pulling
  speed, for one flat pillar and a brush on standard-linear-solid
  connections, between the relaxed and the instantaneous elastic limits.
* ``robustness``: the equal-load-sharing design of `brushbem.design`
  against the flat and the concave brush, under added roughness and tilt
  (its designs are shipped as lengths files, written by
  ``docs/studies/make_robustness_sweeps.py``).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from pathlib import Path

import numpy as np
import pandas as pd

from brushbem.figures.figstyle import styled
from brushbem.studies._ch5_7 import FIS, K, K_TEXT, empty_note, figure, finished, has, save
from brushbem.studies.base import Study
from brushbem.results.columns import summary_column

#: The columns of the sweep table this module reads (`brushbem.results.columns`).
NORMALIZED_PILLARS = summary_column("normalized.pillars")
NORMALIZED_FILLING_FACTOR = summary_column("normalized.filling_factor")
THEORY_PULL_OFF_DISPLACEMENT = summary_column("theory.pull_off_displacement")
THEORY_NORMALIZED_STIFFNESS = summary_column("theory.normalized_stiffness")

CAP = "indenter.tip.radius"
DEPTH = "indenter.tip.depth"
ANGLE = "indenter.tilt.angle"
AMPLITUDE = "indenter.grading.amplitude"
SPEED = "protocol.speed"
RIGID_DC = summary_column("theory.rigid_brush_displacement")
#: The force of these studies: the adhesive force over equal load sharing (eq. 7.4).
F_SHARING = r"$\tilde F = F_\mathrm{A}/(N_\mathrm{p} F_\mathrm{K})$"


def _by_stiffness(ax, frame: pd.DataFrame, x: pd.Series, xlabel: str, title: str, log: bool = False) -> None:
    """F~ against ``x`` for each k~, with the equal-load-sharing line."""
    if not has(frame, FIS, K):
        empty_note(ax)
    else:
        frame = frame.assign(_x=x)
        for k, group in frame.groupby(K):
            mean = group.groupby("_x")[FIS].mean()
            ax.plot(mean.index, mean.to_numpy(), "o-", ms=4, label=rf"{K_TEXT} = {k:g}")
        ax.legend()
    ax.axhline(1.0, ls=":", color="0.5", lw=0.8)
    ax.text(0.02, 1.0, "equal load sharing (eq. 7.4)", fontsize="small", color="0.4", va="bottom",
            transform=ax.get_yaxis_transform())
    ax.set(xlabel=xlabel, ylabel=F_SHARING, title=title, ylim=(0, 1.1))
    if log:
        ax.set_xscale("log")


@styled
def _draw_tip_shape(results: Mapping[str, pd.DataFrame], figures_dir: Path) -> list[Path]:
    written: list[Path] = []
    caps, dishes = finished(results, "caps"), finished(results, "dishes")
    fig, ax = figure(2, 1)
    if has(caps, CAP, NORMALIZED_PILLARS):
        # r / R from the pillar radius r = sqrt(phi A0 / (pi N)); A0 = 1 (square region of side L = 1).
        radius = np.sqrt(caps[NORMALIZED_FILLING_FACTOR] / (math.pi * caps[NORMALIZED_PILLARS]))
        _by_stiffness(ax[0, 0], caps, (radius / caps[CAP]).round(3), CAP_CURVATURE,
                      r"Spherical caps (flat: $r/R_\mathrm{tip} \to 0$)", log=True)
    else:
        _by_stiffness(ax[0, 0], caps, pd.Series(dtype=float), CAP_CURVATURE, "Spherical caps")
    if has(dishes, DEPTH, RIGID_DC):
        _by_stiffness(ax[0, 1], dishes, (dishes[DEPTH] / dishes[RIGID_DC].abs()).round(3),
                      DISH_DEPTH, r"Concave tips (flat: $\delta \to 0$)", log=True)
    else:
        _by_stiffness(ax[0, 1], dishes, pd.Series(dtype=float), DISH_DEPTH, "Concave tips")
    save(fig, Path(figures_dir) / "tip_shape.png", written)
    return written


#: The tip shapes' axes: the cap's curvature against the pillar radius, the dish's depth against |d_c|.
CAP_CURVATURE = r"cap curvature $r/R_\mathrm{tip}$"
DISH_DEPTH = r"dish depth $\delta/|d_\mathrm{c}|$"


@styled
def _draw_grading(results: Mapping[str, pd.DataFrame], figures_dir: Path) -> list[Path]:
    written: list[Path] = []
    frame = finished(results, "amplitude")
    fig, ax = figure(1, 1, size=(6.0, 4.2))
    x = frame[AMPLITUDE] if has(frame, AMPLITUDE) else pd.Series(dtype=float)
    _by_stiffness(ax[0, 0], frame, x, r"radial grading $a$: $k_n = k\,(1 + a\,(r_n/R)^2)$",
                  r"Stiffness gradient, circle, $\phi$ = 0.06 (thesis ch. 7 setting)")
    ax[0, 0].plot([0.0], [0.95], "kP", ms=9, label=rf"thesis: best concave brush, {K_TEXT} = $6 \times 10^{{-4}}$")
    ax[0, 0].legend()
    save(fig, Path(figures_dir) / "grading.png", written)
    return written


@styled
def _draw_tilt(results: Mapping[str, pd.DataFrame], figures_dir: Path) -> list[Path]:
    written: list[Path] = []
    frame = finished(results, "angle")
    fig, ax = figure(2, 1)
    x = frame[ANGLE] if has(frame, ANGLE) else pd.Series(dtype=float)
    _by_stiffness(ax[0, 0], frame, x, r"tilt angle $\theta$ (°)", r"Misaligned base: $\tilde F$ against tilt")
    if has(frame, ANGLE, RIGID_DC):
        # The far edge's lift tan(angle) L against |d_c| (L = 1): where the soft pillars still reach.
        lift = np.tan(np.radians(frame[ANGLE])) / frame[RIGID_DC].abs()
        _by_stiffness(ax[0, 1], frame, lift.round(3), r"edge lift $L \tan\theta/|d_\mathrm{c}|$",
                      "The same against the lift of the far edge")
    else:
        empty_note(ax[0, 1])
    save(fig, Path(figures_dir) / "tilt.png", written)
    return written


@styled
def _draw_viscoelastic(results: Mapping[str, pd.DataFrame], figures_dir: Path) -> list[Path]:
    written: list[Path] = []
    fig, ax = figure(2, 2)
    for row, part in enumerate(("punch", "brush")):
        frame = finished(results, part).sort_values(SPEED) if has(finished(results, part), SPEED) else pd.DataFrame()
        if not len(frame):
            empty_note(ax[row, 0])
            empty_note(ax[row, 1])
            continue
        slowest = frame.iloc[0]
        if part == "punch":
            scale = abs(float(slowest[THEORY_PULL_OFF_DISPLACEMENT])) if THEORY_PULL_OFF_DISPLACEMENT in frame \
                else 1.0
            speed = frame[SPEED] / scale
            xlabel = r"pulling speed $v\tau/|d_\mathrm{A}|$ (relaxed punch)"
        else:
            speed = frame[SPEED] / frame[RIGID_DC].abs()
            xlabel = r"pulling speed $v\tau/|d_\mathrm{c}|$"
        for col, (key, label) in enumerate((("adhesive_force", r"$F_\mathrm{A}/F_\mathrm{A}^\mathrm{slowest}$"),
                                            ("work_of_separation", r"$W/W^\mathrm{slowest}$"))):
            a_ = ax[row, col]
            ratio_to_slowest = frame[key] / float(slowest[key])
            a_.semilogx(speed, ratio_to_slowest, "o-", ms=4)
            a_.set_ylim(0.0, max(1.15, 1.05 * float(ratio_to_slowest.max())))
            a_.axhline(1.0, ls=":", color="0.5", lw=0.8)
            a_.text(0.02, 1.0, r"relaxed (elastic $k_\infty$)", fontsize="small", color="0.4", va="bottom",
                    transform=a_.get_yaxis_transform())
            if part == "punch" and key == "work_of_separation" and THEORY_NORMALIZED_STIFFNESS in frame:
                # Closed form (eq. 2.18-2.19): W = W_rigid (1 + 1/k~); instantaneous k~_0 = 10 k~_inf.
                k_inf = float(slowest[THEORY_NORMALIZED_STIFFNESS])
                ratio = (1 + 1 / (10 * k_inf)) / (1 + 1 / k_inf)
                a_.axhline(ratio, ls="--", color="tab:red", lw=0.8)
                a_.text(0.02, ratio, r"instantaneous (eq. 2.19, $k_0 = 10 k_\infty$)", fontsize="small",
                        color="tab:red", va="bottom", transform=a_.get_yaxis_transform())
            a_.set(xlabel=xlabel, ylabel=label, title=rf"{part}: standard linear solid, $k_0 = 10 k_\infty$")
    save(fig, Path(figures_dir) / "viscoelastic.png", written)
    return written


TIP_SHAPE = Study(
    name="tip_shape",
    title="Beyond the thesis (sec. 8.2, 1): F~ = F_A / (N F_K) against tip curvature and dish depth",
    figures=(),
    parts=("caps", "dishes"),
    draw=_draw_tip_shape,
    draw_tables=_draw_tip_shape,
    notes="No thesis numbers; the limits (flat, one cap = the sphere) are tested in tests/test_tips_grading_tilt.py.",
)

GRADING = Study(
    name="grading",
    title="Beyond the thesis (sec. 8.2, 2): F~ against a radial stiffness gradient (equal load sharing?)",
    figures=(),
    parts=("amplitude",),
    draw=_draw_grading,
    draw_tables=_draw_grading,
    notes="No thesis numbers; a uniform grading is today's brush to 1e-10 (tests/test_tips_grading_tilt.py).",
)

TILT = Study(
    name="tilt",
    title="Beyond the thesis (misalignment): F~ against the tilt of the base, stiff and soft brushes",
    figures=(),
    parts=("angle",),
    draw=_draw_tilt,
    draw_tables=_draw_tilt,
    notes="No thesis numbers; zero tilt is no tilt, state for state (tests/test_tips_grading_tilt.py).",
)

VISCOELASTIC = Study(
    name="viscoelastic",
    title="Beyond the thesis (sec. 8.2, 3): F_A and work against pulling speed, one pillar and a brush",
    figures=(),
    parts=("punch", "brush"),
    draw=_draw_viscoelastic,
    draw_tables=_draw_viscoelastic,
    notes="No thesis numbers; the slow and fast limits and the one-pillar closed form are tested in "
          "tests/test_viscoelastic.py.",
)


# -- the robustness of the equal-load-sharing design (brushbem design) ----------------

LENGTHS = "indenter.lengths_file"
PROFILE = "indenter.profile.amplification"
SIGMA_KEY = "indenter.roughness.sigma"


def _brush_kind(frame: pd.DataFrame) -> pd.Series:
    """flat, concave or designed, from the lengths file and the profile of each case."""
    designed = frame[LENGTHS].astype(str).str.contains(r"\.k[0-9.e-]+\.npy$", regex=True)
    concave = frame[PROFILE].astype(float) > 0
    return pd.Series(np.where(designed, "designed", np.where(concave, "concave", "flat")), index=frame.index)


@styled
def _draw_robustness(results: Mapping[str, pd.DataFrame], figures_dir: Path) -> list[Path]:
    written: list[Path] = []
    styles = {"designed": "o-", "concave": "s--", "flat": "^:"}
    roughness = r"added roughness $\tilde\sigma = \sigma/|d_\mathrm{c}|$"
    for part, key, xlabel, scale_by_dc in (("roughness", SIGMA_KEY, roughness, True),
                                           ("tilt", ANGLE, r"tilt angle $\theta$ (°)", False)):
        frame = finished(results, part)
        stiffnesses = sorted(frame[K].unique()) if has(frame, K, key, LENGTHS, PROFILE, FIS) else []
        fig, ax = figure(max(1, len(stiffnesses)), 1)
        if not stiffnesses:
            empty_note(ax[0, 0])
        for a_, k in zip(ax[0], stiffnesses):
            sub = frame[np.isclose(frame[K], k)]
            sub = sub.assign(kind=_brush_kind(sub),
                             x=(sub[key] / sub[RIGID_DC].abs()).round(4) if scale_by_dc else sub[key])
            for kind, group in sub.groupby("kind"):
                stats = group.groupby("x")[FIS].agg(["mean", "std", "size"])
                error = stats["std"].fillna(0.0) / np.sqrt(stats["size"])
                a_.errorbar(stats.index, stats["mean"], yerr=error, fmt=styles.get(kind, "o-"), ms=4, capsize=2,
                            label=kind)
            a_.axhline(1.0, ls=":", color="0.5", lw=0.8)
            a_.set(xlabel=xlabel, ylabel=F_SHARING, title=rf"{K_TEXT} = {k:g}, $\phi$ = 0.06, circle", ylim=(0, 1.1))
            a_.legend()
        save(fig, Path(figures_dir) / f"robustness_{part}.png", written)
    return written


ROBUSTNESS = Study(
    name="robustness",
    title="Design for equal load sharing (brushbem design) against the flat and the concave brush, "
          "under roughness and tilt",
    figures=(),
    parts=("roughness", "tilt"),
    draw=_draw_robustness,
    draw_tables=_draw_robustness,
    notes="No thesis numbers; the designs are shipped as lengths files written by "
          "docs/studies/make_robustness_sweeps.py.",
)
