"""Brushes (thesis ch. 3-7): structure builders, the soft-pillar preconditioner, limits and consistency.

Units: E* = 1, L = 1, dgamma = 1e-4 unless stated.  Pull-off tests use a 4 x 4
lattice on N = 128 (pillar radius 6 elements, phi ~ 0.11): the limits compared
here are properties of the same discrete problem (the same footprints on the
same mesh), so a coarse grid loses nothing.  Pillar centres fall on element
corners, so every pillar has the same footprint.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from brushbem.physics import theory
from brushbem.runs.assembly import parse_config
from brushbem.runs.case import build_problem, run_case
from brushbem.config import ConfigError, config_to_dict
from brushbem.physics.halfspace import HalfSpace
from brushbem.numerics.operator import ContactOperator, MaskedOperator, Window
from brushbem.protocol import ContactProblem, LoadPath, record_pull_off
from brushbem.numerics.solver import (
    conjugate_gradient,
    laplacian_preconditioner,
    pillar_block_preconditioner,
    spring_preconditioner,
)
from brushbem.physics.structure import (
    Grid,
    Indenter,
    Level,
    Profile,
    StructureError,
    brush,
    flat_punch,
    hierarchy_clusters,
    square_lattice,
)

E_STAR = 1.0
DGAMMA = 1.0e-4
GRID = Grid(1.0, 128)
RADIUS = 6 * GRID.element_size  # 0.0469: phi = 16 pi r^2 = 0.11


def _brush(**kwargs) -> Indenter:
    args = {"layout": "square", "pillars_per_side": 4, "pillar_radius": RADIUS, "contact_modulus": E_STAR,
                "work_of_adhesion": DGAMMA}
    args.update(kwargs)
    return brush(kwargs.pop("grid", GRID), **{k: v for k, v in args.items() if k != "grid"})


def _pull_off(indenter: Indenter, preload: float = 2e-3, grid: Grid = GRID, method: str = "events") -> dict:
    problem = ContactProblem(grid, indenter, contact_modulus=E_STAR, work_of_adhesion=DGAMMA)
    record = record_pull_off(problem, LoadPath(method=method, preload_displacement=preload))
    assert record.summary["converged"], record.summary["reason"]
    return record.summary


# ---------------------------------------------------------------------------
# Structure builders
# ---------------------------------------------------------------------------


def test_square_lattice_geometry_and_filling_factor():
    b = _brush(stiffness=1.0)
    info = b.description
    assert b.n_pillars == 16
    centres, _ = square_lattice(4, 0.25)
    np.testing.assert_allclose(info["centres"], centres)
    # Every pillar has the same rasterised footprint (centres on element corners).
    assert len(set(info["pillar_elements"].tolist())) == 1
    assert info["filling_factor"] == pytest.approx(info["pillar_elements"].sum() / 128**2)
    # The rasterised area approximates pi r^2 to within the staircase error (~2 % at r = 6h).
    assert info["filling_factor"] == pytest.approx(info["nominal_filling_factor"], rel=0.03)
    assert [lv.stiffness for lv in b.levels] == [1.0]


def test_random_layout_is_reproducible_and_never_overlaps():
    kwargs = {"layout": "random", "pillar_count": 40, "pillar_radius": 3 * GRID.element_size, "min_gap": 0.01}
    a, b, c = _brush(seed=5, **kwargs), _brush(seed=5, **kwargs), _brush(seed=6, **kwargs)
    np.testing.assert_array_equal(a.pillar, b.pillar)
    assert not np.array_equal(a.pillar, c.pillar)
    for indenter in (a, c):
        centres = indenter.description["centres"]
        gaps = np.hypot(*(centres[:, None, :] - centres[None, :, :]).transpose(2, 0, 1))
        np.fill_diagonal(gaps, np.inf)
        assert gaps.min() >= 2 * 3 * GRID.element_size + 0.01 - 1e-12
        assert indenter.n_pillars == 40


def test_circular_region_keeps_the_pillars_inside_the_circle():
    b = _brush(pillars_per_side=8, pillar_radius=3 * GRID.element_size, region="circle", stiffness=1.0)
    centres = b.description["centres"]
    assert 0 < b.n_pillars < 64
    assert np.all(np.hypot(centres[:, 0], centres[:, 1]) + 3 * GRID.element_size <= 0.5)
    assert b.description["apparent_area"] == pytest.approx(math.pi / 4)


def test_roughness_offsets_are_seeded_gaussian_and_scale_with_sigma():
    grid = Grid(1.0, 512)
    kw = {"grid": grid, "pillars_per_side": 32, "pillar_radius": 0.006, "stiffness": 1.0, "seed": 3}
    one = _brush(roughness=1e-3, **kw).description["offsets"]
    two = _brush(roughness=2e-3, **kw).description["offsets"]
    flat = _brush(roughness=0.0, **kw).description["offsets"]
    assert one.min() == 0.0 and np.all(flat == 0.0)
    np.testing.assert_allclose(two, 2 * one, rtol=1e-12)  # the same realisation, rescaled
    # 1024 samples: the sample standard deviation is within ~3/sqrt(2*1024) = 7 % of sigma.
    assert np.std(one) == pytest.approx(1e-3, rel=0.07)


def test_concave_profile_offsets_follow_eq_7_3():
    b = _brush(pillars_per_side=8, pillar_radius=3 * GRID.element_size, stiffness=1.0,
               profile=Profile(amplification=0.5))
    info = b.description
    r = np.hypot(info["centres"][:, 0], info["centres"][:, 1])
    g = info["offsets"]
    assert g[np.argmax(r)] == 0.0  # the rim pillars are the longest
    p_c = theory.concave_reference_stress(3 * GRID.element_size, contact_modulus=E_STAR, work_of_adhesion=DGAMMA)
    expected = theory.concave_offsets(r, r.max(), 0.5, p_c, contact_modulus=E_STAR)
    np.testing.assert_allclose(g, expected, rtol=1e-12, atol=1e-18)
    order = np.argsort(r)
    assert np.all(np.diff(g[order]) <= 1e-15)  # shorter towards the centre
    flat = _brush(pillars_per_side=8, pillar_radius=3 * GRID.element_size, stiffness=1.0,
                  profile=Profile(amplification=0.0))
    assert np.all(flat.description["offsets"] == 0.0)


def test_hierarchy_clusters_tile_the_lattice():
    _, index = square_lattice(8, 0.1)
    level2, level3 = hierarchy_clusters(index, 8, (2, 2))
    assert np.bincount(level2).tolist() == [4] * 16
    assert np.bincount(level3).tolist() == [16] * 4
    # A level-3 cluster is a union of level-2 clusters.
    for c in range(16):
        assert len(set(level3[level2 == c])) == 1
    with pytest.raises(StructureError, match="does not tile"):
        hierarchy_clusters(index, 8, (3,))


@pytest.mark.parametrize(
    ("change", "key"),
    [
        ({"pillar_radius": 0.2}, "indenter.pillar_radius"),            # overlapping pillars
        ({"pillar_radius": 0.01}, "indenter.pillar_radius"),           # under 2 elements (h = 1/128)
        ({"levels": [{"cluster": 3, "stiffness": 1.0}]}, "indenter.levels"),  # 3 does not divide 4
        ({"roughness": {"sigma": -1e-3}}, "indenter.roughness.sigma"),
        ({"stiffness": 1.0}, "indenter.stiffness_ratio"),              # both stiffness and ratio
        ({"pillar_count": 10}, "indenter.pillar_count"),               # random-only key on a lattice
        ({"layout": "hexagonal"}, "indenter.layout"),
        ({"levels": [{"cluster": 2}]}, "indenter.levels.0.stiffness_ratio"),
        ({"spacing": 0.5}, "indenter.spacing"),                        # 4 x 0.5 > region
        ({"profile": {"amplification": -1.0}}, "indenter.profile.amplification"),
    ],
)
def test_bad_brush_input_names_the_key(change, key):
    document = _document()
    document["indenter"].update(change)
    with pytest.raises(ConfigError) as error:
        parse_config(document)
    assert any(f"`{key}`" in line for line in error.value.problems), error.value.problems


def test_random_layout_rejects_a_hierarchy():
    document = _document()
    document["indenter"].update({"layout": "random", "pillar_count": 8, "pillars_per_side": None})
    del document["indenter"]["pillars_per_side"]
    document["indenter"]["levels"] = [{"cluster": 2, "stiffness": 1.0}]
    with pytest.raises(ConfigError) as error:
        parse_config(document)
    assert any("`indenter.levels`" in line for line in error.value.problems)


def _document(**indenter) -> dict:
    base = {
        "halfspace": {"contact_modulus": E_STAR, "work_of_adhesion": DGAMMA},
        "grid": {"size": 1.0, "elements": 128},
        "indenter": {"shape": "brush", "layout": "square", "pillars_per_side": 4,
                     "pillar_radius": RADIUS, "stiffness_ratio": 0.5, "seed": 1},
        "protocol": {"preload_displacement": 2e-3},
    }
    base["indenter"].update(indenter)
    return base


def test_brush_config_round_trips_and_converts_the_stiffness_ratio():
    config = parse_config(_document(levels=[{"cluster": 2, "stiffness_ratio": 9e-3}],
                                    roughness={"sigma": 1e-3}))
    assert parse_config(config_to_dict(config)) == config
    problem = build_problem(config)
    assert [lv.stiffness for lv in problem.indenter.levels] == pytest.approx([0.5, 9e-3])


# ---------------------------------------------------------------------------
# Operator and preconditioner
# ---------------------------------------------------------------------------


def _operator(indenter, coupling="segments"):
    halfspace = HalfSpace(GRID.elements, GRID.element_size, E_STAR)
    return ContactOperator(halfspace, indenter, Window.full(GRID.elements), coupling=coupling)


def test_spring_preconditioner_is_symmetric_positive_definite_for_a_hierarchy():
    indenter = _brush(pillars_per_side=8, pillar_radius=3 * GRID.element_size, stiffness=1e-4,
                      levels=(Level(2, 1e-3), Level(2, 1e-2)))
    operator = _operator(indenter)
    rng = np.random.default_rng(0)
    mask = indenter.footprint & (rng.random(indenter.pillar.shape) < 0.7)
    apply = spring_preconditioner(operator, mask)
    x, y = (rng.standard_normal(mask.shape) * mask for _ in range(2))
    xmy, ymx = float(np.sum(x * apply(y))), float(np.sum(y * apply(x)))
    assert xmy == pytest.approx(ymx, rel=1e-10, abs=0.0)
    assert float(np.sum(x * apply(x))) > 0 and float(np.sum(y * apply(y))) > 0


@pytest.mark.parametrize("levels", [(), (Level(2, 1e-5),)])
def test_soft_pillars_need_at_most_twice_the_rigid_iterations(levels):
    """Issue goal: CG iterations per solve at k~ = 1e-5 within 2x of the rigid brush."""
    rng = np.random.default_rng(1)

    def iterations(stiffness, preconditioned=True):
        indenter = _brush(pillars_per_side=8, pillar_radius=3 * GRID.element_size, stiffness=stiffness,
                          roughness=1e-3, seed=2, levels=levels if math.isfinite(stiffness) else ())
        operator = _operator(indenter)
        mask = indenter.footprint & (np.random.default_rng(3).random(indenter.pillar.shape) < 0.8)
        rhs = np.where(mask, 1e-3 - np.where(mask, indenter.height, 0.0), 0.0)
        pc = (spring_preconditioner(operator, mask) if operator.has_springs and preconditioned
              else laplacian_preconditioner(mask))
        result = conjugate_gradient(MaskedOperator(operator, mask), rhs, initial=np.zeros_like(rhs),
                                    tolerance=1e-10, max_iterations=5000, preconditioner=pc)
        assert result.converged
        return result.iterations

    del rng
    rigid = iterations(math.inf)
    soft = iterations(1e-5)
    assert soft <= 2 * rigid, (soft, rigid)
    # ... and the spring preconditioner beats the Laplacian one there.
    assert soft < iterations(1e-5, preconditioned=False)


def _hierarchy_operator_and_set(seed: int = 0):
    indenter = _brush(pillars_per_side=8, pillar_radius=3 * GRID.element_size, stiffness=1e-4,
                      roughness=1e-3, seed=2, levels=(Level(2, 1e-3), Level(2, 1e-2)))
    operator = _operator(indenter)
    mask = indenter.footprint & (np.random.default_rng(seed).random(indenter.pillar.shape) < 0.7)
    return indenter, operator, mask


@pytest.mark.parametrize("coupling", ["segments", "discriminant"])
def test_contact_system_applies_the_operator_on_the_set(coupling):
    """ContactSystem (|S| values, row-pruned transforms) = ContactOperator.apply restricted to S."""
    if coupling == "segments":
        _, operator, mask = _hierarchy_operator_and_set()
    else:  # the discriminant matrix needs clusters narrower than the gaps: one level
        indenter = _brush(stiffness=0.05)
        operator = _operator(indenter, coupling)
        mask = indenter.footprint & (np.random.default_rng(0).random(indenter.pillar.shape) < 0.7)
    system = operator.system(mask)
    assert system.size == int(mask.sum())
    values = np.random.default_rng(1).standard_normal(system.size)
    reference = operator.apply(system.scatter(values), mask)
    # Round-off of transforms on a 256^2 padded grid: 1e-12 of the largest entry.
    np.testing.assert_allclose(system.apply(values), system.gather(reference), rtol=0,
                               atol=1e-12 * np.abs(reference).max())
    np.testing.assert_array_equal(system.gather(system.scatter(values)), values)


def test_pillar_block_preconditioner_is_symmetric_positive_definite_for_a_hierarchy():
    _, operator, mask = _hierarchy_operator_and_set()
    system = operator.system(mask)
    apply = pillar_block_preconditioner(system)
    assert apply is not None
    rng = np.random.default_rng(4)
    x, y = rng.standard_normal((2, system.size))
    xmy, ymx = float(x @ apply(y)), float(y @ apply(x))
    assert xmy == pytest.approx(ymx, rel=1e-10, abs=0.0)
    assert float(x @ apply(x)) > 0 and float(y @ apply(y)) > 0


def test_pillar_block_preconditioner_is_exact_for_one_pillar_on_a_spring():
    """One pillar: B is K_S exactly and the spring is added exactly, so M = A_S and CG takes one step."""
    indenter = flat_punch(GRID, 5 * GRID.element_size, stiffness=0.01)
    operator = _operator(indenter)
    mask = indenter.footprint & (np.random.default_rng(0).random(indenter.pillar.shape) < 0.9)
    system = operator.system(mask)
    apply = pillar_block_preconditioner(system)
    rhs = np.random.default_rng(1).standard_normal(system.size)
    np.testing.assert_allclose(system.apply(apply(rhs)), rhs, rtol=0, atol=1e-9 * np.abs(rhs).max())


def test_pillar_block_preconditioner_refuses_large_pillars():
    """A punch wider than the block limit (here ~800 elements) keeps the Laplacian-type preconditioners."""
    indenter = flat_punch(GRID, 16 * GRID.element_size)
    system = _operator(indenter).system(indenter.footprint)
    assert pillar_block_preconditioner(system) is None


def test_pillar_blocks_cut_the_iterations_at_every_stiffness():
    """Cold-start CG on a rough 8 x 8 brush: the two-level pillar preconditioner needs at most
    half the iterations of the spring (Laplacian-block) preconditioner, for stiff and soft pillars."""
    for stiffness in (math.inf, 1.0, 1e-5):
        indenter = _brush(pillars_per_side=8, pillar_radius=3 * GRID.element_size, stiffness=stiffness,
                          roughness=1e-3, seed=2)
        operator = _operator(indenter)
        mask = indenter.footprint & (np.random.default_rng(3).random(indenter.pillar.shape) < 0.8)
        rhs = np.where(mask, 1e-3 - np.where(mask, indenter.height, 0.0), 0.0)
        system = operator.system(mask)
        blocked = conjugate_gradient(system, system.gather(rhs),
                                     tolerance=1e-10, preconditioner=pillar_block_preconditioner(system))
        pc = spring_preconditioner(operator, mask) if operator.has_springs else laplacian_preconditioner(mask)
        windowed = conjugate_gradient(MaskedOperator(operator, mask), rhs, tolerance=1e-10,
                                      preconditioner=pc)
        assert blocked.converged and windowed.converged
        assert 2 * blocked.iterations <= windowed.iterations, (stiffness, blocked.iterations, windowed.iterations)
        # Both solve to a relative residual of 1e-10; the solutions differ by at most
        # cond(A_S) times that, cond(K_S) ~ 1e3 for contacts a few tens of elements wide.
        np.testing.assert_allclose(system.scatter(blocked.solution), windowed.solution, rtol=0,
                                   atol=1e-6 * np.abs(windowed.solution).max())


def test_segment_sums_equal_the_discriminant_convolution_for_a_brush():
    indenter = _brush(stiffness=0.05)
    seg, disc = _operator(indenter, "segments"), _operator(indenter, "discriminant")
    p = np.random.default_rng(4).standard_normal(indenter.pillar.shape) * indenter.footprint
    np.testing.assert_allclose(disc.apply(p, indenter.footprint), seg.apply(p, indenter.footprint),
                               rtol=0, atol=1e-13 * np.abs(seg.apply(p, indenter.footprint)).max())
    # A hierarchy on a uniform lattice: the level-2 box cannot avoid the next cluster.
    with pytest.raises(ValueError, match="discriminant matrix cannot be used"):
        _operator(_brush(stiffness=0.05, levels=(Level(2, 0.1),)), "discriminant")


def test_segment_sums_equal_the_discriminant_convolution_over_a_pull_off():
    indenter = _brush(stiffness=0.05)
    results = []
    for coupling in ("segments", "discriminant"):
        problem = ContactProblem(GRID, indenter, E_STAR, DGAMMA, coupling=coupling)
        results.append(record_pull_off(problem, LoadPath(preload_displacement=2e-3)).summary["adhesive_force"])
    assert results[1] == pytest.approx(results[0], rel=1e-7)  # solver tolerance 1e-8


# ---------------------------------------------------------------------------
# Limits and consistency on pull-offs
# ---------------------------------------------------------------------------


def test_rigid_brush_equals_one_rigid_body():
    rigid = _brush(stiffness=math.inf)
    body = Indenter(height=rigid.height, pillar=np.where(rigid.footprint, 0, -1))
    # Element events for both: the same path state by state (the default
    # "events" would press the brush as one contact problem, not the body).
    a, b = _pull_off(rigid, method="element_events"), _pull_off(body, method="element_events")
    # The same problem; only the preconditioner differs (pillar blocks for the
    # brush, the Laplacian for the one large body), so the two agree to the
    # CG tolerance 1e-8, i.e. about 1e-7 in the force.
    assert a["adhesive_force"] == pytest.approx(b["adhesive_force"], rel=1e-6)
    assert a["n_states"] == b["n_states"]
    # Continuity: very stiff springs approach the rigid brush (spring stretch ~ F/k ~ 1e-6 d_c).
    stiff = _pull_off(_brush(stiffness=1e6))
    assert stiff["adhesive_force"] == pytest.approx(a["adhesive_force"], rel=1e-3)


def _soft_over_single(grid: Grid, per_side: int, radius: float) -> float:
    """F_A of a very soft brush (k = 1e-6 E* L) over (pillars x the same pillar alone, rigid)."""
    single = _pull_off(flat_punch(grid, radius), grid=grid)["adhesive_force"]
    indenter = _brush(grid=grid, pillars_per_side=per_side, pillar_radius=radius, stiffness=1e-6)
    # Same footprint for every pillar and for the lone punch: centres on element corners.
    assert set(indenter.description["pillar_elements"].tolist()) == {int(flat_punch(grid, radius).footprint.sum())}
    return _pull_off(indenter, grid=grid)["adhesive_force"] / (per_side**2 * single)


def test_soft_pillars_tend_to_the_sum_of_single_pillar_forces():
    """k~ -> 0: equal load sharing, every pillar leaves at its own pull-off force (eq. 4.7).

    The pillars still interact through the half-space: the deflection that the
    other pillars' tension causes is not uniform across a pillar, and a pillar
    that cannot tilt answers with a stress gradient that raises one edge.  This
    lowers F_A by a fraction that grows with the filling factor (measured
    11.5 % at phi = 0.11, 5.3 % at 0.05, 3.4 % at 0.03 on 4 x 4 lattices; the
    k -> 0 limit is reached: k = 1e-4 and 1e-6 agree to 2e-4).  The closed
    form ignores the interaction, so it is the limit of sparse brushes: a
    2 x 2 brush with phi = 0.007 is within 2 %, and the deficit falls as phi falls.
    """
    sparse = _soft_over_single(Grid(1.0, 256), 2, 6 / 256)
    assert sparse == pytest.approx(1.0, abs=0.02)
    dense = _soft_over_single(GRID, 4, 6 * GRID.element_size)      # phi = 0.11
    medium = _soft_over_single(GRID, 4, 3 * GRID.element_size)     # phi = 0.03
    assert dense < medium < sparse <= 1.0 + 1e-3


def test_one_pillar_brush_equals_the_punch_on_a_spring():
    k = 0.02
    a = _pull_off(_brush(pillars_per_side=1, pillar_radius=0.2, stiffness=k))
    b = _pull_off(flat_punch(GRID, 0.2, k))
    for key in ("adhesive_force", "pull_off_displacement", "work_of_separation", "n_states"):
        assert a[key] == pytest.approx(b[key], rel=1e-10, abs=0.0), key


def test_hierarchy_limits():
    one = _pull_off(_brush(stiffness=0.01))["adhesive_force"]
    # A rigid second level adds nothing.
    two_rigid = _pull_off(_brush(stiffness=0.01, levels=(Level(2, math.inf),)))["adhesive_force"]
    assert two_rigid == pytest.approx(one, rel=1e-12, abs=0.0)
    # ... and a very stiff one approaches it (its stretch is 1e-6 of the pillars').
    two_stiff = _pull_off(_brush(stiffness=0.01, levels=(Level(2, 1e4),)))["adhesive_force"]
    assert two_stiff == pytest.approx(one, rel=1e-3)
    # One pillar per cluster: two springs in series, 1/k = 1/k1 + 1/k2.
    series = _pull_off(_brush(stiffness=0.03, levels=(Level(1, 0.015),)))
    single = _pull_off(_brush(stiffness=0.01))
    for key in ("adhesive_force", "pull_off_displacement"):
        assert series[key] == pytest.approx(single[key], rel=1e-6), key


def test_zero_roughness_and_zero_profile_equal_the_flat_brush():
    flat = _pull_off(_brush(stiffness=0.1))["adhesive_force"]
    assert _pull_off(_brush(stiffness=0.1, roughness=0.0, seed=9))["adhesive_force"] == flat
    assert _pull_off(_brush(stiffness=0.1, profile=Profile(0.0)))["adhesive_force"] == flat
    # ... while a real roughness changes it.
    assert _pull_off(_brush(stiffness=0.1, roughness=5e-4, seed=9))["adhesive_force"] != flat


# ---------------------------------------------------------------------------
# Physics in the thesis's terms (ch. 4)
# ---------------------------------------------------------------------------


def _brushes(side: int, elements: int, radius: float) -> dict[float, object]:
    """A side x side lattice, phi ~ 0.12 (r = 3.1 elements), pulled off at k~ = 10, 1, 0.01."""
    out = {}
    for ratio in (10.0, 1.0, 0.01):
        document = {
            "halfspace": {"contact_modulus": 1.0, "work_of_adhesion": 1e-4},
            "grid": {"size": 1.0, "elements": elements},
            "indenter": {"shape": "brush", "layout": "square", "pillars_per_side": side,
                         "pillar_radius": radius, "stiffness_ratio": ratio},
            "protocol": {"preload_displacement": 0.002},
        }
        result = run_case(parse_config(document)).result
        assert result.summary["converged"]
        out[ratio] = result
    return out


@pytest.fixture(scope="module")
def brush_16x16():
    """16 x 16 lattice, phi ~ 0.12 (r = 3.1 elements at N = 256), F~ of eq. 4.11 per k~."""
    return _brushes(16, 256, 0.0122)


@pytest.fixture(scope="module")
def brush_8x8():
    """The same lattice at a quarter of the pillars: 8 x 8, phi ~ 0.12, r = 3.1 elements at N = 128."""
    return _brushes(8, 128, 0.0244)


@pytest.mark.slow
def test_16x16_brush_force_is_near_the_rigid_estimate_for_stiff_pillars(brush_16x16):
    # Thesis Fig. 4-3a: F~ ~ 1.8 at k~ = 0.455; rigid estimate phi^-1/4 = 1.7.
    for ratio in (10.0, 1.0):
        normalized = brush_16x16[ratio].summary["normalized"]
        assert normalized["filling_factor"] == pytest.approx(0.12, abs=0.01)
        assert 1.6 <= normalized["force_by_compact_punch"] <= 2.1, (ratio, normalized)


@pytest.mark.slow
def test_rigid_brush_force_is_resolved_at_four_elements_per_pillar_radius():
    """A rigid 4 x 4 brush (phi = 0.12): F_A / F_c at 4, 8, 16 elements per pillar radius.

    Measured F_A / F_c (F_c of eq. 4.5 on the rasterised phi): 0.937, 0.930,
    0.924 at r/h = 4, 8, 16 - resolved to 1.3 %, the scatter of the
    rasterised filling factor (0.124, 0.117, 0.121) that F_c is computed on.
    So the brush results at the thesis's ~3-4 elements per radius are not a
    discretisation artefact.  That F_A / F_c is not 1 is the lattice: eq. 4.5
    homogenises the pillars into a punch of work phi dgamma, whereas the
    discrete criterion lets the outer row of pillars go at its own Kendall
    force.  At r/h = 4 the ratio grows with the pillar count (0.73, 0.94,
    1.01, 1.05 for 2, 4, 8, 16 pillars per side) towards the thesis's
    F~ ~ 1.8 vs phi^-1/4 = 1.7 of Fig. 4-3a (a ratio of 1.06); the bands
    below allow 2 % for the scatter and +-10 % around the measured 0.93.
    """
    side, phi = 4, 0.12
    radius = math.sqrt(phi / (side * side * math.pi))
    ratios = []
    for per_radius in (4, 8, 16):
        n = round(per_radius / radius)
        n += n % 2
        document = {
            "halfspace": {"contact_modulus": 1.0, "work_of_adhesion": 1e-4},
            "grid": {"size": 1.0, "elements": n},
            "indenter": {"shape": "brush", "layout": "square", "pillars_per_side": side,
                         "pillar_radius": radius, "stiffness_ratio": math.inf},
            "protocol": {"preload_displacement": 0.002},
        }
        result = run_case(parse_config(document)).result
        assert result.summary["converged"], result.summary["reason"]
        ratios.append(result.summary["normalized"]["force_by_rigid_brush"])
    assert max(ratios) / min(ratios) - 1 < 0.02, ratios
    assert all(0.84 < r < 1.03 for r in ratios), ratios


def test_brush_force_grows_as_pillars_soften(brush_8x8):
    """F~ at k~ = 10 <= 1 < 0.01 (Fig. 4-3 a; measured 1.72, 1.74, 2.25 here, 1.81, 1.82, 2.47 at 16 x 16)."""
    forces = [brush_8x8[r].summary["normalized"]["force_by_compact_punch"] for r in (10.0, 1.0, 0.01)]
    assert forces[0] <= forces[1] * (1 + 1e-6) < forces[2]


def test_brush_outputs(brush_8x8, tmp_path):
    from brushbem.io import read_case, write_case

    result = brush_8x8[1.0]
    write_case(result, tmp_path)
    data = read_case(tmp_path)
    assert data.sizes["pillar"] == 64
    for name in ("pillar_x", "pillar_y", "pillar_offset", "pillar_separation_displacement", "pillar_max_tension",
                 "pillar_force", "cross_section_adhesive_force", "attached_pillars"):
        assert name in data, name
    # The pillar forces add up to the total force at the adhesive-force moment.
    snap = next(s for s in result.snapshots if s.name == "adhesive_force")
    assert snap.pillar_force.sum() == pytest.approx(snap.force, rel=1e-12, abs=0.0)
    assert result.summary["normalized"]["attached_pillars_at_pull_off"] <= 64
    assert result.summary["mean_cg_iterations_per_solve"] > 0
    # The snapshot fields are stored gzip-compressed and read back bit for bit (a brush's fields
    # are mostly zeros outside the pillars); the curves stay uncompressed.
    import h5py

    with h5py.File(tmp_path / "result.nc") as handle:
        assert handle["pressure"].compression == "gzip"
        assert handle["force"].compression is None
    assert np.array_equal(data["pressure"].sel(stage="adhesive_force").to_numpy(), snap.pressure)
    assert np.array_equal(data["pillar_force"].sel(stage="adhesive_force").to_numpy(), snap.pillar_force)
    assert (tmp_path / "result.nc").stat().st_size < 0.5 * sum(v.nbytes for v in data.variables.values())


@pytest.mark.slow
def test_nested_loop_per_pillar_equals_the_coupled_operator():
    """Thesis Fig. 3-5 c: the nested loop extended pillar by pillar solves the same equations.

    A rough 5 x 5 brush (different pillars carry different forces), with
    adhesion, walked through a press-and-pull history: the same contact sets
    and pressures within the solver tolerance (1e-10 relative; 1e-7 allows
    for the per-pillar force balance, stopped at 100 x tolerance).
    """
    from brushbem.numerics.nested import nested_loop_brush_equilibrium
    from brushbem.numerics.solver import Settings, Start, equilibrium
    from brushbem.physics.adhesion import critical_stress

    grid = Grid(1.0, 64)
    indenter = brush(grid, layout="square", pillars_per_side=5, pillar_radius=0.06, contact_modulus=E_STAR,
                     work_of_adhesion=1e-3, stiffness=0.05, roughness=2e-3, seed=1)
    halfspace = HalfSpace(64, grid.element_size, E_STAR)
    coupled = ContactOperator(halfspace, indenter, Window.full(64))
    rigid = ContactOperator(halfspace, Indenter(indenter.height, indenter.pillar), Window.full(64))
    critical = critical_stress(E_STAR, 1e-3, grid.element_size)
    c1 = c2 = indenter.footprint
    p1 = p2 = np.zeros(indenter.height.shape)
    for d in (0.004, 0.0, -0.04, -0.068, -0.0713):
        a = equilibrium(coupled, indenter.height, d, Start(contact=c1, pressure=p1), critical=critical,
                        settings=Settings(tolerance=1e-10))
        b = nested_loop_brush_equilibrium(rigid, indenter.pillar, indenter.height, d, 0.05, c2, p2, critical)
        assert a.converged and b.converged
        np.testing.assert_array_equal(a.contact, b.contact)
        np.testing.assert_allclose(b.pressure, a.pressure, atol=1e-7 * np.abs(a.pressure).max())
        c1, p1, c2, p2 = a.contact, a.pressure, b.contact, b.pressure
    assert 0 < int(c1.sum()) < int(indenter.footprint.sum())  # some detachment happened


@pytest.mark.slow
def test_nested_vs_convolution_study_agrees(tmp_path):
    from brushbem.studies import nested_vs_convolution as study

    curves = study.compute(elements=48)
    for name in ("punch", "sphere", "pillars"):
        conv, nested, rigid = (curves[f"{name}_{m}"] for m in ("convolution", "nested", "rigid"))
        np.testing.assert_allclose(nested, conv, atol=1e-7 * np.abs(conv).max())
        assert np.abs(conv).max() < np.abs(rigid).max()  # the springs take part of the depth
    paths = study.draw({}, tmp_path / "figures")
    assert all(p.exists() for p in paths)


@pytest.mark.slow  # over 3 s on 2 cores: `make test` runs it, `make test-fast` does not
def test_events_reach_pillars_outside_the_first_window():
    """Regression: a rough brush touches first with one pillar; the others must still be found.

    The event-driven path works in a window around the contact; pillars
    outside it come into reach as d grows.  Events and small fixed steps
    (step 2e-5 = d_c / 150) must give the same loading state and, within the
    step error, the same adhesive force.
    """
    grid = Grid(1.0, 128)
    indenter = brush(grid, layout="square", pillars_per_side=8, pillar_radius=3 * grid.element_size,
                     contact_modulus=E_STAR, work_of_adhesion=DGAMMA, stiffness=10.0, roughness=2e-3, seed=1)
    problem = ContactProblem(grid, indenter, E_STAR, DGAMMA)
    records = {m: record_pull_off(problem, LoadPath(method=m, preload_displacement=0.006, step=2e-5))
               for m in ("events", "fixed")}
    events, fixed = records["events"], records["fixed"]
    assert events.summary["preload_force"] == pytest.approx(fixed.summary["preload_force"], rel=1e-6)
    assert events.curve.attached_pillars.max() == fixed.curve.attached_pillars.max() > 20
    # Fixed steps miss the exact extremum by O(step): measured 6e-4.
    assert events.summary["adhesive_force"] == pytest.approx(fixed.summary["adhesive_force"], rel=3e-3)


def test_sparse_and_stencil_spring_preconditioners_agree(monkeypatch):
    """The CPU path (sparse B on S) and the array-namespace path (stencils) are the same M^-1."""
    from brushbem import backend
    from brushbem.numerics import solver

    indenter = _brush(pillars_per_side=8, pillar_radius=3 * GRID.element_size, stiffness=1e-4,
                      levels=(Level(2, 1e-3), Level(2, 1e-2)))
    operator = _operator(indenter)
    rng = np.random.default_rng(5)
    mask = indenter.footprint & (rng.random(indenter.pillar.shape) < 0.7)
    residual = rng.standard_normal(mask.shape) * mask
    sparse_path = solver.spring_preconditioner(operator, mask)(residual)
    monkeypatch.setattr(backend, "is_numpy_namespace", lambda xp: False)
    stencil_path = solver.spring_preconditioner(operator, mask)(residual)
    np.testing.assert_allclose(sparse_path * mask, stencil_path * mask, rtol=0, atol=1e-13 * np.abs(stencil_path).max())


# ---------------------------------------------------------------------------
# Local and global detachment cascades
# ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    "stiffness, levels", [(math.inf, ()), (0.01, ()), (1e-6, ()), (0.03, (Level(2, 0.01),))]
)
def test_local_and_global_cascades_give_the_same_pull_off(stiffness, levels):
    problem = ContactProblem(GRID, _brush(stiffness=stiffness, levels=levels), contact_modulus=E_STAR,
                             work_of_adhesion=DGAMMA)
    summaries = {}
    for cascade in ("local", "global"):
        record = record_pull_off(problem, LoadPath(preload_displacement=2e-3, cascade=cascade))
        assert record.summary["converged"], record.summary["reason"]
        summaries[cascade] = record.summary
    local, full = summaries["local"], summaries["global"]
    # The adhesive force is the tension of an equilibrium reached before the
    # peak's cascade, which the two rules reach along the same events: they
    # agree to the CG tolerance 1e-8 (1e-6 with the force's round-off).
    assert local["adhesive_force"] == pytest.approx(full["adhesive_force"], rel=1e-6)
    assert local["pull_off_displacement"] == pytest.approx(full["pull_off_displacement"], rel=1e-6)
    # The work integrates the whole post-peak path, whose cascades may take
    # along an element within the far field's change of the threshold.
    assert local["work_of_separation"] == pytest.approx(full["work_of_separation"], rel=1e-3)
    # The local rounds replace global solves.
    assert local["n_solves"] <= full["n_solves"]


@pytest.mark.parametrize("fraction", [0.99, 0.9])
def test_local_cascade_ends_in_an_equilibrium_that_obeys_the_criterion(fraction):
    """A tensile state of soft pillars with the threshold lowered below its largest tension.

    One element of pillar 5 is forced off (as the event-driven path does) and
    the cascade runs with Sigma_c at ``fraction`` of the largest tension, so
    that many pillars peel over many rounds.  Both rules must end in an
    equilibrium that obeys the criterion.  The two end states need not be the
    same in such an avalanche: they take different orders through it (at
    0.9 the global rule separates every pillar and the local one leaves two
    attached), which is why their agreement is tested on real pull-offs
    (above), where a cascade starts at one element on the threshold.
    """
    from brushbem.numerics.solver import (
        Settings,
        Start,
        equilibrium,
        tip_deflection,
    )
    from brushbem.physics.adhesion import critical_stress

    indenter = _brush(stiffness=1e-3)
    halfspace = HalfSpace(GRID.elements, GRID.element_size, E_STAR)
    operator = ContactOperator(halfspace, indenter, Window.full(GRID.elements))
    critical = critical_stress(E_STAR, DGAMMA, GRID.element_size)
    height = indenter.height
    d = -1e-4
    pressed = equilibrium(operator, height, 2e-3, Start(contact=indenter.footprint, pressure=np.zeros(height.shape)),
                          critical=critical)
    start = equilibrium(operator, height, d, Start(contact=pressed.contact, pressure=pressed.pressure),
                        critical=critical)
    assert start.converged and float(start.pressure.min()) < 0
    on_pillar = start.contact & (indenter.pillar == 5)
    weakest = np.where(on_pillar, start.pressure, np.inf)
    forced = weakest == weakest.min()
    critical = fraction * float(-start.pressure.min())
    solves = {}
    for cascade in ("local", "global"):
        eq = equilibrium(operator, height, d, Start(contact=start.contact, pressure=start.pressure, detach=forced),
                         critical=critical, settings=Settings(cascade=cascade))
        assert eq.converged, eq.reason
        contact = eq.contact
        gap = tip_deflection(operator, eq.pressure) - (d - height)
        if contact.any():
            # No element of S beyond Sigma_c; on S the tip touches the surface
            # (to the CG tolerance 1e-8 relative to the target |d - height| ~ 2e-3).
            assert float(eq.pressure[contact].min()) >= -critical
            assert float(np.abs(gap[contact]).max()) < 1e-9
        # No footprint element outside S penetrates.
        assert float(gap[indenter.footprint & ~contact].min()) > -1e-10
        solves[cascade] = eq.n_solves
    # The pillars peel in local rounds instead of global solves.
    assert solves["local"] < solves["global"]
    with pytest.raises(ValueError, match="cascade"):
        Settings(cascade="fast")
