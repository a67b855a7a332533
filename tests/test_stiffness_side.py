"""k~ = k / (E* L) with L the brush's side (thesis eq. 4.13: the "square area L x L" the pillars are distributed
in, L736), not the domain around it: the same brush in a larger domain has the same k, F_A and reported k~."""

from __future__ import annotations

import pytest

import brushbem


def _brush(domain: float, elements: int, region_size: float | None) -> dict:
    indenter = {"shape": "brush", "layout": "square", "pillars_per_side": 4, "pillar_radius": 0.07,
                "stiffness_ratio": 0.01}
    if region_size is not None:
        indenter["region_size"] = region_size
    return {"halfspace": {"contact_modulus": 1.0, "work_of_adhesion": 1e-4},
            "grid": {"size": domain, "elements": elements}, "indenter": indenter,
            "protocol": {"method": "events", "preload_displacement": 0.002}}


def test_the_same_brush_in_a_padded_domain_keeps_its_stiffness_force_and_k_tilde():
    # h = 1/32 in both: the padded grid (1.5, N = 48) holds the brush's grid (1, N = 32) at its centre, element
    # for element, so the rasterised footprints are the same and only zero-pressure elements are added.
    from brushbem.runs.assembly import parse

    configs = (_brush(1.0, 32, None), _brush(1.5, 48, 1.0))
    alone, padded = (brushbem.run(config) for config in configs)
    stiffness = [float(parse(config).problem.indenter.levels[0].stiffnesses[0]) for config in configs]
    assert stiffness[0] == stiffness[1] == pytest.approx(0.01 * 1.0 * 1.0, rel=1e-15, abs=0.0)  # k = k~ E* L_brush
    # The half-space is the same infinite body (non-periodic convolution): F_A agrees to the CG tolerance
    # (1e-8 relative residual; 1e-6 leaves room for the residual's amplification by the conditioning).
    assert padded.adhesive_force == pytest.approx(alone.adhesive_force, rel=1e-6, abs=0.0)
    for run in (alone, padded):
        assert run.summary["normalized"]["stiffness_ratio"] == pytest.approx(0.01, rel=1e-12, abs=0.0)
    # Without region_size the brush fills the domain: L = grid.size, the meaning of every committed table.
    assert parse(configs[0]).problem.indenter.description.region_size == 1.0
