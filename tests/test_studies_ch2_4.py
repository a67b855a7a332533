"""Studies of thesis chapters 2-4: every quick sweep runs, draws, and reproduces the physics.

Each study runs once per module (fixture) at quick resolution; the tests then
check the figures and a few numbers with tolerances justified by the coarse
mesh.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import run_quick_study


@pytest.fixture(scope="module")
def punch(tmp_path_factory):
    return run_quick_study("punch_spring", tmp_path_factory)


@pytest.fixture(scope="module")
def sphere(tmp_path_factory):
    return run_quick_study("sphere_spring", tmp_path_factory)


@pytest.fixture(scope="module")
def brush(tmp_path_factory):
    return run_quick_study("flat_brush", tmp_path_factory)


@pytest.mark.parametrize("name", ["punch", "sphere", "brush"])
def test_quick_study_draws_every_figure(name, request):
    study, results, figures = request.getfixturevalue(name)
    assert all((frame.status == "finished").all() for frame in results.values())
    assert figures and all(path.exists() and path.stat().st_size > 1000 for path in figures)
    assert all(path.suffix == ".png" for path in figures)
    for number in study.numbers:
        assert math.isfinite(number.compute(results)), number.quantity


def test_punch_work_follows_eq_2_19(punch):
    """w~ / (1 + 1/k~) within 12 % at N = 64 (r = 19 h).

    The mesh criterion of Pohrt-Popov gives F_A a few % above Kendall at 19
    elements per radius; the spring part of w ~ F_A^2 / 2k doubles that error
    for soft springs, hence 12 % rather than a few %.
    """
    _, results, _ = punch
    frame = results["stiffness"]
    k_tilde = frame["theory.normalized_stiffness"].astype(float)
    ratio = frame["theory.ratios.work_of_separation"].astype(float)
    finite = np.isfinite(k_tilde)
    assert finite.sum() >= 3
    assert np.all(np.abs(ratio[finite] - 1) < 0.12)
    # The same F_A for every stiffness (Fig. 2-5: detachment only at the pull-off force).
    force = frame["adhesive_force"].astype(float)
    assert force.max() / force.min() < 1.01


def test_sphere_force_independent_of_stiffness(sphere):
    """F_A / F_JKR is the same for every stiffness (Fig. 2-7) and within 15 % of 1 at a_nor = 7 h."""
    _, results, _ = sphere
    ratio = results["stiffness"]["theory.ratios.adhesive_force"].astype(float)
    assert ratio.max() / ratio.min() < 1.02
    assert abs(ratio.mean() - 1) < 0.15


def test_brush_numbers(brush):
    """F~_A of 16 x 16 at k~ = 0.455 ~ 1.8 (thesis) within 10 %; soft plateau above the rigid limit."""
    study, results, _ = brush
    numbers = {n.quantity: n.compute(results) for n in study.numbers}
    assert numbers["F~_A of 16 x 16 pillars at k~ = 0.455"] == pytest.approx(1.8, rel=0.10)
    regular = results["regular"]
    soft = regular[regular["normalized.stiffness_ratio"] <= 1e-5]
    stiff = regular[regular["normalized.stiffness_ratio"] >= 10]
    # Soft pillars beat the rigid brush, and stay below the contact-splitting limit N^1/4.
    assert (soft["normalized.force_by_compact_punch"].to_numpy() > stiff["normalized.force_by_compact_punch"].max()).all()
    n = soft["normalized.pillars"].to_numpy(dtype=float)
    assert (soft["normalized.force_by_compact_punch"].to_numpy() <= n**0.25 * 1.02).all()
