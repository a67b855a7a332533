"""Tip shapes, graded stiffness and a tilted base (thesis sec. 8.2, future work 1-2; misalignment).

Each feature is checked against the structure it must reduce to: a uniform
per-pillar stiffness is today's brush, a spherical-cap pillar alone is the
sphere on a spring of ch. 2, a very flat cap or a very shallow dish is the
flat pillar, zero tilt is no tilt.  Brushes with a tilt, a gradient or
curved tips are also run through the fast brush path and the element-event
path in `tests/test_brush_paths.py`.  Grids are quick grids: they test the
machinery, not a thesis number.
"""

from __future__ import annotations

import math
import textwrap

import numpy as np
import pytest

from brushbem.runs.assembly import load
from brushbem.config import ConfigError
from brushbem.protocol import ContactProblem, LoadPath, record_pull_off
from brushbem.physics.structure import (
    Grading,
    Grid,
    Level,
    StructureError,
    Tilt,
    Tip,
    brush,
    sphere,
)

GRID = Grid(1.0, 64)
PER_SIDE = 4
RADIUS = math.sqrt(0.16 / math.pi) / PER_SIDE  # phi = 0.16, 3.6 elements at N = 64
DGAMMA = 1e-4


def _brush(grid: Grid = GRID, **extra):
    spec = {"layout": "square", "pillars_per_side": PER_SIDE, "pillar_radius": RADIUS, "contact_modulus": 1.0,
                "work_of_adhesion": DGAMMA, "stiffness": 0.05}
    spec.update(extra)
    return brush(grid, **spec)


def _pull_off(indenter, grid: Grid = GRID, dgamma: float = DGAMMA, **path):
    problem = ContactProblem(grid, indenter, contact_modulus=1.0, work_of_adhesion=dgamma)
    spec = {"method": "events", "preload_displacement": indenter.lowest_height + 0.004, "max_steps": 10**6}
    spec.update(path)
    record = record_pull_off(problem, LoadPath(**spec))
    assert record.summary["converged"], record.summary["reason"]
    return record


def _same_history(a, b) -> None:
    """The same states, displacements and attached pillars, number for number."""
    assert np.array_equal(a.curve.attached_pillars, b.curve.attached_pillars)
    np.testing.assert_allclose(a.curve.displacement, b.curve.displacement, rtol=1e-10, atol=1e-16)


# -- per-pillar stiffness -------------------------------------------------------


def test_uniform_per_pillar_stiffness_is_todays_brush():
    """An array of equal stiffnesses (and a grading of unit factors) gives today's brush to 1e-10.

    The springs then hold one compliance per cluster where they held one per
    level; every product is the same, so the runs agree to rounding (1e-10 is
    far above it and far below any physical effect).
    """
    base = _pull_off(_brush(roughness=0.002, seed=4))
    arrays = _pull_off(_brush(roughness=0.002, seed=4, stiffness=np.full(PER_SIDE**2, 0.05)))
    factors = _pull_off(_brush(roughness=0.002, seed=4, grading=Grading("factors", factors=np.ones(PER_SIDE**2))))
    for other in (arrays, factors):
        for key in ("adhesive_force", "work_of_separation", "preload_force"):
            assert other.summary[key] == pytest.approx(base.summary[key], rel=1e-10, abs=0.0)
        _same_history(base, other)


def test_a_uniform_hierarchy_level_given_per_cluster_is_todays():
    grid = Grid(1.0, 64)
    base = _pull_off(_brush(grid, levels=(Level(2, 0.02),)), grid)
    arrays = _pull_off(_brush(grid, levels=(Level(2, np.full(4, 0.02)),)), grid)
    assert arrays.summary["adhesive_force"] == pytest.approx(base.summary["adhesive_force"], rel=1e-10, abs=0.0)
    assert arrays.summary["work_of_separation"] == pytest.approx(base.summary["work_of_separation"], rel=1e-10, abs=0.0)
    _same_history(base, arrays)


def test_per_pillar_stiffness_acts_pillar_by_pillar():
    """A pillar made rigid-like among soft ones carries more of the preload than its soft twin.

    Pressed without adhesion, the force of every pillar is its spring's force:
    at the same tip height a stiffer spring carries more.  The two diagonal
    corner pillars of the 4 x 4 brush are symmetric in everything but their
    stiffness.
    """
    k = np.full(PER_SIDE**2, 0.01)
    k[0] = 1.0  # one corner stiff, the opposite corner (15) soft
    indenter = _brush(stiffness=k)
    problem = ContactProblem(GRID, indenter, contact_modulus=1.0, work_of_adhesion=0.0)
    record = record_pull_off(problem, LoadPath(method="events", preload_displacement=0.004))
    preload = next(s for s in record.snapshots if s.name == "max_preload")
    forces = preload.pillar_force
    assert forces[0] > 1.5 * forces[-1] > 0


