"""Parameter sweeps: expansion, seeds, validation, resume after a kill, failures, executors.

Every case is a real run on a 32 x 32 grid (a few milliseconds each).
"""

from __future__ import annotations

import io
import json
import logging
import os
import signal
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pandas as pd
import pytest
import xarray as xr
from click.testing import CliRunner
from rich.console import Console

import brushbem.runs.case
import brushbem.sweep as sweep_module
import brushbem.sweep.progress as sweep_progress
import brushbem.sweep.spec as sweep_spec
from brushbem.runs.assembly import parse_config
from brushbem.cli import main
from brushbem.sweep import (
    SweepError,
    load_summary,
    parse_sweep,
    run_sweep,
)

SRC = Path(__file__).resolve().parents[1] / "src"
EXAMPLES = Path(__file__).resolve().parents[1] / "examples"

BASE = {
    "halfspace": {"contact_modulus": 1.0, "work_of_adhesion": 1e-3},
    "grid": {"size": 1.0, "elements": 32},
    "indenter": {"shape": "flat_punch", "radius": 0.25, "stiffness": 0.15},
    "protocol": {"preload_displacement": 0.01},
}

BASE_TOML = """\
[halfspace]
contact_modulus = 1.0
work_of_adhesion = 1e-3

[grid]
size = 1.0
elements = 32

[indenter]
shape = "flat_punch"
radius = 0.25
stiffness = 0.15

[protocol]
preload_displacement = 0.01
"""

# Timing and host provenance differ between two runs of the same case.
TIMING = {"wall_time_s"}


def spec(**changes):
    document = {"base": BASE, "mode": "product", "realizations": 1, "seed": 7, "sweep": {}}
    document.update(changes)
    return document


def write_sweep(folder: Path, body: str, name: str = "sweep.toml") -> Path:
    (folder / "base.toml").write_text(BASE_TOML)
    path = folder / name
    path.write_text('base = "base.toml"\n' + body)
    return path


# ----------------------------------------------------------------------------- expansion


def test_product_order_and_realizations_outermost():
    sweep = parse_sweep(spec(
        realizations=2,
        sweep={"indenter.stiffness": [10.0, 0.1, 0.001], "indenter.radius": [0.2, 0.25]},
    ))
    assert len(sweep.cases) == 12
    assert [c.index for c in sweep.cases] == list(range(12))
    assert [c.realization for c in sweep.cases] == [0] * 6 + [1] * 6
    # The last key varies fastest.
    assert [tuple(c.values.values()) for c in sweep.cases[:6]] == [
        (10.0, 0.2), (10.0, 0.25), (0.1, 0.2), (0.1, 0.25), (0.001, 0.2), (0.001, 0.25),
    ]
    for case in sweep.cases:
        assert case.config.indenter.stiffness == case.values["indenter.stiffness"]
        assert case.config.indenter.radius == case.values["indenter.radius"]
        assert case.case_id.startswith(f"{case.index:04d}-")
    assert len({c.case_id for c in sweep.cases}) == 12


def test_zip_pairs_values():
    sweep = parse_sweep(spec(mode="zip", sweep={
        "indenter.stiffness": [10.0, 0.1, 0.001], "indenter.radius": [0.2, 0.25, 0.3],
    }))
    assert [(c.config.indenter.stiffness, c.config.indenter.radius) for c in sweep.cases] == [
        (10.0, 0.2), (0.1, 0.25), (0.001, 0.3),
    ]


def test_dotted_keys_create_tables():
    sweep = parse_sweep(spec(sweep={"solver.max_iterations": [5, 50]}))
    assert "solver" not in BASE
    assert [c.config.solver.max_iterations for c in sweep.cases] == [5, 50]


