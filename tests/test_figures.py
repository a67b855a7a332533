"""Figures a journal takes: mathematics in the labels, units or "dimensionless", 300 dpi PNG with a PDF beside
it, detached pillars drawn, stage numbers apart, sweep axes named by the configuration's keys.

Every test draws from a small result built here (no run), so each takes well under two seconds.
"""

from __future__ import annotations

import itertools
import json

import matplotlib
import numpy as np
import pandas as pd
import pytest
from matplotlib.text import Text
from matplotlib.transforms import Bbox

from brushbem.figures.plot import plot_pull_off, pull_off_figure
from brushbem.results import CaseResult, Curve, Snapshot
from brushbem.results.units import Units

matplotlib.use("Agg")

N = 16  # elements per side of the fake result's grid
H = 1.0 / N
#: Four pillars of 9 elements (radius 3 h / sqrt(pi)) at (+-0.25, +-0.25); at the adhesive force the two
#: with y < 0 are attached, the two with y > 0 detached.
CENTRES = [(-0.25, -0.25), (0.25, -0.25), (-0.25, 0.25), (0.25, 0.25)]


def _footprints() -> list[np.ndarray]:
    centres = -0.5 + (np.arange(N) + 0.5) * H
    x, y = np.meshgrid(centres, centres)
    return [np.hypot(x - cx, y - cy) <= 1.8 * H for cx, cy in CENTRES]


def _snapshot(name: str, d: float, f: float, attached: list[int]) -> Snapshot:
    contact = np.zeros((N, N), dtype=bool)
    for i in attached:
        contact |= _footprints()[i]
    return Snapshot(name, d, f, np.where(contact, -1.0 if f < 0 else 1.0, 0.0), contact)


def fake_result(config: dict | None = None) -> CaseResult:
    """A 4-pillar pull-off: loading to d = 0.01, unloading to the adhesive force at d = -0.01, two pillars
    peeling, the last two at once (the half-detached state is also the last before separation)."""
    d = np.array([0.0, 0.005, 0.01, 0.005, 0.0, -0.005, -0.01, -0.012, -0.012])
    f = np.array([0.0, 0.5, 1.0, 0.5, 0.0, -0.5, -1.0, -0.6, 0.0])
    loading = np.array([True, True, True, False, False, False, False, False, False])
    curve = Curve(displacement=d, force=f, contact_area=np.full(d.size, 0.1), cg_iterations=np.ones(d.size, int),
                  converged=np.ones(d.size, bool), loading=loading, attached_pillars=np.array([4] * 7 + [2, 0]))
    snapshots = (
        _snapshot("max_preload", 0.01, 1.0, [0, 1, 2, 3]),
        _snapshot("zero_force", 0.0, 0.0, [0, 1, 2, 3]),
        _snapshot("adhesive_force", -0.01, -1.0, [0, 1]),
        _snapshot("half_detached", -0.012, -0.6, [0, 1]),
        _snapshot("before_separation", -0.012, -0.6, [0, 1]),
    )
    pillars = {"x": np.array([c[0] for c in CENTRES]), "y": np.array([c[1] for c in CENTRES]),
               "elements": np.array([int(fp.sum()) for fp in _footprints()])}
    attributes = {"config": json.dumps(config)} if config is not None else {}
    return CaseResult(curve=curve, snapshots=snapshots, summary={"adhesive_force": 1.0, "work_of_separation": 0.011},
                      attributes=attributes, element_size=H, pillars=pillars)


def _texts(figure) -> list[str]:
    return [text.get_text() for text in figure.findobj(Text)]


def test_the_default_run_figure_is_dimensionless_not_in_units_of_the_inputs():
    figure = pull_off_figure(fake_result())
    texts = _texts(figure)
    assert not [text for text in texts if "units of the inputs" in text]
    curve = figure.axes[0]
    # "dimensionless" once, in the title, not on every axis.
    assert curve.get_xlabel() == "base displacement $d$" and curve.get_ylabel() == "force $F$"
    assert sum("dimensionless" in text for text in texts) == 1 and "(dimensionless)" in curve.get_title()
    assert not any("(dimensionless)" in ax.get_xlabel() + ax.get_ylabel() for ax in figure.axes)
    # Numbers in titles are named: the title gives F_A and W by their symbols.
    assert curve.get_title().startswith(r"$F_\mathrm{A}$ = 1,") and "$W$ = 0.011" in curve.get_title()
    # With [units] set, the units of the configuration, with the SI prefix that reads: |d| <= 0.012 mm is
    # drawn in µm, F_A = 1 N in N, W = 0.011 mJ written 11 µJ.
    named = pull_off_figure(fake_result({"units": {"length": "mm", "stress": "MPa"}}))
    assert named.axes[0].get_xlabel() == "base displacement $d$ (µm)"
    assert named.axes[0].get_ylabel() == "force $F$ (N)"
    assert named.axes[0].get_title().endswith("$W$ = 11 µJ")
    assert named.axes[0].get_xlim()[0] == pytest.approx(-12.6, abs=0.5)  # the data in µm, not mm


