"""The tips' criterion calibrated to Kendall's force (``LoadPath.pillar_tip_calibration``, `brushbem.pillars.calibration`).

A lone flat tip on a raster of 3-4 elements per radius comes off several per
cent away from Kendall's force; scaling its critical stress by F_K / F_R (F_R
the lone tip's pull-off on its raster) makes it come off at F_K exactly,
because a lone rigid tip's pull-off is proportional to the critical stress.
The smallest problem that shows it is one pillar of 3.6 elements' radius on a
grid of 32 (the footprint of the validation families, 45 elements).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from brushbem.errors import ParameterError
from brushbem.physics.structure import Grid, brush
from brushbem.physics.theory.punch import kendall_force
from brushbem.pillars import PillarModel
from brushbem.pillars.calibration import lone_pull_off
from brushbem.protocol import ContactProblem, LoadPath, record_pull_off

DGAMMA = 1e-4
#: One pillar of 3.61 elements' radius at N = 32 (the validation families' 8 x 8 footprint, offset by the
#: lattice point at the centre of an element), on a spring a thousand times stiffer than the tip.
ELEMENTS, RADIUS, STIFFNESS = 32, math.sqrt(0.16 / math.pi) / 8, 100.0


def _lone(stiffness: float = STIFFNESS, elements: int = ELEMENTS) -> ContactProblem:
    grid = Grid(0.25, elements)
    indenter = brush(grid, layout="square", pillars_per_side=1, pillar_radius=RADIUS, contact_modulus=1.0,
                     work_of_adhesion=DGAMMA, stiffness=stiffness, seed=3)
    return ContactProblem(grid, indenter, contact_modulus=1.0, work_of_adhesion=DGAMMA)


def _adhesive_force(problem: ContactProblem, method: str, **extra) -> float:
    record = record_pull_off(problem, LoadPath(method=method, preload_displacement=1e-4, max_steps=10**5,
                                               **{"pillar_tip_peel": False, **extra}))
    assert record.summary["converged"], record.summary["reason"]
    return record.summary["adhesive_force"]


def _kendall(problem: ContactProblem) -> float:
    return float(kendall_force(RADIUS, contact_modulus=1.0, work_of_adhesion=problem.work_of_adhesion))


def _footprint(model: PillarModel) -> np.ndarray:
    size = int(np.count_nonzero(model.full[0]))
    return np.stack([model.rows[0][:size], model.cols[0][:size]], axis=1)


def test_the_lone_tips_pull_off_is_the_exact_paths():
    """`lone_pull_off` is the exact event path's F_A for the tip alone on the same raster (to 1e-6: the
    spring, 1000 times stiffer than the tip, lowers the exact path's force by less), and it is away from
    Kendall's: what the calibration removes."""
    problem = _lone()
    model = PillarModel(problem)
    force, events = lone_pull_off(model.bases, _footprint(model), problem.critical_stress, model.h2)
    exact = _adhesive_force(problem, "events")
    assert force == pytest.approx(exact, rel=1e-6)
    assert events >= 1
    assert abs(force / _kendall(problem) - 1) > 0.02


def test_a_calibrated_lone_tip_comes_off_at_kendalls_force():
    """The calibrated criterion makes the lone tip on its raster give F_K (to 1e-6, the stiff spring), on the
    grid's raster and on a finer one of its own; uncalibrated, the pillar model gives the raster's force."""
    problem = _lone()
    kendall = _kendall(problem)
    for tips in (None, 7.0):
        calibrated = _adhesive_force(problem, "pillars", pillar_tip_resolution=tips, pillar_tip_calibration=True)
        assert calibrated == pytest.approx(kendall, rel=1e-6)
    model = PillarModel(problem)
    force = lone_pull_off(model.bases, _footprint(model), problem.critical_stress, model.h2)[0]
    assert _adhesive_force(problem, "pillars") == pytest.approx(force, rel=1e-6)


