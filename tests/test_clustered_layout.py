"""The clustered brush layout (thesis Fig. 6-3): sub-pillars on square lattices inside square clusters.

Units: E* = 1, L = 1, dgamma = 1e-4.  Geometry tests use `clustered_lattice`
alone (no grid); raster tests build brushes on N <= 1024 grids (tens of
milliseconds each); pull-offs use 4 x 4 sub-pillars on N = 64 (r1 = 3.5
elements, a fraction of a second each).
"""

from __future__ import annotations

import dataclasses
import math
import tomllib

import numpy as np
import pytest

import brushbem
from brushbem.runs.assembly import load_config, parse, parse_config
from brushbem.config import ConfigError, config_to_dict
from brushbem.protocol import ContactProblem, LoadPath, record_pull_off
from brushbem.physics.structure import (
    Grid,
    Indenter,
    Level,
    StructureError,
    brush,
    clustered_filling_factors,
    clustered_lattice,
    hierarchy_clusters,
)
from brushbem.studies.base import SWEEPS_DIR

E_STAR = 1.0
DGAMMA = 1.0e-4
RIGID = math.inf

# Three levels: 8 x 8 sub-pillars, 2 x 2 per level-2 cluster, 2 x 2 level-2 clusters per level-3
# cluster, 2 x 2 level-3 clusters in the domain.
PHI = (0.2, 0.4, 0.5)
CLUSTERS = (2, 2)


def _clustered(grid: Grid, *, pillars_per_side: int = 8, clusters=CLUSTERS, filling_factors=PHI,
               stiffness: float = RIGID, level_stiffness=None, **kwargs) -> Indenter:
    level_stiffness = level_stiffness or [RIGID] * len(clusters)
    return brush(grid, layout="clustered", pillars_per_side=pillars_per_side, filling_factors=filling_factors,
                 levels=tuple(Level(c, k) for c, k in zip(clusters, level_stiffness)), stiffness=stiffness,
                 contact_modulus=E_STAR, work_of_adhesion=DGAMMA, **kwargs)


# -- geometry ------------------------------------------------------------------------------


def test_positions_form_square_clusters_with_the_stated_gaps():
    lat = clustered_lattice(8, CLUSTERS, PHI, 1.0)
    r1 = lat.pillar_radius
    (s2, s3), (p1, p2, p3) = lat.sides, lat.pitches
    two_w, two_d2, two_d3 = lat.gaps
    # The construction: top clusters tile the domain (2 per side), each cluster holds the units of the
    # level below centred in the cells of its own lattice.
    assert p3 == pytest.approx(0.5) and s3 == pytest.approx(p3 * math.sqrt(PHI[2]))
    assert p2 == pytest.approx(s3 / 2) and s2 == pytest.approx(p2 * math.sqrt(PHI[1]))
    assert p1 == pytest.approx(s2 / 2) and two_w == pytest.approx(p1 - 2 * r1)
    assert two_d2 == pytest.approx(p2 - s2) and two_d3 == pytest.approx(p3 - s3)
    assert min(two_w, two_d2, two_d3) > 0
    # The filling factors they realise, by their definitions.
    assert math.pi * r1**2 * 2**2 / s2**2 == pytest.approx(PHI[0], rel=1e-12, abs=0.0)
    assert 2**2 * s2**2 / s3**2 == pytest.approx(PHI[1], rel=1e-12, abs=0.0)
    assert 2**2 * s3**2 / 1.0**2 == pytest.approx(PHI[2], rel=1e-12, abs=0.0)
    # Along each axis (the layout is the product of two identical 1-D layouts): neighbours in a
    # level-2 cluster are one sub-pitch 2 r1 + 2 w apart; across a level-2 cluster boundary the
    # gap 2D2 is added (half-cell margins w on each side); across a level-3 boundary also 2D3.
    for axis in (0, 1):
        steps = np.diff(np.unique(lat.centres[:, axis]))
        expected = [p1, p1 + two_d2, p1, p1 + two_d2 + two_d3, p1, p1 + two_d2, p1]
        np.testing.assert_allclose(steps, expected, rtol=1e-12)
    np.testing.assert_allclose(lat.centres.mean(axis=0), 0.0, atol=1e-15)  # centred on the domain
    # The sub-pillars are in lattice order, as square_lattice's.
    assert np.array_equal(lat.index[:, 0] * 8 + lat.index[:, 1], np.arange(64))