def test_seeds_one_per_realization_shared_across_points():
    sweep = parse_sweep(spec(realizations=3, sweep={"indenter.stiffness": [1.0, 2.0]}))
    expected = [
        int(child.generate_state(1, dtype=np.uint32)[0])
        for child in np.random.SeedSequence(7).spawn(3)
    ]
    assert [c.seed for c in sweep.cases] == [s for s in expected for _ in range(2)]
    assert len(set(expected)) == 3
    # The punch takes no seed: recorded only, and the user is told.
    assert not any(c.seed_applied for c in sweep.cases)
    assert any("identical" in w for w in sweep.warnings)


def test_ids_stable_and_kept_when_realizations_grow():
    document = spec(realizations=2, sweep={"indenter.stiffness": [1.0, 2.0]})
    first = parse_sweep(document)
    assert [c.case_id for c in parse_sweep(document).cases] == [c.case_id for c in first.cases]
    grown = parse_sweep({**document, "realizations": 4})
    assert [c.case_id for c in grown.cases[:4]] == [c.case_id for c in first.cases]
    other_seed = parse_sweep({**document, "seed": 8})
    assert not {c.case_id for c in other_seed.cases} & {c.case_id for c in first.cases}


def test_ids_follow_file_contents_not_paths(tmp_path):
    """A case that reads a file is the same case wherever the file lies (a moved
    study, the package installed elsewhere), and another case when the file changes."""
    document = spec(sweep={"indenter.stiffness_ratio": [1.0, 0.1]})
    document["base"] = {
        **BASE, "indenter": {"shape": "brush", "layout": "square", "pillars_per_side": 2, "pillar_radius": 0.1,
                             "spacing": 0.4, "region_size": 1.0, "stiffness_ratio": 1.0,
                             "lengths_file": "lengths.npy"},
    }

    def ids(folder: Path, lengths) -> list[str]:
        folder.mkdir()
        np.save(folder / "lengths.npy", np.asarray(lengths, dtype=float))
        return [case.case_id for case in parse_sweep(document, folder).cases]

    here = ids(tmp_path / "here", [0.0, 1e-3, 0.0, 1e-3])
    assert ids(tmp_path / "there", [0.0, 1e-3, 0.0, 1e-3]) == here
    assert not set(ids(tmp_path / "changed", [0.0, 2e-3, 0.0, 1e-3])) & set(here)


def test_units_leave_the_case_ids_alone():
    """[units] only names the units: the same cases, the same ids (a folder resumes with or without it)."""
    document = spec(sweep={"indenter.stiffness": [1.0, 2.0]})
    named = {**document, "base": {**BASE, "units": {"length": "mm", "stress": "MPa"}}}
    assert [c.case_id for c in parse_sweep(named).cases] == [c.case_id for c in parse_sweep(document).cases]


def test_seed_written_where_the_indenter_takes_one(monkeypatch):
    """An indenter that accepts ``indenter.seed`` (as the brush will) receives it as an int."""
    seen = []

    def parse_with_seed(mapping, base_dir=None):
        mapping = json.loads(json.dumps(mapping))
        seed = mapping["indenter"].pop("seed", None)
        if seed is not None:
            assert isinstance(seed, int) and not isinstance(seed, bool)
            seen.append(seed)
        return parse_config(mapping, base_dir)

    monkeypatch.setattr(sweep_spec, "parse_config", parse_with_seed)
    sweep = parse_sweep(spec(realizations=2, sweep={"indenter.stiffness": [1.0, 2.0]}))
    assert all(c.seed_applied for c in sweep.cases)
    assert seen == [c.seed for c in sweep.cases]
    assert not sweep.warnings
    # A sweep that sets indenter.seed itself keeps its own values.
    seen.clear()
    # (zip with a second key: the stand-in parser drops the seed from the config.)
    sweep = parse_sweep(spec(mode="zip", sweep={"indenter.seed": [11, 12], "indenter.stiffness": [1.0, 2.0]}))
    assert seen == [11, 12]
    assert not any(c.seed_applied for c in sweep.cases)


# ----------------------------------------------------------------------------- validation


def problems_of(document, base_dir=None) -> list[str]:
    with pytest.raises(SweepError) as caught:
        parse_sweep(document, base_dir)
    return caught.value.problems


