"""``indenter.stiffness_ratio`` followed from the TOML file to ``summary.json`` never returns to a package it left.

`STIFFNESS_RATIO_TRACE` lists the steps of the value, in the order it reaches them: the functions that read
k~, convert it (k = k~ E* L, and back to k~ = k / (E* L) for the record) or write it into a record or the file.
A function that only hands on an object holding the value (``brushbem.run``, ``runs.case.run_problem``,
``PullOff.save``, the ``ContactProblem``) is not a step; neither is a helper of the floor that a step calls
(``results.plain.to_json_safe`` under ``io.encoding._json``).  The test runs a small brush from a file, saves
it, records the first call of every step (`sys.setprofile`) and checks that each step is taken, in this
order, that the packages of the steps never come back once left, and that ``summary.json`` holds the k~ of
the file.  The same list is written out in docs/site/internals.md.
"""

from __future__ import annotations

import json
import sys

import pytest

#: (module, function) of each step of k~ from the file to summary.json's ``normalized.stiffness_ratio`` and
#: ``design.spring.stiffness_ratio``.
STIFFNESS_RATIO_TRACE: tuple[tuple[str, str], ...] = (
    ("brushbem.config.loading", "read_toml"),  # the TOML file as tables
    ("brushbem.config.sections_indenter", "IndenterConfig._brush_problems"),  # exactly one of k~ and k
    ("brushbem.runs.assembly", "build_brush"),  # k~ and E* handed to the builder
    ("brushbem.physics.structure.builders", "_pillar_stiffness"),  # k of the brush's side L
    ("brushbem.physics.scales", "stiffness_of_ratio"),  # k = k~ E* L, the one conversion
    ("brushbem.physics.structure.records", "SpringLevel.__post_init__"),  # k of the pillars' level
    ("brushbem.physics.comparison", "spring_numbers"),  # the spring's k and k~ for the design record
    ("brushbem.physics.scales", "normalized_stiffness"),  # k~ = k / (E* L)
    ("brushbem.physics.comparison", "_brush_theory"),  # the closed forms and normalisations of a brush
    ("brushbem.results.normalization", "BrushNormalization.__init__"),  # the typed record
    ("brushbem.results.case", "RunSummary.__init__"),  # the run's summary
    ("brushbem.results.design", "Spring.__init__"),  # design.spring's k and k~
    ("brushbem.io.writing", "write_case"),  # summary.json, written atomically
    ("brushbem.io.encoding", "_json"),  # its text
)

_FILE = """
[halfspace]
contact_modulus = 1.0
work_of_adhesion = 1e-4
[grid]
size = 1.0
elements = 32
[indenter]
shape = "brush"
layout = "square"
region = "square"
pillars_per_side = 2
pillar_radius = 0.1
stiffness_ratio = 0.05
[protocol]
preload_displacement = 2e-3
"""


def _package(module: str) -> str:
    """``brushbem.physics.structure.records`` -> ``brushbem.physics``."""
    return ".".join(module.split(".")[:2])


def returns_to_a_package(modules) -> list[str]:
    """The packages that ``modules`` (in order) enter again after leaving them."""
    left: set[str] = set()
    found = []
    previous = None
    for module in modules:
        package = _package(module)
        if package != previous:
            if package in left:
                found.append(package)
            if previous is not None:
                left.add(previous)
            previous = package
    return found


def test_the_return_check_finds_a_return():
    """The check can fail: a trace that goes back to a package it left is reported."""
    assert returns_to_a_package(["brushbem.runs.case", "brushbem.physics.scales", "brushbem.physics.comparison",
                                 "brushbem.results.case", "brushbem.runs.case"]) == ["brushbem.runs"]
    assert returns_to_a_package(["brushbem.config.loading", "brushbem.runs.assembly"]) == []


def test_the_stiffness_ratio_trace_never_returns_to_a_package():
    assert returns_to_a_package([module for module, _ in STIFFNESS_RATIO_TRACE]) == []


def _step(frame) -> tuple[str, str]:
    """(module, qualified name) of the function ``frame`` runs; a dataclass's generated ``__init__`` by its class."""
    code = frame.f_code
    if code.co_name == "__init__" and "self" in frame.f_locals:
        cls = type(frame.f_locals["self"])
        return cls.__module__, f"{cls.__qualname__}.__init__"
    return frame.f_globals.get("__name__", ""), code.co_qualname


@pytest.mark.slow  # about 4 s: a run and its files under a profiler
def test_the_stiffness_ratio_takes_the_traced_steps_in_order(tmp_path):
    """The steps of `STIFFNESS_RATIO_TRACE` are the ones a run from a file takes, first called in that order."""
    import brushbem

    path = tmp_path / "brush.toml"
    path.write_text(_FILE)
    wanted = set(STIFFNESS_RATIO_TRACE)
    first: dict[tuple[str, str], int] = {}

    def profile(frame, event, arg):
        if event == "call" and frame.f_globals.get("__name__", "").startswith("brushbem"):
            step = _step(frame)
            if step in wanted and step not in first:
                first[step] = len(first)

    sys.setprofile(profile)
    try:
        result = brushbem.run(path)
        result.save(tmp_path / "out", figure=False)
    finally:
        sys.setprofile(None)
    assert result.converged
    assert sorted(first, key=first.get) == list(STIFFNESS_RATIO_TRACE)
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    # k = k~ E* L and back: two roundings of a product and a quotient.
    assert summary["normalized"]["stiffness_ratio"] == pytest.approx(0.05, rel=1e-15)
    assert summary["design"]["spring"]["stiffness_ratio"] == summary["normalized"]["stiffness_ratio"]
    assert summary["provenance"]["config"]["indenter"]["stiffness_ratio"] == 0.05