def test_the_run_figure_is_written_as_png_at_300_dpi_and_pdf(tmp_path):
    from PIL import Image

    figure_path = tmp_path / "pulloff.png"
    plot_pull_off(fake_result(), figure_path)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["pulloff.pdf", "pulloff.png"]  # no temporaries left
    assert (tmp_path / "pulloff.pdf").read_bytes().startswith(b"%PDF")
    with Image.open(figure_path) as image:
        assert image.info["dpi"] == pytest.approx((300, 300), abs=0.5)
        assert image.size[0] >= 300 * 7  # a double column, 7 inches at 300 dpi


def test_detached_pillars_are_drawn_apart_from_attached_and_absent_ones():
    from matplotlib.collections import PatchCollection

    figure = pull_off_figure(fake_result())
    pattern = figure.axes[1]
    collections = {c.get_label(): c for c in pattern.collections if isinstance(c, PatchCollection)}
    detached, attached = collections["detached pillars"], collections["attached pillars"]
    # The two pillars off the surface at the adhesive force: hollow, dashed, where they stand.
    assert len(detached.get_paths()) == 2 and len(attached.get_paths()) == 2
    assert detached.get_facecolor().size == 0 or np.all(detached.get_facecolor()[:, 3] == 0)
    centres = sorted(tuple(np.round(path.vertices[:-1].mean(axis=0), 2)) for path in detached.get_paths())
    assert centres == [(-0.25, 0.25), (0.25, 0.25)]
    assert detached.get_linestyle() != attached.get_linestyle()
    legend = [text.get_text() for legend in figure.legends for text in legend.get_texts()]
    assert any(text.startswith("detached pillar") for text in legend)
    assert any(text.startswith("attached pillar") for text in legend)


def test_stage_numbers_cover_neither_each_other_nor_the_adhesive_force_marker():
    figure = pull_off_figure(fake_result())
    figure.canvas.draw()
    renderer = figure.canvas.get_renderer()
    curve = figure.axes[0]
    numbers = [text for text in curve.texts if text.get_text() in {"1", "2", "3", "4", "5"}]
    assert sorted(text.get_text() for text in numbers) == ["1", "2", "3", "4", "5"]
    boxes = [text.get_window_extent(renderer) for text in numbers]
    for (i, a), (j, b) in itertools.combinations(enumerate(boxes), 2):
        assert not a.overlaps(b), f"stage {numbers[i].get_text()} covers stage {numbers[j].get_text()}"
    # The adhesive-force marker: the open circle at the least force.
    (marker,) = [line for line in curve.lines if line.get_marker() == "o"]
    x, y = curve.transData.transform((marker.get_xdata()[0], marker.get_ydata()[0]))
    half = 0.5 * marker.get_markersize() * figure.dpi / 72.0
    spot = Bbox.from_extents(x - half, y - half, x + half, y + half)
    assert not [text.get_text() for text, box in zip(numbers, boxes) if box.overlaps(spot)]
    # Every number lies inside the curve's axes.
    frame = curve.get_window_extent(renderer)
    assert all(frame.contains(box.x0, box.y0) and frame.contains(box.x1, box.y1) for box in boxes)


def test_sweep_axes_are_named_by_the_configuration_keys(tmp_path):
    from brushbem.report.sweeps import _plot_against

    frame = pd.DataFrame({"indenter.stiffness_ratio": [0.001, 0.01, 0.1],
                          "adhesive_force": [1.0e-3, 2.0e-3, 3.0e-3]})
    path = _plot_against(frame, "indenter.stiffness_ratio", [], "adhesive_force", tmp_path / "fa.png",
                         Units("mm", "MPa"))
    assert path.with_suffix(".pdf").is_file()
    import brushbem.figures.figstyle as figstyle

    assert figstyle.key_label("indenter.stiffness_ratio") == r"pillar stiffness $\tilde k = k/(E^* L)$"
    assert figstyle.key_label("adhesive_force", Units("mm", "MPa")) == r"adhesive force $F_\mathrm{A}$ (N)"
    assert figstyle.key_label("indenter.radius") == "indenter radius $R$"  # no "(dimensionless)" on an axis
    assert figstyle.key_label("indenter.not_a_key") == "indenter.not_a_key"


