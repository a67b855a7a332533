"""Configuration validation: every bad value named, every problem at once."""

from __future__ import annotations

import copy
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from pydantic import ValidationError

from brushbem.runs.assembly import load_config, parse_config
from brushbem.config import (
    ConfigError,
    GridConfig,
    HalfSpaceConfig,
    IndenterConfig,
    RunConfig,
    config_to_dict,
)

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def valid_document() -> dict[str, Any]:
    """A minimal valid configuration: a rigid flat punch, 128 elements."""
    return {
        "halfspace": {"contact_modulus": 1.0, "work_of_adhesion": 1e-3},
        "grid": {"size": 1.0, "elements": 128},
        "indenter": {"shape": "flat_punch", "radius": 0.25, "stiffness": math.inf},
        "protocol": {"preload_displacement": 0.01},
    }


def with_value(dotted: str, value: Any) -> dict[str, Any]:
    document = valid_document()
    section, key = dotted.split(".")
    document[section][key] = value
    return document


def problems_of(document: Any, base_dir: Path | None = None) -> list[str]:
    with pytest.raises(ConfigError) as caught:
        parse_config(document, base_dir)
    assert caught.value.problems, "a ConfigError must list its problems"
    return caught.value.problems


def test_valid_document_parses_with_defaults():
    config = parse_config(valid_document())
    assert isinstance(config, RunConfig)
    assert config.halfspace.effective_modulus == 1.0
    assert config.grid.element_size == pytest.approx(1 / 128)
    assert config.indenter.stiffness == math.inf
    assert config.protocol.method == "events"
    assert config.protocol.step == 1e-4
    assert config.protocol.max_steps == 200_000
    assert config.solver.tolerance == 1e-8
    assert config.solver.max_iterations == 20_000


def test_models_are_frozen():
    config = parse_config(valid_document())
    with pytest.raises(ValidationError, match="frozen"):
        config.grid.size = 2.0  # type: ignore[misc]


@pytest.mark.parametrize("path", sorted(EXAMPLES.glob("*.toml")), ids=lambda p: p.name)
def test_examples_are_valid(path):
    assert isinstance(load_config(path), RunConfig)


def test_default_example_is_the_16x16_brush():
    config = load_config(EXAMPLES / "default.toml")
    assert config.indenter.shape == "brush"
    assert config.indenter.pillars_per_side == 16
    assert config.indenter.stiffness_ratio == 0.455
    assert config.grid.elements == 256


def test_sphere_example_is_the_jkr_sphere_on_a_spring():
    config = load_config(EXAMPLES / "sphere_spring.toml")
    assert config.indenter.shape == "sphere"
    assert config.indenter.radius == 1.0
    assert config.indenter.stiffness == 0.5
    assert config.halfspace.work_of_adhesion == 1e-3


@pytest.mark.slow
def test_sphere_example_does_what_its_header_says():
    """The header: preload contact radius 0.166, beyond a_JKR = 0.152 and below a_o = 0.242, and F_A within
    4.4 % of 3/2 pi dgamma R at this grid (the measured +4.41 %, tests/test_closed_forms_bem.py)."""
    from brushbem.runs.case import run_case

    result = run_case(load_config(EXAMPLES / "sphere_spring.toml")).result
    theory = result.summary["theory"]
    assert theory["preload_contact_radius"] == pytest.approx(0.166, abs=5e-4)
    assert 0.152 < theory["preload_contact_radius"] < theory["zero_force_radius"] == pytest.approx(0.242, abs=5e-4)
    ratio = result.summary["adhesive_force"] / (1.5 * math.pi * 1e-3 * 1.0)
    assert 1.0 < ratio < 1.045


def test_toml_inf_is_rigid(tmp_path):
    path = tmp_path / "c.toml"
    path.write_text(
        "[halfspace]\ncontact_modulus = 1.0\n[grid]\nsize = 1.0\nelements = 64\n"
        '[indenter]\nshape = "flat_punch"\nradius = 0.25\nstiffness = inf\n'
        "[protocol]\npreload_force = 0.5\n"
    )
    assert load_config(path).indenter.stiffness == math.inf


def test_youngs_modulus_and_poisson_ratio_give_contact_modulus():
    halfspace = HalfSpaceConfig(youngs_modulus=3.0, poisson_ratio=0.5 - 0.25)
    assert halfspace.effective_modulus == pytest.approx(3.0 / (1 - 0.25**2))


