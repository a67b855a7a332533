"""The exact event path keeps its answers through the solver's speed-ups.

The coarse pillar matrix of the pillar-block preconditioner is solved through
its last factorisation and a low-rank correction instead of a factorisation
per solve (`brushbem.numerics.solver.preconditioners._CoarseBase`), a unit response
reuses the system and preconditioner of the equilibrium solved on the same
set, and a solve keeps its solution's tip deflection on the window in step
with the iterations (`brushbem.numerics.solver.block_deflection.BlockDeflection`) instead
of transforming the solution again.  Fewer and smaller transforms follow: a
pressure on a few pillars is transformed with a period on a short ladder
(`brushbem.settings.Switches.snap_periods`), a local cascade moves the known
deflection by the change on the pillars it peeled
(`brushbem.settings.Switches.keep_cascade_deflection`), the unit
response's Galerkin guess takes its inner products through the symmetry of A
(`brushbem.settings.Switches.symmetric_products`), and the next events are
searched on the footprint's elements only
(`brushbem.settings.Switches.compact_event_search`).  All give the former
results to rounding, so a pull-off keeps its F_A and work of separation to 1e-9.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
import scipy.linalg

from brushbem import settings
from brushbem.runs.case import brush_scales
from brushbem.physics.halfspace import HalfSpace
from brushbem.numerics import periods
from brushbem.numerics.operator import ContactOperator, Window
from brushbem.protocol import ContactProblem, LoadPath, record_pull_off
from brushbem.numerics.solver import SolverCache, cascade_deflection, equilibria, preconditioners
from brushbem.physics.pillar_laws import PiecewiseLinear
from brushbem.physics.structure import Grid, Indenter, Level, SpringLevel, brush
from brushbem.protocol import contact_loading
from brushbem.protocol import unit_guess as unit_guess_module

GRID = Grid(1.0, 128)
PER_SIDE = 8
RADIUS = math.sqrt(0.16 / math.pi) / PER_SIDE  # phi = 0.16, 3.6 elements at N = 128
DGAMMA = 1e-4

# F_A and the work of separation of ``method = "events"`` on these brushes,
# pressed to the rigid brush's pull-off force F_c, recorded with the package
# at commit 2a34b4b (before the coarse-matrix updates and the reuse of a
# set's system): the same cases through that commit's `record_pull_off`.
RECORDED = {
    "rough soft": ({"stiffness": 0.01, "sigma": 1.0}, 0.008423384648359943, 0.00018407948184698175),
    "rough stiff": ({"stiffness": 10.0, "sigma": 0.3}, 0.005284703116830719, 2.298254860277276e-05),
    "hierarchical rough": ({"stiffness": 0.1, "sigma": 1.0, "levels": (Level(cluster=2, stiffness=0.05),)},
                           0.003969805949173067, 4.9876832002962255e-05),
}


def _problem(stiffness: float, sigma: float, **extra) -> tuple[ContactProblem, float]:
    """The brush with Gaussian lengths of sigma d_c, and F_c (d_c, F_c: the rigid brush's pull-off)."""

    def build(roughness: float) -> ContactProblem:
        indenter = brush(GRID, layout="square", pillars_per_side=PER_SIDE, pillar_radius=RADIUS,
                         contact_modulus=1.0, work_of_adhesion=DGAMMA, stiffness=stiffness,
                         roughness=roughness, seed=3, **extra)
        return ContactProblem(GRID, indenter, contact_modulus=1.0, work_of_adhesion=DGAMMA)

    scales = brush_scales(build(0.0))
    return build(sigma * abs(scales["rigid_brush_displacement"])), scales["rigid_brush_force"]


@pytest.mark.parametrize("case", list(RECORDED))
def test_pull_off_keeps_the_recorded_answer(case, monkeypatch, switches):
    # The recorded answers' preload search: the secant (the model's search ends at another state within
    # the solver's tolerance, `test_the_preload_search_by_the_independent_pillars_ends_at_the_same_state`).
    switches(preload_model=False)
    spec, force, work = RECORDED[case]
    problem, f_c = _problem(**spec)
    summary = record_pull_off(problem, LoadPath(method="events", preload_force=f_c, max_steps=10**6)).summary
    assert summary["converged"], summary["reason"]
    assert summary["adhesive_force"] == pytest.approx(force, rel=1e-9, abs=0.0)
    assert summary["work_of_separation"] == pytest.approx(work, rel=1e-9, abs=0.0)


#: Polonsky-Keer iterations of the loading of the "rough soft" brush with the secant search of F(d)
#: (``Switches.preload_model = False``, the recorded answer's search).
SECANT_LOADING_ITERATIONS = 124


def test_the_preload_search_by_the_independent_pillars_ends_at_the_same_state():
    """The model's search takes fewer iterations to the same preload and the recorded pull-off.

    Each search ends where F is within 1e-9 of F_P or interpolates two solutions of one contact set;
    the solutions are converged to a relative residual of 1e-8 (LoadPath.tolerance), so the two
    preload states, and the pull-offs from them, agree to that and not to rounding.
    """
    assert settings.switches().preload_model
    spec, force, work = RECORDED["rough soft"]
    problem, f_c = _problem(**spec)
    record = record_pull_off(problem, LoadPath(method="events", preload_force=f_c, max_steps=10**6))
    loading = record.curve.loading
    # The loading states carry the search's iterations (the last one those of the samples off the path).
    assert int(np.sum(record.curve.cg_iterations[loading])) < SECANT_LOADING_ITERATIONS
    assert float(record.curve.force[loading][-1]) == pytest.approx(f_c, rel=1e-9)
    assert record.summary["adhesive_force"] == pytest.approx(force, rel=1e-8)
    assert record.summary["work_of_separation"] == pytest.approx(work, rel=1e-8)


def test_independent_pillars_model_is_the_sum_of_punches_on_springs():
    """F(d) of three pillars of 1, 2 and 4 elements at heights 0, 1, 3 on springs k = 2 (hand sums)."""
    height = np.full((4, 4), np.inf)
    pillar = np.full((4, 4), -1)
    for label, (cells, h) in enumerate((([(0, 0)], 0.0), ([(2, 0), (2, 1)], 1.0),
                                        ([(0, 2), (0, 3), (1, 2), (1, 3)], 3.0))):
        for cell in cells:
            height[cell], pillar[cell] = h, label
    indenter = Indenter(height, pillar, levels=(SpringLevel(2.0, np.arange(3)),))
    model = contact_loading._IndependentPillars(indenter, contact_modulus=1.0, h2=1.0)
    k = [1.0 / (1.0 / (2.0 * math.sqrt(n / math.pi)) + 0.5) for n in (1, 2, 4)]
    for d in (0.5, 2.0, 4.0):
        force = sum(ki * max(d - h, 0.0) for ki, h in zip(k, (0.0, 1.0, 3.0)))
        assert model.displacement(force) == pytest.approx(d, rel=1e-14, abs=0.0)


@pytest.mark.slow  # over 3 s on 2 cores: `make test` runs it, `make test-fast` does not
def test_switching_the_speed_ups_off_gives_the_same_pull_off(monkeypatch, switches):
    """The factorised path (rank 0, no reuse) and the updated one agree to rounding on one brush."""
    switches(single_products=False)  # both runs' products in double precision
    problem, f_c = _problem(0.01, 1.0)
    path = LoadPath(method="events", preload_force=f_c, max_steps=10**6)
    fast = record_pull_off(problem, path).summary
    switches(coarse_update_rank=0, reuse_set_solver=False, keep_solution_deflection=False)
    plain = record_pull_off(problem, path).summary
    assert fast["n_solves"] == plain["n_solves"]
    assert fast["adhesive_force"] == pytest.approx(plain["adhesive_force"], rel=1e-12, abs=0.0)
    assert fast["work_of_separation"] == pytest.approx(plain["work_of_separation"], rel=1e-12, abs=0.0)


def _operator(levels=()) -> ContactOperator:
    indenter = brush(GRID, layout="square", pillars_per_side=PER_SIDE, pillar_radius=RADIUS, contact_modulus=1.0,
                     work_of_adhesion=DGAMMA, stiffness=0.01, roughness=1e-3, seed=3, levels=levels)
    halfspace = HalfSpace(GRID.elements, GRID.element_size, 1.0)
    return ContactOperator(halfspace, indenter, Window.full(GRID.elements))


def _coarse_matrix(cache: SolverCache, active, stiffness) -> np.ndarray:
    matrix = cache.pillars.coupling[0][np.ix_(active, active)].copy()
    matrix[np.diag_indices(active.size)] += 1.0 / stiffness
    return matrix


@pytest.mark.parametrize("levels", [(), (Level(cluster=2, stiffness=0.05),)])
def test_coarse_solves_near_a_factor_are_the_factorised_ones(levels):
    """Pillars that leave and pillars that soften: the corrected solve equals a fresh factorisation's."""
    operator, cache = _operator(levels), SolverCache()
    n = operator.indenter.n_pillars
    rng = np.random.default_rng(5)
    # A sequence of sets: each drops one or two pillars and softens two others.
    ids = np.arange(n)
    values = rng.uniform(0.5, 1.0, n)
    preconditioners._coarse_factor(operator, cache, ids, values)
    base = cache.pillars.coarse_base
    for step in range(8):  # 12 pillars leave: within _COARSE_UPDATE_SHRINK of 64
        drop = rng.choice(ids.size, size=1 + step % 2, replace=False)
        keep = np.ones(ids.size, dtype=bool)
        keep[drop] = False
        ids, values = ids[keep], values[keep].copy()
        soften = rng.choice(ids.size, size=2, replace=False)
        values[soften] *= rng.uniform(0.3, 0.9, 2)
        solve, positions, reference, size = preconditioners._coarse_factor(operator, cache, ids, values)
        assert cache.pillars.coarse_base is base, "the factor was not reused"
        assert size == ids.size and np.array_equal(positions, np.arange(ids.size))
        b = rng.standard_normal(ids.size)
        expected = scipy.linalg.solve(_coarse_matrix(cache, ids, values), b, assume_a="pos")
        assert solve(b) == pytest.approx(expected, rel=1e-10, abs=1e-10 * np.abs(expected).max())


def test_a_stiffer_pillar_or_a_new_one_is_factorised_afresh():
    operator, cache = _operator(), SolverCache()
    n = operator.indenter.n_pillars
    ids = np.arange(n - 1)
    values = np.full(ids.size, 0.7)
    preconditioners._coarse_factor(operator, cache, ids, values)
    first = cache.pillars.coarse_base
    stiffer = values.copy()
    stiffer[3] *= 1.5
    preconditioners._coarse_factor(operator, cache, ids, stiffer)
    assert cache.pillars.coarse_base is not first
    second = cache.pillars.coarse_base
    grown = np.arange(n)
    preconditioners._coarse_factor(operator, cache, grown, np.full(n, 0.7))
    assert cache.pillars.coarse_base is not second


def test_many_changes_are_factorised_afresh(switches):
    switches(coarse_update_rank=4)
    operator, cache = _operator(), SolverCache()
    n = operator.indenter.n_pillars
    values = np.full(n, 0.7)
    preconditioners._coarse_factor(operator, cache, np.arange(n), values)
    first = cache.pillars.coarse_base
    preconditioners._coarse_factor(operator, cache, np.arange(n - 4), values[: n - 4])
    assert cache.pillars.coarse_base is first
    preconditioners._coarse_factor(operator, cache, np.arange(n - 5), values[: n - 5])
    assert cache.pillars.coarse_base is not first


@pytest.mark.parametrize("start", ["cold", "initial", "initial and its product"])
@pytest.mark.parametrize("levels", [(), (Level(cluster=2, stiffness=0.05),)])
def test_a_solve_keeps_its_solutions_tip_deflection(start, levels):
    """``tip_deflection`` of a solve's solution is the transform's, on the whole window, to rounding."""
    operator = _operator(levels)
    footprint = np.asarray(operator.indenter.pillar) >= 0
    rng = np.random.default_rng(2)
    mask = footprint & (rng.random(footprint.shape) < 0.9)
    rhs = np.where(mask, 1.0 + 0.1 * rng.standard_normal(mask.shape), 0.0)
    initial = initial_product = None
    if start != "cold":
        initial = np.where(mask, 0.5, 0.0)
        if start == "initial and its product":
            initial_product = operator.tip_deflection(initial)
    cache = SolverCache()
    result = equilibria.solve_on_set(operator, mask, rhs, initial=initial, initial_product=initial_product,
                                     cache=cache)
    assert result.converged and result.iterations > 0
    assert cache.known_tip_deflection(operator, result.solution) is not None
    kept = cache.tip_deflection(operator, result.solution)
    transformed = operator.tip_deflection(result.solution)
    assert kept == pytest.approx(transformed, rel=0.0, abs=1e-12 * np.abs(transformed).max())
    other = np.where(mask, result.solution * (1 + 1e-9), 0.0)  # not the solution: transformed
    assert cache.known_tip_deflection(operator, other) is None
    assert np.array_equal(cache.tip_deflection(operator, other), operator.tip_deflection(other))


def test_a_zero_right_hand_side_keeps_a_zero_deflection():
    """CG returns 0 for a zero right-hand side whatever its start: the kept deflection is 0, not the start's."""
    operator = _operator()
    mask = np.asarray(operator.indenter.pillar) >= 0
    initial = np.where(mask, 0.5, 0.0)
    cache = SolverCache()
    result = equilibria.solve_on_set(operator, mask, np.zeros(mask.shape), initial=initial,
                                     initial_product=operator.tip_deflection(initial), cache=cache)
    assert result.converged and not np.any(result.solution)
    assert np.array_equal(cache.tip_deflection(operator, result.solution), np.zeros(mask.shape))


def test_a_pillar_law_of_factor_one_pieces_is_the_linear_spring():
    """Pieces that move rebuild the operator at the same contact set, and zero right-hand sides come up there."""
    grid = Grid(1.0, 64)
    path = LoadPath(method="fixed", preload_displacement=0.006, step=5e-4)
    flat = brush(grid, layout="square", pillars_per_side=4, pillar_radius=math.sqrt(0.16 / math.pi) / 4,
                 contact_modulus=1.0, work_of_adhesion=1e-4, stiffness=0.05)
    law = PiecewiseLinear(forces=(-1e-4, 1e-4), factors=(1.0, 1.0, 1.0))

    def record(indenter):
        return record_pull_off(ContactProblem(grid, indenter, contact_modulus=1.0, work_of_adhesion=1e-4), path)

    linear, pieces = record(flat), record(dataclasses.replace(flat, pillar_law=law))
    assert pieces.summary["adhesive_force"] == pytest.approx(linear.summary["adhesive_force"], rel=1e-9)
    np.testing.assert_allclose(pieces.curve.force, linear.curve.force, rtol=1e-9, atol=1e-15)


TRANSFORM_SAVINGS = ["snap_periods", "keep_cascade_deflection", "symmetric_products", "compact_event_search"]


@pytest.mark.slow  # over 3 s on 2 cores: `make test` runs it, `make test-fast` does not
def test_the_transform_savings_keep_the_pull_off(monkeypatch, switches):
    """Snapped periods, the cascade's kept deflection, the symmetric unit guess and the event search on the
    footprint, all switched off at once, give the same solves, F_A and work to 1e-12 (rounding)."""
    switches(single_products=False)  # both runs' products in double precision
    problem, f_c = _problem(0.01, 1.0)
    path = LoadPath(method="events", preload_force=f_c, max_steps=10**6)
    fast = record_pull_off(problem, path).summary
    switches(**{switch: False for switch in TRANSFORM_SAVINGS})
    plain = record_pull_off(problem, path).summary
    assert fast["n_solves"] == plain["n_solves"]
    assert fast["adhesive_force"] == pytest.approx(plain["adhesive_force"], rel=1e-12, abs=0.0)
    assert fast["work_of_separation"] == pytest.approx(plain["work_of_separation"], rel=1e-12, abs=0.0)


@pytest.mark.slow  # each saving alone (the fast test switches them off together)
@pytest.mark.parametrize("switch", TRANSFORM_SAVINGS)
def test_each_transform_saving_keeps_the_pull_off(monkeypatch, switch, switches):
    """Each saving alone changes round-off only (the event search on the footprint not even that)."""
    switches(single_products=False)  # both runs' products in double precision
    problem, f_c = _problem(0.01, 1.0)
    path = LoadPath(method="events", preload_force=f_c, max_steps=10**6)
    fast = record_pull_off(problem, path).summary
    switches(**{switch: False})
    plain = record_pull_off(problem, path).summary
    assert fast["n_solves"] == plain["n_solves"]
    assert fast["adhesive_force"] == pytest.approx(plain["adhesive_force"], rel=1e-12, abs=0.0)
    assert fast["work_of_separation"] == pytest.approx(plain["work_of_separation"], rel=1e-12, abs=0.0)


@pytest.mark.parametrize("corner", [(0, 0), (60, 70), (120, 5)])
def test_a_snapped_period_gives_the_whole_windows_transform(corner):
    """A pressure on a few pillars, transformed with a period on the ladder, is the 2m-periodic convolution."""
    operator = _operator()
    r, c = corner
    pressure = np.zeros(operator.window.shape)
    pressure[r : r + 8, c : c + 6] = np.random.default_rng(1).uniform(-1.0, 2.0, (8, 6))
    support = (r, r + 8, c, c + 6)
    full = operator.halfspace.apply(pressure)
    snapped = periods.halfspace_on_support(operator.halfspace, pressure, support)
    assert snapped == pytest.approx(full, rel=0.0, abs=1e-13 * np.abs(full).max())


def test_a_cascade_keeps_the_deflection_in_step():
    """The deflection moved by a change on a few pillars is the transform of the new pressure."""
    operator = _operator((Level(cluster=2, stiffness=0.05),))
    labels = np.asarray(operator.indenter.pillar)
    rng = np.random.default_rng(4)
    before = np.where(labels >= 0, rng.uniform(0.5, 1.0, labels.shape), 0.0)
    after = before.copy()
    peeled = np.isin(labels, [3, 17])
    after[peeled] = np.where(rng.random(int(peeled.sum())) < 0.5, 0.0, rng.uniform(-0.2, 0.3, int(peeled.sum())))
    moved = cascade_deflection.moved_deflection(operator, operator.tip_deflection(before), before, after)
    expected = operator.tip_deflection(after)
    assert moved == pytest.approx(expected, rel=0.0, abs=1e-12 * np.abs(expected).max())


@pytest.mark.parametrize("levels", [(), (Level(cluster=2, stiffness=0.05),)])
def test_the_symmetric_unit_guess_is_the_transformed_one(monkeypatch, levels):
    """The Galerkin guess through A's symmetry and its block on the elements that left equals the two-transform one."""
    operator = _operator(levels)
    labels = np.asarray(operator.indenter.pillar)
    rng = np.random.default_rng(6)
    old = (labels >= 0) & (rng.random(labels.shape) < 0.95)
    new = old & ~np.isin(labels, [5, 40]) & (rng.random(labels.shape) < 0.98)
    unit = np.where(old, rng.uniform(0.8, 1.2, labels.shape), 0.0)
    predicted = np.where(old, rng.uniform(-0.5, 1.0, labels.shape), 0.0)
    pressure = np.where(new, predicted + rng.uniform(-0.05, 0.05, labels.shape), 0.0)
    deflections = [operator.tip_deflection(v) for v in (unit, predicted, pressure)]
    results = []
    for symmetric in (True, False):
        with settings.using(symmetric_products=symmetric):
            record = unit_guess_module.cascade_record(operator, new, predicted, pressure, deflections[2],
                                                      deflections[1])
            assert (record[1] is None) == symmetric
            results.append(unit_guess_module.unit_guess(operator, new, unit, deflections[0], record))
    (guess, product), (plain_guess, plain_product) = results
    assert guess == pytest.approx(plain_guess, rel=0.0, abs=1e-12 * np.abs(plain_guess).max())
    assert product == pytest.approx(plain_product, rel=0.0, abs=1e-12 * np.abs(plain_product).max())
    transformed = operator.tip_deflection(guess)
    assert product == pytest.approx(transformed, rel=0.0, abs=1e-12 * np.abs(transformed).max())
    assert not np.any(guess[~new])
