"""Property test: random configurations run end to end, or are refused at the edge.

`tests/test_config.py` throws arbitrary documents at the validator.  Here the
documents are mostly *valid* - every shape, both load paths, both preloads,
springs from very soft to rigid, moduli and sizes over six decades, solver
settings at their limits - and each one is run through the same path as
``brushbem run``: parse, `run_case`, write the files.  Whatever the draw, the
run must end in one of two ways:

* a `ConfigError` from `parse_config` (then it never started), or
* a result whose summary says whether it converged: if it did, every reported
  number is finite and has the sign the contract gives it; if it did not, a
  reason is given.

No other exception, no NaN presented as a result, no hang (the grids are
small and ``max_steps`` is bounded, so every run ends in seconds).
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

from brushbem.runs.assembly import parse_config
from brushbem.runs.case import run_case
from brushbem.config import ConfigError
from brushbem.io import read_case, write_case

_SCALES = (1e-3, 1.0, 1e3)


@st.composite
def run_documents(draw) -> tuple[dict[str, Any], np.ndarray | None]:
    """A configuration document (mostly valid) and, for a height map, its heights."""
    modulus = draw(st.sampled_from(_SCALES))
    size = draw(st.sampled_from(_SCALES))
    n = draw(st.integers(8, 24))
    h = size / n
    if draw(st.booleans()):
        halfspace: dict[str, Any] = {"contact_modulus": modulus}
    else:
        nu = draw(st.sampled_from([0.0, 0.3, 0.49]))
        halfspace = {"youngs_modulus": modulus * (1 - nu**2), "poisson_ratio": nu}
    # Delta gamma as a multiple of E* h: from no adhesion to Sigma_c ~ E*.
    halfspace["work_of_adhesion"] = modulus * h * draw(st.sampled_from([0.0, 1e-6, 1e-4, 1e-2, 0.4]))

    shape = draw(st.sampled_from(["flat_punch", "sphere", "height_map", "brush"]))
    indenter: dict[str, Any] = {"shape": shape}
    heights = None
    # Preload scale: the displacement that gives a stress ~ E* x strain 1e-2.
    scale = 1e-2 * size
    if shape == "flat_punch":
        indenter["radius"] = size * draw(st.sampled_from([0.05, 0.2, 0.35, 0.5, 0.6]))
    elif shape == "sphere":
        indenter["radius"] = size * draw(st.sampled_from([0.1, 1.0, 10.0]))
    elif shape == "height_map":
        rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
        heights = rng.uniform(0.0, draw(st.sampled_from([0.0, 1e-3, 1e-2])) * size, (n, n))
        indenter["file"] = "tip.npy"
    else:
        side = draw(st.integers(1, 4))
        indenter.update(
            pillar_radius=size / side * draw(st.sampled_from([0.1, 0.3, 0.45])),
            stiffness_ratio=draw(st.sampled_from([1e-3, 0.1, 10.0, math.inf])),
        )
        if draw(st.integers(0, 3)) == 0:
            indenter.update(layout="random", pillar_count=side**2, seed=draw(st.integers(0, 9)))
        else:
            indenter.update(layout="square", pillars_per_side=side)
            if side in (2, 4) and draw(st.booleans()):  # one hierarchy level of 2 x 2 clusters
                indenter["levels"] = [{"cluster": 2, "stiffness_ratio": draw(st.sampled_from([1e-2, 1.0]))}]
        if draw(st.booleans()):
            indenter["roughness"] = {"sigma": scale * draw(st.sampled_from([0.0, 0.1, 1.0]))}
        if draw(st.integers(0, 3)) == 0:
            indenter["profile"] = {"amplification": draw(st.sampled_from([0.5, 5.0]))}
    if shape != "brush":
        # k~ = k / (E* L): from very soft to rigid.
        indenter["stiffness"] = draw(st.sampled_from([1e-3, 0.1, 10.0, math.inf])) * modulus * size

    method = draw(st.sampled_from(["events", "fixed"]))
    protocol: dict[str, Any] = {"method": method, "max_steps": draw(st.sampled_from([5, 50, 400, 400]))}
    if draw(st.booleans()):
        protocol["preload_displacement"] = scale * draw(st.sampled_from([1e-3, 0.1, 1.0, 3.0]))
    else:
        protocol["preload_force"] = modulus * size**2 * draw(st.sampled_from([1e-7, 1e-4, 1e-2]))
    protocol["step"] = scale * draw(st.sampled_from([0.01, 0.1, 1.0, 5.0]))
    solver = {
        "tolerance": draw(st.sampled_from([1e-3, 1e-8, 1e-12])),
        "max_iterations": draw(st.sampled_from([3, 20_000, 20_000, 20_000])),
        "cascade": draw(st.sampled_from(["local", "global"])),
        "coupling": draw(st.sampled_from(["segments", "segments", "discriminant"])),
    }
    document = {
        "halfspace": halfspace,
        "grid": {"size": size, "elements": n},
        "indenter": indenter,
        "protocol": protocol,
        "solver": solver,
    }
    return document, heights


_FINITE_KEYS = (
    "adhesive_force", "pull_off_displacement", "separation_displacement", "work_of_separation",
    "preload_force", "max_displacement",
)


# The suite runs a fixed sample of 60 (derandomized: CI stays reproducible);
# BRUSHBEM_RANDOM_RUNS=600 explores fresh random draws (with
# --hypothesis-show-statistics to see how the runs ended).
_EXPLORE = os.environ.get("BRUSHBEM_RANDOM_RUNS")


#: How every drawn run ended ("refused", "converged", "not converged").
_OUTCOMES: list[str] = []

#: Least share of the runs that started which must converge.  The draws include
#: budgets meant to run out (``max_steps = 5``, ``max_iterations = 3``,
#: ``tolerance`` at its limits), so not every run can; on the fixed sample 20 of
#: the 30 that ran converged (30 were refused: pillars under 2 elements, random
#: layouts that cannot fit).  A regression that leaves most runs unconverged
#: fails here instead of passing as "unconverged with a reason".
MIN_CONVERGED_FRACTION = 0.5


@settings(
    max_examples=int(_EXPLORE or 60),
    derandomize=_EXPLORE is None,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)
@given(drawn=run_documents())
def _run_or_refuse(tmp_path_factory, drawn):
    document, heights = drawn
    folder = Path(tmp_path_factory.mktemp("run"))
    if heights is not None:
        np.save(folder / "tip.npy", heights)
    try:
        config = parse_config(document, base_dir=folder)
    except ConfigError as error:
        assert error.problems and all(p.startswith("`") for p in error.problems)
        event("refused by the validation")
        _OUTCOMES.append("refused")
        return
    result = run_case(config).result
    summary = result.summary
    assert isinstance(summary["converged"], bool)
    assert all(isinstance(w, str) for w in summary["warnings"])
    event("converged" if summary["converged"] else "not converged: " + summary["reason"].split("(")[0][:60])
    _OUTCOMES.append("converged" if summary["converged"] else "not converged")
    if not summary["converged"]:
        assert isinstance(summary.get("reason"), str) and summary["reason"], summary
    else:
        for key in _FINITE_KEYS:
            assert math.isfinite(summary[key]), (key, summary)
        assert summary["adhesive_force"] >= 0.0, summary
        assert summary["work_of_separation"] >= 0.0, summary
        assert summary["preload_force"] > 0.0, summary
        assert summary["max_displacement"] >= summary["separation_displacement"], summary
        # Without adhesion nothing holds the indenter once the force is zero:
        # a tension is at most the solves' error (relative tolerance of the
        # preload's pressure; events interpolate to the zero crossing).
        if document["halfspace"]["work_of_adhesion"] == 0.0:
            bound = 10 * config.solver.tolerance * summary["preload_force"]
            assert summary["adhesive_force"] <= bound, summary
        else:
            # Work against a tensile force needs a tensile force: a pull-off with work
            # but no force (or the reverse) has lost its extremum.  (Both are zero
            # where the whole contact peels at a compressive force, which a contact
            # of a few elements under a weak criterion may.)
            assert (summary["adhesive_force"] > 0.0) == (summary["work_of_separation"] > 0.0), summary
    # What a converged or unconverged run has is written and read back alike.
    write_case(result, folder, config=config)
    written = json.loads((folder / "summary.json").read_text(encoding="utf-8"))
    assert written["converged"] == summary["converged"]
    dataset = read_case(folder)
    assert dataset.sizes["step"] == result.curve.displacement.size


@pytest.mark.slow
def test_random_configurations_run_or_are_refused(tmp_path_factory):
    """Every draw ends refused, converged and sound, or unconverged with a reason; most converge."""
    _OUTCOMES.clear()
    _run_or_refuse(tmp_path_factory)
    ran = _OUTCOMES.count("converged") + _OUTCOMES.count("not converged")
    assert ran >= 20, _OUTCOMES  # the sample must run, not only be refused
    assert _OUTCOMES.count("converged") >= MIN_CONVERGED_FRACTION * ran, _OUTCOMES