def test_grading_rules():
    centres = np.array([[0.0, 0.0], [0.0, 0.5], [0.0, -1.0], [1.0, 0.0]])
    radial = Grading("radial", -0.5, 2.0).apply(2.0, centres, "grading")
    np.testing.assert_allclose(radial, 2.0 * (1 - 0.5 * np.array([0.0, 0.25, 1.0, 1.0])))
    linear = Grading("linear", 0.5).apply(2.0, centres, "grading")
    np.testing.assert_allclose(linear, 2.0 * (1 + 0.5 * np.array([0.0, 0.5, -1.0, 0.0])))
    with pytest.raises(StructureError, match="grading.amplitude"):
        Grading("radial", -1.0).apply(1.0, centres, "grading")
    with pytest.raises(StructureError, match="grading.amplitude"):
        Grading("linear", 1.2).apply(1.0, centres, "grading")
    with pytest.raises(StructureError, match="grading.file"):
        Grading("factors", factors=np.array([1.0, -1.0, 1.0, 1.0])).apply(1.0, centres, "grading")


def test_a_grading_that_can_have_no_effect_is_refused_by_key():
    """A rigid level stays rigid, one spring has nothing to be graded against, and springs that all
    lie at s = 0 keep factor 1: each refused, naming the grading's key, instead of doing nothing."""
    centres = np.array([[0.0, 0.0], [0.0, 0.5], [0.0, -1.0], [1.0, 0.0]])
    with pytest.raises(StructureError, match="rigid") as info:
        Grading("radial", 0.5).apply(math.inf, centres, "levels.1.grading")
    assert info.value.key == "levels.1.grading" and info.value.value["rule"] == "radial"
    with pytest.raises(StructureError, match="one spring"):
        Grading("linear", 0.5).apply(1.0, centres[:1] + 0.3, "grading")
    with pytest.raises(StructureError, match="s = 0"):  # a linear rule along x over centres on the y axis
        Grading("linear", 0.5).apply(1.0, np.array([[-1.0, 0.0], [1.0, 0.0]]), "grading")
    with pytest.raises(StructureError, match="rounding"):
        Grading("radial", 1e-20).apply(1.0, centres, "grading")
    # An amplitude of 0 is a baseline a sweep may hold on purpose, and a factors file scales one spring.
    np.testing.assert_allclose(Grading("radial", 0.0).apply(2.0, centres, "grading"), 2.0)
    np.testing.assert_allclose(Grading("factors", factors=np.array([3.0])).apply(2.0, centres[:1], "grading"), 6.0)
    with pytest.raises(StructureError, match="grading"):
        _brush(pillars_per_side=1, pillar_radius=0.1, grading=Grading("radial", -0.5))
    with pytest.raises(StructureError) as info:
        _brush(levels=(Level(4, 0.02, Grading("radial", 0.5)),))
    assert info.value.key == "levels.0.grading"


def test_discriminant_coupling_refuses_a_graded_level():
    with pytest.raises(ValueError, match="segments"):
        from brushbem.physics.halfspace import HalfSpace
        from brushbem.numerics.operator import ContactOperator, Window

        indenter = _brush(grading=Grading("radial", -0.5))
        ContactOperator(HalfSpace(64, GRID.element_size, 1.0), indenter, Window.full(64), "discriminant")


# -- tip shapes ------------------------------------------------------------------


def test_one_spherical_cap_pillar_is_the_sphere_on_a_spring():
    """A one-pillar brush with a spherical cap is today's sphere on the same spring (JKR on a spring).

    The cap is the sphere's paraboloid on the pillar's footprint, which is wider
    than any contact of the run, so the discrete problems are the same: F_A,
    the work of separation and the contact radius agree to the solver's
    tolerance (1e-6 relative covers the CG tolerance 1e-8 on different window
    sizes).
    """
    grid = Grid(1.0, 96)
    radius, k, dgamma = 0.5, 0.5, 1e-3
    pillar = brush(grid, layout="square", pillars_per_side=1, pillar_radius=0.35, contact_modulus=1.0,
                   work_of_adhesion=dgamma, stiffness=k, tip=Tip("spherical_cap", radius=radius))
    assert pillar.description.tip == "spherical_cap(radius=0.5)"
    reference = _pull_off(sphere(grid, radius, k), grid, dgamma, preload_displacement=0.01)
    cap = _pull_off(pillar, grid, dgamma, preload_displacement=0.01)
    # The footprint's edge (r = 0.35) is never reached: the largest contact is a disc of r < 0.3.
    assert math.sqrt(float(np.max(cap.curve.contact_area)) / math.pi) < 0.3
    for key in ("adhesive_force", "work_of_separation", "pull_off_displacement"):
        assert cap.summary[key] == pytest.approx(reference.summary[key], rel=1e-6)


