"""Nonlinear pillar connections (thesis sec. 8.2, 2): piecewise-linear laws, buckling, a tension cut-off.

Checks, each against an independent result:

* one piece of factor 1 is the linear spring, state for state;
* a flat punch on a three-piece law stays in full contact, where the
  half-space is a linear spring k_h: every state then solves the scalar
  equation F = k_h (d - s(F)), found here by bracketing (brentq) on the law;
* the piece iteration of a buckling brush ends on a consistent state: the
  same brush with every pillar's converged piece as a linear spring and its
  offset as a length, pressed by the ordinary contact solver, has the same
  pillar forces;
* a tension cut-off below Kendall's force breaks the punch at the cut-off;
* bad laws are refused by key.

Grids are quick grids (N = 64): they test the machinery.
"""

from __future__ import annotations

import dataclasses
import math
import textwrap

import numpy as np
import pytest
from scipy.optimize import brentq

from brushbem.runs.assembly import load
from brushbem.config import ConfigError
from brushbem.errors import ParameterError
from brushbem.physics.pillar_laws import PiecewiseLinear, law_path_problems
from brushbem.protocol import ContactProblem, LoadPath, indent, record_pull_off
from brushbem.physics.structure import Grid, SpringLevel, brush, elastic_connection_problems, flat_punch

GRID = Grid(1.0, 64)
RADIUS, STIFFNESS, DGAMMA = 0.2, 0.2, 1e-3
PATH = LoadPath(method="fixed", preload_displacement=0.02, step=5e-4)


def _punch(law=None, stiffness=STIFFNESS):
    return dataclasses.replace(flat_punch(GRID, RADIUS, stiffness), pillar_law=law)


def _record(indenter, dgamma=DGAMMA, path=PATH):
    record = record_pull_off(ContactProblem(GRID, indenter, contact_modulus=1.0, work_of_adhesion=dgamma), path)
    assert record.summary["converged"], record.summary["reason"]
    return record


def _brush(law=None, stiffness=0.05):
    indenter = brush(GRID, layout="square", pillars_per_side=4, pillar_radius=math.sqrt(0.16 / math.pi) / 4,
                     contact_modulus=1.0, work_of_adhesion=1e-4, stiffness=stiffness, roughness=1e-3, seed=5)
    return dataclasses.replace(indenter, pillar_law=law)


@pytest.mark.slow
def test_linear_laws_are_the_linear_spring():
    """One piece of factor 1 is the spring itself; pieces of factor 1 around breakpoints too, state for state.

    The flat brush is pressed by the same fixed steps both ways (level tips:
    no contact-problem loading), so the states must agree to rounding.
    """
    path = dataclasses.replace(PATH, preload_displacement=0.006)
    flat = brush(GRID, layout="square", pillars_per_side=4, pillar_radius=math.sqrt(0.16 / math.pi) / 4,
                 contact_modulus=1.0, work_of_adhesion=1e-4, stiffness=0.05)
    for indenter, dgamma in ((_punch(), DGAMMA), (flat, 1e-4)):
        linear = _record(indenter, dgamma, path)
        for law in (PiecewiseLinear(), PiecewiseLinear(forces=(-1e-4, 1e-4), factors=(1.0, 1.0, 1.0))):
            other = _record(dataclasses.replace(indenter, pillar_law=law), dgamma, path)
            for key in ("adhesive_force", "work_of_separation", "preload_force"):
                assert other.summary[key] == pytest.approx(linear.summary[key], rel=1e-9)
            np.testing.assert_allclose(other.curve.force, linear.curve.force, rtol=1e-9, atol=1e-15)


def test_law_pieces_compress_as_integrated():
    law = PiecewiseLinear(forces=(-0.005, 0.002), factors=(0.5, 1.0, 0.05))
    k = np.array([0.2])
    # s(F) is the integral of dF / (k f(F)) from 0: check against its pieces by hand.
    assert law.compression(np.array([0.001]), k)[0] == pytest.approx(0.001 / 0.2)
    assert law.compression(np.array([0.003]), k)[0] == pytest.approx(0.002 / 0.2 + 0.001 / 0.01)
    assert law.compression(np.array([-0.006]), k)[0] == pytest.approx(-0.005 / 0.2 - 0.001 / 0.1)
    # The affine form on each piece reproduces s(F) inside the piece.
    for force in (-0.02, -0.001, 0.0015, 0.01):
        piece = law.piece(np.array([force]))
        slope, offset = law.affine(piece, k)
        assert force / slope[0] + offset[0] == pytest.approx(law.compression(np.array([force]), k)[0], abs=1e-15)


