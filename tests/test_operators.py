"""The operators compose: half-space on a window + pillar springs, restricted to a contact set.

`ContactOperator` is `HalfSpace` plus `PillarSprings`; `ContactSystem` and
`MaskedOperator` are their sum on a contact set S.  Each piece is checked
against the others and the springs against their closed form (a rigid tip on
a spring of stiffness k deflects by F / k).
"""

from __future__ import annotations

import numpy as np
import pytest

from brushbem.physics.halfspace import HalfSpace
from brushbem.numerics.operator import ContactOperator, ContactSystem, MaskedOperator, Window
from brushbem.physics.springs import PillarSprings
from brushbem.physics.structure import Grid, Level, brush

GRID = Grid(1.0, 48)
E_STAR = 1.0


def _hierarchy():
    return brush(GRID, layout="square", pillars_per_side=4, pillar_radius=0.05, stiffness=0.2,
                 contact_modulus=E_STAR, work_of_adhesion=1e-4, levels=(Level(2, 0.5),))


@pytest.fixture(scope="module")
def parts():
    indenter = _hierarchy()
    halfspace = HalfSpace(GRID.elements, GRID.element_size, E_STAR)
    operator = ContactOperator(halfspace, indenter, Window.full(GRID.elements))
    rng = np.random.default_rng(3)
    pressure = np.where(indenter.footprint, rng.random(indenter.height.shape), 0.0)
    return indenter, halfspace, operator, pressure


def test_the_operator_is_the_half_space_plus_the_springs(parts):
    indenter, halfspace, operator, pressure = parts
    springs = PillarSprings(indenter, GRID.element_size, Window.full(GRID.elements).slices, np)
    assert len(springs.levels) == 2
    total = halfspace.apply(pressure) + springs.apply(pressure)
    # Same arithmetic, same order: equal to the last bit.
    assert np.array_equal(operator.deflection(pressure), total)
    # tip_deflection transforms only the loaded block (the same convolution): equal to rounding.
    np.testing.assert_allclose(operator.tip_deflection(pressure), total, rtol=1e-13, atol=1e-15 * total.max())


def test_springs_deflect_by_force_over_stiffness():
    """One level, a load on one pillar only: every element of that pillar sinks by F / k, the others not at all."""
    indenter = brush(GRID, layout="square", pillars_per_side=3, pillar_radius=0.06, stiffness=0.3,
                     contact_modulus=E_STAR, work_of_adhesion=1e-4)
    springs = PillarSprings(indenter, GRID.element_size, Window.full(GRID.elements).slices, np)
    on = indenter.pillar == 4
    pressure = np.where(on, 2.0, 0.0)
    force = GRID.element_size**2 * pressure.sum()
    deflection = springs.apply(pressure)
    np.testing.assert_allclose(deflection[on], force / 0.3, rtol=1e-13)
    assert np.all(deflection[~on] == 0.0)
    np.testing.assert_allclose(springs.cluster_forces(pressure)[0][4], force, rtol=1e-13)


def test_the_restrictions_to_a_contact_set_agree(parts):
    indenter, _, operator, pressure = parts
    mask = indenter.footprint & (np.add.outer(np.arange(48), np.arange(48)) % 3 != 0)
    system = ContactSystem(operator, mask)
    masked = MaskedOperator(operator, mask)
    on_set = system.gather(pressure * mask)
    expected = masked.apply(pressure * mask)
    # Row-wise transforms against full ones: equal to rounding (1e-12 of the largest deflection).
    scale = float(np.abs(expected).max())
    assert float(np.abs(system.scatter(system.apply(on_set)) - expected).max()) <= 1e-12 * scale
    springs = operator.springs.apply(pressure * mask)
    np.testing.assert_allclose(system.spring_deflection(on_set), system.gather(springs), rtol=1e-13, atol=0.0)