@pytest.mark.parametrize(
    ("dotted", "value"),
    [
        ("halfspace.contact_modulus", math.nan),
        ("halfspace.contact_modulus", math.inf),
        ("halfspace.contact_modulus", -1.0),
        ("halfspace.contact_modulus", 0.0),
        ("halfspace.work_of_adhesion", -1e-3),
        ("halfspace.work_of_adhesion", math.nan),
        ("grid.size", math.nan),
        ("grid.size", math.inf),
        ("grid.size", 0.0),
        ("grid.size", -1.0),
        ("grid.size", "1.0"),
        ("grid.elements", 0),
        ("grid.elements", -128),
        ("grid.elements", 7),
        ("grid.elements", 8193),
        ("grid.elements", 128.0),
        ("grid.elements", True),
        ("indenter.radius", math.nan),
        ("indenter.radius", math.inf),
        ("indenter.radius", 0.0),
        ("indenter.radius", -0.25),
        ("indenter.stiffness", math.nan),
        ("indenter.stiffness", 0.0),
        ("indenter.stiffness", -1.0),
        ("indenter.shape", "cube"),
        ("protocol.method", "bisection"),
        ("protocol.preload_displacement", math.nan),
        ("protocol.preload_displacement", -0.01),
        ("protocol.step", 0.0),
        ("protocol.max_steps", 0),
        ("solver.tolerance", 0.0),
        ("solver.tolerance", 0.1),
        ("solver.max_iterations", 0),
        ("solver.cascade", "fast"),
    ],
)
def test_bad_value_is_named_with_its_value(dotted, value):
    document = valid_document()
    document.setdefault("solver", {})
    section, key = dotted.split(".")
    document[section][key] = value
    problems = problems_of(document)
    assert len(problems) == 1, problems
    assert problems[0].startswith(f"`{dotted}`: {value!r} — "), problems


def test_poisson_ratio_range():
    document = valid_document()
    document["halfspace"] = {"youngs_modulus": 1.0, "poisson_ratio": 0.5 + 1e-9}
    (problem,) = problems_of(document)
    assert "`halfspace.poisson_ratio`" in problem and "[0, 0.5]" in problem


def test_incompressible_halfspace_is_accepted():
    """nu = 0.5 (every elastomer): E* = E / (1 - 1/4) = 4 E / 3 exactly, no division by 1 - 2 nu anywhere."""
    halfspace = HalfSpaceConfig(youngs_modulus=3.0, poisson_ratio=0.5)
    assert halfspace.effective_modulus == pytest.approx(4.0, rel=1e-15, abs=0)


@pytest.mark.parametrize(
    "halfspace",
    [
        {},
        {"youngs_modulus": 1.0},
        {"poisson_ratio": 0.3},
        {"contact_modulus": 1.0, "youngs_modulus": 1.0, "poisson_ratio": 0.3},
    ],
)
def test_exactly_one_way_to_give_the_modulus(halfspace):
    document = valid_document()
    document["halfspace"] = halfspace
    (problem,) = problems_of(document)
    assert problem.startswith("`halfspace`:")
    assert "contact_modulus" in problem and "youngs_modulus" in problem


def test_punch_under_two_elements_in_radius():
    document = with_value("indenter.radius", 0.003)
    (problem,) = problems_of(document)
    assert problem == (
        "`indenter.radius`: 0.003 — under 2 elements (h = 0.0078125); "
        "the punch needs at least 2 elements in radius"
    )


def test_punch_larger_than_the_domain():
    (problem,) = problems_of(with_value("indenter.radius", 0.6))
    assert problem.startswith("`indenter.radius`: 0.6 — ")
    assert "larger than the domain" in problem


def test_sphere_may_be_larger_than_the_domain():
    document = valid_document()
    document["indenter"] = {"shape": "sphere", "radius": 100.0, "stiffness": 1.0}
    assert parse_config(document).indenter.radius == 100.0



@pytest.mark.parametrize("elements, lowest", [(32, 1.0 / 32**2 / 4), (33, 0.0)])
def test_sphere_preload_must_reach_the_lowest_element(elements, lowest):
    """On an even grid the sphere's apex lies on a node, so its lowest elements
    stand h^2 / (4R) above it; a preload displacement at or below that height
    never touches (the run would record no contact), so it is a config error."""
    document = valid_document()
    document["grid"]["elements"] = elements
    document["indenter"] = {"shape": "sphere", "radius": 1.0}
    document["protocol"] = {"preload_displacement": 1e-4, "method": "fixed"}
    if lowest < 1e-4:
        assert isinstance(parse_config(document), RunConfig)
        return
    problems = problems_of(document)
    assert len(problems) == 1, problems
    assert problems[0].startswith("`protocol.preload_displacement`: 0.0001 — must be > 0.000244141"), problems