def test_the_calibration_scales_each_footprint_by_its_own_factor():
    """Pillars of different footprints get different critical stresses (a random layout), those of one shape
    the same, and every one is the raster's Sigma_c times F_K / F_R of its own footprint (to round-off)."""
    grid = Grid(1.0, 64)
    indenter = brush(grid, layout="random", pillar_count=6, pillar_radius=0.05, min_gap=2 / 64, contact_modulus=1.0,
                     work_of_adhesion=DGAMMA, stiffness=1e-2, seed=5)
    problem = ContactProblem(grid, indenter, contact_modulus=1.0, work_of_adhesion=DGAMMA)
    model = PillarModel(problem, criterion="calibrated")
    plain = PillarModel(problem)
    kendall = float(kendall_force(0.05, contact_modulus=1.0, work_of_adhesion=DGAMMA))
    shapes = {}
    for p in range(model.M):
        size = int(np.count_nonzero(model.full[p]))
        foot = np.stack([model.rows[p][:size], model.cols[p][:size]], axis=1)
        key = (foot - foot.min(axis=0)).tobytes()
        force = lone_pull_off(plain.bases, foot - foot.min(axis=0), problem.critical_stress, model.h2)[0]
        assert model.critical[p, 0] == pytest.approx(problem.critical_stress * kendall / force, rel=1e-12)
        shapes.setdefault(key, set()).add(float(model.critical[p, 0]))
    assert all(len(values) == 1 for values in shapes.values())
    assert len({next(iter(values)) for values in shapes.values()}) > 1
    np.testing.assert_array_equal(plain.critical, problem.critical_stress)


def test_the_calibration_is_refused_outside_the_pillar_model():
    with pytest.raises(ParameterError, match="pillar_tip_calibration.*method = 'pillars' only"):
        LoadPath(method="events", preload_force=1e-3, pillar_tip_calibration=True)


def test_the_calibration_from_the_configuration_leaves_case_ids_alone():
    """``protocol.pillar_tip_calibration`` reaches the path; at its default (false) the resolved configuration
    that a case id hashes is what it was."""
    from brushbem.config import config_to_dict, parse_config
    from brushbem.runs.assembly import assemble

    base = {"halfspace": {"contact_modulus": 1.0, "work_of_adhesion": DGAMMA}, "grid": {"size": 1.0, "elements": 64},
            "indenter": {"shape": "brush", "layout": "square", "pillars_per_side": 4, "pillar_radius": 0.056,
                         "stiffness_ratio": 1e-2, "seed": 3},
            "protocol": {"method": "pillars", "preload_force": 1e-3}}
    tuned = {**base, "protocol": {**base["protocol"], "pillar_tip_calibration": True}}
    assert assemble(parse_config(tuned)).path.pillar_tip_calibration is True
    default = {**base, "protocol": {**base["protocol"], "pillar_tip_calibration": False}}
    assert "pillar_tip_calibration" not in config_to_dict(parse_config(default))["protocol"]
    assert config_to_dict(parse_config(default)) == config_to_dict(parse_config(base))


def _calibration_script():
    """``docs/pillars/calibration.py`` as a module."""
    from test_pillar_tips import _pillars_script

    return _pillars_script("calibration.py", "pillar_calibration_table")


def _errors(rows: list[dict], per_radius: str, calibrated: str, name: str = "force_error_extrapolated") -> list[float]:
    return [float(row[name]) for row in rows if row["tip_elements_per_radius"] == per_radius
            and row["calibrated"] == calibrated and row[name] != "nan"]


def test_the_calibration_table_holds_what_the_docs_say():
    """``docs/pillars/calibration.csv``: against the extrapolated exact path (six cases) the default is +2.8 ..
    +7.8 % on F_A, calibrated +2.5 .. +3.5 % (above the 1 % target everywhere: not the default), with tips at
    7.2 per radius +1.1 .. +4.2 % and calibrated +0.4 .. +1.5 %; the work at k~ = 10 (two cases) +15.6 ..
    +16.3 % and calibrated +6.5 .. +7.1 % (`docs/pillars/accuracy.md`, "Calibrated tips"; to the quoted digits)."""
    rows = _calibration_script().load()
    quoted = {("3.611", "False"): (0.028, 0.078), ("3.611", "True"): (0.025, 0.035),
              ("7.222", "False"): (0.011, 0.042), ("7.222", "True"): (0.004, 0.015)}
    for (per_radius, calibrated), (low, high) in quoted.items():
        errors = _errors(rows, per_radius, calibrated)
        assert len(errors) == 6
        assert (min(errors), max(errors)) == pytest.approx((low, high), abs=5e-4), (per_radius, calibrated)
    assert min(_errors(rows, "3.611", "True")) > 0.02
    work = {calibrated: _errors(rows, "3.611", calibrated, "work_error_extrapolated") for calibrated in ("False", "True")}
    assert (min(work["False"]), max(work["False"])) == pytest.approx((0.156, 0.163), abs=5e-4)
    assert (min(work["True"]), max(work["True"])) == pytest.approx((0.065, 0.071), abs=5e-4)


