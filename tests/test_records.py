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


# ---------------------------------------------------------------- the typed results floor, to disk and back


def _small_brush():
    return {"halfspace": {"contact_modulus": 1.0, "work_of_adhesion": 1e-4}, "grid": {"size": 1.0, "elements": 32},
            "indenter": {"shape": "brush", "layout": "square", "region": "square", "pillars_per_side": 2,
                         "pillar_radius": 0.1, "stiffness_ratio": 0.05},
            "protocol": {"method": "events", "preload_displacement": 2e-3}}


@pytest.mark.parametrize("kind", ["brush", "punch_on_spring"])
def test_load_gives_back_the_typed_pull_off_that_run_returned_and_saved(kind, tmp_path):
    """`brushbem.load` rebuilds every record of the summary; only ``run_id`` and ``provenance`` are added."""
    import dataclasses
    import json

    import brushbem
    from brushbem.results import (
        BrushNormalization,
        BrushTheory,
        DesignNumbers,
        Provenance,
        PunchTheory,
        ResolutionRecord,
        RunSummary,
        Spring,
    )

    config = _small_brush() if kind == "brush" else {
        "halfspace": {"contact_modulus": 1.0, "work_of_adhesion": 1e-4}, "grid": {"size": 1.0, "elements": 32},
        "indenter": {"shape": "flat_punch", "radius": 0.25, "stiffness": 0.1},
        "protocol": {"method": "events", "preload_displacement": 1e-3}}
    ran = brushbem.run(config)
    ran.save(tmp_path, figure=False)
    loaded = brushbem.load(tmp_path)
    assert type(loaded) is type(ran) is brushbem.PullOff
    summary = loaded.summary
    assert isinstance(summary, RunSummary) and isinstance(summary.provenance, Provenance)
    assert isinstance(summary.theory, BrushTheory if kind == "brush" else PunchTheory)
    assert isinstance(summary.normalized, BrushNormalization) if kind == "brush" else summary.normalized is None
    assert not isinstance(summary.normalized, dict) and not isinstance(summary.theory, dict)
    assert isinstance(summary.resolution, ResolutionRecord) and isinstance(summary.design, DesignNumbers)
    assert isinstance(summary.design.spring, Spring) and summary.design["spring"]["from"] == summary.design.spring.origin
    assert summary.resolution.length == ("pillar radius" if kind == "brush" else "punch radius")
    assert len(summary.run_id) == 32 and summary.provenance.config == json.loads(json.dumps(
        summary.provenance.config))
    assert dataclasses.replace(summary, run_id=None, provenance=None) == ran.summary
    # summary.json is the loaded record, key by key and in order.
    from brushbem.io.encoding import _json

    assert _json(summary, indent=2) + "\n" == (tmp_path / "summary.json").read_text(encoding="utf-8")
    for name in ("displacement", "force", "contact_area", "loading"):
        np.testing.assert_array_equal(getattr(loaded.curve, name), getattr(ran.curve, name))
    assert loaded.config == ran.config
    assert loaded.snapshots.keys() == ran.snapshots.keys() and loaded.result.element_size == ran.result.element_size
    for name, snapshot in ran.snapshots.items():
        np.testing.assert_array_equal(loaded.snapshots[name].pressure, snapshot.pressure)
    assert loaded.result.pillars.keys() == ran.result.pillars.keys()
    for name, values in ran.result.pillars.items():
        np.testing.assert_array_equal(loaded.result.pillars[name], values)
    assert (ran.reference is None) == (kind == "brush")  # a punch's figure draws its closed form
    if ran.reference is not None:
        np.testing.assert_array_equal(loaded.reference.force, ran.reference.force)
        assert loaded.reference.label == ran.reference.label
    else:
        assert loaded.reference is None


def test_a_record_is_rebuilt_from_its_mapping_and_refuses_another_layout():
    import json

    from brushbem.results import Extrapolation, Refinement, RunSummary

    refinement = Refinement(elements=[16, 32, 64], converged=True,
                            adhesive_force=Extrapolation(values=[1.0, 1.5, 1.75], extrapolated=2.0,
                                                         error_estimate=0.01, observed_order=1.0),
                            work_of_separation=Extrapolation(values=[2.0, 2.5], extrapolated=3.0,
                                                             error_estimate=0.5, observed_order=None))
    decoded = json.loads(json.dumps(refinement.to_dict(), default=dict))
    assert Refinement.from_mapping(decoded) == refinement
    assert isinstance(Refinement.from_mapping(decoded).adhesive_force, Extrapolation)
    with pytest.raises(ValueError, match=r"Refinement: unknown keys \['grids'\]"):
        Refinement.from_mapping({**decoded, "grids": [1]})
    with pytest.raises(ValueError, match="RunSummary: .*critical_stress"):
        RunSummary.from_mapping({key: value for key, value in _a_summary().items() if key != "critical_stress"})


def _a_summary():
    import brushbem

    return dict(brushbem.run(_small_brush()).summary)


def test_the_sweep_table_columns_are_the_record_fields():
    """A run's summary, flattened as a sweep's table flattens it, has only declared columns; a study names an
    undeclared one at import (`summary_column`), with the closest declared ones."""
    import json

    import pandas as pd

    import brushbem
    from brushbem.io.encoding import _json
    from brushbem.results.columns import OPEN_PREFIXES, SUMMARY_COLUMNS, summary_column

    punch = {"halfspace": {"contact_modulus": 1.0, "work_of_adhesion": 1e-4}, "grid": {"size": 1.0, "elements": 32},
             "indenter": {"shape": "flat_punch", "radius": 0.25, "stiffness": 0.1},
             "protocol": {"method": "events", "preload_displacement": 1e-3}}
    sphere = {"halfspace": {"contact_modulus": 1.0, "work_of_adhesion": 1e-3}, "grid": {"size": 1.0, "elements": 32},
              "indenter": {"shape": "sphere", "radius": 1.0, "stiffness": 0.5},
              "protocol": {"method": "events", "preload_displacement": 5e-3}}
    seen = set()
    for config in (_small_brush(), punch, sphere):
        summary = json.loads(_json(brushbem.run(config).summary))
        columns = set(pd.json_normalize([summary], sep=".").columns)
        undeclared = {c for c in columns - SUMMARY_COLUMNS if not any(c.startswith(p + ".") for p in OPEN_PREFIXES)}
        assert not undeclared
        seen |= columns
    assert {"normalized.stiffness_ratio", "theory.equivalent_radius", "theory.zero_force_radius",
            "theory.compact_punch_force", "resolution.force_error_estimate", "design.spring.from",
            "design.adhesion_strength"} <= seen & SUMMARY_COLUMNS
    assert summary_column("theory.ratios.adhesive_force") == "theory.ratios.adhesive_force"  # an open mapping
    with pytest.raises(KeyError, match="'normalized.stifness_ratio' is no column .* normalized.stiffness_ratio"):
        summary_column("normalized.stifness_ratio")