@pytest.mark.parametrize(("n", "clusters", "phi"), [(8, (4,), (0.3, 0.6)), (8, CLUSTERS, PHI), (12, (3, 2), PHI)])
def test_every_cluster_holds_its_units_inside_its_square(n, clusters, phi):
    lat = clustered_lattice(n, clusters, phi, 1.0)
    maps = hierarchy_clusters(lat.index, n, clusters)
    units, unit_half = lat.centres, lat.pillar_radius  # the units of the level below: disks, then squares
    for level, (cluster, squares, side) in enumerate(zip(maps, lat.square_centres, lat.sides)):
        per_side = clusters[level]
        below = cluster if level == 0 else maps[level][np.unique(maps[level - 1], return_index=True)[1]]
        assert len(squares) == (n // int(np.prod(clusters[: level + 1]))) ** 2
        for k, centre in enumerate(squares):
            members = units[below == k]
            assert len(members) == per_side**2
            np.testing.assert_allclose(members.mean(axis=0), centre, atol=1e-15)  # centred in the square
            # Inside it, with the half-gap of the level below as margin.
            margin = 0.5 * lat.gaps[level]
            np.testing.assert_allclose(np.abs(members - centre).max(axis=0) + unit_half + margin, 0.5 * side,
                                       rtol=1e-12)
        units, unit_half = squares, 0.5 * side
    # The top clusters tile the region, with the half-gap at its edges.
    np.testing.assert_allclose(np.abs(units).max(axis=0) + unit_half + 0.5 * lat.gaps[-1], 0.5, rtol=1e-12)


def test_the_thesis_brush_has_the_uniform_lattices_radius_and_narrow_cluster_gaps():
    """40 x 40 sub-pillars, clusters 5 and 4, phi = 0.12, 0.45, 0.45 (sec. 6.2)."""
    lat = clustered_lattice(40, (5, 4), (0.12, 0.45, 0.45), 1.0)
    # r1 = (L / 40) sqrt(phi / pi): the radius of the uniform 40 x 40 lattice of hierarchy.three.toml.
    assert lat.pillar_radius == pytest.approx(0.00219871, rel=1e-6)
    assert lat.sides == pytest.approx((0.05625, 0.5 * math.sqrt(0.45)))
    r2, r3 = 0.5 * lat.sides[0], 0.5 * lat.sides[1]
    w, d2, d3 = (0.5 * g for g in lat.gaps)
    # Fig. 6-3's r1 <= w holds (phi1 <= pi / 16); its r2 <= D cannot with phi2 = 0.45 (needs <= 1/4):
    # D = r (1 / sqrt(phi) - 1) = 0.49 r at both cluster levels.
    assert w / lat.pillar_radius == pytest.approx(math.sqrt(math.pi / 0.12) / 2 - 1)
    assert w / lat.pillar_radius > 1
    assert d2 / r2 == pytest.approx(1 / math.sqrt(0.45) - 1)
    assert d3 / r3 == pytest.approx(1 / math.sqrt(0.45) - 1)
    assert d2 / r2 == pytest.approx(0.4907, abs=1e-4)
    assert d2 / r2 < 1


# -- filling factors on the raster -------------------------------------------------------------


def test_measured_filling_factors_match_the_nominal_within_the_raster_bound():
    """phi1 (sub-pillars' elements over the level-2 squares) lies within the staircase bound, halved per refinement.

    An element belongs to a disk of radius r when its centre lies inside, so the elements of a disk
    cover an area in [pi (r - h/sqrt 2)^2, pi (r + h/sqrt 2)^2] (h/sqrt 2: half an element's diagonal).
    That bounds every sub-pillar's footprint and so their sum: phi1 measured / phi1 lies in
    [(1 - h/(sqrt 2 r))^2, (1 + h/(sqrt 2 r))^2], a band of width ~ 2 sqrt 2 h / r that halves when
    N doubles.  The squares of the clusters are exact (not rasterised), so phi2 and phi3 are the
    nominal ones to rounding, and the product is the brush's rasterised filling factor A / A0.
    """
    widths = []
    for elements in (256, 512, 1024, 2048):
        grid = Grid(1.0, elements)
        info = _clustered(grid).description
        rho = info.pillar_radius / grid.element_size  # r1 in elements: 3.6 at N = 256
        low, high = (1 - 1 / (math.sqrt(2) * rho)) ** 2, (1 + 1 / (math.sqrt(2) * rho)) ** 2
        footprints = info.pillar_elements * grid.element_size**2 / (math.pi * info.pillar_radius**2)
        assert low <= footprints.min() and footprints.max() <= high, elements
        phi1, phi2, phi3 = info.level_filling_factors
        assert low <= phi1 / PHI[0] <= high, elements
        assert (phi2, phi3) == pytest.approx(PHI[1:], rel=1e-12, abs=0.0)
        assert info.nominal_level_filling_factors == PHI
        assert phi1 * phi2 * phi3 == pytest.approx(info.filling_factor, rel=1e-12, abs=0.0)
        widths.append(high - low)
    assert all(fine < 0.55 * coarse for coarse, fine in zip(widths, widths[1:]))  # ~ 1/N
    # The worst case assumes every disk errs the same way; 64 disks at different sub-element offsets
    # mostly cancel (measured: under 0.6 % from N = 256 on, against a band of +-10 % at N = 1024).
    assert phi1 == pytest.approx(PHI[0], rel=0.01)


def test_the_measure_reads_any_raster_of_the_lattice():
    lat = clustered_lattice(8, CLUSTERS, PHI, 1.0)
    grid = Grid(1.0, 512)
    indenter = _clustered(grid)
    info = indenter.description
    assert clustered_filling_factors(grid, indenter.pillar, lat) == info.level_filling_factors
    assert info.cluster_sides == lat.sides
    np.testing.assert_array_equal(info.centres, lat.centres)
    # A raster without any sub-pillar has phi1 = 0; the higher levels are the squares'.
    empty = np.full((512, 512), -1)
    assert clustered_filling_factors(grid, empty, lat) == pytest.approx((0.0, *PHI[1:]))


def test_the_other_layouts_report_no_level_filling_factors():
    info = brush(Grid(1.0, 64), layout="square", pillars_per_side=2, pillar_radius=0.1, contact_modulus=E_STAR,
                 work_of_adhesion=DGAMMA).description
    assert info.level_filling_factors == info.nominal_level_filling_factors == info.cluster_sides == ()


# -- membership ----------------------------------------------------------------------------------


def test_membership_maps_group_each_clusters_sub_pillars():
    grid = Grid(1.0, 256)
    indenter = _clustered(grid, stiffness=1e-3, level_stiffness=[9e-3, 2e-2])
    lat = clustered_lattice(8, CLUSTERS, PHI, 1.0)
    assert [level.n_clusters for level in indenter.levels] == [64, 16, 4]
    # The same block structure as the uniform lattice's hierarchy: only the positions differ.
    uniform = brush(grid, layout="square", pillars_per_side=8, pillar_radius=0.02, contact_modulus=E_STAR,
                    work_of_adhesion=DGAMMA, stiffness=1e-3, levels=(Level(2, 9e-3), Level(2, 2e-2)))
    for ours, theirs in zip(indenter.levels, uniform.levels):
        np.testing.assert_array_equal(ours.cluster, theirs.cluster)
    # Every element of a cluster lies inside that cluster's square (and each cluster has elements).
    x = grid.centres()
    rows, cols = np.nonzero(indenter.footprint)
    for level, squares, side in zip(indenter.levels[1:], lat.square_centres, lat.sides):
        owner = indenter.element_clusters(level)[rows, cols]
        assert np.array_equal(np.unique(owner), np.arange(len(squares)))
        assert np.all(np.abs(x[rows] - squares[owner, 0]) <= 0.5 * side)
        assert np.all(np.abs(x[cols] - squares[owner, 1]) <= 0.5 * side)


# -- pull-off ----------------------------------------------------------------------------------------


def _adhesive_force(grid: Grid, indenter: Indenter, preload: float = 2e-3) -> float:
    problem = ContactProblem(grid, indenter, contact_modulus=E_STAR, work_of_adhesion=DGAMMA)
    record = record_pull_off(problem, LoadPath(preload_displacement=preload))
    assert record.summary["converged"], record.summary["reason"]
    return record.summary["adhesive_force"]


def test_a_rigid_clustered_brush_pulls_off_as_a_rigid_single_level_brush():
    """Hierarchy does nothing when rigid (thesis sec. 6.2): the same footprints on one rigid base."""
    grid = Grid(1.0, 64)
    clustered = _clustered(grid, pillars_per_side=4, clusters=(2,), filling_factors=(0.3, 0.5))
    single = Indenter(height=clustered.height, pillar=clustered.pillar)  # the same positions, no levels
    force = _adhesive_force(grid, clustered)
    assert force > 0
    assert force == pytest.approx(_adhesive_force(grid, single), rel=1e-12)
    # Elastic sub-pillars on rigid clusters: the clusters' level adds nothing either.
    soft = _clustered(grid, pillars_per_side=4, clusters=(2,), filling_factors=(0.3, 0.5), stiffness=0.05)
    assert _adhesive_force(grid, soft) == pytest.approx(
        _adhesive_force(grid, dataclasses.replace(soft, levels=soft.levels[:1])), rel=1e-12)


# -- bad inputs --------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("change", "key", "words"),
    [
        ({"filling_factors": (0.2, 0.4)}, "filling_factors", "must hold 3 values"),
        ({"filling_factors": (0.2, 0.4, 1.0)}, "filling_factors", "phi3 = 1 must lie in (0, 1)"),
        ({"filling_factors": (0.0, 0.4, 0.5)}, "filling_factors", "phi1 = 0 must lie in (0, 1)"),
        ({"filling_factors": (math.nan, 0.4, 0.5)}, "filling_factors", "must lie in (0, 1)"),
        ({"filling_factors": (0.8, 0.4, 0.5)}, "filling_factors", "overlap or touch"),
        ({"filling_factors": (0.01, 0.4, 0.5)}, "filling_factors", "under 2 elements"),  # r1 = 0.8 h
        ({"pillars_per_side": 6}, "pillars_per_side", "multiple of 4"),
        ({"clusters": ()}, "levels", "at least one level"),
        ({"pillar_radius": 0.01}, "pillar_radius", "derives it from filling_factors"),
        ({"region": "circle"}, "region", "square region"),
        ({"filling_factors": None}, "filling_factors", "required"),
    ],
)
def test_bad_clustered_input_names_the_key(change, key, words):
    change = dict(change)
    args = {"pillars_per_side": change.pop("pillars_per_side", 8), "clusters": change.pop("clusters", CLUSTERS),
            "filling_factors": change.pop("filling_factors", PHI)}
    with pytest.raises(StructureError) as error:
        _clustered(Grid(1.0, 256), **args, **change)
    assert error.value.key == key and words in error.value.allowed, str(error.value)


