"""The pillar model's tips on a raster of their own (``LoadPath.pillar_tip_resolution``, `brushbem.pillars.tips`).

A brush on a grid of N elements with tips subdivided f times holds exactly
the footprints of the same brush on a grid of f N elements, so the pillar
model's pull-off must be that grid's to round-off, and within the model's
validated 1 % (F_A) / 3 % (work) of the exact path on the fine grid: the
global grid then only places the pillars.  The smallest brush that shows it
is a rough 4 x 4 lattice at phi = 0.16 (3.6 elements' radius at N = 64).
"""

from __future__ import annotations

import csv
import math

import numpy as np
import pytest

import brushbem
from brushbem.errors import ParameterError
from brushbem.physics.structure import Grid, brush
from brushbem.pillars import PillarModel
from brushbem.pillars.tips import TipRaster, tip_factor
from brushbem.protocol import ContactProblem, LoadPath, record_pull_off

DGAMMA = 1e-4
PHI = 0.16
#: The rough brush's tip heights: sigma = 1.5e-3 (about the rigid 4 x 4 brush's d_c), the same on every grid.
ROUGHNESS = 1.5e-3
#: Its preload, about the rigid brush's F_c (0.0085 at N = 128).
PRELOAD = 0.0085


def _problem(elements: int, per_side: int = 4, stiffness: float = 1e-2, roughness: float = ROUGHNESS,
             **extra) -> ContactProblem:
    grid = Grid(1.0, elements)
    indenter = brush(grid, layout="square", pillars_per_side=per_side, pillar_radius=math.sqrt(PHI / math.pi) / per_side,
                     contact_modulus=1.0, work_of_adhesion=DGAMMA, stiffness=stiffness, roughness=roughness, seed=3,
                     **extra)
    return ContactProblem(grid, indenter, contact_modulus=1.0, work_of_adhesion=DGAMMA)


def _mapping() -> dict:
    """The configuration of the 4 x 4 brush at N = 64 (3.6 elements per radius) in the pillar model."""
    return {
        "halfspace": {"contact_modulus": 1.0, "work_of_adhesion": DGAMMA},
        "grid": {"size": 1.0, "elements": 64},
        "indenter": {"shape": "brush", "layout": "square", "pillars_per_side": 4,
                     "pillar_radius": math.sqrt(PHI / math.pi) / 4, "stiffness_ratio": 1e-2, "seed": 3},
        "protocol": {"method": "pillars", "preload_force": PRELOAD, "pillar_tip_peel": False},
    }


def _summary(problem: ContactProblem, method: str = "pillars", tips: float | None = None) -> dict:
    extra = {"pillar_tip_resolution": tips} if method == "pillars" else {}
    record = record_pull_off(problem, LoadPath(method=method, preload_force=PRELOAD, max_steps=10**6,
                                               pillar_tip_peel=False, **extra))
    assert record.summary["converged"], record.summary["reason"]
    return record.summary


def test_fine_tips_hold_the_fine_grids_footprints():
    """The tips' raster at factor 2 of N = 64 is N = 128's rasterisation, element for element, the criterion
    that grid's, and the tips' heights the brush's."""
    coarse, fine = _problem(64), _problem(128)
    tips = TipRaster.build(coarse, 2)
    reference = TipRaster.build(fine, 1)
    np.testing.assert_array_equal(tips.flat, reference.flat)
    np.testing.assert_array_equal(tips.owner, reference.owner)
    np.testing.assert_array_equal(tips.heights, reference.heights)
    assert tips.critical_stress == pytest.approx(fine.critical_stress, rel=1e-14)
    assert tips.per_radius == pytest.approx(2 * coarse.indenter.description.pillar_radius / coarse.grid.element_size)


def test_tip_factor_is_the_smallest_that_resolves_the_tips():
    problem = _problem(64)  # 3.6 elements per radius
    assert tip_factor(problem, None) == 1
    assert tip_factor(problem, 3.0) == 1
    assert tip_factor(problem, 7.0) == 2
    assert tip_factor(problem, 14.4) == 4  # 4 x 3.6 = 14.4 exactly: no fifth subdivision from round-off
    assert tip_factor(problem, 14.5) == 5


