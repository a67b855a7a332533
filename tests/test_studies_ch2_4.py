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

# Whole quick studies: `make test` runs them, `make test-fast` leaves them out.
pytestmark = pytest.mark.slow


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
        value = number.compute(results)
        if "n/a where a pillar holds on past F_A" in number.evidence:
            # L761's share is n/a by design where F_A's state is not the last with contact; the quick grid's
            # curve may hold on past F_A, so n/a is allowed exactly there and nowhere else.
            curves = results["curves"]  # the curve the number reads: nearest k~ = 0.001, as _leave_at_pull_off
            row = curves.iloc[int(np.argmin(np.abs(np.log(curves["indenter.stiffness_ratio"] / 1e-3))))]
            holds_on = row["separation_displacement"] != row["pull_off_displacement"]
            assert math.isfinite(value) != holds_on, number.quantity
            continue
        assert math.isfinite(value), number.quantity


def test_punch_work_follows_eq_2_19(punch):
    """w~ / (1 + 1/k~) within 6 % at N = 64 (r = 19 h), for every stiffness and the rigid punch.

    Measured 3.8 % (k~ = 0.01, 0.015), 3.9 % (0.3), 4.2 % (1.5), 4.4 % (rigid):
    the Pohrt-Popov criterion gives F_A and d_A a few % above Kendall at 19
    elements per radius, and both parts of w (the punch's F d / 2 and the
    spring's F^2 / 2k) carry about that error, so it barely depends on k~.
    6 % leaves first-order room over 4.4 % (the a/h = 32 BEM test holds 2 %).
    """
    _, results, _ = punch
    frame = results["stiffness"]
    k_tilde = frame["theory.normalized_stiffness"].astype(float)
    ratio = frame["theory.ratios.work_of_separation"].astype(float)
    finite = np.isfinite(k_tilde)
    assert finite.sum() >= 3
    assert np.all(np.abs(ratio - 1) < 0.06), dict(zip(k_tilde, ratio))
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


def test_sphere_work_follows_eq_2_38_beyond_b(sphere):
    """Stiff springs and the rigid sphere: w / w_theory (eq. 2.27, 2.38) at a_JKR = 9.7 h.

    The study presses every case to a contact radius of 1.86 a_JKR, beyond the
    zero-force radius a_o = 1.59 a_JKR, so the unloading passes point B, where
    the thesis starts counting (the summary says so in
    ``theory.work_counted_from``).  At a_JKR/h = 10 the BEM's work is above
    theory, measured 17 % (rigid) and 26 % (k_bar = 4): the force is 14 %
    above, and the spring's F^2 / 2k doubles that share (see
    test_sphere_work_of_separation_converges_to_theory for the convergence).
    So the ratio must lie in (1, 1.35); counted from the wrong point (a
    preload short of B) it was 0.75.
    """
    _, results, _ = sphere
    frame = results["stiffness"]
    k_bar = frame["theory.normalized_stiffness"].astype(float).fillna(np.inf)
    ratio = frame["theory.ratios.work_of_separation"].astype(float)
    start = frame["theory.work_counted_from"].astype(str)
    assert start.str.startswith("B").all(), set(start)
    stiff = k_bar >= 1.7
    assert stiff.sum() >= 2
    assert np.all((ratio[stiff] > 1.0) & (ratio[stiff] < 1.35)), dict(zip(k_bar, ratio))
