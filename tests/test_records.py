"""Typed records above the solver: geometry, theory comparison, reference curves.

Each record reads as attributes (code) and as the mapping of its fields (JSON,
NetCDF attributes, tables), with the keys ``summary.json`` had as dicts.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from brushbem.runs.case import theory_for
from brushbem.protocol import ContactProblem, LoadPath
from brushbem.results import BrushTheory, PunchTheory, ReferenceCurve, SphereTheory
from brushbem.physics.structure import (
    BrushGeometry,
    Geometry,
    Grid,
    Indenter,
    PunchGeometry,
    SphereGeometry,
    brush,
    flat_punch,
    sphere,
)

GRID = Grid(1.0, 32)


def test_geometry_records_are_frozen_and_read_as_mappings():
    punch = flat_punch(GRID, 0.25).description
    assert isinstance(punch, PunchGeometry) and punch.shape == "flat_punch"
    assert list(punch) == ["shape", "radius", "rasterised_area"]
    assert punch["rasterised_area"] == punch.rasterised_area > 0
    with pytest.raises(dataclasses.FrozenInstanceError):
        punch.radius = 1.0
    assert isinstance(sphere(GRID, 0.5).description, SphereGeometry)
    assert Indenter(np.zeros((4, 4)), np.zeros((4, 4), dtype=int)).description == Geometry(shape="custom")
    b = brush(GRID, layout="square", pillars_per_side=2, pillar_radius=0.1, stiffness=1.0,
              contact_modulus=1.0, work_of_adhesion=1e-4)
    info = b.description
    assert isinstance(info, BrushGeometry) and info.n_pillars == 4
    assert info["centres"].shape == (4, 2) and info.filling_factor == info.real_area / info.apparent_area


@pytest.mark.parametrize("stiffness", [math.inf, 0.05])
def test_theory_records_keep_the_keys_of_summary_json(stiffness):
    punch = ContactProblem(GRID, flat_punch(GRID, 0.25, stiffness=stiffness), 1.0, 1e-3)
    summary = {"adhesive_force": 1.0, "max_displacement": 0.01}
    record, reference = theory_for(punch, summary)
    assert isinstance(record, PunchTheory) and isinstance(reference, ReferenceCurve)
    keys = ["model", "equivalent_radius", "adhesive_force", "pull_off_displacement", "work_of_separation"]
    keys += ["normalized_stiffness"] if math.isfinite(stiffness) else []
    assert list(record) == [*keys, "ratios"]
    assert record.ratios == {"adhesive_force": 1.0 / record.adhesive_force}
    ball = ContactProblem(GRID, sphere(GRID, 0.5, stiffness=stiffness), 1.0, 1e-4)
    record, _ = theory_for(ball, summary, LoadPath(method="events", preload_force=1e-3))
    assert isinstance(record, SphereTheory)
    assert list(record)[:3] == ["preload_contact_radius", "zero_force_radius", "work_counted_from"]
    record, _ = theory_for(ball, summary)  # no load path: no preload keys
    assert "preload_contact_radius" not in record and record["model"].startswith("JKR")


def test_brush_and_non_adhesive_theory():
    b = brush(GRID, layout="square", pillars_per_side=2, pillar_radius=0.1, stiffness=1.0,
              contact_modulus=1.0, work_of_adhesion=1e-4)
    record, reference = theory_for(ContactProblem(GRID, b, 1.0, 1e-4), {"adhesive_force": 1e-3})
    assert isinstance(record, BrushTheory) and reference is None
    assert record.rigid_brush_displacement < 0 and set(record.ratios) == {
        "adhesive_force_by_rigid_brush", "adhesive_force_by_ideal_sharing"}
    assert theory_for(ContactProblem(GRID, flat_punch(GRID, 0.25), 1.0, 0.0), {}) == ({}, None)