def test_discriminant_coupling_refused_where_its_size_condition_fails():
    """Eq. 3.14-3.15: the discriminant box must cover a cluster and reach no other.
    Clusters of 2 x 2 pillars 1/8 apart do not satisfy it, so `solver.coupling`
    is named before anything runs; the same brush with segment sums is valid."""
    document = valid_document()
    document["indenter"] = {
        "shape": "brush", "layout": "square", "region": "square", "pillars_per_side": 8,
        "pillar_radius": 0.02, "stiffness_ratio": 0.455,
        "levels": [{"cluster": 2, "stiffness_ratio": 0.1}],
    }
    document["halfspace"]["work_of_adhesion"] = 1e-4
    document["protocol"] = {"preload_displacement": 0.002}
    document["solver"] = {"coupling": "discriminant"}
    problems = problems_of(document)
    assert len(problems) == 1, problems
    assert problems[0].startswith("`solver.coupling`: 'discriminant' — the discriminant matrix cannot be used"), problems
    document["solver"] = {"coupling": "segments"}
    assert isinstance(parse_config(document), RunConfig)

@pytest.mark.parametrize("shape", ["flat_punch", "sphere"])
def test_radius_required(shape):
    document = valid_document()
    document["indenter"] = {"shape": shape}
    (problem,) = problems_of(document)
    assert problem.startswith("`indenter.radius`: missing")


@pytest.mark.parametrize(
    "protocol",
    [{}, {"preload_displacement": 0.01, "preload_force": 1.0}, {"method": "fixed"}],
)
def test_both_or_neither_preload(protocol):
    document = valid_document()
    document["protocol"] = protocol
    (problem,) = problems_of(document)
    assert problem.startswith("`protocol`:")
    assert "preload_displacement" in problem and "preload_force" in problem


def test_unknown_top_level_key():
    document = valid_document()
    document["solvr"] = {"tolerance": 1e-6}
    (problem,) = problems_of(document)
    assert problem.startswith("`solvr`:") and "unknown key" in problem


@pytest.mark.parametrize("section", ["halfspace", "grid", "indenter", "protocol", "solver"])
def test_unknown_nested_key(section):
    document = valid_document()
    document.setdefault(section, {})["colour"] = "red"
    (problem,) = problems_of(document)
    assert problem.startswith(f"`{section}.colour`: 'red' — unknown key")


def test_missing_section_and_section_of_wrong_type():
    document = valid_document()
    del document["grid"]
    document["protocol"] = 0.01
    problems = problems_of(document)
    assert any(p.startswith("`grid`: missing") for p in problems)
    assert any(p.startswith("`protocol`: 0.01 — must be a table") for p in problems)


def test_every_problem_reported_at_once():
    document = valid_document()
    document["halfspace"]["contact_modulus"] = -1.0
    document["indenter"]["radius"] = 0.003  # under 2 elements: a cross-section rule
    document["protocol"]["preload_force"] = 1.0  # both preloads
    document["grid"]["colour"] = "red"
    document["extra"] = {}
    problems = problems_of(document)
    keys = [p.split(":")[0] for p in problems]
    assert sorted(keys) == sorted(
        ["`extra`", "`halfspace.contact_modulus`", "`grid.colour`", "`protocol`"]
    ), problems
    # The grid failed, so the punch rule (which needs it) is not guessed at...
    document["grid"].pop("colour")
    problems = problems_of(document)
    # ...and once the grid validates, the punch is reported beside the others.
    assert any(p.startswith("`indenter.radius`: 0.003 — under 2 elements") for p in problems)
    assert any(p.startswith("`halfspace.contact_modulus`") for p in problems)
    assert len(problems) == 4, problems


