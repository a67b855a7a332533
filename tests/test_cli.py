"""Command line: clean errors for bad input, and the files a run writes.

The numerics are replaced by a fake `run_case` returning the `PullOff` of a
small, known `CaseResult`, so these tests check only the edge of the program.
"""

from __future__ import annotations

import importlib
import json
import math
import subprocess
import sys
import types
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

import brushbem
from brushbem.runs.assembly import Assembly
from brushbem.cli import main
from brushbem.config import RunConfig, config_to_dict
from brushbem.io import read_case
from brushbem.runs.pulloff import PullOff
from brushbem.results import CaseResult, Curve, Snapshot

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"

VALID_TOML = """\
[halfspace]
contact_modulus = 1.0
work_of_adhesion = 1e-3

[grid]
size = 1.0
elements = 128

[indenter]
shape = "flat_punch"
radius = 0.25
stiffness = inf

[protocol]
preload_displacement = 0.01
"""


def fake_result(converged: bool = True, n: int = 8) -> CaseResult:
    """A small pull-off: press to d = 0.01, retract to separation."""
    displacement = np.concatenate([np.linspace(0.0, 0.01, 4), np.linspace(0.008, -0.01, 5)])
    force = np.concatenate([np.linspace(0.0, 0.02, 4), [0.015, 0.0, -0.01, -0.02, 0.0]])
    rows = displacement.size
    curve = Curve(
        displacement=displacement,
        force=force,
        contact_area=np.full(rows, 0.19),
        cg_iterations=np.arange(rows),
        converged=np.full(rows, converged),
        loading=np.arange(rows) < 4,
        attached_pillars=np.ones(rows, dtype=int),
    )
    pressure = np.zeros((n, n))
    pressure[2:6, 2:6] = 0.5
    snapshots = (
        Snapshot("max_preload", 0.01, 0.02, pressure, pressure > 0),
        Snapshot("adhesive_force", -0.005, -0.02, -pressure, pressure > 0),
    )
    summary = {
        "adhesive_force": 0.02,
        "pull_off_displacement": -0.005,
        "separation_displacement": -0.01,
        "work_of_separation": 1.5e-4,
        "preload_force": 0.02,
        "max_displacement": 0.01,
        "converged": converged,
        "reason": "complete separation" if converged else "no convergence in 20000 iterations",
        "n_solves": rows,
        "n_cg_iterations": int(curve.cg_iterations.sum()),
        "wall_time_s": 0.01,
        "theory": {"adhesive_force_ratio": 1.02, "stiffness_ratio": math.inf},
    }
    return CaseResult(
        curve=curve,
        snapshots=snapshots,
        summary=summary,
        attributes={"seeds": [], "backend": "numpy", "method": "events"},
        element_size=1.0 / n,
    )


@pytest.fixture
def fake_run_case(monkeypatch):
    """Replace `brushbem.runs.case.run_case` by a fake; returns the list of its calls."""
    try:
        case_module = importlib.import_module("brushbem.runs.case")
    except ImportError:
        # The numerics may not be installed in this tree: stand in a module.
        case_module = types.ModuleType("brushbem.runs.case")
        monkeypatch.setitem(sys.modules, "brushbem.runs.case", case_module)
        monkeypatch.setattr(brushbem, "case", case_module, raising=False)
    calls: list[RunConfig] = []
    state = {"converged": True}

    def run_case(config, *, progress=None, stop=None):
        calls.append(config)
        if progress is not None:
            progress(0.0, "pressing")
            progress(0.5, "pulling off")
            progress(1.0, "done")
        reference = {
            "displacement": np.array([0.0, -0.01]),
            "force": np.array([0.0, -0.02]),
            "label": "Kendall",
        }
        result = fake_result(converged=state["converged"])
        result.summary["warnings"] = list(state.get("warnings", []))
        return PullOff(result, reference, config.config if isinstance(config, Assembly) else config)

    monkeypatch.setattr(case_module, "run_case", run_case, raising=False)
    run_case.calls = calls  # type: ignore[attr-defined]
    run_case.state = state  # type: ignore[attr-defined]
    return run_case


def write(tmp_path: Path, text: str, name: str = "case.toml") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def invoke(*args: str):
    return CliRunner().invoke(main, list(args))


def assert_clean_failure(result, *fragments: str) -> None:
    assert result.exit_code == 2, result.output
    assert "Traceback" not in result.output
    # A clean exit is a SystemExit; anything else escaped from the command.
    assert result.exception is None or isinstance(result.exception, SystemExit), result.exception
    for fragment in fragments:
        assert fragment in result.output, result.output