def test_fine_tips_decouple_from_the_global_grid():
    """Rough 4 x 4 brush, k~ = 0.01: tips at 7.2 elements per radius on the grid N = 64 (3.6) give the pillar
    model's pull-off on the grid N = 128 to round-off (the same footprints), and are within 1 % (F_A) and 3 %
    (work) of the exact path on N = 128 (the model's validated accuracy; measured -0.17 % and +0.12 %), while the
    grid's own tips are not (+3.4 % and +4.7%; the exact path on N = 64 is +3.4 % and +4.8 % from N = 128)."""
    coarse, fine = _problem(64), _problem(128)
    refined = _summary(coarse, tips=7.2)
    same = _summary(fine)
    exact = _summary(fine, "events")
    coarse_tips = _summary(coarse)
    for key in ("adhesive_force", "work_of_separation"):
        assert refined[key] == pytest.approx(same[key], rel=1e-9)
    assert refined["adhesive_force"] == pytest.approx(exact["adhesive_force"], rel=0.01)
    assert refined["work_of_separation"] == pytest.approx(exact["work_of_separation"], rel=0.03)
    assert refined["attached_pillars_at_pull_off"] == same["attached_pillars_at_pull_off"]
    # The tips' resolution is what moved F_A: the grid's own tips are farther from the fine exact path.
    assert abs(coarse_tips["adhesive_force"] / exact["adhesive_force"] - 1) > 0.01


def test_states_report_on_the_global_grid():
    """With fine tips the states' pressure lies on the global grid, every pillar's force on its own
    footprint (a fine element whose global element is not its pillar's reports to its pillar's nearest),
    the same total force, and the contact area the fine raster's."""
    problem = _problem(64, roughness=0.0)
    labels = np.asarray(problem.indenter.pillar)
    h2 = problem.grid.element_size ** 2
    path = LoadPath(method="pillars", preload_force=PRELOAD, max_steps=10**6, pillar_tip_resolution=7.0,
                    pillar_tip_peel=False)
    checked = 0
    for state in brushbem.protocol.pull_off(problem, path):
        if state.kind == "separated":
            continue
        assert state.pressure.shape == (64, 64)
        assert np.all(labels[state.contact] >= 0)
        assert h2 * float(state.pressure.sum()) == pytest.approx(state.force, rel=1e-12, abs=1e-15)
        assert state.attached_pillars == np.unique(labels[state.contact]).size
        # Its elements: each global element once (several fine ones report to it), its pressure the grid's.
        assert np.array_equal(state.pressed.elements, np.flatnonzero(state.contact))
        assert np.array_equal(state.pressed.pressure, state.pressure.ravel()[state.pressed.elements])
        checked += 1
    assert checked >= 5
    model = PillarModel(problem, tips=3)
    assert model.h2 == pytest.approx(h2 / 9)
    assert model.critical == pytest.approx(problem.critical_stress * math.sqrt(3))


def test_tip_resolution_refused_outside_its_range():
    problem = _problem(64)
    for value in (1.0, 0.0, -3.0, math.nan, math.inf):
        with pytest.raises(ParameterError, match="pillar_tip_resolution"):
            LoadPath(method="pillars", preload_force=PRELOAD, pillar_tip_resolution=value)
    with pytest.raises(ParameterError, match="pillar_tip_resolution.*method = 'pillars' only"):
        LoadPath(method="events", preload_force=PRELOAD, pillar_tip_resolution=8.0)
    with pytest.raises(ParameterError, match="pillar_tip_resolution"):
        tip_factor(problem, math.nan)


def test_tip_resolution_from_the_configuration_leaves_case_ids_alone():
    """``protocol.pillar_tip_resolution`` reaches the path; at its default (None) the resolved configuration
    that a case id hashes is what it was (`config_to_dict` leaves the later key out)."""
    from brushbem.config import config_to_dict, parse_config
    from brushbem.runs.assembly import assemble

    base = _mapping()
    tuned = {**base, "protocol": {**base["protocol"], "pillar_tip_resolution": 8.0}}
    assert assemble(parse_config(tuned)).path.pillar_tip_resolution == 8.0
    default = {**base, "protocol": {**base["protocol"], "pillar_tip_resolution": None}}
    assert "pillar_tip_resolution" not in config_to_dict(parse_config(default))["protocol"]
    assert config_to_dict(parse_config(default)) == config_to_dict(parse_config(base))
    assert config_to_dict(parse_config(tuned))["protocol"]["pillar_tip_resolution"] == 8.0