def test_rules_between_keys_reported_beside_the_bad_values_of_their_table():
    """A table whose value fails still has its rules between keys checked, in the same pass.

    Pydantic skips a model's after-validator once one of its fields failed;
    every rule below would otherwise appear only after the bad value is fixed.
    """
    document = valid_document()
    document["halfspace"] = {"contact_modulus": math.nan, "youngs_modulus": 2.0, "poisson_ratio": 0.3}
    document["indenter"].update(radius=-1.0, file="tip.npy")  # file: a height_map key on a punch
    document["protocol"] = {"preload_displacement": -0.1, "preload_force": 1.0, "step": 0.0}
    problems = problems_of(document)
    expected = {
        "`halfspace.contact_modulus`: nan — must be a finite number > 0",
        "`halfspace`: contact_modulus = nan, youngs_modulus = 2.0, poisson_ratio = 0.3 — give either",
        "`indenter.radius`: -1.0 — must be a finite number > 0",
        "`indenter.file`: 'tip.npy' — file not found",
        "`indenter.file`: 'tip.npy' — only used when shape = 'height_map'; remove it",
        "`protocol.preload_displacement`: -0.1 — must be a finite number > 0",
        "`protocol.step`: 0.0 — must be a finite number > 0",
        "`protocol`: preload_displacement = -0.1, preload_force = 1.0 — give exactly one",
    }
    assert len(problems) == len(expected), problems
    for start in expected:
        assert sum(p.startswith(start) for p in problems) == 1, (start, problems)


def test_rules_of_each_hierarchy_level_reported_beside_its_bad_values():
    document = valid_document()
    document["indenter"] = {
        "shape": "brush", "layout": "square", "pillars_per_side": 4, "pillar_radius": 0.05,
        "stiffness_ratio": 1.0,
        "levels": [
            {"cluster": 0, "stiffness": 1.0, "stiffness_ratio": 2.0},  # a bad value and both stiffnesses
            {"cluster": 2},  # neither stiffness
        ],
    }
    problems = problems_of(document)
    assert sorted(p.split(" — ")[0].split(":")[0] for p in problems) == [
        "`indenter.levels.0.cluster`", "`indenter.levels.0.stiffness_ratio`", "`indenter.levels.1.stiffness_ratio`",
    ], problems
    assert any(p.startswith("`indenter.levels.0.cluster`: 0 — must be an integer in [1, 4096]") for p in problems)


def test_a_shape_that_fails_skips_only_the_rules_that_depend_on_it():
    document = valid_document()
    document["indenter"] = {"shape": "cube", "radius": 0.25, "stiffness": -1.0}
    problems = problems_of(document)
    assert [p.split(":")[0] for p in problems] == ["`indenter.shape`", "`indenter.stiffness`"], problems


def test_height_map_resolved_relative_to_the_config_file(tmp_path):
    np.save(tmp_path / "tip.npy", np.zeros((64, 64)))
    path = tmp_path / "c.toml"
    path.write_text(
        "[halfspace]\ncontact_modulus = 1.0\n[grid]\nsize = 1.0\nelements = 64\n"
        '[indenter]\nshape = "height_map"\nfile = "tip.npy"\n'
        "[protocol]\npreload_displacement = 0.01\n"
    )
    config = load_config(path)
    assert Path(config.indenter.file) == (tmp_path / "tip.npy").resolve()


def height_map_document(file: str) -> dict[str, Any]:
    document = valid_document()
    document["grid"]["elements"] = 16
    document["indenter"] = {"shape": "height_map", "file": file}
    return document


def test_missing_height_map_file(tmp_path):
    (problem,) = problems_of(height_map_document("nowhere.npy"), tmp_path)
    assert problem.startswith("`indenter.file`: 'nowhere.npy' — file not found")


@pytest.mark.parametrize(
    ("array", "message"),
    [
        (np.zeros((16, 8)), "square"),
        (np.zeros(16), "square"),
        (np.full((16, 16), np.nan), "finite"),
        (np.full((16, 16), "a"), "real numbers"),
        (np.zeros((32, 32)), "grid.elements = 16"),
    ],
)
def test_bad_height_map_contents(tmp_path, array, message):
    np.save(tmp_path / "tip.npy", array)
    (problem,) = problems_of(height_map_document("tip.npy"), tmp_path)
    assert problem.startswith("`indenter.file`: ") and message in problem, problem


def test_height_map_file_that_is_not_npy(tmp_path):
    (tmp_path / "tip.npy").write_text("not an array")
    (problem,) = problems_of(height_map_document("tip.npy"), tmp_path)
    assert "cannot be read" in problem