def test_sweep_figure_labels_read_the_key_names(monkeypatch, tmp_path):
    from brushbem.report import sweeps as report

    drawn = []
    monkeypatch.setattr(report, "_save", lambda figure, path: drawn.append(figure) or path)
    frame = pd.DataFrame({"indenter.stiffness_ratio": [0.001, 0.01, 0.1], "indenter.roughness.sigma": [0.0] * 3,
                          "adhesive_force": [1.0e-3, 2.0e-3, 3.0e-3]})
    report._plot_against(frame, "indenter.stiffness_ratio", ["indenter.roughness.sigma"], "adhesive_force",
                         tmp_path / "fa.png")
    axes = drawn[0].axes[0]
    assert axes.get_xlabel() == r"pillar stiffness $\tilde k = k/(E^* L)$"
    assert axes.get_ylabel() == r"adhesive force $F_\mathrm{A}$"
    assert [t.get_text() for t in axes.get_legend().get_texts()] == [r"$\sigma$ = 0"]
    assert "indenter." not in axes.get_title()


def _punch_case(folder, k_tilde: float) -> dict:
    """A summary row of the punch study and its case file: a flat punch pulled off at r = 0.3, E* = 1."""
    import xarray as xr

    d = np.array([0.0, 0.01, 0.0, -0.02, -0.02])
    force = np.array([0.0, 0.02, 0.0, -0.03, 0.0])
    area = np.array([0.28, 0.28, 0.28, 0.28, 0.0])
    path = folder / f"case-{k_tilde:g}.nc"
    config = {"halfspace": {"contact_modulus": 1.0, "work_of_adhesion": 1e-3}}
    xr.Dataset({"displacement": ("step", d), "force": ("step", force), "contact_area": ("step", area),
                "loading": ("step", np.array([1, 1, 0, 0, 0], dtype=np.int8))},
               attrs={"config": json.dumps(config)}).to_netcdf(path)
    stiffness = 2 * 0.3 * k_tilde
    return {"status": "finished", "case_id": path.stem, "case_file": str(path), "indenter.stiffness": stiffness,
            "theory.normalized_stiffness": k_tilde, "theory.equivalent_radius": 0.3,
            "theory.work_of_separation": 1e-4 * (1 + 1 / k_tilde), "work_of_separation": 1.1e-4 * (1 + 1 / k_tilde),
            "separation_displacement": -0.02}


def test_study_figures_speak_mathematics_and_keep_their_titles(tmp_path, monkeypatch):
    from brushbem.studies import punch_spring

    drawn = []
    monkeypatch.setattr(punch_spring, "save", lambda figure, path: drawn.append(figure) or path)
    frame = pd.DataFrame([_punch_case(tmp_path, 0.1), _punch_case(tmp_path, 1.0)])
    punch_spring.draw({"stiffness": frame}, tmp_path / "figures")
    assert len(drawn) == 3  # Fig. 2-4, 2-5, 2-6
    fig4, fig5, fig6 = drawn
    # No plain-text notation ("F~ = F / F_K", "k~"): mathtext.
    for figure in drawn:
        assert not [text for text in _texts(figure) if "~" in text], _texts(figure)
    assert fig4.axes[0].get_ylabel() == r"$\tilde F = F/F_\mathrm{K}$"
    assert fig5.axes[0].get_xlabel() == r"$\tilde a = a/r$"
    assert fig6.axes[0].get_xlabel() == r"$\tilde k = k/(2E^* r)$"
    # Fig. 2-5's title lies inside its figure (not cut off).
    fig5.canvas.draw()
    title = fig5.axes[0].title.get_window_extent(fig5.canvas.get_renderer())
    assert fig5.bbox.x0 <= title.x0 and title.x1 <= fig5.bbox.x1


# --------------------------------------------------------------------------- figures that read (issue 62)

