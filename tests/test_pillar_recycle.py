"""The pillar-level CG's recycled Ritz vectors (`brushbem.pillars.recycle`, ``Switches.recycled_vectors``).

The kept vectors only precondition: every solve must still be the dense
solve of its own system (1e-9: the CG stops at a relative residual of
1e-11 and these systems' condition number is below 1e2), on a set that
changes from solve to solve, and even where the kept products are stale;
and once pillars leave, the kept vectors are restricted to the new set and
their products made afresh.
"""

from __future__ import annotations

import numpy as np
import pytest

from brushbem import pillars
from brushbem.pillars import cg as pillar_cg
from test_pillar_cg import _problem


def _scattered(per_side: int = 16):
    """A 16 x 16 lattice (k~ = 1e-2) with a random half of it attached: a scattered set (near-field factor)."""
    problem, _ = _problem(per_side, 1e-2)
    model = pillars.PillarModel(problem)
    attached = np.random.default_rng(4).random(model.M) < 0.5
    rhs = np.stack([model.force, model.force * np.linspace(-1.0, 1.0, model.M)], axis=1)
    return model, attached, rhs


def _dense(model, attached, rhs):
    S = np.flatnonzero(attached)
    return S, model.uniform_block(S, S) + model.spring_matrix(S)


def _check(model, attached, rhs, x, fields):
    S, A = _dense(model, attached, rhs)
    dense = np.linalg.solve(A, rhs[S])
    assert np.abs(x[S] - dense).max() < 1e-9 * np.abs(dense).max()
    assert not x[~attached].any()
    assert np.abs(fields - model.fields(x)).max() < 1e-9 * np.abs(fields).max()


def test_solves_with_recycled_vectors_are_the_dense_solves_as_pillars_leave_and_peel(switches):
    """Five solves on sets that lose pillars and peel rasters (5 of about 128 a solve, 16 % in all: the kept
    vectors, made in the first solve, are let go stale that far): each is the dense solve to 1e-9, the kept
    vectors serve from the second on, and they take fewer iterations than the near field alone (measured: 35
    against 41)."""
    counts = {}
    for vectors in (0, 40):
        switches(recycled_vectors=vectors, recycled_stale=0.2)
        model, attached, rhs = _scattered()
        solver = pillar_cg.LatticeCG(model)
        assert solver.near_factor(attached) is not None
        start = None
        rng = np.random.default_rng(5)
        for step in range(5):
            if step:
                S = np.flatnonzero(attached)
                attached[rng.choice(S, 3, replace=False)] = False
                for p in rng.choice(np.flatnonzero(attached), 2, replace=False):
                    mask = model.raster[p].copy()
                    mask[np.flatnonzero(mask)[:3]] = False
                    model.set_raster(int(p), mask)
            x, fields = solver.solve(attached, rhs, start=start)
            _check(model, attached, rhs, x, fields)
            start = x
            if vectors and step:
                assert solver.recycler.space(np.flatnonzero(attached)) is not None
        counts[vectors] = solver.iterations
    assert counts[40] < counts[0], counts


def test_stale_kept_products_cost_iterations_not_accuracy(switches):
    """Kept products Y that are not A W (here: W's products scrambled) leave the two-level preconditioner
    symmetric positive definite (`brushbem.pillars.recycle`): the solve is still the dense one to 1e-9."""
    switches(recycled_vectors=40)
    model, attached, rhs = _scattered()
    solver = pillar_cg.LatticeCG(model)
    solver.solve(attached, rhs)
    recycler = solver.recycler
    rng = np.random.default_rng(6)
    recycler.Y = recycler.Y * (1.0 + 0.5 * rng.random(recycler.Y.shape)) + 0.1 * rng.standard_normal(
        recycler.Y.shape) * np.abs(recycler.Y).max()
    recycler.Y[~attached] = 0.0
    recycler.serials = solver.serials(attached)  # not due: the scrambled products serve the next solve
    x, fields = solver.solve(attached, 0.5 * rhs)
    _check(model, attached, 0.5 * rhs, x, fields)


def test_the_kept_vectors_follow_the_set_once_pillars_detach(switches):
    """After more than ``Switches.recycled_stale`` (2 %) of the attached pillars leave, the next solve restricts the kept vectors to
    the new set and makes their products afresh: W is zero off the set and Y = A_S W there (to 1e-5 of Y:
    the products take the far field in single precision, of relative error at most
    `brushbem.pillars.cg.SINGLE_ERROR` = 3e-7 a product; 1e-9 in double).  Without the refresh Y would keep
    the columns of the pillars that left (about 5 % of A W here), and this fails."""
    switches(recycled_vectors=40)
    model, attached, rhs = _scattered()
    solver = pillar_cg.LatticeCG(model)
    solver.solve(attached, rhs)
    S = np.flatnonzero(attached)
    leaving = np.random.default_rng(7).choice(S, int(0.05 * S.size) + 1, replace=False)
    attached[leaving] = False
    before, before_products = solver.recycler.W.copy(), solver.recycler.Y.copy()
    x, _ = solver.solve(attached, rhs, start=None)
    recycler = solver.recycler
    assert recycler.W is not before
    assert np.array_equal(recycler.serials, solver.serials(attached))
    assert not recycler.W[~attached].any() and not recycler.Y[~attached].any()
    S, A = _dense(model, attached, rhs)
    assert np.abs(A @ recycler.W[S] - recycler.Y[S]).max() < 1e-5 * np.abs(recycler.Y).max()
    stale = np.abs(A @ before[S] - before_products[S])  # the old vectors' products, restricted: not A_S W
    assert stale.max() > 1e-3 * np.abs(before_products).max()


@pytest.mark.parametrize("vectors", [0, 40])
def test_a_compact_set_keeps_no_vectors(switches, vectors):
    """The circulant serves a compact set (the full lattice): no near factor, so nothing is kept."""
    switches(recycled_vectors=vectors)
    model, _, rhs = _scattered()
    solver = pillar_cg.LatticeCG(model)
    attached = np.ones(model.M, dtype=bool)
    x, fields = solver.solve(attached, rhs)
    _check(model, attached, rhs, x, fields)
    assert solver.recycler is None or solver.recycler.W is None
