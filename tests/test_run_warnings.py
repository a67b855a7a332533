"""Warnings of a finished run (`brushbem.runs.case.run_warnings`): converged, but questionable.

Each warning is provoked by a small run and absent from its well-posed twin,
so that neither the condition nor its absence is taken on trust.
"""

from __future__ import annotations

import math

import pytest

from brushbem.runs.assembly import parse_config
from brushbem.runs.case import run_case


def _document(shape: str, radius: float, **protocol) -> dict:
    return {
        "halfspace": {"contact_modulus": 1.0, "work_of_adhesion": 1e-3},
        "grid": {"size": 1.0, "elements": 32},
        "indenter": {"shape": shape, "radius": radius, "stiffness": math.inf},
        "protocol": protocol,
    }


def _warnings(document: dict) -> list[str]:
    result = run_case(parse_config(document)).result
    assert result.summary["converged"], result.summary["reason"]
    return result.summary["warnings"]


@pytest.mark.parametrize(("preload", "cut"), [(0.04, False), (0.36, True)])
def test_sphere_contact_at_the_domain_edge(preload, cut):
    # R = 1: the Hertz contact radius sqrt(R d) is 0.2 (inside the unit
    # domain) at d = 0.04 and 0.6 (beyond its half-width 0.5) at d = 0.36.
    warnings = _warnings(_document("sphere", 1.0, preload_displacement=preload))
    assert any("edge of the domain" in w for w in warnings) == cut, warnings


def test_punch_that_fills_the_domain_is_not_cut():
    # A punch of diameter L touches the domain's edge rows, but the punch ends
    # there: nothing of it lies outside, so nothing is cut.
    warnings = _warnings(_document("flat_punch", 0.5, preload_displacement=0.01))
    assert not any("edge of the domain" in w for w in warnings), warnings


@pytest.mark.parametrize(("step", "coarse"), [(2e-3, False), (2e-2, True)])
def test_fixed_steps_too_coarse_for_the_tensile_branch(step, coarse):
    # JKR sphere R = 1 at N = 32: the force is tensile from d ~ 0 to the
    # separation near d = -0.02; steps of 2e-3 sample it 12 times (measured),
    # steps of 2e-2 once.
    warnings = _warnings(_document("sphere", 1.0, method="fixed", preload_displacement=0.01, step=step))
    assert any("spans only" in w for w in warnings) == coarse, warnings
    if coarse:
        assert any(f"protocol.step = {step:g}" in w for w in warnings), warnings


def test_preload_beyond_the_domain_size():
    warnings = _warnings(_document("flat_punch", 0.25, preload_displacement=2.0))
    assert any("exceeds the domain size" in w for w in warnings), warnings
    assert _warnings(_document("flat_punch", 0.25, preload_displacement=0.01)) == []