def test_a_peeled_rasters_modes_from_its_footprints_inverse_are_its_own():
    """`Bases` on a footprint of `SCHUR_ELEMENTS` or more gives a peeled raster's modes through the Schur
    complement of the footprint's kept inverse: the same modes, gram, moments and fit as the raster's own
    factorisation, to round-off (1e-9 of their size; the inverse's condition is ~1e3)."""
    from brushbem.physics.halfspace import influence_coefficients
    from brushbem.pillars.modes import MODES, SCHUR_ELEMENTS, Bases

    radius = 12.2  # 469 elements
    i, j = np.mgrid[-13:14, -13:14]
    inside = (i + 0.3) ** 2 + (j - 0.2) ** 2 <= radius**2
    footprint = np.stack([i[inside], j[inside]], axis=1) + 13
    assert footprint.shape[0] >= SCHUR_ELEMENTS
    span = np.arange(30, dtype=np.float64)
    ktab = influence_coefficients(span[:, None], span[None, :], 1.0, 1.0)
    rng = np.random.default_rng(4)
    for lost in (1, 40, 200):  # one element, a rim, less than half of the footprint
        edge = np.argsort(np.hypot(*(footprint - footprint.mean(axis=0)).T) + 0.5 * rng.random(footprint.shape[0]))
        mask = np.ones(footprint.shape[0], dtype=bool)
        mask[edge[-lost:]] = False
        schur = Bases(ktab, MODES["quadratic"]).get(footprint, mask)
        direct = Bases(ktab, MODES["quadratic"])._direct(schur.offsets)
        for name in ("phi", "gram", "m0", "m1", "m2", "fit"):
            a, b = getattr(schur, name), getattr(direct, name)
            np.testing.assert_allclose(a, b, rtol=0, atol=1e-9 * np.max(np.abs(b)), err_msg=name)


def test_refine_refines_the_pillar_models_tips_on_the_configured_grid():
    """``--refine`` with ``method = "pillars"``: the tips at q0, 2 q0, 4 q0 elements per radius on the
    configured grid, q0 the smallest multiple of the grid's (3.6 at N = 64) that reaches 8 (`MIN_REFINE_ELEMENTS`),
    or the configured tips' where they are finer; the events path keeps refining the grid."""
    from brushbem.config import parse_config
    from brushbem.runs.refine import MIN_REFINE_ELEMENTS, refined_configs

    mapping = _mapping()
    per_radius = math.sqrt(PHI / math.pi) / 4 * 64
    configs = refined_configs(parse_config(mapping), 3)
    assert [c.grid.elements for c in configs] == [64, 64, 64]
    tips = [c.protocol.pillar_tip_resolution for c in configs]
    assert tips == pytest.approx([3 * per_radius, 6 * per_radius, 12 * per_radius])
    assert tips[0] >= MIN_REFINE_ELEMENTS > 2 * per_radius
    finer = {**mapping, "protocol": {**mapping["protocol"], "pillar_tip_resolution": 14.0}}
    tips = [c.protocol.pillar_tip_resolution for c in refined_configs(parse_config(finer), 2)]
    assert tips == pytest.approx([4 * per_radius, 8 * per_radius])


@pytest.mark.slow
def test_refine_of_the_pillar_model_reports_the_configured_run_and_its_tips():
    """A 4 x 4 brush at 3.6 elements per radius (N = 64) refined on two tip resolutions (10.8, 21.7): the result
    is the configured run's, the refinement's values the tips' runs, the extrapolation the formal first order
    (two levels bound no error) and its ``elements`` the grids that resolve the tips as much."""
    from brushbem.config import parse_config
    from brushbem.runs.refine import refined_run

    config = parse_config(_mapping())
    pulled = refined_run(config, 2)
    summary = pulled.result.summary
    refinement = summary["refinement"]
    assert pulled.config == config
    assert refinement["elements"] == [192, 384]
    assert refinement["tip_elements_per_radius"] == pytest.approx([10.83, 21.66], rel=1e-3)
    direct = brushbem.run(config).summary
    assert summary["adhesive_force"] == pytest.approx(direct["adhesive_force"], rel=1e-12)
    force = refinement["adhesive_force"]
    assert force["extrapolated"] == pytest.approx(2 * force["values"][1] - force["values"][0], rel=1e-12)
    assert force["error_estimate"] is None