def test_spec_problems_all_at_once():
    problems = problems_of({
        "base": BASE, "mode": "zap", "realizations": 0, "seed": -1, "colour": 1,
        "sweep": {"indenter.radius": [], "grid.size": 3},
    })
    text = "\n".join(problems)
    assert len(problems) == 6, text
    for fragment in ("`mode`: 'zap'", "'product', 'zip'", "`realizations`: 0", "`seed`: -1",
                     '`sweep."indenter.radius"`: []', '`sweep."grid.size"`: 3', "`colour`"):
        assert fragment in text


def test_zip_lengths_and_key_rules():
    text = "\n".join(problems_of(spec(mode="zip", sweep={"indenter.radius": [0.2], "grid.size": [1.0, 2.0]})))
    assert "different lengths" in text and "indenter.radius has 1" in text
    text = "\n".join(problems_of(spec(sweep={"indenter": [{}], "indenter.radius": [0.2], "a..b": [1]})))
    assert "overlaps" in text and '"a..b"' in text


def test_key_rules_and_base_file_reported_beside_bad_spec_values(tmp_path):
    """A bad ``realizations`` does not hide the sweep table's rules or a missing base file."""
    problems = problems_of({
        "base": "missing.toml", "mode": "zip", "realizations": 0,
        "sweep": {"indenter": [{}], "indenter.radius": [0.2, 0.3]},
    }, tmp_path)
    text = "\n".join(problems)
    assert len(problems) == 4, text
    for fragment in ("`realizations`: 0", '`sweep."indenter.radius"`: overlaps `sweep."indenter"`',
                     "different lengths", "`base`: 'missing.toml' — file not found"):
        assert fragment in text
    # A sweep table that itself fails is not guessed at.
    problems = problems_of({"base": "missing.toml", "mode": "zip", "sweep": {"a": [1], "b": []}}, tmp_path)
    assert not any("different lengths" in p for p in problems), problems


def test_every_case_validated_before_running(tmp_path, monkeypatch):
    calls = []
    monkeypatch.setattr(brushbem.runs.case, "run_case", lambda *a, **k: calls.append(a))
    problems = problems_of(spec(realizations=2, sweep={
        "indenter.radius": [0.25, -1.0, 0.9],
        "indenter.stiffnes": [10.0],
        "grid.elements.x": [1],
    }))
    text = "\n".join(problems)
    assert "`indenter.radius`: -1.0" in text and "(cases 1, 4)" in text
    assert "`indenter.stiffnes`: 10.0 — unknown key" in text and "(all 6 cases)" in text
    assert '`sweep."grid.elements.x"`: cannot set it' in text
    # Rules between sections run on the cases whose sections are valid.
    text = "\n".join(problems_of(spec(realizations=2, sweep={"indenter.radius": [0.25, -1.0, 0.9]})))
    assert "larger than the domain (grid.size = 1) (cases 2, 5)" in text
    with pytest.raises(SweepError):
        run_sweep(spec(sweep={"indenter.radius": [-1.0]}), tmp_path / "out")
    assert not calls and not (tmp_path / "out").exists()


def test_repeated_case_is_rejected():
    text = "\n".join(problems_of(spec(sweep={"indenter.radius": [0.25, 0.25]})))
    assert "cases 0 and 1 have the same configuration and seed" in text


@pytest.mark.parametrize("path", sorted((EXAMPLES / "sweeps").glob("*.toml")), ids=lambda p: p.name)
def test_example_sweeps_validate(path):
    result = CliRunner().invoke(main, ["sweep", str(path), "--out", "unused", "--dry-run"])
    assert result.exit_code == 0, result.output
    assert not Path("unused").exists()


