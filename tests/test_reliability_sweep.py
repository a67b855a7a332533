"""Sweeps under abuse: corrupt files, foreign sweeps, killed drivers and workers, signals.

Each test attacks a sweep folder from outside, the way a full disk, a batch
system or a careless rerun would, and asserts the promise: nothing read as a
result that is not one, nothing deleted, every case present exactly once
after a rerun, the report saying what happened, and no traceback through the
command line.  Cases are punches on a 16 x 16 grid (milliseconds each).
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from concurrent.futures import Future, ThreadPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from pathlib import Path
from types import SimpleNamespace

import pandas as pd
import pytest
from click.testing import CliRunner

from brushbem.cli import main
from brushbem.sweep import (
    INCIDENTS_FILE,
    SweepFolderError,
    SweepWarning,
    load_summary,
    read_incidents,
    run_sweep,
)

SRC = Path(__file__).resolve().parents[1] / "src"

BASE_TOML = """\
[halfspace]
contact_modulus = 1.0
work_of_adhesion = 1e-3

[grid]
size = 1.0
elements = 16

[indenter]
shape = "flat_punch"
radius = 0.25
stiffness = 0.15

[protocol]
preload_displacement = 0.01
"""

STIFFNESSES = [0.1, 0.2, 0.3, 0.4]

#: Installed in every process of a subprocess sweep: each call of run_case
#: logs its process id, sleeps, and, for the stiffnesses named in the
#: environment, raises or ends its worker process.
SITECUSTOMIZE = """\
import os
if os.environ.get("BRUSHBEM_TEST_LOG"):
    import time
    import brushbem.runs.case as _case
    _real = _case.run_case
    def _hooked(config, **kwargs):
        with open(os.environ["BRUSHBEM_TEST_LOG"], "a") as log:
            log.write(f"{os.getpid()} {config.indenter.stiffness}\\n")
        stiffness = repr(config.indenter.stiffness)
        if stiffness in os.environ.get("BRUSHBEM_TEST_EXIT", "").split():
            os._exit(9)
        if stiffness in os.environ.get("BRUSHBEM_TEST_RAISE", "").split():
            raise FloatingPointError(f"boom at stiffness {stiffness}")
        time.sleep(float(os.environ.get("BRUSHBEM_TEST_SLEEP", "0")))
        return _real(config, **kwargs)
    _case.run_case = _hooked