def test_keys_of_another_shape_are_rejected(tmp_path):
    np.save(tmp_path / "tip.npy", np.zeros((16, 16)))
    document = height_map_document("tip.npy")
    document["indenter"]["radius"] = 0.25
    (problem,) = problems_of(document, tmp_path)
    assert problem.startswith("`indenter.radius`: 0.25 — only used when shape = ")


def test_missing_file_and_toml_syntax_error(tmp_path):
    with pytest.raises(ConfigError, match="file not found"):
        load_config(tmp_path / "absent.toml")
    path = tmp_path / "broken.toml"
    path.write_text("[grid\nsize = 1.0\n")
    with pytest.raises(ConfigError, match="not valid TOML"):
        load_config(path)


def test_config_to_dict_is_json_with_inf_as_string_and_round_trips():
    import json

    config = parse_config(valid_document())
    data = config_to_dict(config)
    assert data["indenter"]["stiffness"] == "inf"
    text = json.dumps(data, allow_nan=False)
    assert parse_config(json.loads(text)) == config


def test_config_to_dict_of_a_pillar_model_config_round_trips():
    """The resolved form of a ``method = "pillars"`` file writes every key, those the pillar model does not use
    at their defaults: it re-parses to an equal configuration (through JSON, as summary.json holds it), while
    such a key set to a value of its own is still refused."""
    import json

    from brushbem.runs.assembly import parse_config as parse_with_structure

    document = {
        "halfspace": {"contact_modulus": 1.0, "work_of_adhesion": 1e-4},
        "grid": {"size": 1.0, "elements": 64},
        "indenter": {"shape": "brush", "layout": "square", "region": "square", "pillars_per_side": 4,
                     "pillar_radius": 0.05, "stiffness_ratio": 0.05},
        "protocol": {"method": "pillars", "preload_displacement": 2e-3},
    }
    config = parse_with_structure(document)
    data = json.loads(json.dumps(config_to_dict(config), allow_nan=False))
    assert data["solver"]["tolerance"] == config.solver.tolerance and "step" in data["protocol"]
    again = parse_with_structure(data)
    assert again == config
    assert config_to_dict(again) == data
    data["solver"]["tolerance"] = 1e-6
    with pytest.raises(ConfigError, match=r"solver\.tolerance.*not used by protocol.method = 'pillars'"):
        parse_with_structure(data)


def test_models_validate_when_built_in_python():
    with pytest.raises(ValueError):
        GridConfig(size=1.0, elements=4)
    with pytest.raises(ValueError):
        IndenterConfig(shape="sphere")
    with pytest.raises(ValueError):
        RunConfig(
            halfspace=HalfSpaceConfig(contact_modulus=1.0),
            grid=GridConfig(size=1.0, elements=128),
            indenter=IndenterConfig(shape="flat_punch", radius=0.001),
            protocol={"preload_displacement": 0.01},
        )


# --- property test: any document either parses or raises ConfigError ------------

_KEYS = {
    "halfspace": ["contact_modulus", "youngs_modulus", "poisson_ratio", "work_of_adhesion"],
    "grid": ["size", "elements"],
    "indenter": ["shape", "radius", "stiffness", "file"],
    "protocol": ["method", "preload_displacement", "preload_force", "step", "max_steps"],
    "solver": ["tolerance", "max_iterations", "coupling", "cascade"],
}

_values = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([math.nan, math.inf, -math.inf, -1.0, 0.0, 1e-300, 1e300, 0.25, 1.0]),
    st.integers(min_value=-(2**70), max_value=2**70),
    st.sampled_from([8, 16, 64, 128, 8192]),
    st.text(max_size=20),
    st.sampled_from(["flat_punch", "sphere", "height_map", "events", "fixed", "inf", ".", "local", "global"]),
    st.booleans(),
    st.none(),
    st.lists(st.integers(), max_size=3),
)


@st.composite
def documents(draw) -> Any:
    if draw(st.integers(0, 20)) == 0:
        return draw(_values)  # not even a table
    document: dict[Any, Any] = {}
    for section, keys in _KEYS.items():
        if draw(st.integers(0, 9)) == 0:
            continue
        if draw(st.integers(0, 19)) == 0:
            document[section] = draw(_values)
            continue
        table = {key: draw(_values) for key in keys if draw(st.booleans())}
        if draw(st.integers(0, 9)) == 0:
            table[draw(st.text(max_size=8))] = draw(_values)
        document[section] = table
    if draw(st.integers(0, 9)) == 0:
        document[draw(st.text(max_size=8))] = draw(_values)
    return document