@pytest.mark.parametrize("shape", ["spherical_cap", "concave"])
def test_nearly_flat_tips_approach_the_flat_pillar(shape):
    """A cap of growing radius (a dish of shrinking depth) approaches the flat brush; the error shrinks with the curvature.

    The tip's height range r^2/(2R) (or the depth) goes 1e-3, 1e-5, 1e-7 of
    the pillar radius; F_A's difference from the flat brush must fall with
    it and be below 1e-4 at the last.
    """
    flat = _pull_off(_brush()).summary["adhesive_force"]
    errors = []
    for rise in (1e-3, 1e-5, 1e-7):
        drop = rise * RADIUS
        tip = Tip("spherical_cap", radius=RADIUS**2 / (2 * drop)) if shape == "spherical_cap" else Tip(
            "concave", depth=drop)
        errors.append(abs(_pull_off(_brush(tip=tip)).summary["adhesive_force"] / flat - 1))
    assert errors[1] < errors[0] and errors[2] <= errors[1] + 1e-12
    assert errors[-1] < 1e-4


def test_tip_profiles_from_a_function_or_an_array():
    """A profile function equal to the cap gives the cap's heights; an array is interpolated linearly."""
    cap = Tip("spherical_cap", radius=0.3)
    function = Tip("profile", profile=lambda rho: rho**2 / 0.6)
    a, b = _brush(tip=cap), _brush(tip=function)
    np.testing.assert_allclose(a.height, b.height, rtol=1e-14)
    samples = Tip("profile", profile=np.linspace(0.0, RADIUS, 2))  # z = rho (a cone)
    cone = _brush(tip=samples)
    rows, cols = np.nonzero(cone.pillar == 0)
    x = GRID.centres()
    centre = cone.description.centres[0]
    rho = np.hypot(x[rows] - centre[0], x[cols] - centre[1])
    np.testing.assert_allclose(cone.height[rows, cols] - cone.description.offsets[0], rho, rtol=1e-12)


def test_tips_per_pillar():
    tips = [Tip("flat")] * (PER_SIDE**2 - 1) + [Tip("concave", depth=1e-3)]
    indenter = _brush(tip=tips)
    assert indenter.description.tip == "per pillar"
    flat = _brush()
    last = indenter.pillar == PER_SIDE**2 - 1
    assert np.array_equal(indenter.height[~last], flat.height[~last])
    assert float(indenter.height[last].max()) > 0.5e-3
    with pytest.raises(StructureError, match="one per pillar"):
        _brush(tip=[Tip("flat")] * 3)


@pytest.mark.parametrize("kwargs, key", [
    ({"shape": "spherical_cap", "radius": -1.0}, "tip.radius"),
    ({"shape": "concave"}, "tip.depth"),
    ({"shape": "flat", "radius": 1.0}, "tip.radius"),
    ({"shape": "dome"}, "tip.shape"),
    ({"shape": "profile", "profile": [0.0, -1.0]}, "tip.profile"),
])
def test_bad_tips_are_refused_by_key(kwargs, key):
    with pytest.raises(StructureError, match=key.replace(".", r"\.")):
        Tip(**kwargs)


# -- tilt ------------------------------------------------------------------------


def test_zero_tilt_is_no_tilt():
    a, b = _brush(tilt=Tilt(0.0, 37.0)), _brush()
    assert np.array_equal(a.height, b.height)
    _same_history(_pull_off(a), _pull_off(b))


def test_a_tilt_is_a_plane_over_the_footprint():
    """Every tip element lies on the plane tan(angle) (x cos az + y sin az), shifted so the lowest is 0."""
    tilt = Tilt(1.0, 30.0)
    indenter = _brush(tilt=tilt)
    rows, cols = np.nonzero(indenter.footprint)
    x = GRID.centres()
    plane = tilt.heights(x[rows], x[cols])
    np.testing.assert_allclose(indenter.height[rows, cols], plane - plane.min(), atol=1e-15)
    assert indenter.lowest_height == 0.0
    assert indenter.description.tilt_angle == 1.0
    # The pillars along the azimuth recede: the tilt orders the offsets.
    centres, offsets = indenter.description.centres, indenter.description.offsets
    along = centres[:, 1] * math.cos(math.radians(30)) + centres[:, 0] * math.sin(math.radians(30))
    assert np.all(np.diff(offsets[np.argsort(along)]) > 0)