"""


def write_sweep(folder: Path, stiffnesses=STIFFNESSES, name: str = "sweep.toml", **settings) -> Path:
    (folder / "base.toml").write_text(BASE_TOML)
    lines = ['base = "base.toml"', *(f"{key} = {value}" for key, value in settings.items()),
             "[sweep]", f'"indenter.stiffness" = {list(stiffnesses)}']
    path = folder / name
    path.write_text("\n".join(lines) + "\n")
    return path


def cli(*args: str):
    result = CliRunner().invoke(main, list(args))
    assert "Traceback" not in result.output, result.output
    assert result.exception is None or isinstance(result.exception, SystemExit), result.output
    return result


def case_ids(out: Path) -> list[str]:
    return [case["case_id"] for case in json.loads((out / "sweep.json").read_text())["cases"]]


def assert_every_case_once(out: Path, status: str = "finished") -> pd.DataFrame:
    """One readable case file per case id of sweep.json, one summary row each, all of ``status``."""
    ids = case_ids(out)
    assert sorted(p.name for p in (out / "cases").iterdir()) == sorted(f"{i}.nc" for i in ids)
    frame = load_summary(out, rebuild=True)
    assert list(frame["case_id"]) == ids
    assert set(frame["status"]) == {status}, frame[["case_id", "status", "reason"]]
    return frame


def hooked_sweep(args: list[str], tmp_path: Path, **env: str) -> subprocess.Popen:
    """``brushbem sweep ARGS`` in its own process group, with the run_case hook installed."""
    hooks = tmp_path / "hooks"
    hooks.mkdir(exist_ok=True)
    (hooks / "sitecustomize.py").write_text(SITECUSTOMIZE)
    variables = dict(os.environ)
    variables["PYTHONPATH"] = os.pathsep.join([str(hooks), str(SRC), variables.get("PYTHONPATH", "")])
    variables.update({f"BRUSHBEM_TEST_{key.upper()}": value for key, value in env.items()})
    return subprocess.Popen(
        [sys.executable, "-m", "brushbem", "sweep", *args],
        env=variables, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
        start_new_session=True,
    )


def logged_pids(log: Path) -> set[int]:
    return {int(line.split()[0]) for line in log.read_text().splitlines()} if log.exists() else set()


def running(pid: int) -> bool:
    """Whether process ``pid`` exists and is not a zombie."""
    try:
        text = Path(f"/proc/{pid}/stat").read_text()
    except FileNotFoundError:
        return False
    except OSError:
        try:
            os.kill(pid, 0)
        except ProcessLookupError:
            return False
        return True
    return text[text.rfind(")") + 2] not in "ZX"


def wait_for(predicate, timeout: float, what: str) -> None:
    deadline = time.monotonic() + timeout
    while not predicate():
        if time.monotonic() > deadline:
            raise AssertionError(f"timed out after {timeout} s waiting for {what}")
        time.sleep(0.05)


def stop_group(process: subprocess.Popen) -> None:
    """Clean up after a test, passed or failed half-way: the process, what it started, and its pipe."""
    if process.poll() is None:
        os.killpg(process.pid, signal.SIGKILL)
        process.wait(timeout=30)
    else:
        try:
            os.killpg(process.pid, signal.SIGKILL)
        except (ProcessLookupError, PermissionError):
            pass
    if process.stdout is not None:
        process.stdout.close()


# ----------------------------------------------------------------------------- corrupt case files


def corrupt(path: Path, how: str, other: Path) -> None:
    data = path.read_bytes()
    if how == "truncated":  # a copy cut short by a full disk
        path.write_bytes(data[: len(data) // 3])
    elif how == "empty":
        path.write_bytes(b"")
    elif how == "garbage":
        path.write_bytes(os.urandom(4096))
    elif how == "another case":  # a complete NetCDF file, but not this case's
        path.write_bytes(other.read_bytes())


@pytest.mark.slow
def test_corrupt_case_files_are_listed_then_set_aside_and_recomputed(tmp_path):
    path = write_sweep(tmp_path)
    out = tmp_path / "out"
    assert cli("sweep", str(path), "--out", str(out), "--workers", "1", "--quiet").exit_code == 0
    ids = case_ids(out)
    files = [out / "cases" / f"{case_id}.nc" for case_id in ids]
    damage = ("truncated", "empty", "garbage", "another case")
    for file, how in zip(files, damage):
        corrupt(file, how, files[-1] if file != files[-1] else files[0])
    damaged = {file.name: file.read_bytes() for file in files}

    # Readers: the corrupt files are listed as such, never read as results.
    frame = load_summary(out)
    assert list(frame["status"]) == ["corrupt"] * 4
    assert all("a rerun moves it to corrupt/" in reason for reason in frame["reason"])
    assert "adhesive_force" not in frame or frame["adhesive_force"].isna().all()
    result = cli("report", str(out))
    assert result.exit_code == 0, result.output
    report = (out / "report.html").read_text()
    assert report.count('class="case case-corrupt"') == 4
    assert all(case_id in report.split('id="problems"')[1].split("</div>")[0] for case_id in ids)
    result = cli("figure", str(out))
    assert result.exit_code == 0, result.output

    # The rerun sets them aside (nothing deleted) and computes them again.
    result = cli("sweep", str(path), "--out", str(out), "--workers", "1", "--quiet")
    assert result.exit_code == 0, result.output
    assert_every_case_once(out)
    aside = {p.name: p.read_bytes() for p in (out / "corrupt").iterdir()}
    assert aside == damaged
    incidents = [i for i in read_incidents(out) if i["event"] == "corrupt"]
    assert sorted(i["case_id"] for i in incidents) == sorted(ids)
    assert {i["moved_to"] for i in incidents} == {f"corrupt/{case_id}.nc" for case_id in ids}
    assert cli("report", str(out)).exit_code == 0
    happened = (out / "report.html").read_text().split('id="incidents"')[1]
    assert all(f"corrupt/{case_id}.nc" in happened for case_id in ids)

    # Corrupt again: a second copy is set aside beside the first, not over it.
    corrupt(files[0], "garbage", files[1])
    assert cli("sweep", str(path), "--out", str(out), "--workers", "1", "--quiet").exit_code == 0
    assert (out / "corrupt" / f"{ids[0]}.1.nc").exists()
    assert_every_case_once(out)


@pytest.mark.slow
@pytest.mark.parametrize("damage", ["garbage", "truncated", "empty"])
def test_unreadable_summary_is_rebuilt_with_a_notice(tmp_path, damage):
    out = tmp_path / "out"
    with ThreadPoolExecutor(2) as pool:
        run_sweep(write_sweep(tmp_path), out, pool)
    summary = out / "summary.parquet"
    data = summary.read_bytes()
    summary.write_bytes({"garbage": os.urandom(len(data)), "truncated": data[: len(data) // 2],
                         "empty": b""}[damage])

    result = cli("report", str(out))
    assert result.exit_code == 0, result.output
    assert "warning:" in result.output and "summary.parquet cannot be read" in result.output
    html = (out / "report.html").read_text()
    assert "rebuilt from the case files" in html.split('id="incidents"')[1]
    assert html.count('class="case case-finished"') == 4
    # Rebuilt and written: the next reader gets it without a notice.
    frame = pd.read_parquet(summary)
    assert list(frame["case_id"]) == case_ids(out)

    summary.write_bytes(b"PAR1 not really")
    with pytest.warns(SweepWarning, match="summary.parquet cannot be read"):
        assert list(load_summary(out)["status"]) == ["finished"] * 4


# ----------------------------------------------------------------------------- one folder, one sweep


@pytest.mark.slow
def test_a_different_sweep_into_the_folder_is_refused(tmp_path):
    first = write_sweep(tmp_path, name="first.toml")
    out = tmp_path / "out"
    assert cli("sweep", str(first), "--out", str(out), "--workers", "1", "--quiet").exit_code == 0
    kept = {name: (out / name).read_bytes() for name in ("sweep.json", "summary.parquet")}

    for other in (write_sweep(tmp_path, [0.1, 0.2, 0.3, 0.5], name="edited.toml"),
                  write_sweep(tmp_path, [0.4, 0.3, 0.2, 0.1], name="reordered.toml"),
                  write_sweep(tmp_path, STIFFNESSES, name="reseeded.toml", seed=5),
                  write_sweep(tmp_path, STIFFNESSES[:2], name="fewer.toml")):
        result = cli("sweep", str(other), "--out", str(out), "--workers", "1", "--quiet")
        assert result.exit_code == 2, (other.name, result.output)
        assert str(out) in result.output and "holds a different sweep" in result.output
        assert "new --out folder" in result.output
        assert {name: (out / name).read_bytes() for name in kept} == kept

    # The same sweep resumes (nothing to compute) ...
    result = cli("sweep", str(first), "--out", str(out), "--workers", "1")
    assert result.exit_code == 0 and "computed 0, kept 4" in result.output
    # ... and one that only adds cases (more realizations) extends the folder.
    grown = write_sweep(tmp_path, name="grown.toml", realizations=2)
    result = cli("sweep", str(grown), "--out", str(out), "--workers", "1")
    assert result.exit_code == 0 and "computed 4, kept 4" in result.output, result.output
    assert_every_case_once(out)
    assert [i["detail"] for i in read_incidents(out) if i["event"] == "extended"] == [
        "the sweep grew from 4 to 8 cases"]


@pytest.mark.slow
def test_an_unreadable_sweep_record_is_judged_by_the_case_files(tmp_path):
    document = {"base": tomllib_base(), "sweep": {"indenter.stiffness": STIFFNESSES}}
    out = tmp_path / "out"
    with ThreadPoolExecutor(2) as pool:
        run_sweep(document, out, pool)
        (out / "sweep.json").write_text('{"cases": [')  # cut short
        # Its case files belong to this sweep: rewritten, nothing recomputed.
        run = run_sweep(document, out, pool)
        assert not run.computed and len(run.skipped) == 4
        assert [i["event"] for i in read_incidents(out)] == ["unreadable-record"]
        (out / "sweep.json").write_text("garbage")
        other = {**document, "sweep": {"indenter.stiffness": [1.0, 2.0]}}
        with pytest.raises(SweepFolderError, match="case files of a different sweep"):
            run_sweep(other, out, pool)
    result = cli("report", str(out))
    assert result.exit_code == 2 and "sweep.json" in result.output and "cannot be read" in result.output


def tomllib_base() -> dict:
    import tomllib

    return tomllib.loads(BASE_TOML)


# ----------------------------------------------------------------------------- stale temporaries


@pytest.mark.slow
def test_temporaries_of_a_killed_driver_are_removed(tmp_path):
    document = {"base": tomllib_base(), "sweep": {"indenter.stiffness": STIFFNESSES[:2]}}
    out = tmp_path / "out"
    with ThreadPoolExecutor(1) as pool:
        run_sweep(document, out, pool)
        stale = [out / ".sweep.json.k3j4.tmp", out / ".summary.parquet.x9y8.tmp",
                 out / "cases" / f".{case_ids(out)[0]}.nc.abcd.tmp"]
        for path in stale:
            path.write_bytes(b"half")
        run_sweep(document, out, pool)
    assert not any(path.exists() for path in stale)
    (incident,) = read_incidents(out)
    assert incident["event"] == "stale-temporary" and "3 half-written" in incident["detail"]
    assert_every_case_once(out)


# ----------------------------------------------------------------------------- lost cases


class Scripted(ThreadPoolExecutor):
    """Computes cases in threads, except that the stiffnesses in ``errors`` fail with that error."""

    def __init__(self, errors: dict[float, BaseException]) -> None:
        super().__init__(2)
        self.errors = errors

    def submit(self, fn, /, *args, **kwargs):
        error = self.errors.get(args[0].indenter.stiffness)
        if error is None:
            return super().submit(fn, *args, **kwargs)
        future: Future = Future()
        future.set_exception(error)
        return future


@pytest.mark.slow
def test_infrastructure_losses_are_missing_not_failed(tmp_path):
    from distributed.comm.core import CommClosedError
    from distributed.scheduler import KilledWorker

    document = {"base": tomllib_base(),
                "sweep": {"indenter.stiffness": [0.1, 0.2, 0.3, 0.4, 0.5, 0.6]}}
    out = tmp_path / "out"
    errors = {
        0.1: KilledWorker("compute_case-1", SimpleNamespace(address="tcp://127.0.0.1:4711"), allowed_failures=3),
        0.2: CommClosedError("in <TCP (closed)>: Stream is closed"),
        0.3: BrokenProcessPool("A process in the process pool was terminated abruptly"),
        0.4: TypeError("cannot unpickle the result"),  # about the case: deterministic
    }
    with Scripted(errors) as pool:
        run = run_sweep(document, out, pool)
    assert run.counts == {"missing": 3, "failed": 1, "finished": 2}
    frame = load_summary(out)
    assert list(frame["status"]) == ["missing", "missing", "missing", "failed", "finished", "finished"]
    assert "its worker was lost (KilledWorker" in frame.loc[0, "reason"]
    assert [i["case_id"] for i in read_incidents(out) if i["event"] == "lost"] == case_ids(out)[:3]

    # A plain rerun computes the lost cases and keeps the failed one ...
    with ThreadPoolExecutor(2) as pool:
        run = run_sweep(document, out, pool)
    assert sorted(run.computed) == sorted(case_ids(out)[:3]) and run.counts["failed"] == 1
    # ... which --retry-failed recomputes.
    with ThreadPoolExecutor(2) as pool:
        run = run_sweep(document, out, pool, retry_failed=True)
    assert list(run.computed) == [case_ids(out)[3]]
    assert_every_case_once(out)
    result = cli("report", str(out))
    happened = (out / "report.html").read_text().split('id="incidents"')[1]
    assert result.exit_code == 0 and happened.count("<b>lost</b>") == 3


@pytest.mark.slow
def test_dask_worker_dying_on_a_case_leaves_it_missing_for_the_rerun(tmp_path, monkeypatch):
    pytest.importorskip("dask.distributed")
    path = write_sweep(tmp_path, [0.1, 0.2, 0.3, 0.4, 0.5])
    out = tmp_path / "out"
    args = [str(path), "--out", str(out), "--dask", "--workers", "2", "--quiet"]
    # The scheduler gives up on a case after its first lost worker: KilledWorker at once.
    monkeypatch.setenv("DASK_DISTRIBUTED__SCHEDULER__ALLOWED_FAILURES", "0")

    def sweep(log: str, **hooks: str) -> str:
        process = hooked_sweep(args, tmp_path, log=str(tmp_path / log), **hooks)
        try:
            output = process.communicate(timeout=240)[0]
        finally:
            stop_group(process)
        assert "Traceback" not in output
        process.output = output
        return process

    # Case 1 ends its worker process; case 2 raises.
    first = sweep("calls1", exit="0.2", **{"raise": "0.3"})
    assert first.returncode == 3, first.output
    frame = load_summary(out)
    status = list(frame["status"])
    assert status[1] == "missing" and "its worker was lost (KilledWorker" in frame.loc[1, "reason"]
    # A case queued on the dying worker may be lost with it; none is recorded as failed for it.
    assert status[2] in {"failed", "missing"} and set(status[:2] + status[3:]) <= {"finished", "missing"}
    lost = status.count("missing")

    # A plain rerun computes exactly the lost cases; the one that raised stays failed.
    second = sweep("calls2", **{"raise": "0.3"})
    assert second.returncode == 3, second.output
    assert (tmp_path / "calls2").read_text().count("\n") == lost
    assert list(load_summary(out)["status"]) == ["finished", "finished", "failed", "finished", "finished"]
    third = sweep("calls3")  # without the fault: still nothing to compute
    assert third.returncode == 3 and not (tmp_path / "calls3").exists(), third.output
    fourth = hooked_sweep([*args, "--retry-failed"], tmp_path, log=str(tmp_path / "calls4"))
    output = fourth.communicate(timeout=240)[0]  # waits, and closes its pipe
    assert fourth.returncode == 0 and (tmp_path / "calls4").read_text().count("\n") == 1, output
    assert_every_case_once(out)
    result = cli("report", str(out))
    happened = (out / "report.html").read_text().split('id="incidents"')[1]
    assert result.exit_code == 0 and happened.count("<b>lost</b>") == lost


# ----------------------------------------------------------------------------- killed driver, signals


@pytest.mark.slow
def test_killed_driver_takes_its_workers_along(tmp_path):
    path = write_sweep(tmp_path)
    log = tmp_path / "calls"
    driver = hooked_sweep([str(path), "--out", str(tmp_path / "out"), "--workers", "2", "--quiet"],
                          tmp_path, log=str(log), sleep="60")
    try:
        wait_for(lambda: len(logged_pids(log)) == 2 or driver.poll() is not None, 120, "two busy workers")
        workers = logged_pids(log)
        assert driver.poll() is None and all(running(pid) for pid in workers), driver.communicate()[0]
        os.kill(driver.pid, signal.SIGKILL)  # the driver alone, not its process group
        driver.wait(timeout=30)
        wait_for(lambda: not any(running(pid) for pid in workers), 15, f"the workers {workers} to exit")
    finally:
        stop_group(driver)


@pytest.mark.slow
@pytest.mark.parametrize(("number", "status", "said"), [
    (signal.SIGTERM, 143, "terminated (SIGTERM)"), (signal.SIGINT, 130, "interrupted")])
def test_signal_keeps_the_finished_cases_and_stops_the_workers(tmp_path, number, status, said):
    path = write_sweep(tmp_path, [0.1, 0.2, 0.3, 0.4, 0.5, 0.6])
    out = tmp_path / "out"
    log = tmp_path / "calls"
    driver = hooked_sweep([str(path), "--out", str(out), "--workers", "1", "--quiet"],
                          tmp_path, log=str(log), sleep="1.5")
    try:
        wait_for(lambda: any((out / "cases").glob("*.nc")) or driver.poll() is not None, 120,
                 "the first case file")
        os.kill(driver.pid, number)  # the driver alone, as `kill` or a batch system's first notice
        output = driver.communicate(timeout=60)[0]
        assert driver.returncode == status, output
        assert said in output and "Traceback" not in output
        wait_for(lambda: not any(running(pid) for pid in logged_pids(log)), 15, "the workers to exit")
    finally:
        stop_group(driver)
    kept = sorted(p.stem for p in (out / "cases").glob("*.nc"))
    assert 1 <= len(kept) < 6
    frame = load_summary(out)
    assert list(frame["status"]).count("finished") == len(kept)
    (incident,) = [i for i in read_incidents(out) if i["event"] == "interrupted"]
    assert incident["detail"].endswith(f"{6 - len(kept)} missing")

    result = cli("sweep", str(path), "--out", str(out), "--workers", "1")
    assert result.exit_code == 0 and f"computed {6 - len(kept)}, kept {len(kept)}" in result.output
    assert_every_case_once(out)


@pytest.mark.slow
def test_folder_conflict_in_a_study_names_the_part(tmp_path, monkeypatch):
    from brushbem import studies

    monkeypatch.setattr(studies, "sweep_file", lambda study, part, quick, sampled=False, subset=None: write_sweep(
        tmp_path, STIFFNESSES[:2] if quick else STIFFNESSES[2:], name=f"{part}{quick}.toml"))
    monkeypatch.setitem(studies.STUDIES, "tiny", studies.Study(
        name="tiny", title="tiny", figures=(), parts=("a",), draw=lambda results, folder: []))
    out = tmp_path / "study"
    assert cli("study", "tiny", "--out", str(out), "--workers", "1", "--quiet").exit_code == 0
    result = cli("study", "tiny", "--quick", "--out", str(out), "--workers", "1", "--quiet")
    assert result.exit_code == 2 and "holds study 'tiny' (quick: False)" in result.output, result.output
    # The part's folder guards itself too, whatever study.json says.
    (out / "study.json").write_text("{")
    result = cli("study", "tiny", "--quick", "--out", str(out), "--workers", "1", "--quiet")
    assert result.exit_code == 2 and str(out / "a") in result.output and "different sweep" in result.output


def test_incidents_survive_a_torn_last_line(tmp_path):
    (tmp_path / INCIDENTS_FILE).write_text('{"event": "lost", "case_id": "0001-x", "detail": "d"}\n{"ev')
    assert [i["case_id"] for i in read_incidents(tmp_path)] == ["0001-x"]


# ----------------------------------------------------------------------------- the lock file, other files


@pytest.mark.parametrize("dangling", [False, True])
def test_a_sweep_lock_that_is_a_symlink_is_refused_and_its_target_untouched(tmp_path, dangling):
    """``.sweep.lock`` as a symlink (in a shared folder, aimed at someone else's file) is refused with
    exit 2 naming it, before any case runs; the file it points to keeps its content (it used to be
    emptied), and a dangling link does not create one."""
    out = tmp_path / "out"
    out.mkdir()
    victim = tmp_path / "someone-elses-file"
    victim.write_text("precious\n")
    lock = out / ".sweep.lock"
    lock.symlink_to(tmp_path / "nothing-here" if dangling else victim)
    result = cli("sweep", str(write_sweep(tmp_path)), "--out", str(out), "--workers", "1", "--quiet")
    assert result.exit_code == 2, result.output
    assert str(lock) in result.output and "symbolic link" in result.output
    assert victim.read_text() == "precious\n" and not (tmp_path / "nothing-here").exists()
    assert not list((out / "cases").glob("*.nc")) and not (out / "sweep.json").exists()


def test_only_the_drivers_own_temporaries_are_removed(tmp_path):
    """A killed driver's temporaries (``.<its file>.<random>.tmp``) are removed; a user's hidden
    ``*.tmp`` files, in the folder or in ``cases/``, are kept (every one in ``cases/`` used to go)."""
    from brushbem.sweep.store import _remove_stale_temporaries

    out = tmp_path / "out"
    (out / "cases").mkdir(parents=True)
    ours = [out / ".sweep.json.k3j4.tmp", out / ".summary.parquet.x9y8.tmp",
            out / "cases" / ".0000-6efc536def.nc.ab_12cd3.tmp"]
    theirs = [out / ".vimswap.tmp", out / ".sweep.json.tmp", out / "cases" / ".notes.tmp",
              out / "cases" / ".draft.txt.abcd1234.tmp"]
    for path in ours + theirs:
        path.write_text("x")
    _remove_stale_temporaries(out)
    assert not any(path.exists() for path in ours)
    assert all(path.read_text() == "x" for path in theirs)
    (incident,) = read_incidents(out)
    assert "3 half-written" in incident["detail"]


def test_an_empty_out_is_refused_for_a_sweep(tmp_path, monkeypatch):
    """``sweep --out ""`` is refused with exit 2 instead of running into the working folder."""
    path = write_sweep(tmp_path)
    monkeypatch.chdir(tmp_path)
    before = sorted(tmp_path.iterdir())
    result = cli("sweep", str(path), "--out", "", "--dry-run")
    assert result.exit_code == 2 and "empty path" in result.output, result.output
    assert sorted(tmp_path.iterdir()) == before


# ----------------------------------------------------------------------------- bounds on the sweep file


def test_an_oversized_sweep_file_is_refused_before_it_is_parsed(tmp_path, monkeypatch):
    """A sweep file over MAX_SWEEP_BYTES (a 2.9 MB one used to be accepted) is refused with exit 2,
    naming the file, its size and the limit; tomllib never sees it."""
    import tomllib

    from brushbem.config import MAX_SWEEP_BYTES

    path = write_sweep(tmp_path)
    with path.open("a") as stream:
        stream.write(f"# {'x' * 98}\n" * (MAX_SWEEP_BYTES // 100 + 1))
    size = path.stat().st_size

    def parse(*args, **kwargs):
        raise AssertionError("parsed")

    monkeypatch.setattr(tomllib, "loads", parse)
    result = cli("sweep", str(path), "--dry-run")
    assert result.exit_code == 2, result.output
    assert str(path) in result.output and f"{size} bytes" in result.output
    assert f"larger than {MAX_SWEEP_BYTES} bytes" in result.output


def test_an_oversized_base_file_is_refused(tmp_path):
    """The sweep's base file is read within a run configuration's limit (MAX_CONFIG_BYTES)."""
    from brushbem.config import MAX_CONFIG_BYTES

    path = write_sweep(tmp_path)
    with (tmp_path / "base.toml").open("a") as stream:
        stream.write(f"# {'x' * 98}\n" * (MAX_CONFIG_BYTES // 100 + 1))
    result = cli("sweep", str(path), "--dry-run")
    assert result.exit_code == 2, result.output
    assert "`base`" in result.output and f"larger than {MAX_CONFIG_BYTES} bytes" in result.output


@pytest.mark.parametrize(("levels", "found"), [
    (2000, "nested too deeply (2000 levels"),  # beyond tomllib's recursion: a RecursionError, exit 1, before
    (100, "nested 101 levels deep"),  # parsed (sweep > key > 99 more lists), then refused
])
def test_a_deeply_nested_sweep_file_is_refused(tmp_path, levels, found):
    """A sweep file nested deeper than MAX_SWEEP_DEPTH is refused with exit 2, naming the file, the
    depth found and the limit (2000 levels used to end in a RecursionError and exit 1)."""
    from brushbem.config import MAX_SWEEP_DEPTH

    path = tmp_path / "deep.toml"
    (tmp_path / "base.toml").write_text(BASE_TOML)
    path.write_text(f'base = "base.toml"\n[sweep]\n"indenter.stiffness" = {"[" * levels}{"]" * levels}\n')
    result = cli("sweep", str(path), "--dry-run")
    assert result.exit_code == 2, result.output
    assert str(path) in result.output and found in result.output
    assert f"more than {MAX_SWEEP_DEPTH} levels" in result.output


def test_a_deeply_nested_sweep_mapping_is_refused(tmp_path):
    """`parse_sweep` on a mapping: the same limit, a SweepError naming where, never a RecursionError."""
    from brushbem.sweep import SweepError, parse_sweep

    value: list = []
    for _ in range(5000):
        value = [value]
    with pytest.raises(SweepError, match=r"nested 5002 levels deep — a sweep nests at most \d+"):
        parse_sweep({"base": tomllib_base(), "sweep": {"indenter.stiffness": value}}, tmp_path)


@pytest.mark.parametrize(("settings", "sweep", "says"), [
    ("realizations = 1000000", {"indenter.stiffness": "[0.1]"}, "`realizations`: 1000000 cases"),
    ("", {"indenter.stiffness": "[" + ", ".join(f"0.{i + 1:04d}" for i in range(3000)) + "]",
          "indenter.radius": "[" + ", ".join(f"0.{i + 1:04d}" for i in range(3000)) + "]"},
     '`sweep."indenter.stiffness"` x `sweep."indenter.radius"`: 3000 x 3000 = 9000000 cases'),
    ("", {"solver.max_iterations": "[" + "1," * 100_001 + "]"},
     '`sweep."solver.max_iterations"`: 100001 cases'),
    ('mode = "zip"\nrealizations = 7', {"solver.max_iterations": "[" + "1," * 20_000 + "]",
                                        "protocol.max_steps": "[" + "1," * 20_000 + "]"},
     "x `realizations`: 20000 x 7 = 140000 cases"),
], ids=["realizations", "product", "long-list", "zip"])
def test_a_sweep_of_too_many_cases_is_refused_before_any_case_is_built(tmp_path, monkeypatch, settings, sweep,
                                                                        says):
    """A sweep expanding to more than MAX_SWEEP_CASES cases is refused with exit 2, naming the keys,
    the count and the limit, from the counts alone: no seed drawn, no case built, so --dry-run answers
    at once (it used to be silent past 120 s)."""
    from brushbem.config import MAX_SWEEP_CASES
    from brushbem.sweep import spec

    def built(*args, **kwargs):
        raise AssertionError("a case was built")

    monkeypatch.setattr(spec, "_realization_seeds", built)
    monkeypatch.setattr(spec, "_validate_case", built)
    (tmp_path / "base.toml").write_text(BASE_TOML)
    path = tmp_path / "many.toml"
    path.write_text("\n".join(['base = "base.toml"', settings, "[sweep]",
                               *(f'"{key}" = {values}' for key, values in sweep.items())]) + "\n")
    result = cli("sweep", str(path), "--dry-run")
    assert result.exit_code == 2, result.output
    assert says in result.output and f"at most {MAX_SWEEP_CASES} cases" in result.output


def test_the_case_limit_admits_every_shipped_sweep():
    """MAX_SWEEP_CASES is above the largest shipped sweep (counted, not expanded)."""
    import math
    import tomllib

    from brushbem.config import MAX_SWEEP_CASES

    sweeps = Path(__file__).resolve().parents[1] / "src" / "brushbem" / "studies" / "sweeps"
    counts = {}
    for path in sweeps.glob("*.toml"):
        document = tomllib.loads(path.read_text())
        lengths = [len(values) for values in document.get("sweep", {}).values()]
        points = (lengths[0] if lengths else 1) if document.get("mode") == "zip" else math.prod(lengths)
        counts[path.name] = points * document.get("realizations", 1)
    assert counts and max(counts.values()) <= MAX_SWEEP_CASES, max(counts.items(), key=lambda item: item[1])