@settings(max_examples=400, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(document=documents())
def test_any_document_parses_or_raises_config_error(tmp_path_factory, document):
    base_dir = tmp_path_factory.getbasetemp()
    try:
        config = parse_config(copy.deepcopy(document), base_dir)
    except ConfigError as error:
        assert error.problems
        assert all(isinstance(p, str) and p.startswith("`") for p in error.problems)
    else:
        assert isinstance(config, RunConfig)


@settings(max_examples=300, deadline=None)
@given(
    section_key=st.sampled_from([(s, k) for s, keys in _KEYS.items() for k in keys]),
    value=_values,
)
def test_one_mutated_key_parses_or_names_itself(tmp_path_factory, section_key, value):
    section, key = section_key
    document = valid_document()
    document.setdefault(section, {})[key] = value
    try:
        config = parse_config(document, tmp_path_factory.getbasetemp())
    except ConfigError as error:
        # The mutated key is named, or its section (rules over several keys of
        # one section), or the indenter key a grid-dependent rule is about.
        named = (f"`{section}.{key}`", f"`{section}`", "`indenter.radius`", "`indenter.file`")
        assert any(p.startswith(named) for p in error.problems), error.problems
    else:
        assert getattr(config, section) is not None


def test_three_mistakes_are_reported_in_one_pass_each_once(tmp_path):
    """A negative modulus, a misspelt key and overlapping pillars: three lines, one per mistake, one pass.

    The misspelt ``stifness_ratio`` gets a "did you mean" and its twin's
    "give exactly one of stiffness_ratio and stiffness" (which follows from
    it) is not repeated; the overlap is found on the layout keys although
    other indenter keys failed.
    """
    from brushbem.runs.assembly import load_config as full_check

    path = tmp_path / "three.toml"
    path.write_text(
        "[halfspace]\ncontact_modulus = -1.0\nwork_of_adhesion = 1.0e-4\n[grid]\nsize = 1.0\nelements = 256\n"
        '[indenter]\nshape = "brush"\nlayout = "square"\npillars_per_side = 16\npillar_radius = 0.04\n'
        "stifness_ratio = 0.455\n[protocol]\npreload_displacement = 0.002\n")
    with pytest.raises(ConfigError) as info:
        full_check(path)
    lines = info.value.problems
    assert len(lines) == 3, lines
    assert lines[0].startswith("`halfspace.contact_modulus`")
    assert lines[1].startswith("`indenter.stifness_ratio`") and "did you mean `stiffness_ratio`" in lines[1]
    assert lines[2].startswith("`indenter.pillar_radius`") and "overlap" in lines[2]
    assert not any("None" in line for line in lines)


# --------------------------------------------------------------------------- messages and unit names (issue 62)


def test_a_missing_protocol_names_what_it_needs_and_only_that_as_required():
    from brushbem.config import ConfigError, parse_config as load_mapping

    mapping = {"halfspace": {"contact_modulus": 1.0, "work_of_adhesion": 1e-3},
               "grid": {"size": 1.0, "elements": 32}, "indenter": {"shape": "flat_punch", "radius": 0.25}}
    with pytest.raises(ConfigError) as caught:
        load_mapping(mapping)
    (line,) = [line for line in str(caught.value).splitlines() if "`protocol`" in line]
    required, _, optional = line.partition("(optional: ")
    assert "exactly one of preload_displacement and preload_force" in required
    for key in ("method", "step", "max_steps", "speed"):  # defaults: not required
        assert key not in required and key in optional
    with pytest.raises(ConfigError) as caught:
        load_mapping({key: value for key, value in mapping.items() if key != "halfspace"}
                     | {"protocol": {"preload_displacement": 0.01}})
    assert "give contact_modulus, or youngs_modulus and poisson_ratio (optional: work_of_adhesion)" in str(caught.value)


@pytest.mark.parametrize("name", ["um", "µm", "μm", "micron", "micrometre", "micrometer"])
def test_the_micrometre_is_accepted_by_its_usual_names(name):
    from brushbem.config import parse_config as load_mapping

    config = load_mapping({"halfspace": {"contact_modulus": 1.0}, "grid": {"size": 1.0, "elements": 32},
                           "indenter": {"shape": "flat_punch", "radius": 0.25},
                           "protocol": {"preload_displacement": 0.01}, "units": {"length": name, "stress": "MPa"}})
    assert config.units.length == "um"  # written as UDUNITS-2's um, shown as µm