def test_filling_factors_belong_to_the_clustered_layout_only():
    with pytest.raises(StructureError, match="only used with layout = 'clustered'") as error:
        brush(Grid(1.0, 64), layout="square", pillars_per_side=2, pillar_radius=0.1, contact_modulus=E_STAR,
              work_of_adhesion=DGAMMA, filling_factors=(0.3, 0.5))
    assert error.value.key == "filling_factors"
    with pytest.raises(StructureError, match="required with layout = 'square'"):
        brush(Grid(1.0, 64), layout="square", pillars_per_side=2, contact_modulus=E_STAR, work_of_adhesion=DGAMMA)


# -- configuration -------------------------------------------------------------------------------------


CONFIG = """\
[halfspace]
contact_modulus = 1.0
work_of_adhesion = 1e-4

[grid]
size = 1.0
elements = 64

[indenter]
shape = "brush"
layout = "clustered"
pillars_per_side = 4
filling_factors = [0.3, 0.5]     # sub-pillars in a cluster, clusters in the domain
stiffness_ratio = 0.05

[[indenter.levels]]
cluster = 2
stiffness_ratio = 0.05

[protocol]
preload_displacement = 2e-3
"""


def _document(**indenter) -> dict:
    document = tomllib.loads(CONFIG)
    for key, value in indenter.items():
        if value is None:
            document["indenter"].pop(key, None)
        else:
            document["indenter"][key] = value
    return document