@pytest.mark.slow
def test_a_punch_on_a_three_piece_law_solves_its_scalar_equation():
    """Softer in tension, linear around 0, buckled (5 % slope) beyond F = 0.002: F = k_h (d - s(F)) at every state.

    1e-7 covers the CG tolerance (1e-8) of k_h and of each state.
    """
    law = PiecewiseLinear(forces=(-0.005, 0.002), factors=(0.5, 1.0, 0.05))
    record = _record(_punch(law))
    rigid = ContactProblem(GRID, flat_punch(GRID, RADIUS), contact_modulus=1.0, work_of_adhesion=0.0)
    k_h = indent(rigid, 0.01).force / 0.01
    k = np.array([STIFFNESS])
    curve = record.curve
    full = curve.contact_area == curve.contact_area.max()
    assert full.sum() > 50
    for d, force in zip(curve.displacement[full], curve.force[full]):
        expected = brentq(lambda f, d=d: f - k_h * (d - law.compression(np.array([f]), k)[0]), -1.0, 1.0,
                          xtol=1e-14)
        assert force == pytest.approx(expected, rel=1e-7, abs=1e-12)
    # Buckled: the preload force stays near the buckling load instead of k_series d.
    assert record.summary["preload_force"] < 1.1 * 0.002 + 0.05 * STIFFNESS * 0.02
    # Kendall's force still decides the pull-off (the law only changes the stretch).
    assert record.summary["adhesive_force"] == pytest.approx(_record(_punch()).summary["adhesive_force"], rel=1e-7)


def test_the_piece_iteration_of_a_buckling_brush_ends_on_the_law():
    """The buckled brush's preload state equals the linear brush of its converged pieces (1e-7, CG tolerance).

    Pressed without adhesion beyond the buckling load of its pillars, every
    pillar ends on a piece; a brush whose springs are those pieces' slopes
    (k f_i) and whose tips are raised by their offsets b_i is linear, and the
    ordinary contact solver pressed to the same d must find the same forces.
    Also, the buckled pillars carry at most the buckling load plus the
    plateau's slope times their compression.
    """
    buckling = 4e-5
    law = PiecewiseLinear(forces=(buckling,), factors=(1.0, 0.02))
    indenter = _brush(law, stiffness=0.05)
    path = LoadPath(method="fixed", preload_displacement=0.004, step=2e-4)
    record = _record(indenter, 0.0, path)
    preload = next(s for s in record.snapshots if s.name == "max_preload")
    forces = preload.pillar_force
    pieces = law.piece(forces)
    assert pieces.min() == 0 and pieces.max() == 1  # some pillars buckled, some not
    stiffness, offsets = law.affine(pieces, np.full(forces.size, 0.05))
    labels = indenter.pillar
    height = np.where(labels >= 0, indenter.height + offsets[np.maximum(labels, 0)], np.inf)
    linear = dataclasses.replace(indenter, height=height, pillar_law=None,
                                 levels=(SpringLevel(stiffness, indenter.levels[0].cluster),))
    problem = ContactProblem(GRID, linear, contact_modulus=1.0, work_of_adhesion=0.0)
    state = indent(problem, path.preload_displacement)
    reference = GRID.element_size**2 * np.bincount(
        labels[state.contact & (labels >= 0)], weights=state.pressure[state.contact & (labels >= 0)],
        minlength=forces.size)
    np.testing.assert_allclose(forces, reference, rtol=1e-7, atol=1e-7 * np.abs(forces).max())
    assert forces.max() < buckling + 0.02 * 0.05 * path.preload_displacement


