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

A GPU namespace also refuses to be turned into a NumPy array implicitly
(CuPy raises on ``np.asarray``); ``array_api_strict`` allows it on its CPU
device.  Here it refuses too (``_refuse_implicit_conversion``), so every
host copy must go through the one boundary, ``backend.to_numpy``, and a
stray ``np.asarray`` of a solver array fails here instead of on the first
GPU run.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from brushbem import backend
from brushbem.protocol import ContactProblem, LoadPath, record_pull_off
from brushbem.physics.structure import Grid, Level, Profile, brush, flat_punch, sphere

strict = pytest.importorskip("array_api_strict")


@pytest.fixture(autouse=True)
def _refuse_implicit_conversion(monkeypatch):
    """``np.asarray`` of an ``array_api_strict`` array raises, as it does for a CuPy array."""

    def refuse(self, dtype=None, copy=None):
        raise RuntimeError("implicit conversion of a device array to NumPy (use backend.to_numpy)")

    monkeypatch.setattr(type(strict.asarray(0.0)), "__array__", refuse)


def test_implicit_conversion_is_refused_and_the_boundary_copies():
    """The fixture is in force (a test that cannot fail otherwise), and ``to_numpy`` still copies."""
    array = strict.asarray([[1.0, 2.0], [3.0, 4.0]])
    with pytest.raises(RuntimeError, match="implicit conversion"):
        np.asarray(array)
    np.testing.assert_array_equal(backend.to_numpy(array), [[1.0, 2.0], [3.0, 4.0]])
    assert backend.bounding_box(strict, array > 2.5) == (1, 2, 0, 2)
    assert backend.bounding_box(strict, array > 9.0) is None

GRID = Grid(1.0, 64)


def _brush(pillars_per_side: int = 4, **kwargs):
    return brush(GRID, layout="square", pillars_per_side=pillars_per_side, pillar_radius=3 / 64, contact_modulus=1.0,
                 work_of_adhesion=1e-4, **kwargs)


CASES = {
    "hertz": (lambda: sphere(GRID, 1.0), 0.0, "events"),
    "jkr": (lambda: sphere(GRID, 1.0), 1e-3, "events"),
    "punch on a spring": (lambda: flat_punch(GRID, 0.2, 0.05), 1e-4, "events"),
    "soft brush": (lambda: _brush(stiffness=1e-3), 1e-4, "events"),
    "hierarchy": (lambda: _brush(stiffness=1e-2, levels=(Level(2, 1e-2),)), 1e-4, "events"),
    "rigid brush, fixed steps": (lambda: _brush(stiffness=math.inf), 1e-4, "fixed"),
    "rigid punch": (lambda: flat_punch(GRID, 0.2), 1e-4, "events"),
    "sphere on a spring, fixed steps": (lambda: sphere(GRID, 1.0, 0.5), 1e-3, "fixed"),
    "rough brush": (lambda: _brush(stiffness=1e-2, roughness=5e-4, seed=3), 1e-4, "events"),
    # 2 x 2 pillars: the element-event path solves once per element event (the 4 x 4 brush: 40 s).
    "rough brush, element events": (lambda: _brush(2, stiffness=1e-2, roughness=5e-4, seed=3), 1e-4,
                                    "element_events"),
    "rough brush, fixed steps": (lambda: _brush(stiffness=1e-2, roughness=5e-4, seed=3), 1e-4, "fixed"),
    "concave brush": (lambda: _brush(stiffness=6e-4, profile=Profile(amplification=0.5)), 1e-4, "events"),
}


@pytest.mark.slow
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


def test_pull_off_to_a_preload_force_on_the_strict_array_api_equals_numpy():
    """The force-preload searches (contact problems, then events) in the strict namespace."""
    indenter = _brush(stiffness=1e-2, roughness=5e-4, seed=3)
    summaries = []
    for xp in (np, strict):
        problem = ContactProblem(GRID, indenter, 1.0, 1e-4, xp=xp)
        record = record_pull_off(problem, LoadPath(method="events", preload_force=1e-3))
        assert record.summary["converged"], record.summary["reason"]
        summaries.append(record.summary)
    on_numpy, on_strict = summaries
    assert on_strict["n_states"] == on_numpy["n_states"]
    for key in ("preload_force", "adhesive_force", "work_of_separation"):
        assert on_strict[key] == pytest.approx(on_numpy[key], rel=1e-6), key


@pytest.mark.parametrize("levels", [(), (Level(2, 1e-2),)], ids=["one level", "two levels"])
def test_a_cg_iteration_copies_only_its_convergence_scalars_to_the_host(monkeypatch, levels):
    """Per CG iteration one host copy (the residual norm with the curvature), the preconditioner's none.

    Counted on the strict namespace: every ``float``/``bool``/``int`` of a
    device array and every `backend.to_numpy` of one.  Two solves of the
    same system to tolerances 1e-4 and 1e-10 differ in iterations only, so
    the difference of their counts over the difference of their iterations
    is the cost of one iteration; before, the spring preconditioner's coarse
    solve copied its pillar sums to the host and back (2 per iteration) and
    CG synchronised three scalars (4 in all).
    """
    from brushbem.physics.halfspace import HalfSpace
    from brushbem.numerics.operator import ContactOperator, MaskedOperator, Window
    from brushbem.numerics.solver import conjugate_gradient, contact_preconditioner

    counts = {"syncs": 0}
    array_type = type(strict.asarray(0.0))
    for name in ("__float__", "__bool__", "__int__", "__index__"):
        original = getattr(array_type, name)

        def counted(self, _original=original):
            counts["syncs"] += 1
            return _original(self)

        monkeypatch.setattr(array_type, name, counted)
    to_numpy = backend.to_numpy

    def counted_copy(array):
        if isinstance(array, array_type):
            counts["syncs"] += 1
        return to_numpy(array)

    monkeypatch.setattr(backend, "to_numpy", counted_copy)
    indenter = _brush(stiffness=1e-2, levels=levels)
    operator = ContactOperator(HalfSpace(GRID.elements, GRID.element_size, 1.0, xp=strict), indenter,
                               Window.full(GRID.elements))
    mask = strict.asarray(np.asarray(indenter.pillar) >= 0)
    rhs = strict.asarray(np.where(np.asarray(indenter.pillar) >= 0, 1e-3, 0.0))
    preconditioner = contact_preconditioner(operator, mask)
    runs = []
    for tolerance in (1e-3, 1e-12):
        counts["syncs"] = 0
        result = conjugate_gradient(MaskedOperator(operator, mask), rhs, tolerance=tolerance,
                                    preconditioner=preconditioner)
        assert result.converged, result.reason
        runs.append((result.iterations, counts["syncs"]))
    (few, few_syncs), (many, many_syncs) = runs
    assert many > few + 3
    assert (many_syncs - few_syncs) == many - few