def test_a_clustered_config_validates_round_trips_and_runs(tmp_path):
    path = tmp_path / "clustered.toml"
    path.write_text(CONFIG)
    config = load_config(path)
    assert config.indenter.layout == "clustered" and config.indenter.filling_factors == (0.3, 0.5)
    assert config.indenter.pillar_radius is None
    assert parse_config(config_to_dict(config)) == config
    indenter = parse(_document()).problem.indenter
    assert indenter.description.nominal_level_filling_factors == (0.3, 0.5)
    assert [level.stiffness for level in indenter.levels] == pytest.approx([0.05, 0.05])
    result = brushbem.run(path)
    assert result.converged and result.adhesive_force > 0
    # The file builds the brush the Python API builds.
    grid = Grid(1.0, 64)
    built = brush(grid, layout="clustered", pillars_per_side=4, filling_factors=(0.3, 0.5), stiffness=0.05,
                  levels=(Level(2, 0.05),), contact_modulus=E_STAR, work_of_adhesion=DGAMMA)
    direct = brushbem.pull_off(grid, built, contact_modulus=E_STAR, work_of_adhesion=DGAMMA,
                               preload_displacement=2e-3)
    assert direct.adhesive_force == pytest.approx(result.adhesive_force, rel=1e-12, abs=0.0)