def test_cli_invalid_sweep_exits_2(tmp_path):
    path = write_sweep(tmp_path, 'mode = "zip"\n[sweep]\n"indenter.radius" = [0.2, -1.0]\n"grid.size" = [1.0]\n')
    result = CliRunner().invoke(main, ["sweep", str(path), "--out", str(tmp_path / "out")])
    assert result.exit_code == 2, result.output
    assert "different lengths" in result.output and "Traceback" not in result.output
    path = write_sweep(tmp_path, '[sweep]\n"indenter.radius" = [0.2, -1.0]\n')
    result = CliRunner().invoke(main, ["sweep", str(path), "--out", str(tmp_path / "out")])
    assert result.exit_code == 2 and "`indenter.radius`: -1.0" in result.output
    assert not (tmp_path / "out").exists()
    missing = tmp_path / "m.toml"
    missing.write_text('base = "nope.toml"\n')
    result = CliRunner().invoke(main, ["sweep", str(missing), "--out", str(tmp_path / "out")])
    assert result.exit_code == 2 and "file not found" in result.output


# ----------------------------------------------------------------------------- running


@pytest.mark.slow
def test_failures_recorded_and_others_finish(tmp_path, monkeypatch):
    real = brushbem.runs.case.run_case
    calls = []

    def flaky(config, **kwargs):
        calls.append(config)
        if config.indenter.radius == 0.2:
            raise FloatingPointError("boom at radius 0.2")
        return real(config, **kwargs)

    monkeypatch.setattr(brushbem.runs.case, "run_case", flaky)
    # One CG iteration cannot solve a punch of over 1000 elements (a punch of a few
    # hundred would be solved exactly by its one-block preconditioner).
    base = {**BASE, "grid": {"size": 1.0, "elements": 96}}
    document = spec(base=base, sweep={"indenter.radius": [0.2, 0.25], "solver.max_iterations": [1, 20000]})
    out = tmp_path / "out"
    with ThreadPoolExecutor(2) as pool:
        run = run_sweep(document, out, pool)
    assert run.counts == {"failed": 2, "unconverged": 1, "finished": 1}
    assert not run.complete
    frame = load_summary(out)
    assert list(frame["status"]) == ["failed", "failed", "unconverged", "finished"]
    assert frame.loc[0, "reason"] == "FloatingPointError: boom at radius 0.2"
    assert "no convergence" in frame.loc[2, "reason"]
    assert frame.loc[3, "converged"] and frame.loc[3, "adhesive_force"] > 0
    assert np.isnan(frame.loc[0, "adhesive_force"])
    failed = sweep_module._case_attributes(out / "cases" / f"{frame.loc[0, 'case_id']}.nc")
    assert "boom at radius 0.2" in failed["traceback"]
    assert json.loads(failed["config"])["indenter"]["radius"] == 0.2
    # The metadata read without xarray is xarray's, for every kind of case file.
    from brushbem.sweep.store import _metadata

    for path in sorted((out / "cases").glob("*.nc")):
        with xr.open_dataset(path, engine="h5netcdf") as dataset:
            assert _metadata(path) == (dict(dataset.attrs), set(dataset.variables)), path.name

    # A rerun keeps every recorded case, failed ones included ...
    calls.clear()
    with ThreadPoolExecutor(2) as pool:
        run = run_sweep(document, out, pool)
    assert not calls and not run.computed and len(run.skipped) == 4
    # ... unless asked to retry the failed ones (never the unconverged one).
    monkeypatch.setattr(brushbem.runs.case, "run_case", lambda c, **k: (calls.append(c), real(c, **k))[1])
    with ThreadPoolExecutor(2) as pool:
        run = run_sweep(document, out, pool, retry_failed=True)
    assert sorted(run.computed) == sorted(frame.loc[:1, "case_id"])
    assert list(load_summary(out)["status"]) == ["unconverged", "finished", "unconverged", "finished"]


def case_files(out: Path) -> dict[str, xr.Dataset]:
    return {p.stem: xr.load_dataset(p, engine="h5netcdf") for p in sorted((out / "cases").glob("*.nc"))}


