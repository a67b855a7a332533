"""Cost before compute: ``brushbem sweep/study --estimate`` extrapolates sampled cases."""

from __future__ import annotations

from pathlib import Path

import pytest
from click.testing import CliRunner

from brushbem.cli import main
from brushbem.sweep.estimate import SweepEstimate, estimate_sweep, sample_indices
from brushbem.sweep import load_sweep

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "sweeps" / "punch_stiffness.toml"


def test_samples_span_the_sweep_from_first_to_last_case():
    assert sample_indices(8, 3) == [0, 4, 7]  # round(3.5) = 4 (banker's rounding of linspace)
    assert sample_indices(8, 1) == [0]
    assert sample_indices(2, 5) == [0, 1]     # never more samples than cases, never a case twice
    assert sample_indices(0, 3) == []


def test_estimate_extrapolates_the_mean_sampled_time():
    estimate = SweepEstimate(cases=100, sampled=("a", "b"), seconds=(30.0, 42.0), statuses=("finished",) * 2)
    assert estimate.cpu_hours == pytest.approx(100 * 36.0 / 3600)
    # Standard error of the mean times the cases: stdev 8.485 s / sqrt(2) = 6 s.
    assert estimate.cpu_hours_error == pytest.approx(100 * 6.0 / 3600)
    assert estimate.wall_hours(8) == pytest.approx(estimate.cpu_hours / 8)
    assert estimate.wall_hours(1000) == pytest.approx(estimate.cpu_hours / 100)  # at most one case per worker
    with pytest.raises(ValueError, match="workers = 0"):
        estimate.wall_hours(0)


def test_one_sample_says_it_has_no_spread(capsys):
    """One sampled case has no spread: the error is not known (it printed "± 0"), and the total says so."""
    from brushbem.cli.sweep_commands import _print_estimates

    one = SweepEstimate(cases=10, sampled=("a",), seconds=(1.12,), statuses=("finished",))
    assert one.cpu_hours_error is None
    _print_estimates({"one": one, "two": SweepEstimate(cases=10, sampled=("a", "b"), seconds=(1.0, 2.0),
                                                       statuses=("finished",) * 2)}, workers=1)
    shown = " ".join(capsys.readouterr().out.split())
    assert "one sample" in shown and "error not known" in shown and "± 0 " not in shown


def test_estimate_runs_the_sampled_cases_and_writes_nothing(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    sweep = load_sweep(EXAMPLE)
    estimate = estimate_sweep(sweep, samples=2)
    assert estimate.cases == len(sweep.cases)
    assert estimate.sampled == (sweep.cases[0].case_id, sweep.cases[-1].case_id)
    assert all(t > 0 for t in estimate.seconds) and set(estimate.statuses) == {"finished"}
    assert list(tmp_path.iterdir()) == []


def test_cli_estimates_a_sweep_and_a_study_without_out():
    result = CliRunner().invoke(main, ["sweep", str(EXAMPLE), "--estimate", "--samples", "1", "--workers", "4",
                                       "--quiet"])
    assert result.exit_code == 0, result.output
    assert "expected cost (wall time on 4 workers)" in result.output
    result = CliRunner().invoke(main, ["study", "punch_spring", "--quick", "--estimate", "--samples", "1",
                                       "--quiet"])
    assert result.exit_code == 0, result.output
    assert "stiffness" in result.output
    # Without --estimate, --out stays required.
    result = CliRunner().invoke(main, ["sweep", str(EXAMPLE)])
    assert result.exit_code == 2 and "--out" in result.output
