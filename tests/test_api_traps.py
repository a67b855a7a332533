"""The Python API without traps (issue: one material per run, no silent zero adhesion, the file's keys).

Each test states the promise it keeps; the grids are the smallest that build the objects (no physics
is measured here beyond one tiny pull-off).
"""

from __future__ import annotations

import math

import pytest

import brushbem
from brushbem.physics.structure import StructureError

GRID = brushbem.Grid(1.0, 32)


def _pillars(**kwargs):
    args = {"layout": "square", "pillars_per_side": 2, "pillar_radius": 0.1, "contact_modulus": 1.0,
            "work_of_adhesion": 1e-4}
    return brushbem.brush(GRID, **{**args, **kwargs})


def test_a_brush_takes_the_files_stiffness_ratio():
    """brush(stiffness_ratio=k~) is k = k~ E* L, as indenter.stiffness_ratio in a configuration file."""
    by_ratio = _pillars(stiffness_ratio=0.01, contact_modulus=2.0)
    by_stiffness = _pillars(stiffness=0.01 * 2.0 * GRID.size, contact_modulus=2.0)
    assert by_ratio.levels[0].stiffness == pytest.approx(by_stiffness.levels[0].stiffness)
    with pytest.raises(StructureError, match="stiffness_ratio"):
        _pillars(stiffness=1.0, stiffness_ratio=0.01)


def test_a_brush_keeps_its_material_and_a_different_one_is_refused():
    pillars = _pillars()
    with pytest.raises(ValueError, match="contact_modulus = 2.0 differs"):
        brushbem.pull_off(GRID, pillars, contact_modulus=2.0, work_of_adhesion=1e-4, preload_force=1e-3)
    with pytest.raises(ValueError, match="work_of_adhesion = 0.001 differs"):
        brushbem.pull_off(GRID, pillars, contact_modulus=1.0, work_of_adhesion=1e-3, preload_force=1e-3)
    implied = brushbem.pull_off(GRID, pillars, preload_force=1e-3)  # the brush's own E* and dgamma
    given = brushbem.pull_off(GRID, pillars, contact_modulus=1.0, work_of_adhesion=1e-4, preload_force=1e-3)
    assert implied.adhesive_force == given.adhesive_force > 0


def test_a_missing_work_of_adhesion_is_refused_not_taken_as_zero():
    punch = brushbem.flat_punch(GRID, 0.2)
    with pytest.raises(ValueError, match="work_of_adhesion is required"):
        brushbem.pull_off(GRID, punch, contact_modulus=1.0, preload_displacement=1e-3)
    no_adhesion = brushbem.pull_off(GRID, punch, contact_modulus=1.0, work_of_adhesion=0.0,
                                    preload_displacement=1e-3)
    assert no_adhesion.adhesive_force == 0.0 and math.isfinite(no_adhesion.work_of_separation)


def test_a_result_prints_its_headline_not_its_arrays():
    result = brushbem.pull_off(GRID, brushbem.flat_punch(GRID, 0.2), contact_modulus=1.0, work_of_adhesion=1e-4,
                               preload_displacement=1e-3)
    text = repr(result)
    assert len(text) < 400 and "adhesive force F_A=" in text and "array" not in text
    assert "<table>" in result._repr_html_() and "work of separation W" in result._repr_html_()


def test_the_spring_closed_forms_are_named_not_applicable_to_a_nonlinear_or_viscoelastic_spring():
    """The theory block compares only what its closed form describes: F_A always, the base displacement
    and the work of eq. 2.18-2.19 only on a linear elastic spring."""
    import dataclasses

    from brushbem.physics.pillar_laws import PiecewiseLinear
    from brushbem.physics.viscoelastic import Viscoelastic

    punch = brushbem.flat_punch(GRID, 0.2, 0.05)
    linear = brushbem.pull_off(GRID, punch, contact_modulus=1.0, work_of_adhesion=1e-4, preload_displacement=1e-3)
    assert set(linear.summary["theory"]["ratios"]) == {"adhesive_force", "pull_off_displacement", "work_of_separation"}
    assert "not_applicable" not in linear.summary["theory"]
    # Which closed forms apply depends on the spring, not on the step: the coarsest step that runs (1e-3).
    for changed, kwargs in (
        (dataclasses.replace(punch, pillar_law=PiecewiseLinear(forces=(-0.005, 0.002), factors=(0.5, 1.0, 0.05))),
         {"method": "fixed", "step": 1e-3}),
        (dataclasses.replace(punch, viscoelastic=Viscoelastic("kelvin_voigt", 1.0)), {"speed": 1e-3, "method": "fixed",
                                                                                     "step": 1e-3}),
    ):
        theory = brushbem.pull_off(GRID, changed, contact_modulus=1.0, work_of_adhesion=1e-4,
                                   preload_displacement=1e-3, **kwargs).summary["theory"]
        assert set(theory["ratios"]) == {"adhesive_force"}
        assert set(theory["not_applicable"]) == {"pull_off_displacement", "work_of_separation"}
