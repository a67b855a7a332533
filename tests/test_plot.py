"""Figures: any form of a run, on the caller's axes, in the configuration's units, jumps drawn as jumps."""

from __future__ import annotations

import dataclasses

import matplotlib
import numpy as np
import pytest
import xarray as xr
from matplotlib.figure import Figure

import brushbem
from brushbem.figures.plot import as_case_result, draw_with_jumps, pull_off_figure
from brushbem.report.sweeps import _case_label, _plot_curves
from brushbem.results.units import Units

matplotlib.use("Agg")

PUNCH = {
    "halfspace": {"contact_modulus": 1.0, "work_of_adhesion": 1e-3},
    "grid": {"size": 1.0, "elements": 32},
    "indenter": {"shape": "flat_punch", "radius": 0.25, "stiffness": 0.15},
    "protocol": {"preload_displacement": 0.01},
}


@pytest.fixture(scope="module")
def punch(tmp_path_factory):
    run = brushbem.run({**PUNCH, "units": {"length": "mm", "stress": "MPa"}})
    folder = tmp_path_factory.mktemp("punch")
    run.save(folder)
    return run, folder


def test_every_form_of_a_run_gives_the_same_curve(punch):
    run, folder = punch
    forms = [run, run.result, folder, folder / "result.nc", xr.load_dataset(folder / "result.nc")]
    for form in forms:
        result = as_case_result(form)
        np.testing.assert_array_equal(result.curve.force, run.curve.force)
        np.testing.assert_array_equal(result.curve.loading, run.curve.loading)
        assert {s.name for s in result.snapshots} == set(run.snapshots)
        assert result.summary["adhesive_force"] == run.adhesive_force
        assert result.element_size == pytest.approx(run.result.element_size, rel=1e-12, abs=0.0)
    with pytest.raises(TypeError, match="is not a run"):
        as_case_result(3.0)
    with pytest.raises(FileNotFoundError, match="no such case folder"):
        as_case_result(folder / "absent")


def test_the_callers_axes_and_the_configured_units(punch):
    import matplotlib.pyplot as plt

    run, folder = punch
    figure, axes = plt.subplots()
    try:
        assert pull_off_figure(folder, ax=axes) is figure
        # |d| up to 0.18 mm reads in µm, F_A = 0.021 N in mN (the SI prefix that reads).
        assert axes.get_xlabel().endswith("(µm)") and axes.get_ylabel().endswith("(mN)")
        assert len(figure.axes) == 1  # the detachment pattern is not added to the caller's figure
    finally:
        plt.close(figure)
    own = pull_off_figure(run)
    assert isinstance(own, Figure) and len(own.axes) >= 2  # curve, pattern (and its colour bar)
    plain = pull_off_figure(run, units=Units())
    assert plain.axes[0].get_xlabel() == "base displacement $d$"  # no unit; the title says "dimensionless"


def test_a_jump_at_fixed_displacement_is_drawn_dotted():
    figure = Figure()
    axes = figure.add_subplot()
    # Peeling (a falls with d), then the jump to separation at the last d: a -> 0, F -> 0.
    d = np.array([0.0, -0.1, -0.2, -0.2])
    a = np.array([1.0, 0.9, 0.7, 0.0])
    f = np.array([0.0, -0.5, -0.8, 0.0])
    draw_with_jumps(axes, a, f, d, color="tab:green", label="case")
    solid, jump = axes.lines
    np.testing.assert_array_equal(solid.get_xdata(), a[:3])
    np.testing.assert_array_equal(jump.get_xdata(), a[2:])
    assert solid.get_linestyle() == "-" and jump.get_linestyle() == ":"
    assert jump.get_color() == solid.get_color() == "tab:green"
    assert [line.get_label() for line in axes.lines].count("case") == 1


def test_jump_styles_take_aliases_and_the_label_goes_to_a_solid_piece():
    figure = Figure()
    axes = figure.add_subplot()
    d = np.array([0.0, 0.0, 0.1, 0.2])  # the curve starts with a jump
    draw_with_jumps(axes, d, d, d, c="r", lw=2.0, label="case")
    jump, solid = axes.lines
    assert jump.get_linestyle() == ":" and solid.get_linestyle() == "-"
    assert solid.get_label() == "case" and jump.get_label().startswith("_")
    assert solid.get_linewidth() == 2.0 and jump.get_color() == solid.get_color() == "r"


def test_a_pull_off_draws_its_closed_form_and_a_reloaded_nan_is_a_number(punch):
    run, _ = punch
    assert run.reference is not None
    labels = [line.get_label() for line in pull_off_figure(run).axes[0].lines]
    assert str(run.reference["label"]) in labels
    from brushbem.io import from_dataset, to_dataset

    result = dataclasses.replace(run.result, summary={**run.result.summary, "work_of_separation": float("nan")})
    reloaded = from_dataset(to_dataset(result))
    assert np.isnan(reloaded.summary["work_of_separation"])
    pull_off_figure(reloaded)  # the title formats a nan


def test_units_name_forces_works_and_refuse_half_a_system():
    assert Units("mm", "MPa").of("force") == "N" and Units("mm", "MPa").of("energy") == "mJ"
    assert Units("um", "MPa").label("force / length") == "µN/µm"
    assert Units().of("force") == "1"
    with pytest.raises(ValueError, match="both length and stress"):
        Units("mm", None)
    with pytest.raises(ValueError, match="must be one of"):
        Units("furlong", "MPa")
    with pytest.raises(brushbem.config.ConfigError, match="units.stress"):
        brushbem.run({**PUNCH, "units": {"length": "mm"}})


def test_sweep_curves_are_labelled_by_swept_value(tmp_path, punch, monkeypatch):
    import pandas as pd

    from brushbem.report import sweeps as report

    drawn = []
    monkeypatch.setattr(report, "_save", lambda figure, path: drawn.append(figure) or path)
    _, folder = punch
    cases = tmp_path / "cases"
    cases.mkdir()
    (cases / "0000-aaaa.nc").write_bytes((folder / "result.nc").read_bytes())
    frame = pd.DataFrame({"case_id": ["0000-aaaa"], "indenter.stiffness": [0.15], "realization": [0]})
    assert _case_label(frame.iloc[0], ["indenter.stiffness"], realizations=False) == "$k$ = 0.15"
    assert _plot_curves(frame, cases, tmp_path / "curves.png", ["indenter.stiffness"]) is not None
    legend = drawn[0].axes[0].get_legend()
    assert [text.get_text() for text in legend.get_texts()] == ["$k$ = 0.15"]