def test_the_resolution_warning_counts_the_tips_raster():
    """At 3.6 elements per radius the pillar model warns with the tips' fix; its tips at 16 resolve the radius
    (no warning) and the estimated error is that of 18 elements per radius (the grid subdivided 5 times)."""
    from brushbem.config import parse_config
    from brushbem.config.advice import resolution, resolution_warnings

    coarse = parse_config(_mapping())
    (warning,) = resolution_warnings(coarse)
    assert "protocol.pillar_tip_resolution" in warning and "raise grid.elements" not in warning
    fine = parse_config({**_mapping(), "protocol": {**_mapping()["protocol"], "pillar_tip_resolution": 16.0}})
    assert resolution_warnings(fine) == []
    assert resolution(fine).elements == pytest.approx(5 * resolution(coarse).elements)


def _pillars_script(file: str, name: str):
    """``docs/pillars/<file>`` as a module named ``name`` (the scripts import ``validation`` from beside them)."""
    import importlib.util
    import sys
    from pathlib import Path

    folder = Path(__file__).resolve().parents[1] / "docs" / "pillars"
    sys.path.insert(0, str(folder))
    try:
        spec = importlib.util.spec_from_file_location(name, folder / file)
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
    finally:
        sys.path.remove(str(folder))
    return module


def _tips_script():
    """``docs/pillars/tips.py`` as a module."""
    return _pillars_script("tips.py", "pillar_tips_table")


def test_the_tips_table_holds_the_models_targets():
    """``docs/pillars/tips.csv``: with its tips at f times the grid's resolution the pillar model is within
    1 % (F_A) and 3 % (work) of the exact path on the grid f N, every family and k~ it holds (the 8 x 8 ones at
    f = 2 at least: 15 rows), but for the two cases the docs name, with tips at 14.4 elements per radius: the
    concave brush at k~ = 10 (+2.3 % on F_A) and the random one at 1e-5 (-1.2 %) (`brushbem.pillars`, "Tip
    resolution")."""
    rows = [row for row in _tips_script().load() if row["events_converged"] == "True"]
    assert sum(row["tip_factor"] == "2" and row["pillars_per_side"] == "8" for row in rows) == 15
    outside = {(row["family"], row["pillars_per_side"], row["stiffness_ratio"], row["tip_factor"]) for row in rows
               if abs(float(row["adhesive_force_error"])) > 0.01 or abs(float(row["work_error"])) > 0.03}
    assert outside == {("concave", "8", "10", "4"), ("random", "8", "1e-05", "4")}


@pytest.mark.slow
def test_the_tips_table_is_what_its_script_computes():
    """One row of ``docs/pillars/tips.csv`` (the hierarchical 8 x 8 brush at k~ = 1e-2, tips at 7.2 elements
    per radius, the exact path on N = 256) computed again: the same numbers to the table's six digits."""
    script = _tips_script()
    (written,) = [row for row in script.load()
                  if (row["family"], row["pillars_per_side"], row["stiffness_ratio"], row["tip_factor"])
                  == ("hierarchy", "8", "0.01", "2")]
    row = script.run_case("hierarchy", 8, 1e-2, 2, {})
    for name in ("events_adhesive_force", "events_work", "pillars_adhesive_force", "pillars_work",
                 "grid_tips_adhesive_force_error"):
        assert row[name] == pytest.approx(float(written[name]), rel=1e-5), name


def test_the_extrapolated_tips_table_is_that_of_the_tips_table():
    """``docs/pillars/tips_extrapolated.csv`` is `extrapolate` of ``tips.csv`` and ``validation.jsonl`` (to its six
    digits): the errors against the extrapolated exact path that the docs quote are those of the tables."""
    script = _tips_script()
    with script.EXTRAPOLATED.open(newline="") as stream:
        written = list(csv.DictReader(stream))
    computed = script.extrapolate(script.load())
    assert [row["family"] for row in written] == [row["family"] for row in computed] and written
    for row, again in zip(written, computed, strict=True):
        for name in ("extrapolated_adhesive_force", "observed_order", "grid_tips_error", "tips_14_error"):
            assert float(row[name]) == pytest.approx(again[name], rel=1e-5, abs=1e-9, nan_ok=True), name


def _pillars_table(name: str) -> list[dict]:
    """The rows of ``docs/pillars/<name>`` (a committed CSV), as strings."""
    from pathlib import Path

    with (Path(__file__).resolve().parents[1] / "docs" / "pillars" / name).open(newline="") as stream:
        return list(csv.DictReader(stream))