def test_a_level_brushs_calibrated_force_is_its_force_over_the_lone_tips():
    """On a level lattice (flat and hierarchical brushes: one footprint, every tip pressed alike) F_A is
    proportional to the critical stress, so the calibrated F_A is the uncalibrated one over 1 + the lone tip's
    error, at every tip resolution: the table's pairs hold it to its six digits."""
    rows = _calibration_script().load()
    pairs = {}
    for row in rows:
        if row["family"] in ("flat", "hierarchy"):
            key = (row["family"], row["stiffness_ratio"], row["tip_elements_per_radius"])
            pairs.setdefault(key, {})[row["calibrated"]] = row
    assert len(pairs) == 16
    for key, pair in pairs.items():
        plain, calibrated = pair["False"], pair["True"]
        expected = float(plain["adhesive_force"]) / (1 + float(plain["lone_tip_error"]))
        assert float(calibrated["adhesive_force"]) == pytest.approx(expected, rel=2e-5), key


def test_the_calibration_table_is_what_its_script_computes():
    """One pair of rows (the flat 8 x 8 brush at k~ = 1e-2, the grid's tips) computed again: the same F_A,
    work and lone tip's error to the table's six digits."""
    script = _calibration_script()
    case, preload = script.problem("flat", 8, 1e-2)
    for written in [row for row in script.load() if (row["family"], row["stiffness_ratio"],
                                                     row["tip_elements_per_radius"]) == ("flat", "0.01", "3.611")]:
        summary = record_pull_off(case, LoadPath(method="pillars", preload_force=preload, max_steps=10**6,
                                                 pillar_tip_calibration=written["calibrated"] == "True",
                                                 pillar_tip_peel=False)).summary
        assert summary["adhesive_force"] == pytest.approx(float(written["adhesive_force"]), rel=1e-5)
        assert summary["work_of_separation"] == pytest.approx(float(written["work"]), rel=1e-5)
        assert script.lone_tip_error(case, 1) == pytest.approx(float(written["lone_tip_error"]), rel=1e-5)


def test_per_element_criteria_take_every_element_of_a_lone_tip_at_kendalls_force():
    """The per-element variant (`tip_criteria(per_element=True)`): every element's critical stress in
    proportion to its pressure under the lone tip's uniform pull, so the lone tip on its raster comes off
    in one event with every element at its criterion, at F_K (to 1e-9: one linear solve); through the path
    as well (to 1e-6, the stiff spring)."""
    from unittest import mock

    import brushbem.pillars.calibration
    from brushbem.pillars.calibration import tip_criteria

    problem = _lone()
    model = PillarModel(problem)
    criteria = tip_criteria(model, problem, problem.critical_stress, True, per_element=True)
    size = int(np.count_nonzero(model.full[0]))
    phi = model.bases.get(_footprint(model) - _footprint(model).min(axis=0)).phi[:, 0]
    ratio = criteria[0, :size] / phi
    np.testing.assert_allclose(ratio, ratio[0], rtol=1e-12)
    assert np.ptp(criteria[0, :size]) > 0.5 * criteria[0, :size].max()  # edge and centre differ: not a constant
    force, events = lone_pull_off(model.bases, _footprint(model), criteria[0, :size], model.h2)
    assert force == pytest.approx(_kendall(problem), rel=1e-9)
    assert events == 1

    def per_element(model, problem, critical, calibrate):
        return tip_criteria(model, problem, critical, calibrate, per_element=True)

    with mock.patch.object(brushbem.pillars.calibration, "tip_criteria", per_element):
        assert _adhesive_force(problem, "pillars", pillar_tip_calibration=True) == pytest.approx(_kendall(problem),
                                                                                                 rel=1e-6)