#: A brush's closed-form limits as summary.json records them: F_c and N_p F_K, and -|d_c|.
BRUSH_THEORY = {"model": "brush limits (thesis eq. 4.5-4.13, 5.3-5.5, 7.4)", "rigid_brush_force": 0.8,
                "ideal_sharing_force": 1.6, "rigid_brush_displacement": -0.008, "compact_punch_force": 0.5}


def _with_theory(result: CaseResult, theory: dict) -> CaseResult:
    import dataclasses

    return dataclasses.replace(result, summary={**result.summary, "theory": theory})


def test_a_brush_curve_shows_its_reference_limits_and_both_branches():
    figure = pull_off_figure(_with_theory(fake_result(), BRUSH_THEORY))
    curve = figure.axes[0]
    limits = {line.get_label(): line.get_ydata()[0] for line in curve.lines
              if "rigid brush" in line.get_label() or "equal sharing" in line.get_label()}
    assert sorted(limits.values()) == [-1.6, -0.8], limits  # -N_p F_K and -F_c
    assert curve.get_ylim()[0] < -1.6  # the limit lies inside the view
    (loading,) = [line for line in curve.lines if line.get_label() == "loading"]
    (unloading,) = [line for line in curve.lines if line.get_label() == "unloading"]
    # The loading branch is drawn dashed on top of the unloading one: where they coincide both show.
    assert loading.get_zorder() > unloading.get_zorder() and loading.get_linestyle() != "-"


def test_numbers_and_axes_take_the_si_prefix_that_reads():
    from brushbem.figures.curve_axes import si_prefixed as _prefixed

    assert _prefixed("µN", 6.208e4) == pytest.approx((1e-3, "mN"))
    assert _prefixed("pJ", 4.335e5) == pytest.approx((1e-3, "nJ"))
    assert _prefixed("N", 2.1e-2) == pytest.approx((1e3, "mN"))
    assert _prefixed("N/mm", 2.1e-2) == (1.0, "N/mm")  # a compound unit keeps its own
    assert _prefixed("mm", 0.0) == (1.0, "mm")
    # um and MPa: forces in µN; a brush of 6.208e4 µN is titled in mN.
    import dataclasses

    result = fake_result({"units": {"length": "um", "stress": "MPa"}})
    curve = dataclasses.replace(result.curve, force=result.curve.force * 6.208e4)
    result = dataclasses.replace(result, curve=curve, summary={"adhesive_force": 6.208e4, "work_of_separation": 4.335e5})
    axes = pull_off_figure(result).axes[0]
    assert axes.get_title().startswith(r"$F_\mathrm{A}$ = 62.08 mN") and "e+0" not in axes.get_title()
    assert axes.get_ylabel() == "force $F$ (mN)"


def test_normalised_axes_are_the_thesis_groups():
    figure = pull_off_figure(_with_theory(fake_result(), BRUSH_THEORY), normalized=True)
    curve = figure.axes[0]
    assert "d_\\mathrm{c}" in curve.get_xlabel() and "N_\\mathrm{p} F_\\mathrm{K}" in curve.get_ylabel()
    (unloading,) = [line for line in curve.lines if line.get_label() == "unloading"]
    assert min(unloading.get_ydata()) == pytest.approx(-1.0 / 1.6, rel=1e-12, abs=0.0)  # F / (N_p F_K)
    assert min(unloading.get_xdata()) == pytest.approx(-0.012 / 0.008, rel=1e-12, abs=0.0)  # d / |d_c|
    with pytest.raises(ValueError, match="no closed form"):
        pull_off_figure(fake_result(), normalized=True)


def test_the_pressure_map_of_ten_thousand_pillars_is_not_covered_by_outlines():
    import dataclasses

    from matplotlib.collections import PatchCollection

    side = 100  # 10^4 pillars on the 16 x 16 map
    centres = -0.5 + (np.arange(side) + 0.5) / side
    x, y = np.meshgrid(centres, centres)
    many = {"x": x.ravel(), "y": y.ravel(), "elements": np.ones(side * side)}
    figure = pull_off_figure(dataclasses.replace(fake_result(), pillars=many))
    pattern = figure.axes[1]
    assert not [c for c in pattern.collections if isinstance(c, PatchCollection)]  # no outline drawn
    assert any("too small to outline" in text for text in _texts(figure))
    # Four pillars are outlined as before.
    few = pull_off_figure(fake_result()).axes[1]
    assert [c for c in few.collections if isinstance(c, PatchCollection)]
