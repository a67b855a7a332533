"""The snapshot stages of a pull-off (thesis Fig. 4-3) are what their names say, or are absent with the reason.

* ``max_preload``: the end of the loading branch (the largest d).
* ``zero_force``: the unloading state at F = 0, interpolated between two
  states on one contact set (the pressure is affine in d there), so its
  force is 0 to rounding; where the force jumps across 0 in a cascade it is
  absent and ``stages_not_reached`` says so.
* ``adhesive_force``: the state of the most tensile force, F = -F_A.
* ``half_detached``: the first state with at most half of the preload's
  attached pillars still attached (brushes only), or absent with the reason
  when they all come off at once.
* ``before_separation``: the last state with contact.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from brushbem.protocol import ContactProblem, LoadPath, record_pull_off
from brushbem.physics.structure import Grid, brush, flat_punch, sphere

GRID = Grid(1.0, 64)


def _snapshots(record):
    return {snapshot.name: snapshot for snapshot in record.snapshots}


def _check_common(record, preload_d):
    snaps = _snapshots(record)
    summary = record.summary
    assert snaps["max_preload"].displacement == pytest.approx(preload_d, rel=1e-12, abs=0.0)
    assert snaps["adhesive_force"].force == pytest.approx(-summary["adhesive_force"], rel=1e-12, abs=0.0)
    assert snaps["before_separation"].displacement == pytest.approx(summary["separation_displacement"], rel=1e-12, abs=0.0)
    if "zero_force" in snaps:
        zero = snaps["zero_force"]
        # 0 to the rounding of the pressures summed (1e-12 of the preload force).
        assert abs(zero.force) <= 1e-12 * summary["preload_force"]
        assert np.sum(zero.contact) > 0
        # Between the preload and the adhesive-force moment along the unloading.
        assert snaps["adhesive_force"].displacement <= zero.displacement <= snaps["max_preload"].displacement
    else:
        assert "zero_force" in (summary.get("stages_not_reached") or {})
    return snaps


@pytest.mark.parametrize("method", ["events", "fixed"])
def test_punch_stages(method):
    punch = flat_punch(GRID, 0.2, 0.3)
    record = record_pull_off(ContactProblem(GRID, punch, contact_modulus=1.0, work_of_adhesion=1e-3),
                             LoadPath(method=method, preload_displacement=0.01, step=5e-4))
    snaps = _check_common(record, 0.01)
    assert "zero_force" in snaps  # a punch unloads on its full contact: the crossing is interpolated
    assert "half_detached" not in snaps and "half_detached" not in (record.summary.get("stages_not_reached") or {})


def test_sphere_stages():
    ball = sphere(GRID, 1.0)
    record = record_pull_off(ContactProblem(GRID, ball, contact_modulus=1.0, work_of_adhesion=1e-3),
                             LoadPath(method="events", preload_force=0.02))
    _check_common(record, record.summary["max_displacement"])


def test_brush_stages_and_a_cascade_that_skips_half_detached():
    """A stiff flat brush comes off in one cascade (no half-detached state); a rough soft one peels pillar by pillar."""
    radius = math.sqrt(0.16 / math.pi) / 4

    def run(**extra):
        indenter = brush(GRID, layout="square", pillars_per_side=4, pillar_radius=radius, contact_modulus=1.0,
                         work_of_adhesion=1e-4, **extra)
        problem = ContactProblem(GRID, indenter, contact_modulus=1.0, work_of_adhesion=1e-4)
        return record_pull_off(problem, LoadPath(method="events", preload_displacement=0.006))

    stiff = run(stiffness=10.0)
    snaps = _check_common(stiff, 0.006)
    reasons = stiff.summary["stages_not_reached"]
    assert "half_detached" not in snaps and "one detachment cascade" in reasons["half_detached"]
    rough = run(stiffness=1e-3, roughness=2e-3, seed=3)
    snaps = _check_common(rough, 0.006)
    half = snaps["half_detached"]
    preload_attached = int(np.sum(_attached(rough, snaps["max_preload"])))
    attached = int(np.sum(_attached(rough, half)))
    assert 0 < attached <= preload_attached / 2


def _attached(record, snapshot):
    return np.asarray(snapshot.pillar_force) != 0