BAD_VALUES = [
    ("contact_modulus = 1.0", "contact_modulus = nan", "halfspace.contact_modulus"),
    ("contact_modulus = 1.0", "contact_modulus = inf", "halfspace.contact_modulus"),
    ("contact_modulus = 1.0", "contact_modulus = -1.0", "halfspace.contact_modulus"),
    ("contact_modulus = 1.0", "contact_modulus = 0.0", "halfspace.contact_modulus"),
    ("size = 1.0", "size = nan", "grid.size"),
    ("size = 1.0", "size = 0.0", "grid.size"),
    ("size = 1.0", "size = -1.0", "grid.size"),
    ("elements = 128", "elements = 0", "grid.elements"),
    ("elements = 128", "elements = -128", "grid.elements"),
    ("radius = 0.25", "radius = nan", "indenter.radius"),
    ("radius = 0.25", "radius = inf", "indenter.radius"),
    ("radius = 0.25", "radius = -0.25", "indenter.radius"),
    ("radius = 0.25", "radius = 0.003", "under 2 elements"),
    ("radius = 0.25", "radius = 0.75", "larger than the domain"),
    ("preload_displacement = 0.01", "", "preload_force"),
    ("preload_displacement = 0.01", "preload_displacement = 0.01\npreload_force = 1.0",
     "preload_force"),
    ("[grid]", "colour = 'red'\n[grid]", "colour"),
    ("elements = 128", "elements = 128\nsise = 2.0", "grid.sise"),
    ("shape = \"flat_punch\"", "shape = \"cube\"", "indenter.shape"),
    ("[protocol]", "[protocl]", "protocl"),
]


@pytest.mark.parametrize(("old", "new", "named"), BAD_VALUES)
@pytest.mark.parametrize("command", ["validate", "run"])
def test_bad_config_exits_2_naming_the_key(tmp_path, fake_run_case, command, old, new, named):
    assert old in VALID_TOML
    path = write(tmp_path, VALID_TOML.replace(old, new, 1))
    args = [command, str(path)] + (["--out", str(tmp_path / "out")] if command == "run" else [])
    result = invoke(*args)
    assert_clean_failure(result, f"invalid configuration {path}:", named)
    assert not fake_run_case.calls
    assert not (tmp_path / "out").exists()


def test_missing_height_map_file(tmp_path):
    text = VALID_TOML.replace(
        'shape = "flat_punch"\nradius = 0.25', 'shape = "height_map"\nfile = "tip.npy"'
    )
    result = invoke("validate", str(write(tmp_path, text)))
    assert_clean_failure(result, "indenter.file", "file not found")


def test_toml_syntax_error_and_missing_file(tmp_path):
    assert_clean_failure(invoke("validate", str(write(tmp_path, "[grid\n"))), "not valid TOML")
    assert_clean_failure(invoke("validate", str(tmp_path / "absent.toml")), "file not found")


def test_several_problems_reported_at_once(tmp_path):
    text = (
        VALID_TOML.replace("contact_modulus = 1.0", "contact_modulus = -1.0")
        .replace("radius = 0.25", "radius = 0.003")
        .replace("elements = 128", "elements = 128\nsise = 1")
        .replace("size = 1.0", "size = 1.0", 1)
    )
    result = invoke("validate", str(write(tmp_path, text)))
    assert_clean_failure(result, "halfspace.contact_modulus", "grid.sise")
    lines = [line for line in result.output.splitlines() if line.strip().startswith("`")]
    assert len(lines) == 2, result.output
    # With the grid fixed, the punch rule runs too and is reported beside the modulus.
    text = text.replace("\nsise = 1", "")
    result = invoke("validate", str(write(tmp_path, text)))
    assert_clean_failure(result, "halfspace.contact_modulus", "under 2 elements")


@pytest.mark.parametrize("path", sorted(EXAMPLES.glob("*.toml")), ids=lambda p: p.name)
def test_validate_examples(path):
    result = invoke("validate", str(path))
    assert result.exit_code == 0, result.output
    # The default brush ships at 3.1 elements per pillar radius (its comment states the error): a warning.
    if path.name == "default.toml":
        assert result.output.startswith("ok, with 1 warning\n"), result.output
        assert "spans 3.12 elements" in result.output and "raise grid.elements to 656" in result.output
    else:
        assert result.output.strip() == "ok"