def test_a_tension_cut_off_breaks_the_punch_at_the_cut_off():
    """A cut-off at half Kendall's force (N = 32, coarse steps of 2e-3): the break is located inside its step.

    Below Kendall's force the punch stays in full contact, so the force is
    affine in d on one contact set until the break: the break lies where
    the tension equals the limit (F_A = limit to the CG tolerance; before,
    0.994 x the limit), and the tensile work is the triangle limit^2 / (2 k)
    of that line's slope k, the same at steps 2e-3 and 2e-4 (before, a step
    added |F| x step past the break).
    """
    grid = Grid(1.0, 32)
    kendall = 1.5 * 0.2 * math.sqrt(8 * math.pi * DGAMMA * 0.2)  # F_K = sqrt(8 pi E* dgamma a^3), E* = 1
    limit = 0.5 * kendall

    def run(step):
        indenter = dataclasses.replace(flat_punch(grid, RADIUS, STIFFNESS), pillar_law=PiecewiseLinear(
            tension_limit=limit))
        path = LoadPath(method="fixed", preload_displacement=0.02, step=step)
        return record_pull_off(ContactProblem(grid, indenter, contact_modulus=1.0, work_of_adhesion=DGAMMA), path)

    coarse, fine = run(2e-3), run(2e-4)
    for record in (coarse, fine):
        assert record.summary["adhesive_force"] == pytest.approx(limit, rel=1e-7)
        assert record.curve.contact_area[-1] == 0.0
    curve = fine.curve
    tensile = ~curve.loading & (curve.force < 0) & (curve.contact_area > 0)
    slope = np.polyfit(curve.displacement[tensile], curve.force[tensile], 1)[0]
    assert coarse.summary["work_of_separation"] == pytest.approx(limit**2 / (2 * slope), rel=1e-6)
    assert coarse.summary["work_of_separation"] == pytest.approx(fine.summary["work_of_separation"], rel=1e-7)


def test_a_brush_breaks_pillar_by_pillar():
    law = PiecewiseLinear(tension_limit=2e-5)
    record = _record(_brush(law, stiffness=0.05), 1e-4, LoadPath(method="fixed", preload_displacement=0.004,
                                                                  step=2e-4))
    attached = record.curve.attached_pillars[~record.curve.loading]
    assert np.all(np.diff(attached) <= 0) and attached[-1] == 0
    assert record.summary["adhesive_force"] <= 16 * 2e-5 * (1 + 1e-9)


@pytest.mark.parametrize("kwargs, message", [
    ({"forces": (0.1, 0.05), "factors": (1, 1, 1)}, "strictly increasing"),
    ({"forces": (0.1,), "factors": (1.0,)}, "2 pieces"),
    ({"forces": (0.1,), "factors": (1.0, -0.1)}, "monotone"),
    ({"tension_limit": -1.0}, "tension_limit"),
])
def test_bad_laws_are_refused(kwargs, message):
    with pytest.raises(ValueError, match=message):
        PiecewiseLinear(**kwargs)


def test_laws_need_fixed_steps_and_a_stiffness():
    with pytest.raises(ValueError, match="method = 'fixed'"):
        record_pull_off(ContactProblem(GRID, _punch(PiecewiseLinear()), contact_modulus=1.0, work_of_adhesion=DGAMMA),
                        LoadPath(method="events", preload_displacement=0.01))
    with pytest.raises(ValueError, match="must be finite with Indenter.pillar_law"):
        _punch(PiecewiseLinear(), stiffness=math.inf)


def test_the_rigid_pillar_rule_has_one_home():
    """The indenter and the path rule (what the configuration names by key) refuse a rigid pillar under a law
    with the one problem of `elastic_connection_problems`: the same owner, parameter and words."""
    law = PiecewiseLinear()
    [expected] = elastic_connection_problems(math.inf, viscoelastic=False, pillar_law=law)
    assert (expected.owner, expected.parameter) == ("Indenter", "levels")
    assert law_path_problems(law, method="fixed", preload_displacement=0.01, viscoelastic=False,
                             stiffness=math.inf) == [expected]
    with pytest.raises(ParameterError) as refused:
        _punch(law, stiffness=math.inf)
    assert (refused.value.owner, refused.value.parameter, refused.value.message) == (
        expected.owner, expected.parameter, expected.message)
    assert elastic_connection_problems(STIFFNESS, viscoelastic=True, pillar_law=law) == []


def test_config_names_a_non_monotone_law(tmp_path):
    path = tmp_path / "case.toml"
    path.write_text(textwrap.dedent("""
        [halfspace]
        contact_modulus = 1.0
        work_of_adhesion = 1e-3
        [grid]
        size = 1.0
        elements = 64
        [indenter]
        shape = "flat_punch"
        radius = 0.2
        stiffness = 0.2
        pillar_law = {forces = [0.002, 0.001], factors = [1.0, -0.5]}
        [protocol]
        preload_displacement = 0.01
        """))
    with pytest.raises(ConfigError) as info:
        load(path)
    message = str(info.value)
    assert "indenter.pillar_law.forces" in message and "indenter.pillar_law.factors" in message
    assert "monotone" in message
    path.write_text(path.read_text().replace("[0.002, 0.001], factors = [1.0, -0.5]",
                                             "[0.002], factors = [1.0, 0.05], tension_limit = 0.01"))
    with pytest.raises(ConfigError, match="protocol.method"):
        load(path)
    path.write_text(path.read_text() + 'method = "fixed"\nstep = 5e-4\n')
    built = load(path)
    assert built.problem.indenter.pillar_law == PiecewiseLinear((0.002,), (1.0, 0.05), 0.01)