@pytest.mark.parametrize(
    ("change", "key"),
    [
        ({"pillar_radius": 0.05}, "indenter.pillar_radius"),       # derived from the filling factors
        ({"filling_factors": [0.3]}, "indenter.filling_factors"),  # one per level: 2
        ({"filling_factors": [0.3, 1.2]}, "indenter.filling_factors"),
        ({"filling_factors": "0.3"}, "indenter.filling_factors"),
        ({"filling_factors": [0.9, 0.5]}, "indenter.filling_factors"),  # sub-pillars overlap
        ({"filling_factors": None}, "indenter.filling_factors"),
        ({"levels": None}, "indenter.levels"),
        ({"levels": []}, "indenter.levels"),
        ({"pillars_per_side": 5}, "indenter.pillars_per_side"),
        ({"region": "circle"}, "indenter.region"),
        ({"spacing": 0.2}, "indenter.spacing"),
        ({"layout": "square"}, "indenter.filling_factors"),        # and pillar_radius missing
        ({"layout": "square", "filling_factors": None}, "indenter.pillar_radius"),
    ],
)
def test_bad_clustered_config_names_the_key(change, key):
    with pytest.raises(ConfigError) as error:
        parse_config(_document(**change))
    assert any(line.startswith(f"`{key}`") for line in error.value.problems), error.value.problems


def test_the_clustered_parts_share_the_sub_pillars_and_differ_only_in_the_springs():
    """hierarchy.clustered_{one,two,three}(.quick).toml: the ch. 6 brushes in the Fig. 6-3 layout.

    One, two and three levels keep the same positions, radius, points and seeds (so the same drawn
    lengths); one level makes the clusters' springs rigid, two the level-3 springs.
    """
    from brushbem.sweep.spec import load_sweep

    files = {name: tomllib.loads((SWEEPS_DIR / f"hierarchy.clustered_{name}.toml").read_text(encoding="utf-8"))
             for name in ("one", "two", "three")}
    for name in files:
        assert load_sweep(SWEEPS_DIR / f"hierarchy.clustered_{name}.quick.toml").cases  # every case validates
    bases = {name: dict(f["base"]["indenter"]) for name, f in files.items()}
    levels = {name: base.pop("levels") for name, base in bases.items()}
    assert bases["one"] == bases["two"] == bases["three"]
    assert (bases["one"]["pillars_per_side"], bases["one"]["filling_factors"]) == (40, [0.12, 0.45, 0.45])
    assert [lv.get("stiffness_ratio", lv.get("stiffness")) for lv in levels["one"]] == [math.inf, math.inf]
    assert [lv.get("stiffness_ratio", lv.get("stiffness")) for lv in levels["two"]] == [9e-3, math.inf]
    assert [lv.get("stiffness_ratio", lv.get("stiffness")) for lv in levels["three"]] == [9e-3, 2e-2]
    # two levels add the plateau on N = 1536 (their set mesh: the level tie's second grid); on the base grid
    # N = 1024 they sweep one level's points
    two = files["two"]["sweep"]
    on_base = [i for i, n in enumerate(two["grid.elements"]) if n == 1024]
    assert {key: [values[i] for i in on_base] for key, values in two.items() if key != "grid.elements"} \
        == files["one"]["sweep"]
    assert isinstance(parse_config(files["three"]["base"]), brushbem.RunConfig)  # builds at N = 1024