def assert_bit_identical(a: Path, b: Path) -> None:
    first, second = case_files(a), case_files(b)
    assert first.keys() == second.keys() and first
    for case_id, one in first.items():
        two = second[case_id]
        assert list(one.variables) == list(two.variables)
        for name in one.variables:
            assert one[name].dtype == two[name].dtype
            assert one[name].values.tobytes() == two[name].values.tobytes(), (case_id, name)
        attrs_one = {k: v for k, v in one.attrs.items() if k not in TIMING}
        attrs_two = {k: v for k, v in two.attrs.items() if k not in TIMING}
        summary_one = json.loads(attrs_one.pop("summary"))
        summary_two = json.loads(attrs_two.pop("summary"))
        assert attrs_one == attrs_two
        for key in TIMING:
            summary_one.pop(key), summary_two.pop(key)
        assert summary_one == summary_two


def comparable(frame: pd.DataFrame) -> pd.DataFrame:
    return frame.drop(columns=list(TIMING))


def study_spec():
    """Both existing shapes, two stiffnesses, two realizations: 8 cases.

    dgamma = 2e-3: the sphere's JKR pull-off contact (a = 0.076) spans 2.4
    elements at N = 32, above the 2 that validation asks for.
    """
    base = {**BASE, "halfspace": {**BASE["halfspace"], "work_of_adhesion": 2e-3}}
    document = spec(base=base, realizations=2, sweep={"indenter.stiffness": [0.15, 1.0]})
    document["sweep"]["indenter.shape"] = ["flat_punch", "sphere"]
    return document


@pytest.mark.slow
def test_local_processes_and_dask_agree_bit_for_bit(tmp_path):
    pytest.importorskip("dask.distributed")
    document = study_spec()
    run_sweep(document, tmp_path / "local", workers=2)
    with sweep_module.dask_client(workers=2, processes=False, dashboard_address=None) as client:
        run_sweep(document, tmp_path / "dask", client)
    local, dask = load_summary(tmp_path / "local"), load_summary(tmp_path / "dask")
    assert len(local) == 8 and set(local["status"]) == {"finished"}
    assert set(local["indenter.shape"]) == {"flat_punch", "sphere"}
    pd.testing.assert_frame_equal(comparable(local), comparable(dask))
    assert_bit_identical(tmp_path / "local", tmp_path / "dask")


@pytest.mark.slow
def test_rerun_gives_bit_identical_results(tmp_path):
    document = study_spec()
    for name in ("a", "b"):
        with ThreadPoolExecutor(2) as pool:
            run_sweep(document, tmp_path / name, pool)
    assert_bit_identical(tmp_path / "a", tmp_path / "b")
    pd.testing.assert_frame_equal(comparable(load_summary(tmp_path / "a")),
                                  comparable(load_summary(tmp_path / "b")))
    frame = pd.read_parquet(tmp_path / "a" / "summary.parquet")
    assert {"case_id", "index", "realization", "seed", "indenter.stiffness", "indenter.shape",
            "status", "reason", "adhesive_force", "theory.model"} <= set(frame.columns)
    record = json.loads((tmp_path / "a" / "sweep.json").read_text())
    assert [c["case_id"] for c in record["cases"]] == list(frame["case_id"])
    assert record["seed"] == 7 and record["mode"] == "product"


def test_plain_progress_lines_when_not_a_terminal(tmp_path, monkeypatch):
    monkeypatch.setattr(sweep_progress, "LOG_INTERVAL_S", 0.0)
    stream = io.StringIO()
    with ThreadPoolExecutor(1) as pool:
        run_sweep(spec(sweep={"indenter.stiffness": [1.0, 2.0]}), tmp_path / "o", pool,
                  progress=True, console=Console(file=stream, force_terminal=False))
    lines = stream.getvalue().splitlines()
    assert lines[0].startswith("sweep: 0/2 computed")
    assert lines[-1].startswith("sweep: 2/2 computed (2 finished)")


# ----------------------------------------------------------------------------- kill and resume