def test_a_law_beyond_the_documented_magnitudes_is_refused():
    """pillar_law.forces = [1e300] passed the documented 1e30 limit of every number; now refused by name."""
    from brushbem.runs.assembly import parse_config
    from brushbem.config import ConfigError

    config = {"halfspace": {"contact_modulus": 1.0, "work_of_adhesion": 1e-4}, "grid": {"size": 1.0, "elements": 32},
              "indenter": {"shape": "flat_punch", "radius": 0.2, "stiffness": 0.05,
                           "pillar_law": {"forces": [1e300], "factors": [1.0, 0.5]}},
              "protocol": {"method": "fixed", "preload_displacement": 1e-3, "step": 1e-4}}
    with pytest.raises(ConfigError, match="pillar_law.forces"):
        parse_config(config)


def test_a_fixed_step_that_cannot_reach_the_preload_within_max_steps_is_refused():
    """step = 1e-12 on a 1e-3 preload is 1e9 steps: refused up front, naming the step that would do."""
    from brushbem.runs.assembly import parse_config
    from brushbem.config import ConfigError

    config = {"halfspace": {"contact_modulus": 1.0, "work_of_adhesion": 1e-4}, "grid": {"size": 1.0, "elements": 32},
              "indenter": {"shape": "flat_punch", "radius": 0.2, "stiffness": 0.05},
              "protocol": {"method": "fixed", "preload_displacement": 1e-3, "step": 1e-12}}
    with pytest.raises(ConfigError, match="protocol.step.*at least 5e-09"):
        parse_config(config)


def test_no_work_without_adhesive_force_at_a_break():
    """tension_limit = 1e-29 breaks the spring at once.  The work once integrated the trial force from
    before the break, so W > 0 with F_A = 0."""
    import dataclasses

    import brushbem

    grid = brushbem.Grid(1.0, 32)
    punch = dataclasses.replace(brushbem.flat_punch(grid, 0.2, 0.05), pillar_law=PiecewiseLinear(tension_limit=1e-29))
    result = brushbem.pull_off(grid, punch, contact_modulus=1.0, work_of_adhesion=1e-4, preload_displacement=1e-3,
                               method="fixed", step=2e-5)
    # The break is located where the tension reaches the limit: F_A is the limit, and the work the
    # triangle under the line up to it, positive as F_A is (F_A > 0 exactly when W > 0).
    assert result.adhesive_force == pytest.approx(1e-29, rel=1e-6)
    assert 0.0 < result.work_of_separation <= result.adhesive_force * abs(result.pull_off_displacement)


def test_the_pieces_and_the_connections_are_values():
    """A law's pieces and breaks (`PieceState`) and the connections' state (`ConnectionState`) are frozen values:
    every change gives a new one and leaves the old as it was (a saved path state holds them as they were)."""
    from brushbem.physics.pillar_laws import PieceState
    from brushbem.protocol.connections import ConnectionState

    law = PiecewiseLinear(forces=(-0.005, 0.002), factors=(0.5, 1.0, 0.05), tension_limit=0.01)
    start = PieceState.start(law, np.full(3, STIFFNESS))
    pieces, broken = start.pieces.copy(), start.broken.copy()
    forces = np.array([-0.02, 0.0, 0.003])  # past the limit, on the middle piece, on the soft piece
    moved_state, moved = start.update(forces)
    assert moved.tolist() == [True, False, True] and moved_state.pieces.tolist() == [0, 1, 2]
    broken_state, new = moved_state.breaking(forces)
    assert new.tolist() == [True, False, False] and broken_state.broken.tolist() == [True, False, False]
    assert np.array_equal(start.pieces, pieces) and np.array_equal(start.broken, broken)  # the old value kept
    assert not moved_state.broken.any()
    with pytest.raises(dataclasses.FrozenInstanceError):
        start.pieces = pieces

    problem = ContactProblem(GRID, _punch(law), contact_modulus=1.0, work_of_adhesion=DGAMMA)
    connections, _ = ConnectionState.begin(problem, LoadPath(method="fixed", preload_displacement=0.01))
    after, _, _, change = connections.update(forces[:1], problem)
    assert change is not None and after is not connections and connections.pieces.pieces.tolist() == [1]
    back, restored = after.restore(connections, problem)
    assert back.pieces is connections.pieces and restored is not None
    same, nothing = connections.restore(connections, problem)
    assert same is connections and nothing is None
