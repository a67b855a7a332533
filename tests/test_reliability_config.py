"""Reliability of the inputs: every bad configuration, file or grid refused through the CLI.

The program is attacked from outside, as a user would: TOML files written
to disk and passed to ``brushbem validate`` (and ``brushbem run`` on small
grids).  The promise asserted every time: exit status 2, the offending key
named in the message, and no traceback.  A value that is accepted must run:
``run`` ends converged (0) or reports non-convergence with its reason (3),
never a traceback.
"""

from __future__ import annotations

import copy
import json
import math
import pickle
import re
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from click.testing import CliRunner
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from brushbem.runs.assembly import load_config
from brushbem.cli import main
from brushbem.config import (
    MAGNITUDE_RANGE,
    GradingConfig,
    GridConfig,
    HalfSpaceConfig,
    IndenterConfig,
    LevelConfig,
    PillarLawConfig,
    ProfileConfig,
    ProtocolConfig,
    RoughnessConfig,
    SolverConfig,
    TiltConfig,
    TipConfig,
    ViscoelasticConfig,
)
from brushbem.config.resources import (
    MEMORY_LIMIT_VARIABLE,
    available_memory,
    memory_estimate,
    parse_bytes,
    result_size_estimate,
)
from brushbem.physics.structure import StructureError, random_positions

# -- documents --------------------------------------------------------------------

HALFSPACE = {"contact_modulus": 1.0, "work_of_adhesion": 1e-3}
GRID = {"size": 1.0, "elements": 32}

BASES: dict[str, dict[str, Any]] = {
    "punch": {
        "halfspace": HALFSPACE, "grid": GRID,
        "indenter": {"shape": "flat_punch", "radius": 0.25, "stiffness": 0.15},
        "protocol": {"method": "fixed", "preload_displacement": 0.01, "step": 1e-3, "max_steps": 1000},
        "solver": {"tolerance": 1e-8, "max_iterations": 1000},
    },
    "sphere": {
        "halfspace": {"youngs_modulus": 1.0, "poisson_ratio": 0.3, "work_of_adhesion": 1e-3},
        "grid": GRID,
        "indenter": {"shape": "sphere", "radius": 1.0},
        "protocol": {"preload_force": 1e-3, "event_window": 1e-7},
    },
    "height_map": {
        "halfspace": HALFSPACE, "grid": GRID,
        "indenter": {"shape": "height_map", "file": "heights.npy"},
        "protocol": {"preload_displacement": 0.01},
    },
    "square_brush": {
        "halfspace": HALFSPACE, "grid": GRID,
        "indenter": {
            "shape": "brush", "layout": "square", "pillars_per_side": 4, "pillar_radius": 0.07,
            "spacing": 0.24, "region_size": 1.0, "stiffness_ratio": 0.5, "seed": 1,
            "lengths_file": "lengths.npy", "roughness": {"sigma": 1e-3},
            "profile": {"amplification": 0.01, "reference_stress": 0.01},
            "levels": [{"cluster": 2, "stiffness_ratio": 0.1}, {"cluster": 2, "stiffness": 0.2}],
        },
        "protocol": {"preload_displacement": 0.01},
    },
    "graded_tilted_brush": {
        "halfspace": HALFSPACE, "grid": GRID,
        "indenter": {
            "shape": "brush", "layout": "square", "pillars_per_side": 4, "pillar_radius": 0.07,
            "stiffness_ratio": 0.5, "tip": {"shape": "spherical_cap", "radius": 0.5},
            "tilt": {"angle": 0.5, "azimuth": 30.0},
            "grading": {"rule": "radial", "amplitude": -0.5, "exponent": 2.0},
            "levels": [{"cluster": 2, "stiffness_ratio": 0.1,
                        "grading": {"rule": "linear", "amplitude": 0.3, "azimuth": 10.0}}],
        },
        "protocol": {"preload_displacement": 0.01},
    },
    "concave_tips": {
        "halfspace": HALFSPACE, "grid": GRID,
        "indenter": {
            "shape": "brush", "layout": "square", "pillars_per_side": 4, "pillar_radius": 0.07,
            "stiffness": 0.5, "tip": {"shape": "concave", "depth": 1e-3},
            "grading": {"rule": "linear", "amplitude": 0.2, "azimuth": 45.0},
            "levels": [{"cluster": 2, "stiffness": 0.2,
                        "grading": {"rule": "radial", "amplitude": 0.5, "exponent": 1.5}}],
        },
        "protocol": {"preload_displacement": 0.01},
    },
    "viscoelastic_punch": {
        "halfspace": HALFSPACE, "grid": GRID,
        "indenter": {"shape": "flat_punch", "radius": 0.25, "stiffness": 0.15,
                     "viscoelastic": {"model": "standard_linear_solid", "relaxation_time": 1.0,
                                      "instantaneous_factor": 3.0}},
        "protocol": {"method": "fixed", "preload_displacement": 0.01, "step": 1e-3, "speed": 0.01},
    },
    "law_punch": {
        "halfspace": HALFSPACE, "grid": GRID,
        "indenter": {"shape": "flat_punch", "radius": 0.25, "stiffness": 0.15,
                     "pillar_law": {"forces": [0.002], "factors": [1.0, 0.05], "tension_limit": 0.01}},
        "protocol": {"method": "fixed", "preload_displacement": 0.01, "step": 1e-3},
    },
    "pillar_brush": {
        "halfspace": HALFSPACE, "grid": GRID,
        "indenter": {"shape": "brush", "layout": "square", "pillars_per_side": 4, "pillar_radius": 0.07,
                     "stiffness_ratio": 0.5, "seed": 1},
        "protocol": {"method": "pillars", "preload_displacement": 0.01, "pillar_near": 6.0,
                     "pillar_modes": "tilt", "pillar_solve": "kept", "pillar_tip_resolution": 4.0,
                     "pillar_tip_calibration": True},
    },
    "random_brush": {
        "halfspace": HALFSPACE, "grid": GRID,
        "indenter": {
            "shape": "brush", "layout": "random", "region": "circle", "pillar_count": 5,
            "min_gap": 0.01, "pillar_radius": 0.07, "stiffness": 0.5,
        },
        "protocol": {"preload_displacement": 0.01},
    },
}

# Values that no numeric key accepts on its own: the key itself must be named.
REFUSED_ALONE = {
    "nan": math.nan, "-inf": -math.inf, "-1": -1, "-1.0": -1.0, "-1e300": -1e300, "1e300": 1e300,
    "1e-300": 1e-300, "1e-200": 1e-200, "10**40": 10**40, "string": "1.0", "list": [1.0],
    "table": {"x": 1}, "bool": True,
}
# Values some keys accept (inf = rigid, 0 = none, 1.5 in range): accepted, or refused naming a key.
PLAUSIBLE = {"inf": math.inf, "0": 0, "0.0": 0.0, "1.5": 1.5, "2**70": 2**70, "1e-30": 1e-30, "1e30": 1e30}