SITECUSTOMIZE = """\
import os
if os.environ.get("BRUSHBEM_TEST_CALLS"):
    import time
    import brushbem.runs.case as _case
    _real = _case.run_case
    def _counted(config, **kwargs):
        with open(os.environ["BRUSHBEM_TEST_CALLS"], "a") as log:
            log.write("call\\n")
        time.sleep(float(os.environ.get("BRUSHBEM_TEST_SLEEP", "0")))
        return _real(config, **kwargs)
    _case.run_case = _counted
"""


def run_cli(args: list[str], hooks: Path, calls: Path, sleep: float) -> subprocess.Popen:
    """The CLI in its own process group, every worker counting (and slowing) run_case."""
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(hooks), str(SRC), env.get("PYTHONPATH", "")])
    env["BRUSHBEM_TEST_CALLS"] = str(calls)
    env["BRUSHBEM_TEST_SLEEP"] = str(sleep)
    return subprocess.Popen(
        [sys.executable, "-m", "brushbem", "sweep", *args],
        env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
        start_new_session=True,
    )


@pytest.mark.slow
def test_killed_sweep_resumes_exactly_the_missing_cases(tmp_path):
    hooks = tmp_path / "hooks"
    hooks.mkdir()
    (hooks / "sitecustomize.py").write_text(SITECUSTOMIZE)
    path = write_sweep(tmp_path, 'seed = 3\n[sweep]\n"indenter.stiffness" = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6]\n')
    out = tmp_path / "out"
    cases = out / "cases"

    first = run_cli([str(path), "--out", str(out), "--workers", "1"], hooks, tmp_path / "calls1", 0.5)
    deadline = time.monotonic() + 120
    while not list(cases.glob("*.nc")):
        assert first.poll() is None, first.communicate()[0]
        assert time.monotonic() < deadline, "no case file appeared"
        time.sleep(0.02)
    os.killpg(first.pid, signal.SIGKILL)  # the driver and its workers, as a batch system would
    first.wait()
    first.stdout.close()
    survivors = {p.name: (p.stat().st_ino, p.stat().st_mtime_ns) for p in cases.glob("*.nc")}
    assert 1 <= len(survivors) < 6
    assert not (out / "summary.parquet").exists()
    frame = load_summary(out)  # rebuilt from what is there
    assert (frame["status"] == "finished").sum() == len(survivors)
    assert (frame["status"] == "missing").sum() == 6 - len(survivors)

    second = run_cli([str(path), "--out", str(out), "--workers", "2"], hooks, tmp_path / "calls2", 0.0)
    output = second.communicate(timeout=300)[0]
    assert second.returncode == 0, output
    assert (tmp_path / "calls2").read_text().count("call") == 6 - len(survivors)
    record = json.loads((out / "sweep.json").read_text())
    ids = [c["case_id"] for c in record["cases"]]
    assert sorted(p.name for p in cases.iterdir()) == sorted(f"{i}.nc" for i in ids)
    for name, stat in survivors.items():
        assert ((cases / name).stat().st_ino, (cases / name).stat().st_mtime_ns) == stat
    frame = load_summary(out)
    assert list(frame["case_id"]) == ids and set(frame["status"]) == {"finished"}


def test_executor_options_are_exclusive_and_dask_is_optional(tmp_path, monkeypatch):
    path = write_sweep(tmp_path, '[sweep]\n"indenter.radius" = [0.2]\n')
    out = str(tmp_path / "out")
    result = CliRunner().invoke(main, ["sweep", str(path), "--out", out, "--dask", "--scheduler", "tcp://x:1"])
    assert result.exit_code == 2 and "at most one of" in result.output
    result = CliRunner().invoke(main, ["sweep", str(path), "--out", out, "--scheduler", "tcp://x:1",
                                       "--workers", "2"])
    assert result.exit_code == 2 and "--workers" in result.output
    monkeypatch.setitem(sys.modules, "dask.distributed", None)  # as if not installed
    result = CliRunner().invoke(main, ["sweep", str(path), "--out", out, "--dask"])
    assert result.exit_code == 1 and "pip install 'brushbem[distributed]'" in result.output
    assert not (tmp_path / "out").exists()