def test_run_writes_the_three_files(tmp_path, fake_run_case):
    path = write(tmp_path, VALID_TOML)
    out = tmp_path / "out" / "nested"
    result = invoke("run", str(path), "--out", str(out))
    assert result.exit_code == 0, result.output
    assert "adhesive force" in result.output
    assert "adhesive_force_ratio" in result.output
    assert len(fake_run_case.calls) == 1
    # The run gets the configuration built from its one rasterisation (brushbem.runs.assembly).
    assert isinstance(fake_run_case.calls[0], Assembly)
    assert isinstance(fake_run_case.calls[0].config, RunConfig)

    # .brushbem.lock: the run's lock on the folder (kept; the kernel releases the lock itself).
    assert sorted(p.name for p in out.iterdir()) == [".brushbem.lock", "curve.csv", "pulloff.pdf", "pulloff.png", "result.nc",
                                                     "summary.json"]
    assert (out / "pulloff.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"

    summary = json.loads((out / "summary.json").read_text())
    assert summary["adhesive_force"] == 0.02
    assert summary["converged"] is True
    # JSON has no infinity; it is written as the string "inf", never as null.
    assert summary["theory"]["stiffness_ratio"] == "inf"


def test_result_nc_round_trips(tmp_path, fake_run_case):
    path = write(tmp_path, VALID_TOML)
    out = tmp_path / "out"
    assert invoke("run", str(path), "--out", str(out), "--quiet").exit_code == 0
    expected = fake_result()
    dataset = read_case(out)

    assert dataset.sizes["step"] == expected.curve.force.size
    np.testing.assert_array_equal(dataset["displacement"], expected.curve.displacement)
    np.testing.assert_array_equal(dataset["force"], expected.curve.force)
    np.testing.assert_array_equal(dataset["loading"], expected.curve.loading)
    np.testing.assert_array_equal(dataset["converged"], expected.curve.converged)
    np.testing.assert_array_equal(dataset["cg_iterations"], expected.curve.cg_iterations)

    h = expected.element_size
    np.testing.assert_allclose(dataset["x"], (np.arange(8) + 0.5) * h - 0.5)
    np.testing.assert_allclose(dataset["y"], dataset["x"])
    assert list(dataset["stage"].values) == [snapshot.name for snapshot in expected.snapshots]
    assert dataset["pressure"].dims == ("stage", "y", "x") and dataset["contact"].dims == ("stage", "y", "x")
    assert dataset["contact"].dtype == np.int8
    for snapshot in expected.snapshots:
        pressure = dataset["pressure"].sel(stage=snapshot.name)
        contact = dataset["contact"].sel(stage=snapshot.name)
        np.testing.assert_array_equal(pressure, snapshot.pressure)
        np.testing.assert_array_equal(contact.values.astype(bool), snapshot.contact)
        assert float(pressure["stage_displacement"]) == snapshot.displacement
        assert float(pressure["stage_force"]) == snapshot.force

    assert dataset.attrs["brushbem_version"] == brushbem.__version__
    assert dataset.attrs["backend"] == "numpy"
    assert json.loads(dataset.attrs["seeds"]) == []
    assert dataset.attrs["method"] == "events"
    recorded = json.loads(dataset.attrs["config"])
    assert recorded == config_to_dict(fake_run_case.calls[0].config)
    assert recorded["indenter"]["stiffness"] == "inf"


@pytest.mark.slow  # over 3 s on 2 cores: `make test` runs it, `make test-fast` does not
def test_run_again_replaces_files_and_leaves_no_temporaries(tmp_path, fake_run_case):
    """A second run into a folder of results is refused unless --overwrite; with it, it replaces them."""
    path = write(tmp_path, VALID_TOML)
    out = tmp_path / "out"
    assert invoke("run", str(path), "--out", str(out), "--quiet").exit_code == 0
    refused = invoke("run", str(path), "--out", str(out), "--quiet")
    assert refused.exit_code == 2 and "--overwrite" in refused.output
    assert invoke("run", str(path), "--out", str(out), "--quiet", "--overwrite").exit_code == 0
    # .brushbem.lock: the run's lock on the folder (kept; the kernel releases the lock itself).
    assert sorted(p.name for p in out.iterdir()) == [".brushbem.lock", "curve.csv", "pulloff.pdf", "pulloff.png", "result.nc",
                                                     "summary.json"]


def test_not_converged_writes_results_and_exits_3(tmp_path, fake_run_case):
    fake_run_case.state["converged"] = False
    path = write(tmp_path, VALID_TOML)
    out = tmp_path / "out"
    result = invoke("run", str(path), "--out", str(out))
    assert result.exit_code == 3, result.output
    assert "did not converge" in result.output
    reason = json.loads((out / "summary.json").read_text())["reason"]
    assert reason and reason in result.output, result.output  # the reason is said, not only written
    assert (out / "summary.json").exists() and (out / "result.nc").exists()
    assert json.loads((out / "summary.json").read_text())["converged"] is False


def test_warnings_of_a_converged_run_are_said_and_written(tmp_path, fake_run_case):
    fake_run_case.state["warnings"] = ["the contact at the preload reaches the edge of the domain"]
    out = tmp_path / "out"
    result = invoke("run", str(write(tmp_path, VALID_TOML)), "--out", str(out))
    assert result.exit_code == 0, result.output
    assert "warning: the contact at the preload reaches the edge of the domain" in result.output
    assert json.loads((out / "summary.json").read_text())["warnings"] == fake_run_case.state["warnings"]


def test_out_that_cannot_be_created_exits_2_before_running(tmp_path, fake_run_case):
    path = write(tmp_path, VALID_TOML)
    blocker = tmp_path / "afile"
    blocker.write_text("")
    result = invoke("run", str(path), "--out", str(blocker / "sub"))
    assert_clean_failure(result, "--out", "cannot create the output folder")
    assert not fake_run_case.calls  # refused before the computation


def test_python_dash_m_brushbem(tmp_path):
    path = write(tmp_path, VALID_TOML.replace("size = 1.0", "size = -1.0"))
    completed = subprocess.run(
        [sys.executable, "-m", "brushbem", "validate", str(path)],
        capture_output=True, text=True, check=False,
    )
    assert completed.returncode == 2
    assert "grid.size" in completed.stderr
    assert "Traceback" not in completed.stderr


@pytest.mark.parametrize("width", [50, 80, 200])
def test_tables_never_cut_the_names_a_user_types(width, monkeypatch):
    """``study --list`` and ``sweep --dry-run`` show every study name, case id and swept key whole."""
    from brushbem.studies import STUDIES, sweep_file

    monkeypatch.setenv("COLUMNS", str(width))
    listed = CliRunner().invoke(main, ["study", "--list"])
    assert listed.exit_code == 0
    for name in STUDIES:
        assert name in listed.output, (width, name)
    path = sweep_file("concave", "curves", quick=True)
    dry = CliRunner().invoke(main, ["sweep", str(path), "--dry-run", "--out", "unused"])
    assert dry.exit_code == 0
    for key in ("indenter.profile.amplification", "protocol.preload_force", "0000-"):
        assert key in dry.output, (width, key)


def test_the_command_line_imports_no_numerics_until_a_command_runs():
    """`brushbem --help` stays light: importing the command line loads neither numpy, pydantic nor rich."""
    import subprocess
    import sys

    code = ("import sys, brushbem.cli; "
            "print(sorted(m for m in ('numpy', 'pydantic', 'rich', 'scipy', 'xarray') if m in sys.modules))")
    loaded = subprocess.run([sys.executable, "-c", code], check=True, capture_output=True, text=True).stdout.strip()
    assert loaded == "[]"


def test_study_list_fits_80_columns_with_a_cost_per_study():
    """``study --list``: one line a study with its cost, the title wrapped beneath, nothing wider than 80."""
    from brushbem.cli.sweep_commands import STUDY_COSTS
    from brushbem.studies import STUDIES

    listed = CliRunner().invoke(main, ["study", "--list"])
    assert listed.exit_code == 0, listed.output
    lines = listed.output.splitlines()
    assert max(len(line) for line in lines) <= 80
    assert any(line.split()[-1:] == ["cost"] for line in lines[:5])  # the cost column's heading
    rows = {line.split()[0]: line for line in lines if line and not line.startswith(" ") and line.split()[0] in STUDIES}
    assert set(rows) == set(STUDIES)  # one line a study, its name whole
    for name, row in rows.items():
        assert row.rstrip().endswith(STUDY_COSTS.get(name, "--estimate" if STUDIES[name].parts else "no sweep"))
    assert len(lines) < 6 * len(STUDIES)  # no title folded into 6-10 lines of a narrow column


def test_the_pillar_model_does_not_report_zero_cg_iterations(tmp_path):
    """The pillar model's solves are not element CG solves: its summary row says so instead of "0"."""
    config = tmp_path / "pillars.toml"
    # phi = 16 pi 0.05^2 = 0.126, inside the pillar model's validated domain; 3.2 elements per radius.
    config.write_text(
        '[halfspace]\ncontact_modulus = 1.0\nwork_of_adhesion = 1e-4\n[grid]\nsize = 1.0\nelements = 64\n'
        '[indenter]\nshape = "brush"\nlayout = "square"\npillars_per_side = 4\npillar_radius = 0.05\n'
        'stiffness_ratio = 0.01\n[protocol]\nmethod = "pillars"\npreload_displacement = 0.002\n')
    done = CliRunner().invoke(main, ["run", str(config), "--out", str(tmp_path / "out")])
    assert done.exit_code == 0, done.output
    (row,) = [line for line in done.output.splitlines() if "CG iterations per solve" in line]
    assert "pillar model: not counted" in row and not row.rstrip(" │").endswith(" 0")