def test_a_tilted_brush_detaches_at_a_smaller_force():
    """Misalignment costs adhesion: a tilt of the order of the pillars' stretch at pull-off lowers F_A."""
    level = _pull_off(_brush(stiffness=1.0)).summary["adhesive_force"]
    tilted = _pull_off(_brush(stiffness=1.0, tilt=Tilt(0.3, 0.0)), preload_displacement=0.01)
    assert tilted.summary["adhesive_force"] < 0.95 * level
    with pytest.raises(StructureError, match=r"tilt\.angle"):
        Tilt(50.0)


# -- configuration ----------------------------------------------------------------


def _config(tmp_path, indenter_extra: str):
    text = textwrap.dedent("""
        [halfspace]
        contact_modulus = 1.0
        work_of_adhesion = 1e-4
        [grid]
        size = 1.0
        elements = 64
        [indenter]
        shape = "brush"
        layout = "square"
        pillars_per_side = 4
        pillar_radius = 0.05
        stiffness_ratio = 0.05
        """) + textwrap.dedent(indenter_extra) + textwrap.dedent("""
        [protocol]
        preload_displacement = 0.02
        """)
    path = tmp_path / "case.toml"
    path.write_text(text)
    return path


def test_config_builds_tips_tilt_and_grading(tmp_path):
    np.save(tmp_path / "radii.npy", np.linspace(0.5, 1.0, 16))  # JKR contacts of 2.9-4.5 elements
    np.save(tmp_path / "factors.npy", np.linspace(0.5, 1.5, 16))
    path = _config(tmp_path, """
        tip = {shape = "spherical_cap", radius = "radii.npy"}
        tilt = {angle = 0.5, azimuth = 90.0}
        grading = {rule = "file", file = "factors.npy"}
        [[indenter.levels]]
        cluster = 2
        stiffness_ratio = 0.1
        grading = {rule = "radial", amplitude = -0.5}
        """)
    indenter = load(path).problem.indenter
    assert indenter.description.tip == "per pillar"
    assert indenter.description.graded
    np.testing.assert_allclose(indenter.levels[0].stiffnesses, 0.05 * np.linspace(0.5, 1.5, 16))
    # The four clusters are symmetric about the centre: one radial distance, the rim value.
    np.testing.assert_allclose(indenter.levels[1].stiffnesses, 0.1 * 0.5)
    assert indenter.description.tilt_azimuth == 90.0


def test_config_reports_every_bad_new_key_at_once(tmp_path):
    path = _config(tmp_path, """
        tip = {shape = "spherical_cap", radius = -2.0}
        tilt = {angle = 60.0}
        grading = {rule = "radial", amplitude = -1.5}
        [[indenter.levels]]
        cluster = 2
        stiffness_ratio = 0.1
        grading = {rule = "linear", amplitude = 1.0}
        """)
    with pytest.raises(ConfigError) as info:
        load(path)
    message = str(info.value)
    for key in ("indenter.tip.radius", "indenter.tilt.angle", "indenter.grading.amplitude",
                "indenter.levels.0.grading.amplitude"):
        assert key in message, message


def test_config_refuses_a_discriminant_coupling_on_a_graded_brush(tmp_path):
    path = _config(tmp_path, """
        grading = {rule = "linear", amplitude = 0.5}
        [solver]
        coupling = "discriminant"
        """.replace("[solver]", "").replace('coupling = "discriminant"', ""))
    text = path.read_text() + '\n[solver]\ncoupling = "discriminant"\n'
    path.write_text(text)
    with pytest.raises(ConfigError, match="solver.coupling"):
        load(path)


def test_a_cap_too_small_for_the_grid_is_refused_like_a_sphere():
    """A spherical cap detaches as a JKR sphere of its radius: its pull-off contact needs 2 elements too
    (N = 64, R = 0.05: a = 0.6 elements, refused; N = 256: 2.5 elements, accepted)."""
    from brushbem.config import ConfigError

    from brushbem.runs.assembly import parse_config

    config = {"halfspace": {"contact_modulus": 1.0, "work_of_adhesion": 1e-4}, "grid": {"size": 1.0, "elements": 64},
              "indenter": {"shape": "brush", "layout": "square", "pillars_per_side": 1, "pillar_radius": 0.1,
                           "stiffness_ratio": 0.1, "tip": {"shape": "spherical_cap", "radius": 0.05}},
              "protocol": {"preload_displacement": 0.002}}
    with pytest.raises(ConfigError, match="indenter.tip.radius"):
        parse_config(config)
    parse_config({**config, "grid": {"size": 1.0, "elements": 256}})