def test_inline_base_table_and_api_from_a_file(tmp_path):
    inline = "\n".join(
        line.replace("[", "[base.", 1) if line.startswith("[") else line
        for line in BASE_TOML.splitlines()
    )
    path = tmp_path / "inline.toml"
    path.write_text('mode = "zip"\n[sweep]\n"grid.elements" = [32, 40]\n"indenter.radius" = [0.2, 0.3]\n'
                    + inline + "\n")
    sweep = sweep_module.load_sweep(path)
    assert sweep.base_file is None and sweep.source == path
    assert [(c.config.grid.elements, c.config.indenter.radius) for c in sweep.cases] == [(32, 0.2), (40, 0.3)]
    with ThreadPoolExecutor(2) as pool:
        run = run_sweep(path, tmp_path / "out", pool)
    assert run.complete and run.counts == {"finished": 2}


def test_one_driver_per_folder(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    with (
        ThreadPoolExecutor(1) as pool,
        sweep_module._exclusive(out),
        pytest.raises(RuntimeError, match="another sweep"),
    ):
        run_sweep(spec(sweep={"indenter.radius": [0.2]}), out, pool)


def test_a_busy_folder_is_refused_with_status_2(tmp_path):
    """A second `brushbem sweep` on a folder in use exits 2 (a busy --out, as for `run`), not 1."""
    out = tmp_path / "out"
    out.mkdir()
    path = write_sweep(tmp_path, '[sweep]\n"indenter.radius" = [0.2]\n')
    with sweep_module._exclusive(out):
        result = CliRunner().invoke(main, ["sweep", str(path), "--out", str(out), "--workers", "1", "--quiet"])
    assert result.exit_code == 2 and "another sweep is running" in result.output


def test_brush_realizations_get_their_seeds_and_differ(tmp_path):
    """With a real seeded indenter (a rough brush): realizations differ, reruns are bit-identical."""
    document = {
        "base": {
            "halfspace": {"contact_modulus": 1.0, "work_of_adhesion": 1e-4},
            "grid": {"size": 1.0, "elements": 32},
            "indenter": {"shape": "brush", "layout": "square", "pillars_per_side": 2, "pillar_radius": 0.1,
                         "stiffness_ratio": 0.1, "roughness": {"sigma": 2e-3}},
            "protocol": {"preload_displacement": 5e-3},
        },
        "realizations": 2,
        "seed": 7,
    }
    sweep = parse_sweep(document)
    assert all(c.seed_applied for c in sweep.cases)
    assert [c.config.indenter.seed for c in sweep.cases] == [c.seed for c in sweep.cases]
    run_sweep(sweep, tmp_path / "a", executor=ThreadPoolExecutor(1))
    run_sweep(sweep, tmp_path / "b", executor=ThreadPoolExecutor(1))
    first, again = load_summary(tmp_path / "a"), load_summary(tmp_path / "b")
    forces = first.sort_values("case_id")["adhesive_force"].to_numpy()
    assert forces[0] != forces[1]
    np.testing.assert_array_equal(forces, again.sort_values("case_id")["adhesive_force"].to_numpy())


def test_a_closing_dask_worker_drops_only_its_heartbeat_failure():
    """The shutdown race's one record goes; the same record from a running worker, or any other, stays."""
    pytest.importorskip("dask.distributed")
    from distributed.core import Status

    from brushbem.sweep.dask_quiet import HEARTBEAT_FAILED, QuietShutdown

    worker = SimpleNamespace(status=Status.running)
    plugin = QuietShutdown()
    plugin.setup(worker)
    try:
        def kept(message: str) -> bool:
            record = logging.LogRecord("distributed.worker", logging.ERROR, __file__, 1, message, None, None)
            return logging.getLogger("distributed.worker").filter(record)

        assert kept(HEARTBEAT_FAILED)
        worker.status = Status.closing
        assert not kept(HEARTBEAT_FAILED)
        assert kept("Compute Failed")
    finally:
        logging.getLogger("distributed.worker").removeFilter(plugin.filter)
