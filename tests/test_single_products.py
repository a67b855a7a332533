"""Single-precision products in the late CG iterations of the exact path keep its answers.

`ContactSystem.apply_block(..., single=True)` transforms in single precision; `conjugate_gradient`
takes it for the iterations whose error would add at most ``PRODUCT_SHARE`` of the
converged residual, and a `ProductLedger` per chain of kept deflections bounds the
error those carry into the next solves (refreshed by a transform once it passes
``REFRESH_SHARE``).  The tests check the product's error against its bound, a
solve's true residual, and a pull-off against double-precision products.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from brushbem.numerics.operator import SINGLE_ERROR, ContactOperator, ContactSystem, Window
from brushbem.numerics.solver import cg, set_solve
from brushbem.numerics.solver.cg import ProductLedger
from brushbem.physics.halfspace import HalfSpace
from brushbem.physics.structure import Grid, brush
from brushbem.protocol import ContactProblem, LoadPath, record_pull_off
from brushbem.runs.case import brush_scales

GRID = Grid(1.0, 128)
PER_SIDE = 8
RADIUS = math.sqrt(0.16 / math.pi) / PER_SIDE  # phi = 0.16, 3.6 elements at N = 128
DGAMMA = 1e-4


def _operator() -> ContactOperator:
    indenter = brush(GRID, layout="square", pillars_per_side=PER_SIDE, pillar_radius=RADIUS, contact_modulus=1.0,
                     work_of_adhesion=DGAMMA, stiffness=0.01, roughness=1e-3, seed=3)
    return ContactOperator(HalfSpace(GRID.elements, GRID.element_size, 1.0), indenter, Window.full(GRID.elements))


def _counting(monkeypatch) -> dict:
    """Count the products of `ContactSystem` by precision."""
    counts = {"single": 0, "double": 0}
    original = ContactSystem._apply

    def counted(self, values, whole, single=False):
        counts["single" if single else "double"] += 1
        return original(self, values, whole, single)

    monkeypatch.setattr(ContactSystem, "_apply", counted)
    return counts


def test_a_single_precision_product_is_within_its_bound():
    """Relative error of a single-precision product: above double rounding (it is single) and below SINGLE_ERROR."""
    operator = _operator()
    system = operator.system(operator.indenter.footprint)
    values = np.random.default_rng(0).uniform(0.0, 1.0, system.size)
    exact, single = system.apply_block(values)[0], system.apply_block(values, single=True)[0]
    error = np.linalg.norm(single - exact) / np.linalg.norm(exact)
    assert 1e-12 < error < SINGLE_ERROR


def test_a_solve_with_single_products_meets_its_tolerance(monkeypatch):
    """A cold solve on every tip: its late products single, its true residual within the chain's share of the
    tolerance, its solution that of double products to the tolerance."""
    operator = _operator()
    mask = operator.indenter.footprint
    rhs = np.where(mask, 1.0, 0.0)
    counts = _counting(monkeypatch)
    ledger = ProductLedger()
    single = set_solve.solve_on_set(operator, mask, rhs, tolerance=1e-8, ledger=ledger)
    assert single.converged and counts["single"] > 0
    plain = set_solve.solve_on_set(operator, mask, rhs, tolerance=1e-8)
    system = operator.system(mask)
    x = system.gather(single.solution)
    b = system.gather(rhs)
    true_residual = np.linalg.norm(b - system.apply(x))
    # The solve stops at a recursion residual <= its threshold (<= ledger.scale); the products' error adds at
    # most CHAIN_SHARE of it.
    assert true_residual <= (1.0 + cg.CHAIN_SHARE) * ledger.scale
    assert ledger.carried <= cg.CHAIN_SHARE * ledger.scale
    difference = np.linalg.norm(single.solution - plain.solution) / np.linalg.norm(plain.solution)
    assert difference < 1e-7  # both within the tolerance 1e-8 of the solution times the conditioning


@pytest.mark.slow  # two pull-offs, 5 s on 2 cores
def test_a_pull_off_with_single_products_keeps_its_answer(monkeypatch, switches):
    """The soft rough brush: F_A and the work the same to 1e-9 (issue 46's bound for a faster exact path), a
    third or more of the products single, the ledgers refreshed and never above CHAIN_SHARE."""

    def build(roughness: float) -> ContactProblem:
        indenter = brush(GRID, layout="square", pillars_per_side=PER_SIDE, pillar_radius=RADIUS,
                         contact_modulus=1.0, work_of_adhesion=DGAMMA, stiffness=0.01, roughness=roughness, seed=3)
        return ContactProblem(GRID, indenter, contact_modulus=1.0, work_of_adhesion=DGAMMA)

    scales = brush_scales(build(0.0))
    problem = build(abs(scales["rigid_brush_displacement"]))
    path = LoadPath(method="events", preload_force=scales["rigid_brush_force"], max_steps=10**6)
    counts = _counting(monkeypatch)
    checks = []
    due = ProductLedger.due

    def watched(self):
        checks.append((self.carried, self.scale))
        return due(self)

    monkeypatch.setattr(ProductLedger, "due", watched)
    fast = record_pull_off(problem, path).summary
    share = counts["single"] / (counts["single"] + counts["double"])
    switches(single_products=False)
    plain = record_pull_off(problem, path).summary
    assert share >= 0.3  # 53 % when written
    assert fast["n_solves"] == plain["n_solves"]
    assert fast["adhesive_force"] == pytest.approx(plain["adhesive_force"], rel=1e-9, abs=0.0)
    assert fast["work_of_separation"] == pytest.approx(plain["work_of_separation"], rel=1e-9, abs=0.0)
    assert any(carried > cg.REFRESH_SHARE * scale for carried, scale in checks)  # refreshed at least once
    assert all(carried <= cg.CHAIN_SHARE * scale for carried, scale in checks)


@pytest.mark.slow  # two pull-offs, 4 s on 2 busy cores
def test_a_soft_brush_keeps_its_answer(monkeypatch, switches):
    """Springs of k~ = 1e-6 carry all but 5e-5 of the unit response's right-hand side: the solves' shares
    are measured by the half-space part at the current iterate, not at the cold start (which put F_A 8e-9
    off on the 8 x 8 brush), so F_A and the work stay within 1e-9 of double products."""
    import brushbem

    config = {"halfspace": {"contact_modulus": 1.0, "work_of_adhesion": DGAMMA}, "grid": {"size": 1.0, "elements": 128},
              "indenter": {"shape": "brush", "layout": "square", "pillars_per_side": 8, "pillar_radius": 0.02443,
                           "stiffness_ratio": 1e-6, "seed": 1},
              "protocol": {"method": "events", "preload_displacement": 0.002}}
    counts = _counting(monkeypatch)
    fast = brushbem.run(config)
    assert counts["single"] > 0
    switches(single_products=False)
    plain = brushbem.run(config)
    assert fast.adhesive_force == pytest.approx(plain.adhesive_force, rel=1e-9, abs=0.0)
    assert fast.work_of_separation == pytest.approx(plain.work_of_separation, rel=1e-9, abs=0.0)
