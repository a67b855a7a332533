"""The pull-off on a GPU (CuPy) equals the one on NumPy: run where a CUDA device and CuPy are present.

The CPU stand-in is ``tests/test_array_api.py`` (the strict array API); this
file is the real device.  A brush takes different CG systems on the two
(pillar blocks on the host for NumPy, the window with the spring
preconditioner on the device), so they agree to the CG tolerance 1e-8, about
1e-7 relative in the force (``rel=1e-6`` below leaves a factor 10); a punch
or sphere takes the same path and agrees closer.  Skipped without a device
(CI has none); ``benchmarks/gpu.py`` times the same comparison.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from brushbem.protocol import ContactProblem, LoadPath, record_pull_off
from brushbem.physics.structure import Grid, Level, brush, flat_punch, sphere

cupy = pytest.importorskip("cupy")
try:
    DEVICES = cupy.cuda.runtime.getDeviceCount()
except Exception:  # no driver: CuPy imports but finds no device
    DEVICES = 0
pytestmark = pytest.mark.skipif(DEVICES == 0, reason="no CUDA device")

GRID = Grid(1.0, 128)


def _brush(**kwargs):
    return brush(GRID, layout="square", pillars_per_side=8, pillar_radius=math.sqrt(0.16 / math.pi) / 8,
                 contact_modulus=1.0, work_of_adhesion=1e-4, **kwargs)


CASES = {
    "jkr sphere": (lambda: sphere(GRID, 1.0), 1e-3, "events"),
    "punch on a spring": (lambda: flat_punch(GRID, 0.2, 0.05), 1e-4, "events"),
    "rough brush": (lambda: _brush(stiffness=1e-2, roughness=5e-4, seed=3), 1e-4, "events"),
    "hierarchy": (lambda: _brush(stiffness=1e-2, levels=(Level(2, 1e-2),)), 1e-4, "events"),
    "rough brush, fixed steps": (lambda: _brush(stiffness=1e-2, roughness=5e-4, seed=3), 1e-4, "fixed"),
}


@pytest.mark.parametrize("name", list(CASES))
def test_pull_off_on_the_gpu_equals_numpy(name):
    make, dgamma, method = CASES[name]
    indenter = make()
    summaries = []
    for xp in (np, cupy):
        problem = ContactProblem(GRID, indenter, 1.0, dgamma, xp=xp)
        record = record_pull_off(problem, LoadPath(method=method, preload_displacement=2e-3, step=4e-4))
        assert record.summary["converged"], record.summary["reason"]
        summaries.append(record.summary)
    on_numpy, on_gpu = summaries
    assert on_gpu["n_states"] == on_numpy["n_states"]
    for key in ("preload_force", "adhesive_force", "pull_off_displacement", "work_of_separation"):
        assert on_gpu[key] == pytest.approx(on_numpy[key], rel=1e-6, abs=1e-15), key