def toml_value(value: Any) -> str:
    """``value`` as a TOML literal (floats round-trip, nan and inf included)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)
    if isinstance(value, list):
        return "[" + ", ".join(toml_value(item) for item in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{toml_value(k)} = {toml_value(v)}" for k, v in value.items()) + "}"
    raise TypeError(f"no TOML for {value!r}")


def to_toml(document: dict[str, Any]) -> str:
    """A document of tables of (inline) values as TOML text."""
    lines = []
    for section, table in document.items():
        if isinstance(table, dict):
            lines.append(f"[{toml_value(section)}]")
            lines.extend(f"{toml_value(key)} = {toml_value(value)}" for key, value in table.items())
        else:
            lines.insert(0, f"{toml_value(section)} = {toml_value(table)}")
    return "\n".join(lines) + "\n"


def numeric_keys(document: Any, prefix: tuple = ()) -> list[tuple]:
    """Locations of every number in ``document`` (tables and arrays of tables walked)."""
    keys = []
    items = document.items() if isinstance(document, dict) else enumerate(document)
    for key, value in items:
        if isinstance(value, (dict, list)) and not (isinstance(value, list) and value and not isinstance(value[0], dict)):
            keys.extend(numeric_keys(value, (*prefix, key)))
        elif isinstance(value, (int, float)) and not isinstance(value, bool):
            keys.append((*prefix, key))
    return keys


def with_value(document: dict[str, Any], loc: tuple, value: Any) -> dict[str, Any]:
    document = copy.deepcopy(document)
    table = document
    for part in loc[:-1]:
        table = table[part]
    table[loc[-1]] = value
    return document


def dotted(loc: tuple) -> str:
    return ".".join(str(part) for part in loc)


@pytest.fixture(scope="module")
def folder(tmp_path_factory) -> Path:
    """A folder with the files the base documents refer to."""
    path = tmp_path_factory.mktemp("configs")
    np.save(path / "heights.npy", np.zeros((32, 32)))
    np.save(path / "lengths.npy", np.linspace(0.0, 1e-3, 16))
    return path


_RUNNER = CliRunner()


def invoke(*args: str) -> Any:
    """Run the CLI in-process; fail on any traceback or uncaught exception."""
    result = _RUNNER.invoke(main, list(args))
    assert result.exception is None or isinstance(result.exception, SystemExit), (
        f"uncaught {type(result.exception).__name__}: {result.exception}\n{result.output}"
    )
    assert "Traceback" not in result.output, result.output
    return result


def validate(folder: Path, text: str | bytes, name: str = "case.toml") -> Any:
    path = folder / name
    path.write_bytes(text if isinstance(text, bytes) else text.encode())
    return invoke("validate", str(path))


def problem_lines(output: str) -> list[str]:
    return [line.strip() for line in output.splitlines() if line.startswith("  `")]


def assert_refused(result: Any, *keys: str) -> None:
    """Exit 2, every line a problem naming its key, and each of ``keys`` named."""
    assert result.exit_code == 2, result.output
    lines = problem_lines(result.output)
    assert lines, result.output
    assert "None" not in result.output, result.output
    for key in keys:
        assert any(line.startswith(f"`{key}`") for line in lines), (key, result.output)


# -- the schema is covered --------------------------------------------------------


def test_the_base_documents_cover_every_numeric_key_of_the_schema(folder):
    """A numeric key added to the schema must appear in some base document, so it is fuzzed too."""
    models = {
        "halfspace": HalfSpaceConfig, "grid": GridConfig, "indenter": IndenterConfig,
        "protocol": ProtocolConfig, "solver": SolverConfig, "indenter.roughness": RoughnessConfig,
        "indenter.profile": ProfileConfig, "indenter.levels": LevelConfig, "indenter.tip": TipConfig,
        "indenter.tilt": TiltConfig, "indenter.grading": GradingConfig, "indenter.levels.grading": GradingConfig,
        "indenter.viscoelastic": ViscoelasticConfig, "indenter.pillar_law": PillarLawConfig,
    }
    schema = {
        f"{prefix}.{name}"
        for prefix, model in models.items()
        for name, field in model.model_fields.items()
        # Arrays of numbers (a pillar law's breakpoints) are checked as a whole, in their own tests.
        if re.search(r"\b(int|float)\b", str(field.annotation)) and not str(field.annotation).startswith("tuple")
    }
    covered = {
        re.sub(r"\.\d+\.", ".", dotted(loc)) for document in BASES.values() for loc in numeric_keys(document)
    }
    assert schema <= covered, schema - covered
    for name, document in BASES.items():
        assert validate(folder, to_toml(document), f"{name}.toml").exit_code == 0, name


# -- every numeric key, every bad value -------------------------------------------


def key_of(loc: tuple) -> str:
    """The schema key at ``loc`` (a level's index dropped: every level has the same keys)."""
    return re.sub(r"\.\d+\.", ".", dotted(loc))


def _locations() -> dict[str, list[tuple[str, tuple]]]:
    """Schema key -> every (base, location) of it in the base documents, in document order."""
    found: dict[str, list[tuple[str, tuple]]] = {}
    for base, document in BASES.items():
        for loc in numeric_keys(document):
            found.setdefault(key_of(loc), []).append((base, loc))
    return found


def _cases(values: dict[str, Any]) -> list[Any]:
    """Each numeric key once with each kind of value.

    A key found in several base documents (or levels) takes them in turn, kind
    after kind, so every place a key is read is attacked too whenever there are
    at least as many kinds as places.
    """
    return [
        pytest.param(*places[i % len(places)], value, id=f"{key}={label}")
        for key, places in _locations().items()
        for i, (label, value) in enumerate(values.items())
    ]


def test_each_key_meets_each_kind_of_value_and_every_place_of_a_key_is_attacked():
    """The lists below hold every (key, kind) pair once; no base document's number is left unattacked."""
    for values in (REFUSED_ALONE, PLAUSIBLE):
        cases = [param.values for param in _cases(values)]
        pairs = {(key_of(loc), repr(value)) for _, loc, value in cases}
        assert len(pairs) == len(cases) == len(_locations()) * len(values)
    attacked = {(base, loc) for base, loc, _ in (param.values for param in _cases(REFUSED_ALONE))}
    assert attacked == {(base, loc) for base, document in BASES.items() for loc in numeric_keys(document)}


@pytest.mark.parametrize(("base", "loc", "value"), _cases(REFUSED_ALONE))
def test_a_bad_number_is_refused_naming_its_key(folder, base, loc, value):
    result = validate(folder, to_toml(with_value(BASES[base], loc, value)))
    assert_refused(result, dotted(loc))


@pytest.mark.parametrize(("base", "loc", "value"), _cases(PLAUSIBLE))
def test_a_plausible_number_is_accepted_or_refused_naming_a_key(folder, base, loc, value):
    result = validate(folder, to_toml(with_value(BASES[base], loc, value)))
    if result.exit_code != 0:
        assert_refused(result)


def test_values_outside_the_magnitude_range_state_the_range(folder):
    """grid.size = 1e-200 validated and then divided by zero in the solver; 1e300 overflowed."""
    low, high = MAGNITUDE_RANGE
    for value in (1e-200, 1e300):
        result = validate(folder, to_toml(with_value(BASES["punch"], ("grid", "size"), value)))
        assert_refused(result, "grid.size")
        assert f"between {low:g} and {high:g}" in result.output, result.output
    result = validate(folder, to_toml(with_value(BASES["random_brush"], ("indenter", "min_gap"), 1e300)))
    assert_refused(result, "indenter.min_gap")
    assert f"0 or between {low:g} and {high:g}" in result.output, result.output


def test_a_missing_stiffness_is_not_shown_as_python_none(folder):
    document = copy.deepcopy(BASES["square_brush"])
    del document["indenter"]["stiffness_ratio"]
    del document["indenter"]["levels"][0]["stiffness_ratio"]
    del document["protocol"]["preload_displacement"]
    result = validate(folder, to_toml(document))
    assert_refused(result, "indenter.stiffness_ratio", "indenter.levels.0.stiffness_ratio", "protocol")
    assert "stiffness_ratio = not given" in result.output


@pytest.mark.parametrize("base", list(BASES))
def test_every_key_missing_or_misspelt_is_refused_or_defaulted(folder, base):
    document = BASES[base]
    for loc in numeric_keys(document):
        removed = copy.deepcopy(document)
        table = removed
        for part in loc[:-1]:
            table = table[part]
        value = table.pop(loc[-1])
        result = validate(folder, to_toml(removed))
        if result.exit_code != 0:  # a required key: named, or the rule that needs it
            assert_refused(result)
        table[f"{loc[-1]}_"] = value
        assert_refused(validate(folder, to_toml(removed)), dotted((*loc[:-1], f"{loc[-1]}_")))


def test_unknown_sections_and_unicode_keys_and_values(folder):
    document = copy.deepcopy(BASES["punch"])
    document["grïd"] = {"size": 1.0}
    document["indenter"]["rädius\u200b"] = 0.25
    document["indenter"]["shape"] = "flat_pünch \U0001f600"
    document["halfspace"]["\x1b[31mred"] = 1.0
    result = validate(folder, to_toml(document))
    assert_refused(result, "grïd", "indenter.rädius\u200b", "indenter.shape")
    assert "\x1b" not in result.output  # a terminal escape in a key is shown escaped


# -- whole files ------------------------------------------------------------------


@pytest.mark.parametrize(
    ("text", "says"),
    [
        pytest.param("", "missing — a required table", id="empty"),
        pytest.param("\n\n# only a comment\n", "missing — a required table", id="comment"),
        pytest.param(bytes(range(256)) * 16, "not UTF-8", id="binary"),
        pytest.param(b"\xef\xbb\xbf[grid]\nsize = 1.0\n", "byte-order mark (U+FEFF)", id="byte-order-mark"),
        pytest.param("[grid\nsize = 1", "not valid TOML", id="truncated"),
        pytest.param("[grid]\nsize = 1.0\nsize = 2.0\n", "not valid TOML", id="duplicate-key"),
        pytest.param("x = " + "[" * 1000 + "]" * 1000, "nested too deeply", id="array-1000-deep"),
        pytest.param("x = " + "{a = " * 1000 + "1" + "}" * 1000, "nested too deeply", id="table-1000-deep"),
        pytest.param("x = " + "[" * 100 + "]" * 100, "nested more than", id="array-100-deep"),
        pytest.param("[" + ".".join(["a"] * 200) + "]\nb = 1\n", "nested more than", id="dotted-200-deep"),
    ],
)
def test_malformed_files_are_refused_without_a_traceback(folder, text, says):
    result = validate(folder, text)
    assert result.exit_code == 2, result.output
    assert says in result.output, result.output


def test_a_very_large_file_is_refused_before_it_is_parsed(folder):
    text = to_toml(BASES["punch"]) + "".join(f"# {'x' * 100}\n" for _ in range(12_000))
    result = validate(folder, text)
    assert result.exit_code == 2
    assert "larger than 1048576 bytes" in result.output


def test_thousands_of_unknown_keys_are_counted_not_listed(folder):
    document = copy.deepcopy(BASES["punch"])
    document["grid"].update({f"key{i}": i for i in range(5000)})
    result = validate(folder, to_toml(document))
    assert_refused(result, "grid.key0")
    lines = problem_lines(result.output)
    assert len(lines) == 101 and lines[-1] == "`...`: 4900 more problems not shown", lines[-3:]


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(
    text=st.one_of(
        st.text(max_size=300),
        st.binary(max_size=300),
        st.lists(
            st.tuples(st.sampled_from([*(f"[{s}]" for s in BASES["punch"]), "[indenter.profile]"]), st.text(max_size=40)),
            max_size=8,
        ).map(lambda pairs: "\n".join(f"{a}\n{b}" for a, b in pairs)),
    )
)
def test_random_text_is_valid_or_refused_with_exit_2(folder, text):
    result = validate(folder, text, "random.toml")
    assert result.exit_code in (0, 2), result.output
    if result.exit_code == 2:
        assert problem_lines(result.output), result.output


# -- height-map and lengths files ---------------------------------------------------


def _write(path: Path, kind: str) -> None:
    """A bad ``.npy`` (or not-.npy) file of the given kind at ``path``."""
    if kind == "text":
        path.write_text("0 0 0\n0 0 0\n")
    elif kind == "garbage":
        path.write_bytes(bytes(range(256)))
    elif kind == "empty":
        path.write_bytes(b"")
    elif kind == "truncated":
        np.save(path, np.zeros((32, 32)))
        path.write_bytes(path.read_bytes()[:300])
    elif kind == "npz":
        with path.open("wb") as stream:
            np.savez(stream, a=np.zeros(3))
    elif kind == "pickle":
        path.write_bytes(pickle.dumps(np.zeros((32, 32))))
    elif kind == "object":
        np.save(path, np.array([{"a": 1}] * 16, dtype=object), allow_pickle=True)
    elif kind == "complex":
        np.save(path, np.zeros((32, 32), dtype=complex))
    elif kind == "bool":
        np.save(path, np.zeros((32, 32), dtype=bool))
    elif kind == "strings":
        np.save(path, np.array(["a"] * 16))
    elif kind == "nan":
        values = np.zeros((32, 32))
        values[3, 4] = np.nan
        np.save(path, values)
    elif kind == "inf":
        np.save(path, np.full((32, 32), np.inf))
    elif kind == "huge":
        np.save(path, np.full((32, 32), 1e300))
    elif kind == "3d":
        np.save(path, np.zeros((2, 32, 32)))
    elif kind == "scalar":
        np.save(path, np.float64(1.0))
    else:
        raise ValueError(kind)


BAD_FILE_KINDS = {
    "text": "not a .npy file", "garbage": "not a .npy file", "empty": "not a .npy file",
    "truncated": "cannot be read as a .npy array", "npz": "not a .npy file", "pickle": "not a .npy file",
    "object": "never unpickles", "complex": "must hold real numbers", "bool": "must hold real numbers",
    "strings": "must hold real numbers", "nan": "must hold finite values", "inf": "must hold finite values",
    "huge": "must be at most 1e+30", "3d": "shape", "scalar": "shape",
}


@pytest.mark.parametrize(("shape", "key"), [("height_map", "indenter.file"), ("square_brush", "indenter.lengths_file")])
@pytest.mark.parametrize("kind", list(BAD_FILE_KINDS))
def test_a_bad_data_file_is_refused_naming_the_key_and_the_file(tmp_path, shape, key, kind):
    name = f"bad_{kind}.npy"
    _write(tmp_path / name, kind)
    np.save(tmp_path / "lengths.npy", np.zeros(16))
    np.save(tmp_path / "heights.npy", np.zeros((32, 32)))
    result = validate(tmp_path, to_toml(with_value(BASES[shape], tuple(key.split(".")), name)))
    assert_refused(result, key)
    assert BAD_FILE_KINDS[kind] in result.output, result.output
    assert name in result.output


def test_a_pickled_object_array_is_never_unpickled(tmp_path, monkeypatch):
    """An object array in a .npy is a pickle: refused from its header, its pickle never run."""
    ran = tmp_path / "ran"

    class Payload:
        def __reduce__(self):
            return (Path.touch, (ran,))

    np.save(tmp_path / "tip.npy", np.array([Payload()] * 4, dtype=object), allow_pickle=True)
    assert not ran.exists()
    monkeypatch.setattr(np, "load", _refuse_pickles(np.load))
    result = validate(tmp_path, to_toml(with_value(BASES["height_map"], ("indenter", "file"), "tip.npy")))
    assert_refused(result, "indenter.file")
    assert "never unpickles (allow_pickle is off)" in result.output
    assert not ran.exists()


def _refuse_pickles(load):
    def checked(*args, allow_pickle=False, **kwargs):
        assert not allow_pickle, "np.load called with allow_pickle=True"
        return load(*args, allow_pickle=allow_pickle, **kwargs)
    return checked


@pytest.mark.parametrize(("shape", "key"), [("height_map", "indenter.file"), ("square_brush", "indenter.lengths_file")])
def test_a_missing_file_a_folder_or_a_device_is_refused(tmp_path, shape, key):
    np.save(tmp_path / "lengths.npy", np.zeros(16))
    np.save(tmp_path / "heights.npy", np.zeros((32, 32)))
    (tmp_path / "folder.npy").mkdir()
    for name, says in [("absent.npy", "file not found"), ("folder.npy", "is a folder"), ("", "is a folder"),
                       ("/dev/null", "not a regular file"), ("a\x00b.npy", "not a usable path")]:
        document = with_value(BASES[shape], tuple(key.split(".")), name)
        text = to_toml(document)
        result = validate(tmp_path, text)
        assert_refused(result, key)
        assert says in result.output, (name, result.output)


def test_wrong_lengths_and_heights_shapes_name_the_file(tmp_path):
    np.save(tmp_path / "heights.npy", np.zeros((16, 16)))
    np.save(tmp_path / "lengths.npy", np.zeros(5))
    result = validate(tmp_path, to_toml(BASES["height_map"]))
    assert_refused(result, "indenter.file")
    assert "heights.npy" in result.output and "16 x 16" in result.output
    document = with_value(BASES["square_brush"], ("indenter", "lengths_file"), "lengths.npy")
    result = validate(tmp_path, to_toml(document))
    assert_refused(result, "indenter.lengths_file")
    assert "lengths.npy" in result.output and "holds 5 values; must hold 16" in result.output


def test_paths_resolve_against_the_config_folder_and_may_leave_it(tmp_path):
    """Relative names are read from the configuration's folder; a path outside it is allowed."""
    inside = tmp_path / "case"
    shared = tmp_path / "shared"
    inside.mkdir()
    shared.mkdir()
    np.save(shared / "heights.npy", np.zeros((32, 32)))
    for name in ("../shared/heights.npy", str(shared / "heights.npy")):
        (inside / "case.toml").write_text(to_toml(with_value(BASES["height_map"], ("indenter", "file"), name)))
        assert invoke("validate", str(inside / "case.toml")).exit_code == 0
        assert load_config(inside / "case.toml").indenter.file == str(shared / "heights.npy")
    (inside / "case.toml").write_text(to_toml(BASES["height_map"]))  # heights.npy: not in case/
    result = invoke("validate", str(inside / "case.toml"))
    assert_refused(result, "indenter.file")
    assert str(inside / "heights.npy") in result.output


# -- random layouts: refused up front, bounded search -------------------------------


def test_a_random_layout_that_cannot_fit_is_refused_before_any_draw(folder):
    """pillar_count = 1000000 searched at random without end; now the area is checked first."""
    document = with_value(BASES["random_brush"], ("indenter", "pillar_count"), 1_000_000)
    result = validate(folder, to_toml(document))
    assert_refused(result, "indenter.pillar_count")
    assert "cannot fit" in result.output and "pillar_radius" in result.output and "min_gap" in result.output


def test_a_random_layout_beyond_the_jamming_limit_stops_after_its_draws():
    """Fits by area (0.8 of the densest packing) but not at random: a bounded search, named keys."""
    rng = np.random.default_rng(0)
    with pytest.raises(StructureError) as caught:
        random_positions(60, 0.05, 0.0, "square", 1.0, rng, max_attempts_per_pillar=50)
    assert caught.value.key == "pillar_count"
    assert "after 3072 draws" in str(caught.value) and "min_gap" in str(caught.value)


def test_random_layouts_keep_their_distance():
    rng = np.random.default_rng(3)
    centres = random_positions(2000, 0.004, 0.002, "circle", 1.0, rng)
    gaps = np.linalg.norm(centres[:, None] - centres[None], axis=2) + np.eye(len(centres))
    assert gaps.min() >= 0.01 and np.all(np.hypot(*centres.T) <= 0.5 - 0.004)


# -- resources ---------------------------------------------------------------------


def test_a_grid_beyond_the_memory_limit_is_refused_with_the_estimate(folder, monkeypatch):
    document = with_value(BASES["punch"], ("grid", "elements"), 1024)
    monkeypatch.setenv(MEMORY_LIMIT_VARIABLE, "200M")
    result = validate(folder, to_toml(document))
    assert_refused(result, "grid.elements")
    assert "1024 x 1024 elements needs about" in result.output
    assert "200 MiB of BRUSHBEM_MEMORY_LIMIT=200M" in result.output
    monkeypatch.setenv(MEMORY_LIMIT_VARIABLE, "off")
    assert validate(folder, to_toml(document)).exit_code == 0


def test_run_refuses_the_grid_before_computing(folder, monkeypatch, tmp_path):
    monkeypatch.setenv(MEMORY_LIMIT_VARIABLE, "1M")
    (tmp_path / "case.toml").write_text(to_toml(BASES["punch"]))
    result = invoke("run", str(tmp_path / "case.toml"), "--out", str(tmp_path / "out"))
    assert_refused(result, "grid.elements")
    assert not (tmp_path / "out" / "result.nc").exists()


@pytest.mark.parametrize("setting", ["lots", "-5G", "0", "1e-3", "1e400", "5 GB extra", "nan"])
def test_a_bad_memory_limit_is_refused_naming_the_variable(folder, monkeypatch, setting):
    monkeypatch.setenv(MEMORY_LIMIT_VARIABLE, setting)
    result = validate(folder, to_toml(BASES["punch"]))
    assert_refused(result, MEMORY_LIMIT_VARIABLE)


def test_memory_limit_units():
    assert parse_bytes("8589934592") == parse_bytes("8G") == parse_bytes("8 GiB") == parse_bytes("8gb") == 8 << 30
    assert parse_bytes("512M") == 512 << 20 and parse_bytes("1.5k") == 1536


def test_available_memory_is_read_from_the_system(monkeypatch):
    monkeypatch.delenv(MEMORY_LIMIT_VARIABLE, raising=False)
    limit, source = available_memory()
    if Path("/proc/meminfo").exists():
        assert limit is not None and limit > 0 and source


def test_the_estimate_grows_with_the_grid(folder):
    small = load_config(_written(folder, BASES["sphere"], "small.toml"))
    large = load_config(_written(folder, with_value(BASES["sphere"], ("grid", "elements"), 4096), "large.toml"))
    assert memory_estimate(large) > 10 * memory_estimate(small) > 0
    assert 2.6e9 < memory_estimate(large) < 6.5e9  # measured: 2.6 GB peak at N = 4096
    assert result_size_estimate(large) == 16 * result_size_estimate(
        load_config(_written(folder, with_value(BASES["sphere"], ("grid", "elements"), 1024), "mid.toml")))


def _written(folder: Path, document: dict[str, Any], name: str) -> Path:
    (folder / name).write_text(to_toml(document))
    return folder / name


# -- accepted extremes run without a traceback -------------------------------------------


_RUN_VALUES = {"1e-30": 1e-30, "1e30": 1e30, "0": 0.0, "inf": math.inf}


def _run_cases() -> list[Any]:
    cases = []
    for base in ("punch", "sphere", "random_brush"):
        for loc in numeric_keys(BASES[base]):
            if loc[0] == "grid" and loc[1] == "elements":
                continue
            for label, value in _RUN_VALUES.items():
                cases.append(pytest.param(base, loc, value, id=f"{base}:{dotted(loc)}={label}"))
    return cases


@pytest.mark.slow
@pytest.mark.parametrize(("base", "loc", "value"), _run_cases())
def test_an_accepted_extreme_value_runs_to_an_answer(tmp_path, base, loc, value):
    """What validate accepts, run finishes: converged (0), or not converged with a reason (3)."""
    document = with_value(BASES[base], loc, value)
    if base != "punch":
        document["protocol"] = {**document["protocol"], "max_steps": 2000}
    document["grid"] = {**document["grid"], "elements": 16} if loc[0] != "grid" else document["grid"]
    config = tmp_path / "case.toml"
    config.write_text(to_toml(document))
    if invoke("validate", str(config)).exit_code != 0:
        return
    result = invoke("run", str(config), "--out", str(tmp_path / "out"), "--quiet")
    assert result.exit_code in (0, 3), result.output
    if result.exit_code == 3:
        assert "did not converge (" in result.output
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert summary["converged"] == (result.exit_code == 0)


def test_a_byte_order_mark_is_refused_with_what_to_do(folder):
    result = validate(folder, b"\xef\xbb\xbf" + to_toml(BASES["punch"]).encode(), name="bom.toml")
    assert result.exit_code == 2 and "byte-order mark" in result.output and "without BOM" in result.output


# -- the newer keys under the same attacks --------------------------------------------
#
# One list of (TOML snippet, key the refusal must name), validated only (no pull-off).  A snippet's
# lines ``dotted.key = value`` are set on a flat, elastic 4 x 4 brush (`NEW_BASE`), ``-dotted.key``
# removes a key; the prefixes below switch the protocol or the shape a table needs.

NEW_BASE = {
    "halfspace.contact_modulus": "1.0", "halfspace.work_of_adhesion": "1e-3",
    "grid.size": "1.0", "grid.elements": "32",
    "indenter.shape": '"brush"', "indenter.layout": '"square"', "indenter.pillars_per_side": "4",
    "indenter.pillar_radius": "0.07", "indenter.stiffness_ratio": "0.5",
    "protocol.preload_displacement": "0.01",
}
PUNCH = ('indenter.shape = "flat_punch"\nindenter.radius = 0.25\nindenter.stiffness = 0.15\n-indenter.layout\n'
         "-indenter.pillars_per_side\n-indenter.pillar_radius\n-indenter.stiffness_ratio\n")
RIGID = "-indenter.stiffness_ratio\nindenter.stiffness = inf\n"
FIXED = 'protocol.method = "fixed"\nprotocol.step = 1e-3\n'
VISCO = FIXED + "protocol.speed = 0.01\n"
KV = 'indenter.viscoelastic = {model = "kelvin_voigt", relaxation_time = 1.0}\n'
LAW = "indenter.pillar_law = {forces = [0.002], factors = [1.0, 0.5]}\n"
LEVEL = "indenter.levels = [{cluster = 2, stiffness_ratio = 0.1, grading = %s}]"


def _tip(text: str) -> str:
    return f'indenter.tip = {{shape = "spherical_cap", radius = {text}}}'


def _grading(text: str) -> str:
    return f'indenter.grading = {{rule = "radial", {text}}}'


def _law(text: str) -> str:
    return FIXED + f"indenter.pillar_law = {{{text}}}"


def _visco(text: str) -> str:
    return VISCO + f"indenter.viscoelastic = {{{text}}}"


NEW_KEY_ATTACKS = [
    # [indenter.tip]
    ("indenter.tip = 5", "indenter.tip"),
    ("indenter.tip = {}", "indenter.tip.shape"),
    ("indenter.tip = {shape = 1}", "indenter.tip.shape"),
    ('indenter.tip = {shape = ""}', "indenter.tip.shape"),
    ('indenter.tip = {shape = "cone"}', "indenter.tip.shape"),
    ('indenter.tip = {shape = ["flat"]}', "indenter.tip.shape"),
    ('indenter.tip = {shape = "spherical_cap"}', "indenter.tip.radius"),
    *((_tip(v), "indenter.tip.radius") for v in (
        "nan", "inf", "-inf", "-0.5", "0.0", "0", "-3", "1e300", "1e-300", "true", "[0.5]", "{r = 1}", '""',
        '"missing.npy"', '"negative.npy"', '"matrix.npy"', '"five.npy"', '"text.npy"')),
    ('indenter.tip = {shape = "spherical_cap", radius = 0.5, colour = 1}', "indenter.tip.colour"),
    ('indenter.tip = {shape = "spherical_cap", radius = 0.5, depth = 1e-3}', "indenter.tip.depth"),
    *((f'indenter.tip = {{shape = "concave", depth = {v}}}', "indenter.tip.depth") for v in (
        "nan", "-1e-3", "0.0", "1e300", '"five.npy"')),
    *((f'indenter.tip = {{shape = "profile", file = {v}}}', "indenter.tip.file") for v in (
        "3", '""', '"missing.npy"', '"matrix.npy"', '"negative.npy"', '["a.npy"]')),
    ('indenter.tip = {shape = "flat", radius = 0.5}', "indenter.tip.radius"),
    (PUNCH + 'indenter.tip = {shape = "spherical_cap", radius = 0.5}', "indenter.tip"),
    # [indenter.tilt]
    ("indenter.tilt = 5", "indenter.tilt"),
    ("indenter.tilt = {}", "indenter.tilt.angle"),
    *((f"indenter.tilt = {{angle = {v}}}", "indenter.tilt.angle") for v in (
        "nan", "inf", "-1.0", "45.0", "1e300", "1e-300", '"1"', "true", "[1.0]")),
    *((f"indenter.tilt = {{angle = 1.0, azimuth = {v}}}", "indenter.tilt.azimuth") for v in (
        "nan", "-1.0", "360.0", "1e300", '"0"')),
    ("indenter.tilt = {angle = 1.0, spin = 1.0}", "indenter.tilt.spin"),
    (PUNCH + "indenter.tilt = {angle = 1.0}", "indenter.tilt"),
    # [indenter.grading] and a level's grading
    ("indenter.grading = 5", "indenter.grading"),
    ("indenter.grading = {}", "indenter.grading.rule"),
    *((f"indenter.grading = {{rule = {v}, amplitude = 0.5}}", "indenter.grading.rule") for v in (
        "1", '""', '"spiral"', '["radial"]')),
    ('indenter.grading = {rule = "radial"}', "indenter.grading.amplitude"),
    *((_grading(f"amplitude = {v}"), "indenter.grading.amplitude") for v in (
        "nan", "inf", "-1.0", "-2.0", "1e300", "1e-300", '"0.5"', "true", "[0.5]")),
    *((_grading(f"amplitude = 0.5, exponent = {v}"), "indenter.grading.exponent") for v in (
        "nan", "0.0", "-1.0", "1e300", '"2"')),
    (_grading("amplitude = 0.5, azimuth = 10.0"), "indenter.grading.azimuth"),
    ('indenter.grading = {rule = "linear", amplitude = 1.0}', "indenter.grading.amplitude"),
    ('indenter.grading = {rule = "linear", amplitude = 0.5, azimuth = 360.0}', "indenter.grading.azimuth"),
    ('indenter.grading = {rule = "linear", amplitude = 0.5, exponent = 2.0}', "indenter.grading.exponent"),
    ('indenter.grading = {rule = "file"}', "indenter.grading.file"),
    *((f'indenter.grading = {{rule = "file", file = {v}}}', "indenter.grading.file") for v in (
        "3", '""', '"missing.npy"', '"five.npy"', '"negative.npy"', '"matrix.npy"', '"text.npy"')),
    ('indenter.grading = {rule = "file", file = "ones.npy", amplitude = 0.5}', "indenter.grading.amplitude"),
    (_grading("amplitude = 0.5, bogus = 1"), "indenter.grading.bogus"),
    (RIGID + _grading("amplitude = 0.5"), "indenter.grading"),  # a rigid level stays rigid
    ("indenter.pillars_per_side = 1\n" + _grading("amplitude = 0.5"), "indenter.grading"),  # one pillar
    ('indenter.pillars_per_side = 1\nindenter.grading = {rule = "linear", amplitude = 0.5}', "indenter.grading"),
    ("indenter.levels = 5", "indenter.levels"),
    ("indenter.levels = [5]", "indenter.levels.0"),
    (LEVEL % 7, "indenter.levels.0.grading"),
    (LEVEL % '{rule = "radial", amplitude = nan}', "indenter.levels.0.grading.amplitude"),
    (LEVEL % '{rule = "linear", amplitude = -1.5}', "indenter.levels.0.grading.amplitude"),
    (LEVEL % '{rule = "file", file = "ones.npy"}', "indenter.levels.0.grading.file"),  # 16 for 4 clusters
    ('indenter.levels = [{cluster = 4, stiffness_ratio = 0.1, grading = {rule = "radial", amplitude = 0.5}}]',
     "indenter.levels.0.grading"),  # one cluster
    ('indenter.levels = [{cluster = 2, stiffness = inf, grading = {rule = "radial", amplitude = 0.5}}]',
     "indenter.levels.0.grading"),  # a rigid level
    ('indenter.grading = {rule = "file", file = "one_soft.npy"}', "indenter.grading.file"),  # 1e-12: unresolvable
    (_grading("amplitude = -0.999999999999"), "indenter.grading.amplitude"),
    (PUNCH + _grading("amplitude = 0.5"), "indenter.grading"),
    # [indenter.pillar_law]
    ("indenter.pillar_law = 5", "indenter.pillar_law"),
    *((_law(f"forces = {v}, factors = [1.0, 0.5]"), "indenter.pillar_law.forces") for v in (
        "1.0", '"a"', "[true]", "[[1.0]]", "{a = 1}", "[nan]", "[inf]", "[1e300]", "[-1e300]", "[1e-300]", "[1e31]")),
    (_law("forces = [0.2, 0.1], factors = [1.0, 0.5, 0.2]"), "indenter.pillar_law.forces"),
    *((_law(f"forces = [0.002], factors = {v}"), "indenter.pillar_law.factors") for v in (
        "2.0", "[]", "[nan, 1.0]", "[inf, 1.0]", "[0.0, 1.0]", "[-1.0, 1.0]", "[1e300, 1.0]", "[1e-300, 1.0]",
        '["x", 1.0]', "[1.0]")),
    *((_law(f"tension_limit = {v}"), "indenter.pillar_law.tension_limit") for v in (
        "nan", "inf", "-1.0", "0.0", "1e300", "1e-300", '"1"', "true")),
    (_law("slope = 1"), "indenter.pillar_law.slope"),
    ("protocol.step = 1e-3\n" + LAW, "protocol.method"),  # the law is followed step by step
    (FIXED + "-protocol.preload_displacement\nprotocol.preload_force = 0.01\n" + LAW, "protocol.preload_force"),
    (FIXED + RIGID + LAW, "indenter.stiffness"),
    # [indenter.viscoelastic]
    (VISCO + "indenter.viscoelastic = 5", "indenter.viscoelastic"),
    (_visco(""), "indenter.viscoelastic.model"),
    *((_visco(f"model = {v}, relaxation_time = 1.0"), "indenter.viscoelastic.model") for v in (
        "1", '""', '"maxwell"')),
    (_visco('model = "kelvin_voigt"'), "indenter.viscoelastic.relaxation_time"),
    *((_visco(f'model = "kelvin_voigt", relaxation_time = {v}'), "indenter.viscoelastic.relaxation_time")
      for v in ("nan", "inf", "-1.0", "0.0", "1e300", "1e-300", '"1"', "true")),
    (_visco('model = "kelvin_voigt", relaxation_time = 1.0, instantaneous_factor = 2.0'),
     "indenter.viscoelastic.instantaneous_factor"),
    *((_visco(f'model = "standard_linear_solid", relaxation_time = 1.0{v}'),
       "indenter.viscoelastic.instantaneous_factor")
      for v in ("", ", instantaneous_factor = 1.0", ", instantaneous_factor = 0.5", ", instantaneous_factor = inf",
                ", instantaneous_factor = nan", ", instantaneous_factor = 1e300")),
    (_visco('model = "kelvin_voigt", relaxation_time = 1.0, bogus = 2'), "indenter.viscoelastic.bogus"),
    (FIXED + KV, "protocol.speed"),  # no pulling speed
    ("protocol.speed = 0.01", "protocol.speed"),  # a speed without viscoelastic pillars
    ("protocol.speed = 0.01\n" + KV, "protocol.method"),
    (VISCO + KV + LAW, "indenter.pillar_law"),
    (VISCO + RIGID + KV, "indenter.stiffness"),
    # the protocol's extremes
    *((f"protocol.preload_displacement = {v}", "protocol.preload_displacement") for v in ("1e29", "1001.0")),
    *((f"-protocol.preload_displacement\nprotocol.preload_force = {v}", "protocol.preload_force")
      for v in ("1e29", "1e12")),
    *((f'protocol.method = "fixed"\nprotocol.step = {v}', "protocol.step") for v in ("1e-12", "2.0")),
    ('protocol.method = "fixed"\nprotocol.step = 1e-12\n-protocol.preload_displacement\nprotocol.preload_force = '
     "0.01", "protocol.step"),
    ('protocol.method = "fixed"\nprotocol.max_steps = 5\nprotocol.preload_displacement = 100.0', "protocol.max_steps"),
]


def snippet_document(snippet: str) -> str:
    """`NEW_BASE` with the snippet's keys set (``-key`` removes one), as TOML of dotted keys."""
    document = dict(NEW_BASE)
    for line in snippet.splitlines():
        if line.startswith("-"):
            document.pop(line[1:].strip(), None)
        elif line.strip():
            key, _, value = line.partition(" = ")
            document[key.strip()] = value
    return "".join(f"{key} = {value}\n" for key, value in document.items())


@pytest.fixture(scope="module")
def new_key_folder(tmp_path_factory) -> Path:
    """A folder with the per-pillar files the attacks name (16 pillars of the 4 x 4 brush)."""
    path = tmp_path_factory.mktemp("new_keys")
    np.save(path / "ones.npy", np.ones(16))
    np.save(path / "five.npy", np.ones(5))
    np.save(path / "negative.npy", np.linspace(-1.0, 1.0, 16))
    np.save(path / "matrix.npy", np.ones((4, 4)))
    one_soft = np.ones(16)
    one_soft[5] = 1e-12
    np.save(path / "one_soft.npy", one_soft)
    (path / "text.npy").write_text("1 2 3\n")
    return path


def assert_named_with_value_and_range(result: Any, key: str) -> None:
    """Refused naming ``key``; every line names a key, a value and what is allowed, in words."""
    assert_refused(result, key)
    for line in problem_lines(result.output):
        found = re.fullmatch(r"`([^`]+)`: (.+?) — (.+)", line)
        assert found is not None, line
        assert found.group(3) not in ("must be a value", "must be a string"), line
    for mark in ("must be a value", "Config(", "``:", "Traceback"):
        assert mark not in result.output, (mark, result.output)


def test_the_attacks_reach_every_key_of_the_newer_tables():
    """Each key of tip, tilt, grading, pillar law and viscoelastic tables is attacked at least once."""
    tables = {"tip": TipConfig, "tilt": TiltConfig, "grading": GradingConfig, "pillar_law": PillarLawConfig,
              "viscoelastic": ViscoelasticConfig}
    named = {key for _, key in NEW_KEY_ATTACKS}
    for table, model in tables.items():
        for field in model.model_fields:
            assert f"indenter.{table}.{field}" in named, (table, field)


@pytest.mark.parametrize(("snippet", "key"), [pytest.param(s, k, id=f"{k}:{s.splitlines()[-1][-48:]}")
                                              for s, k in NEW_KEY_ATTACKS])
def test_a_bad_value_of_a_newer_key_is_refused_naming_key_value_and_range(new_key_folder, snippet, key):
    result = validate(new_key_folder, snippet_document(snippet))
    assert_named_with_value_and_range(result, key)


def test_the_new_key_base_is_valid(new_key_folder):
    assert validate(new_key_folder, snippet_document("")).exit_code == 0
    for snippet in (_tip('"ones.npy"'), LEVEL % '{rule = "radial", amplitude = 0.5}', FIXED + LAW, VISCO + KV,
                    'indenter.grading = {rule = "file", file = "ones.npy"}', "indenter.tilt = {angle = 1.0}"):
        result = validate(new_key_folder, snippet_document(snippet))
        assert result.exit_code == 0, (snippet, result.output)


# `brushbem design` and `run --refine`: options refused by name before anything runs.
CLI_ATTACKS = [
    (("design", "--target", ""), "--target"),
    (("design", "--target", "sideways"), "--target"),
    (("design", "--target", "1"), "--target"),
    *((("design", "--iterations", v), "--iterations") for v in ("-1", "51", "nan", "", "1e300", "2.5", "inf")),
    *((("run", "--refine", v), "--refine") for v in ("1", "4", "-2", "", "nan", "x", "2.5")),
]


@pytest.mark.parametrize(("args", "option"), CLI_ATTACKS)
def test_a_bad_design_or_refine_option_is_refused_naming_it(new_key_folder, tmp_path, args, option):
    config = new_key_folder / "base.toml"
    config.write_text(snippet_document(""))
    result = invoke(args[0], str(config), "--out", str(tmp_path / "out"), *args[1:])
    assert result.exit_code == 2, result.output
    assert option in result.output, result.output
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize(("snippet", "says"), [
    ("indenter.pillars_per_side = 1", "one pillar"),
    ('indenter.tip = {shape = "concave", depth = 1e-3}', "indenter.tip"),
    ("halfspace.work_of_adhesion = 0.0", "work_of_adhesion"),
    (VISCO + KV, "viscoelastic"),
])
def test_a_brush_the_design_cannot_handle_is_refused_before_any_pull_off(new_key_folder, tmp_path, snippet, says):
    config = new_key_folder / "design.toml"
    config.write_text(snippet_document(snippet))
    result = invoke("design", str(config), "--out", str(tmp_path / "out"), "--quiet")
    assert result.exit_code == 2, result.output
    assert says in result.output, result.output


# -- extremes refused with their range (issue: a preload of 1e29 ran to F_A = 0 "converged") ------------


def test_an_extreme_preload_is_refused_with_its_range(folder):
    """A preload beyond 1000 domain sizes: the displacement's rounding swamps the pull-off (a punch
    pressed to 1e29 gave F_A = 0 "converged"; one pressed by a force of 1e12 was 0.5 % off)."""
    result = validate(folder, to_toml(with_value(BASES["punch"], ("protocol", "preload_displacement"), 1e29)))
    assert_refused(result, "protocol.preload_displacement")
    assert "must be in (0, 1000]" in result.output and "1e+29" in result.output
    document = copy.deepcopy(BASES["punch"])
    del document["protocol"]["preload_displacement"]
    document["protocol"]["preload_force"] = 1e29
    result = validate(folder, to_toml(document))
    assert_refused(result, "protocol.preload_force")
    assert "must be in (0, 1.41e+03]" in result.output
    # The edge of the range and a force well inside it are accepted.
    edge = with_value(BASES["punch"], ("protocol", "preload_displacement"), 1000.0)
    edge["protocol"]["method"] = "events"
    assert validate(folder, to_toml(edge)).exit_code == 0
    document["protocol"]["preload_force"] = 1.0
    assert validate(folder, to_toml(document)).exit_code == 0


def test_a_fixed_step_too_small_for_max_steps_is_refused_with_its_range(folder):
    """step = 1e-12 on a preload of 1e-3 is 1e9 steps: refused with the range of steps that fit."""
    document = with_value(BASES["punch"], ("protocol", "step"), 1e-12)
    document["protocol"]["max_steps"] = 200_000
    result = validate(folder, to_toml(document))
    assert_refused(result, "protocol.step")
    assert "must be in [5e-08, 1]" in result.output, result.output
    # A preload force bounds the depth from below: the same refusal (it was accepted).
    del document["protocol"]["preload_displacement"]
    document["protocol"]["preload_force"] = 0.01
    result = validate(folder, to_toml(document))
    assert_refused(result, "protocol.step")
    assert "must be in [" in result.output and "at least" in result.output, result.output


@pytest.mark.parametrize(("law", "key"), [
    ({"forces": [1e300], "factors": [1.0, 0.5]}, "forces"),
    ({"forces": [-1e31], "factors": [1.0, 0.5]}, "forces"),
    ({"forces": 1.0, "factors": [1.0, 0.5]}, "forces"),  # a traceback
    ({"forces": [0.1], "factors": [math.nan, 0.5]}, "factors"),  # was reported under forces
    ({"forces": [0.1], "factors": 2.0}, "factors"),
])
def test_pillar_law_values_beyond_the_documented_limit_are_refused_by_key(folder, law, key):
    """Each of the law's arrays names its own key, the value and the documented range (1e30)."""
    document = copy.deepcopy(BASES["law_punch"])
    document["indenter"]["pillar_law"] = law
    result = validate(folder, to_toml(document))
    assert_refused(result, f"indenter.pillar_law.{key}")
    assert "1e+30" in result.output and "must be a value" not in result.output, result.output
    other = "factors" if key == "forces" else "forces"
    assert not any(line.startswith(f"`indenter.pillar_law.{other}`") for line in problem_lines(result.output))


# -- no silent no-ops, messages that name key, value and range ----------------------------------


@pytest.mark.parametrize(("snippet", "says"), [
    (RIGID + _grading("amplitude = 0.5"), "rigid"),
    ("indenter.pillars_per_side = 1\n" + _grading("amplitude = 0.5"), "one spring"),
    ('indenter.layout = "random"\n-indenter.pillars_per_side\nindenter.pillar_count = 1\n' + _grading("amplitude = 0.5"),
     "one spring"),
    ('indenter.levels = [{cluster = 4, stiffness_ratio = 0.1, grading = {rule = "radial", amplitude = 0.5}}]',
     "one spring"),
    ('indenter.levels = [{cluster = 2, stiffness = inf, grading = {rule = "linear", amplitude = 0.5}}]', "rigid"),
])
def test_a_grading_that_can_have_no_effect_is_refused(new_key_folder, snippet, says):
    """Grading rigid springs, a single pillar or a single cluster did nothing, without a word."""
    result = validate(new_key_folder, snippet_document(snippet))
    assert_named_with_value_and_range(result, "indenter.levels.0.grading" if "levels" in snippet else "indenter.grading")
    assert says in result.output and "{'rule': " in result.output, result.output


def test_a_table_in_a_message_is_shown_as_given_not_as_a_model(new_key_folder):
    result = validate(new_key_folder, snippet_document(PUNCH + _grading("amplitude = 0.5")))
    assert_refused(result, "indenter.grading")
    assert "`indenter.grading`: {'rule': 'radial', 'amplitude': 0.5} — only used when shape = 'brush'" in result.output
    result = validate(new_key_folder, snippet_document(FIXED + RIGID + LAW))  # was "``: {'halfspace': ..."
    assert problem_lines(result.output) == [
        "`indenter.stiffness`: inf — must be finite with indenter.pillar_law (its slopes are factors of it)"]


def test_a_per_pillar_file_names_its_key_its_file_and_what_is_wrong(new_key_folder):
    result = validate(new_key_folder, snippet_document(_tip('"five.npy"')))  # was `indenter.tip`: '5 values'
    assert_refused(result, "indenter.tip.radius")
    assert "five.npy" in result.output and "holds 5 values; must hold one per pillar (16)" in result.output
    result = validate(new_key_folder, snippet_document(_tip('"negative.npy"')))  # the shape was shown
    assert "holds values down to -1" in result.output and "shape" not in result.output, result.output
    result = validate(new_key_folder, snippet_document(LEVEL % '{rule = "file", file = "ones.npy"}'))
    assert_refused(result, "indenter.levels.0.grading.file")  # was `indenter.levels.grading.file`: '16 values'
    assert "ones.npy" in result.output and "holds 16 values" in result.output


def test_the_memory_limit_message_shows_the_value_given(folder, monkeypatch):
    monkeypatch.setenv(MEMORY_LIMIT_VARIABLE, "1e-3")
    result = validate(folder, to_toml(BASES["punch"]))
    assert_refused(result, MEMORY_LIMIT_VARIABLE)
    assert "'1e-3'" in result.output and "0 B" not in result.output, result.output


# -- springs too soft for double precision: refused alike, however soft ---------------------------


@pytest.mark.parametrize("factor", [3e-9, 1e-9, 1e-12, 1e-15, 1e-20, 1e-30])
def test_every_pillar_too_soft_to_resolve_is_refused_alike(new_key_folder, factor):
    """One pillar graded by 1e-9 failed its run (exit 3) while one graded by 1e-12 ran to "converged":
    the solver's check sees only a residual that has not already rounded to zero.  Every factor
    below the bound is now refused at validation, naming the grading file and the smallest k."""
    factors = np.ones(16)
    factors[5] = factor
    np.save(new_key_folder / "soft.npy", factors)
    result = validate(new_key_folder, snippet_document('indenter.grading = {rule = "file", file = "soft.npy"}'))
    assert_named_with_value_and_range(result, "indenter.grading.file")
    assert "too soft to resolve" in result.output and "k >= " in result.output, result.output


def test_a_soft_pillar_the_solver_resolves_is_accepted(new_key_folder):
    """The refusal has a margin below the solver's own floor: a factor of 1e-7 converges, and is accepted."""
    factors = np.ones(16)
    factors[5] = 1e-7
    np.save(new_key_folder / "resolved.npy", factors)
    assert validate(new_key_folder, snippet_document('indenter.grading = {rule = "file", file = "resolved.npy"}')
                    ).exit_code == 0


def test_the_spring_floor_is_the_solvers():
    from brushbem.config.limits import SPRING_ROUNDING_FLOOR
    from brushbem.numerics.solver import ROUNDING_FLOOR

    assert SPRING_ROUNDING_FLOOR == ROUNDING_FLOOR


@pytest.mark.parametrize(("table", "key", "value"), [
    ("solver", "tolerance", 1e-6), ("solver", "max_iterations", 50), ("solver", "coupling", "discriminant"), ("solver", "cascade", "global"),
    ("protocol", "step", 1e-5),
])
def test_the_pillar_model_refuses_keys_it_does_not_use(table, key, value):
    """The pillar model ignored solver.tolerance, max_iterations, coupling, cascade and protocol.step: given, each is
    refused naming the key; their defaults (not given) are accepted."""
    from brushbem.runs.assembly import parse_config
    from brushbem.config import ConfigError

    config = {
        "halfspace": {"contact_modulus": 1.0, "work_of_adhesion": 1e-4},
        "grid": {"size": 1.0, "elements": 64},
        "indenter": {"shape": "brush", "layout": "square", "region": "square", "pillars_per_side": 4,
                     "pillar_radius": 0.05, "stiffness_ratio": 0.05, "seed": 3},
        "protocol": {"method": "pillars", "preload_displacement": 2e-3},
    }
    assert parse_config(copy.deepcopy(config)).protocol.method == "pillars"
    config.setdefault(table, {})[key] = value
    with pytest.raises(ConfigError, match=rf"{table}\.{key}.*not used by protocol.method = 'pillars'"):
        parse_config(config)
