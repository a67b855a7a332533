"""The numerics on an array namespace other than NumPy.

``array_api_strict`` implements the array API standard and nothing more: no
integer-array assignment, no mixing of booleans into arithmetic, no
``bincount``, no methods outside the standard.  A pull-off that runs on it
uses only what a GPU namespace (CuPy, PyTorch) is guaranteed to provide, so
this is the CPU stand-in for the GPU path.  Each case is compared with the
same run on NumPy: the two use different preconditioners on brushes (pillar
blocks on the host for NumPy, the device-side window path otherwise) and
agree to the CG tolerance 1e-8, i.e. about 1e-7 in the force; a case that
takes the same path agrees to round-off.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from brushbem.protocol import ContactProblem, LoadPath, record_pull_off
from brushbem.structure import Grid, Level, brush, flat_punch, sphere

strict = pytest.importorskip("array_api_strict")

GRID = Grid(1.0, 64)


def _brush(**kwargs):
    return brush(GRID, layout="square", pillars_per_side=4, pillar_radius=3 / 64, contact_modulus=1.0,
                 work_of_adhesion=1e-4, **kwargs)


CASES = {
    "hertz": (lambda: sphere(GRID, 1.0), 0.0, "events"),
    "jkr": (lambda: sphere(GRID, 1.0), 1e-3, "events"),
    "punch on a spring": (lambda: flat_punch(GRID, 0.2, 0.05), 1e-4, "events"),
    "soft brush": (lambda: _brush(stiffness=1e-3), 1e-4, "events"),
    "hierarchy": (lambda: _brush(stiffness=1e-2, levels=(Level(2, 1e-2),)), 1e-4, "events"),
    "rigid brush, fixed steps": (lambda: _brush(stiffness=math.inf), 1e-4, "fixed"),
}


@pytest.mark.parametrize("name", list(CASES))
def test_pull_off_on_the_strict_array_api_equals_numpy(name):
    make, dgamma, method = CASES[name]
    indenter = make()
    summaries = []
    for xp in (np, strict):
        problem = ContactProblem(GRID, indenter, 1.0, dgamma, xp=xp)
        record = record_pull_off(problem, LoadPath(method=method, preload_displacement=2e-3, step=4e-4))
        assert record.summary["converged"], record.summary["reason"]
        summaries.append(record.summary)
    on_numpy, on_strict = summaries
    assert on_strict["n_states"] == on_numpy["n_states"]
    for key in ("preload_force", "adhesive_force", "pull_off_displacement", "work_of_separation"):
        assert on_strict[key] == pytest.approx(on_numpy[key], rel=1e-6, abs=1e-15), key
