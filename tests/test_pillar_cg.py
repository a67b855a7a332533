"""The pillar model's solve without a kept inverse (`brushbem.pillars.cg.LatticeCG`).

CG on the lattice's FFT product must give the kept inverse's answer: the
same solution of the same pillar-level system (checked against a dense
solve), and the same pull-off when the solver drops the inverse and takes it
up again along the path.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from brushbem.config import parse_config
from brushbem.physics.structure import Grid, Level, brush
from brushbem import pillars
from brushbem.pillars import cg as pillar_cg
from brushbem.pillars import solver as pillar_solver
from brushbem.protocol import ContactProblem, LoadPath, record_pull_off
from brushbem.protocol.paths import pull_off
from brushbem.runs.case import brush_scales
from brushbem.config.resources import kept_partial_count, memory_estimate, pillar_kept_bytes

DGAMMA = 1e-4


def _problem(per_side: int, stiffness: float, sigma: float = 0.0, **extra) -> tuple[ContactProblem, float]:
    """A square lattice of phi = 0.12 at 3.1 elements' radius (the ``size`` study's) and its F_c."""
    grid = Grid(1.0, 16 * per_side)

    def build(roughness: float) -> ContactProblem:
        indenter = brush(grid, layout="square", pillars_per_side=per_side,
                         pillar_radius=math.sqrt(0.12 / math.pi) / per_side, contact_modulus=1.0,
                         work_of_adhesion=DGAMMA, stiffness=stiffness, roughness=roughness, seed=3, **extra)
        return ContactProblem(grid, indenter, contact_modulus=1.0, work_of_adhesion=DGAMMA)

    scales = brush_scales(build(0.0))
    return build(sigma * abs(scales["rigid_brush_displacement"])), scales["rigid_brush_force"]


def test_cg_solves_the_kept_inverse_system():
    """On a set with holes, peeled rasters and two spring levels (springs coupling the pillars of a
    cluster), CG's solution and fields are the dense solve's to 1e-9 (its tolerance is 1e-11 on the
    residual; the system's condition number is below 1e2 here)."""
    problem, _ = _problem(6, 1e-2, levels=(Level(cluster=2, stiffness=5e-3),))
    model = pillars.PillarModel(problem)
    for p in (3, 14, 27):
        mask = model.full[p].copy()
        mask[np.flatnonzero(mask)[:4]] = False
        model.set_raster(p, mask)
    attached = np.ones(model.M, dtype=bool)
    attached[[0, 7, 20, 35]] = False
    S = np.flatnonzero(attached)
    rhs = np.stack([model.force, model.force * np.linspace(-1.0, 1.0, model.M)], axis=1)
    solver = pillar_cg.LatticeCG(model)
    x, fields = solver.solve(attached, rhs)
    dense = np.linalg.solve(model.uniform_block(S, S) + model.spring_matrix(S), rhs[S])
    assert np.abs(x[S] - dense).max() < 1e-9 * np.abs(dense).max()
    assert not x[~attached].any()
    assert np.abs(fields - model.fields(x)).max() < 1e-9 * np.abs(fields).max()


def test_circulant_preconditioner_is_near_exact_on_the_full_lattice():
    """Cold solves on the full 16 x 16 lattice take at most 10 iterations (6 measured at 32 x 32, 8-9 at
    10^4 and 10^5 pillars); the diagonal alone needs 16-47."""
    problem, _ = _problem(16, 10.0)
    model = pillars.PillarModel(problem)
    solver = pillar_cg.LatticeCG(model)
    attached = np.ones(model.M, dtype=bool)
    solver.solve(attached, model.force[:, None])
    assert 1 <= solver.iterations <= 10


def test_near_field_preconditioner_on_a_rough_brushs_partial_contact(monkeypatch, switches):
    """The loading of a rough 24 x 24 brush (sigma~ = 1) by CG throughout: its partial contact sets (at most
    half of the lattice) preconditioned by their near field take 833 iterations in all, at most 11 a solve
    (632 and 10 with the Ritz vectors kept, `brushbem.pillars.recycle`, as by default), against the
    circulant's 1301 and 24 (measured); held to two thirds and 14 (the circulant's 24 is
    farther off as the brush grows: 42 at 64 x 64), with the same contact and force at the preload."""
    problem, force = _problem(24, 1e-2, 1.0)
    path = LoadPath(method="pillars", preload_force=force, max_steps=10**6, pillar_solve="cg")
    runs, solve = {}, pillar_cg.LatticeCG.solve
    for near in (True, False):
        switches(near_preconditioner=near)
        counts = []

        def counted(self, *args, _counts=counts, **kwargs):
            start = self.iterations
            out = solve(self, *args, **kwargs)
            _counts.append(self.iterations - start)
            return out

        monkeypatch.setattr(pillar_cg.LatticeCG, "solve", counted)
        for state in pull_off(problem, path):
            if not state.loading:
                break
        runs[near] = (counts, state)
    (near, loaded), (circulant, reference) = runs[True], runs[False]
    assert len(near) == len(circulant)  # the same rounds
    assert sum(near) <= 2 * sum(circulant) / 3 and max(near) <= 14
    assert loaded.attached_pillars == reference.attached_pillars
    assert loaded.force == pytest.approx(reference.force, rel=1e-9)


def test_the_preconditioner_follows_the_sets_boundary():
    """`boundary_share` (attached pillars with a detached neighbour) decides the preconditioner, not the set's
    share of the lattice: the full lattice (0) and a disk (0.36) take the circulant, a checkerboard (1.0) and
    a random 70 % of the lattice (0.93, more than half of it attached) the near field's LU; CG gives the dense
    solve on each to 1e-9 (its tolerance is 1e-11 on the residual).  Measured on the ``size`` study's systems
    (`brushbem.pillars.cg`): shares of 0.23 or less on a level brush's peel, where the circulant took 5-6
    iterations and the near field 9-13, and 0.93 or more on the sigma~ = 0.1 brush, where the near field took
    12-25 and the circulant 19-52."""
    problem, _ = _problem(16, 1e-2)
    model = pillars.PillarModel(problem)
    iy, ix = model.lattice.index.T
    sets = {"all": (np.ones(model.M, dtype=bool), 0.0),
            "disk": (np.hypot(iy - 7.5, ix - 7.5) < 6.4, 0.355),
            "checkerboard": ((iy + ix) % 2 == 0, 1.0),
            "random": (np.random.default_rng(1).random(model.M) < 0.7, 0.928)}
    rhs = np.stack([model.force, model.force * np.linspace(-1.0, 1.0, model.M)], axis=1)
    for name, (attached, share) in sets.items():
        assert pillar_cg.boundary_share(model, attached) == pytest.approx(share, abs=1e-3), name
        solver = pillar_cg.LatticeCG(model)
        assert (solver.near_factor(attached) is not None) == (share > pillar_cg.BOUNDARY_SHARE), name
        x, _ = solver.solve(attached, rhs)
        S = np.flatnonzero(attached)
        dense = np.linalg.solve(model.uniform_block(S, S) + model.spring_matrix(S), rhs[S])
        assert np.abs(x[S] - dense).max() < 1e-9 * np.abs(dense).max(), name
    assert pillar_cg.boundary_share(model, np.zeros(model.M, dtype=bool)) == 0.0


def test_a_level_brushs_peel_is_preconditioned_by_the_circulant(monkeypatch):
    """A level 24 x 24 brush pulled off by CG throughout peels from its edges: its attached sets are compact
    (`boundary_share` at most ``BOUNDARY_SHARE``) down to well below half of the lattice, and the circulant
    serves them; only its last remnant (24 pillars, share 0.83) is scattered and takes the near field.  The
    pull-off is the kept inverse's (F_A and the work to 1e-9: every solve reaches 1e-11)."""
    problem, force = _problem(24, 1e-2)
    shares, solve = [], pillar_cg.LatticeCG.solve

    def recorded(self, attached, *args, **kwargs):
        shares.append((pillar_cg.boundary_share(self.model, attached), self.near_factor(attached) is None,
                       int(attached.sum())))
        return solve(self, attached, *args, **kwargs)

    monkeypatch.setattr(pillar_cg.LatticeCG, "solve", recorded)
    path = LoadPath(method="pillars", preload_force=force, max_steps=10**6, pillar_solve="cg")
    iterative = record_pull_off(problem, path).summary
    kept = record_pull_off(problem, LoadPath(method="pillars", preload_force=force, max_steps=10**6,
                                             pillar_solve="kept")).summary
    assert all(circulant == (share <= pillar_cg.BOUNDARY_SHARE) for share, circulant, _ in shares)
    compact = [count for share, circulant, count in shares if circulant]
    assert len(compact) >= len(shares) - 2 and min(compact) < problem.indenter.n_pillars // 4
    assert iterative["adhesive_force"] == pytest.approx(kept["adhesive_force"], rel=1e-9)
    assert iterative["work_of_separation"] == pytest.approx(kept["work_of_separation"], rel=1e-9)


def test_a_solve_that_does_not_converge_says_so(monkeypatch, switches):
    problem, _ = _problem(6, 10.0)
    model = pillars.PillarModel(problem)
    switches(pillar_cg_iterations=1)
    with pytest.raises(pillar_cg.NotConverged, match=r"relative residual of .* not 1e-11, in 1 iterations"):
        pillar_cg.LatticeCG(model).solve(np.ones(model.M, dtype=bool), model.force[:, None])


@pytest.mark.parametrize(("stiffness", "sigma"), [(1e-2, 0.0), (1e-2, 1.0)])
def test_pull_off_without_the_kept_inverse_is_the_same(monkeypatch, stiffness, sigma, switches):
    """With the kept inverse dropped beyond 16 attached pillars (taken up again under 8; the partial sets'
    memory budget ``kept_partial_bytes`` as low, 16 pillars' `pillar_kept_bytes`, so that the rough loading's
    higher-mode feedback runs warm-started CG solves), an 8 x 8 pull-off
    - level, or rough so that pillars join and leave across the limit - is the kept inverse's: F_A and the
    work to 1e-9 (both solves reach 1e-11 on every system), the pillars attached at pull-off and the
    solves exactly."""
    problem, force = _problem(8, stiffness, sigma)
    path = LoadPath(method="pillars", preload_force=force, max_steps=10**6)
    kept = record_pull_off(problem, path).summary
    switches(kept_pillars=16, kept_partial_bytes=int(pillar_kept_bytes(16)))  # partial sets too (the rough loading)
    iterative = record_pull_off(problem, path).summary
    assert iterative["converged"], iterative["reason"]
    assert iterative["adhesive_force"] == pytest.approx(kept["adhesive_force"], rel=1e-9)
    assert iterative["work_of_separation"] == pytest.approx(kept["work_of_separation"], rel=1e-9)
    assert iterative["attached_pillars_at_pull_off"] == kept["attached_pillars_at_pull_off"]
    assert iterative["n_solves"] == kept["n_solves"]


def test_pull_off_stops_unconverged_with_the_reason(monkeypatch, switches):
    problem, force = _problem(6, 1e-2)
    switches(kept_pillars=4)
    switches(pillar_cg_iterations=1)
    record = record_pull_off(problem, LoadPath(method="pillars", preload_force=force, max_steps=10**6))
    assert not record.summary["converged"]
    assert "pillar-level CG" in record.summary["reason"]


def test_a_zero_right_hand_side_gives_zero_from_any_start():
    problem, _ = _problem(6, 1e-2)
    model = pillars.PillarModel(problem)
    attached = np.ones(model.M, dtype=bool)
    rhs = np.stack([model.force, np.zeros(model.M)], axis=1)
    x, _ = pillar_cg.LatticeCG(model).solve(attached, rhs, start=np.ones((model.M, 2)))
    assert not x[:, 1].any() and x[:, 0].any()


def _scattered_solve(per_side: int = 32):
    """A 32 x 32 lattice (k~ = 1e-2) with a random 40 % attached (a scattered set: the near-field factor) and
    three peeled rasters, a right-hand side of two columns, and the dense solve."""
    problem, _ = _problem(per_side, 1e-2)
    model = pillars.PillarModel(problem)
    for p in (5, 300, 777):
        mask = model.full[p].copy()
        mask[np.flatnonzero(mask)[:4]] = False
        model.set_raster(p, mask)
    attached = np.random.default_rng(8).random(model.M) < 0.4
    rhs = np.stack([model.force, model.force * np.linspace(-1.0, 1.0, model.M)], axis=1)
    S = np.flatnonzero(attached)
    dense = np.linalg.solve(model.uniform_block(S, S) + model.spring_matrix(S), rhs[S])
    return model, attached, rhs, dense


def test_a_single_precision_far_field_is_within_its_bound():
    """The product (G00 + H) p with the far field in single precision is the double one to
    `SINGLE_ERROR` (3e-7, relative, 2-norms) for scattered and smooth vectors on a scattered set with peeled
    rasters (measured 1.3e-8 - 4.5e-8 here; the far field alone 1.5e-7 of its norm at 100 x 100 and 316 x 316)."""
    model, attached, _, _ = _scattered_solve()
    solver = pillar_cg.LatticeCG(model)
    rng = np.random.default_rng(9)
    smooth = np.cos(np.linspace(0.0, 3.0, model.M))
    for v in (rng.standard_normal((model.M, 2)), np.stack([model.force, smooth], axis=1)):
        v = np.where(attached[:, None], v, 0.0)
        columns = np.ones(2, dtype=bool)
        double = solver._product(v, attached, columns)
        single = solver._product(v, attached, columns, single=True)
        error = np.linalg.norm(single - double, axis=0) / np.linalg.norm(double, axis=0)
        assert np.all(error < pillar_cg.SINGLE_ERROR) and np.all(error > 0), error



def test_the_products_field_on_the_attached_pillars_is_the_whole_fields_there():
    """`PillarModel.fields` on the attached rows only (the CG's product): the same numbers there, bit for bit,
    and zero elsewhere."""
    model, attached, _, _ = _scattered_solve()
    x = np.where(attached[:, None], np.random.default_rng(1).standard_normal((model.M, 2)), 0.0)
    whole = model.fields(x, uniform=True)
    rows = model.fields(x, uniform=True, rows=np.flatnonzero(attached))
    assert np.array_equal(rows[:, attached], whole[:, attached]) and not rows[:, ~attached].any()

def test_single_precision_products_leave_the_solve_within_its_tolerance(switches):
    """A cold solve on the scattered set takes most of its products in single precision and its true
    residual still meets the tolerance (1e-11): the solution is the dense solve's to 1e-9 (condition number
    below 1e2) and the double-precision solve's to 1e-10, at no more iterations than that."""
    model, attached, rhs, dense = _scattered_solve()
    runs = {}
    for single in (False, True):
        switches(single_pillar_products=single)
        solver = pillar_cg.LatticeCG(model)
        x, fields = solver.solve(attached, rhs)
        residual = rhs - fields[0] - np.stack([model.spring_product(x[:, c], attached) for c in range(2)], axis=1)
        residual[~attached] = 0.0
        assert np.all(np.linalg.norm(residual, axis=0) <= pillar_cg.TOLERANCE * np.linalg.norm(rhs, axis=0))
        assert np.abs(x[attached] - dense).max() < 1e-9 * np.abs(dense).max()
        runs[single] = (x, solver)
    (x64, double), (x32, single) = runs[False], runs[True]
    assert double.single_products == 0 and single.single_products >= single.products // 3
    assert single.restarts == 0 and single.iterations <= double.iterations
    assert np.abs(x32 - x64).max() < 1e-10 * np.abs(x64).max()


def test_a_solve_whose_single_products_miss_the_tolerance_goes_on_in_double():
    """With the single products' bound taken as zero (every product single, from the first), the recursive
    residual drifts from the true one; the true residual at the end misses the tolerance, and the solve goes
    on from it in double precision: the dense solve's answer to 1e-9 all the same."""
    model, attached, rhs, dense = _scattered_solve()
    solver = pillar_cg.LatticeCG(model)
    solver.single_error = 0.0
    x, _ = solver.solve(attached, rhs)
    assert solver.restarts == 1
    assert np.abs(x[attached] - dense).max() < 1e-9 * np.abs(dense).max()


def test_memory_estimate_of_the_pillar_model_at_ten_to_the_five_pillars(monkeypatch):
    """The size study's 316 x 316 brush (N = 5056) by the pillar model: above its measured peaks (3.0-3.5 GB,
    5.8 GB sampled in a sweep's worker) and within the 8 GB the model is meant to run in; the element path's estimate of the same grid is
    far above (its operator's arrays per element)."""

    config = {"grid": {"size": 1.0, "elements": 5056},
              "halfspace": {"contact_modulus": 1.0, "work_of_adhesion": DGAMMA},
              "indenter": {"shape": "brush", "layout": "square", "pillars_per_side": 316,
                           "pillar_radius": 0.000618484, "stiffness_ratio": 0.01},
              "protocol": {"method": "pillars", "preload_force": 0.0075}}
    monkeypatch.setenv("BRUSHBEM_MEMORY_LIMIT", "off")  # the element path's grid would not validate here
    pillar_bytes = memory_estimate(parse_config(config))
    config["protocol"]["method"] = "events"
    element_bytes = memory_estimate(parse_config(config))
    assert 5.8e9 < pillar_bytes < 8e9
    assert element_bytes > 2 * pillar_bytes


def test_memory_estimate_counts_the_kept_inverse_of_a_partial_contact(monkeypatch, switches):
    """A rough brush may keep its inverse on a partial set while it fits in ``kept_partial_bytes`` (half of the
    lattice at most): the estimate counts it (9 n^2 numbers at its peak, `pillar_kept_bytes`), and above the
    memory at hand the refusal names the switches; an explicit ``kept_partial`` is counted instead.  Where more
    pillars may attach than the inverse is kept for, the CG's kept Ritz vectors count too (4 k M numbers: the
    rough brush's scattered sets, not the level one's)."""
    from brushbem.config import ConfigError

    config = {"grid": {"size": 1.0, "elements": 5056},
              "halfspace": {"contact_modulus": 1.0, "work_of_adhesion": DGAMMA},
              "indenter": {"shape": "brush", "layout": "square", "pillars_per_side": 316,
                           "pillar_radius": 0.000618484, "stiffness_ratio": 0.01},
              "protocol": {"method": "pillars", "preload_force": 0.0075}}
    monkeypatch.setenv("BRUSHBEM_MEMORY_LIMIT", "off")
    level = memory_estimate(parse_config(config))
    config["indenter"]["roughness"] = {"sigma": 1e-4}
    rough = memory_estimate(parse_config(config))
    # Beyond the kept inverse, the CG's 40 kept Ritz vectors and their products (and copies while refreshed):
    # a rough brush's scattered sets only.
    recycled = 1.1 * 8 * 4 * 40 * 316**2
    assert rough - level == pytest.approx(1.1 * (pillar_kept_bytes(5461) - pillar_kept_bytes(1024)) + recycled,
                                          rel=1e-6)
    switches(recycled_vectors=0)
    assert memory_estimate(parse_config(config)) == pytest.approx(rough - recycled, rel=1e-6)
    switches(recycled_vectors=40)
    switches(kept_partial=16384)
    assert memory_estimate(parse_config(config)) > 8 * 2**30
    monkeypatch.setenv("BRUSHBEM_MEMORY_LIMIT", "8G")
    with pytest.raises(ConfigError, match=r"of it the pillar model's kept inverse of up to 16384 attached pillars: "
                                          r"lower Switches.kept_pillars or kept_partial_bytes"):
        parse_config(config)


def test_the_partial_limit_is_the_most_pillars_whose_kept_inverse_fits_its_budget(switches):
    """`kept_partial_count`: the most n with `pillar_kept_bytes` (n) within ``kept_partial_bytes`` (5461 in the
    default 2 GiB: the 316 x 316 rough brush's 4270 attached at its preload fit), one byte less gives one pillar
    less; ``kept_partial`` overrides the budget; a budget that is no amount of bytes is refused, naming it.  The
    solver applies it to partial sets only (at most half of the lattice), ``kept_pillars`` above."""
    from brushbem import settings

    assert kept_partial_count(settings.switches()) == 5461
    assert pillar_kept_bytes(5461) <= 2 * 2**30 < pillar_kept_bytes(5462)
    assert pillar_kept_bytes(4270) <= 2 * 2**30
    assert kept_partial_count(settings.Switches(kept_partial_bytes=int(pillar_kept_bytes(20)))) == 20
    assert kept_partial_count(settings.Switches(kept_partial_bytes=int(pillar_kept_bytes(20)) - 1)) == 19
    assert kept_partial_count(settings.Switches(kept_partial=7, kept_partial_bytes=int(pillar_kept_bytes(20)))) == 7
    for bad in (0, -1, float("nan")):
        with pytest.raises(ValueError, match=r"Switches.kept_partial_bytes must be a positive, finite number"):
            kept_partial_count(settings.Switches(kept_partial_bytes=bad))
    with pytest.raises(ValueError, match=r"Switches.kept_partial must be None or at least 0 .*got -2"):
        kept_partial_count(settings.Switches(kept_partial=-2))
    problem, _ = _problem(8, 1e-2, 1.0)
    solver = pillar_solver.Solver(pillars.PillarModel(problem))
    switches(kept_pillars=4, kept_partial_bytes=int(pillar_kept_bytes(20)))
    assert (solver._kept_limit(32), solver._kept_limit(33)) == (20, 4)  # M = 64: half of it is partial
    switches(kept_partial=10)
    assert solver._kept_limit(32) == 10


def test_a_kept_inverse_beyond_the_memory_at_hand_warns_and_solves_by_cg(monkeypatch):
    """Under a memory limit too small for a kept inverse of the brush's pillars the solver says so and keeps
    it only up to what fits (21 pillars in 64 KiB), solving by CG beyond: the same pull-off (F_A and the
    work to 1e-9: every solve reaches 1e-11)."""
    problem, force = _problem(8, 1e-2, 1.0)
    path = LoadPath(method="pillars", preload_force=force, max_steps=10**6)
    monkeypatch.setenv("BRUSHBEM_MEMORY_LIMIT", "off")
    kept = record_pull_off(problem, path).summary
    monkeypatch.setenv("BRUSHBEM_MEMORY_LIMIT", "64k")
    with pytest.warns(RuntimeWarning, match=r"kept_partial_bytes = 2 GiB \(5461 pillars\): .* keeps it up to 21 "
                                            r"pillars and solves by CG"):
        capped = record_pull_off(problem, path).summary
    assert capped["adhesive_force"] == pytest.approx(kept["adhesive_force"], rel=1e-9)
    assert capped["work_of_separation"] == pytest.approx(kept["work_of_separation"], rel=1e-9)


def test_the_solve_is_chosen_by_the_load_path():
    """``LoadPath.pillar_solve``: the kept inverse always, CG always and the default limits give one answer on
    a rough 8 x 8 pull-off (F_A and the work to 1e-9: every solve reaches 1e-11), and CG ran where asked."""
    problem, force = _problem(8, 1e-2, 1.0)
    summaries = {}
    for solve in ("auto", "kept", "cg"):
        path = LoadPath(method="pillars", preload_force=force, max_steps=10**6, pillar_solve=solve)
        summaries[solve] = record_pull_off(problem, path).summary
    for solve in ("kept", "cg"):
        assert summaries[solve]["adhesive_force"] == pytest.approx(summaries["auto"]["adhesive_force"], rel=1e-9)
        assert summaries[solve]["work_of_separation"] == pytest.approx(summaries["auto"]["work_of_separation"],
                                                                       rel=1e-9)
    model = pillars.PillarModel(problem)
    solver = pillar_solver.Solver(model, "cg")
    solver.add_many(np.arange(4))
    assert solver.iterative
    assert not pillar_solver.Solver(model, "kept")._kept_limit(model.M) < np.inf


def test_the_modes_and_near_radius_are_reachable_from_the_configuration():
    """``protocol.pillar_modes``, ``pillar_near`` and ``pillar_solve`` reach the path; the uniform mode alone
    is another model (F_A 6.5-22 % off, `docs/pillars/variants.md`); with another method they are refused,
    naming the key, as are values out of range."""
    from brushbem.config import ConfigError
    from brushbem.runs.assembly import build_path

    config = {
        "halfspace": {"contact_modulus": 1.0, "work_of_adhesion": 1e-4},
        "grid": {"size": 1.0, "elements": 64},
        "indenter": {"shape": "brush", "layout": "square", "region": "square", "pillars_per_side": 4,
                     "pillar_radius": 0.05, "stiffness_ratio": 0.05, "seed": 3},
        "protocol": {"method": "pillars", "preload_displacement": 2e-3, "pillar_modes": "uniform",
                     "pillar_near": 4.0, "pillar_solve": "kept"},
    }
    path = build_path(parse_config(config))
    assert (path.pillar_modes, path.pillar_near, path.pillar_solve) == ("uniform", 4.0, "kept")
    problem, force = _problem(4, 1e-2)
    default = record_pull_off(problem, LoadPath(method="pillars", preload_force=force)).summary
    uniform = record_pull_off(problem, LoadPath(method="pillars", preload_force=force,
                                                pillar_modes="uniform")).summary
    assert uniform["adhesive_force"] / default["adhesive_force"] - 1 > 0.03
    config["protocol"]["method"] = "events"
    with pytest.raises(ConfigError, match=r"protocol\.pillar_modes.*method = 'pillars' only"):
        build_path(parse_config(config))
    for key, value in (("pillar_modes", "cubic"), ("pillar_near", 0.0), ("pillar_solve", "lu")):
        with pytest.raises(ValueError, match=key):
            LoadPath(method="pillars", preload_force=1.0, **{key: value})


def test_the_load_path_names_the_modes_of_the_model():
    """`brushbem.protocol.problem.PILLAR_MODES` (the protocol does not import the model) are the model's."""
    from brushbem.protocol.problem import PILLAR_MODES

    assert set(PILLAR_MODES) == set(pillars.MODES)
