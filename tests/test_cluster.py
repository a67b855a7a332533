"""Scale-out on a real dask cluster: a scheduler and two workers as separate processes.

``brushbem sweep --scheduler-file`` drives the sweep; one worker is killed
(SIGKILL, by its process id) once the first cases are written.  The
scheduler hands the lost worker's cases to the other one; every case must
then be recorded exactly once, all finished, and equal to a local run bit
for bit (the computation is deterministic; only the wall times differ).
"""

from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from test_sweep import assert_bit_identical, comparable

from brushbem.sweep import load_summary, run_sweep

pytest.importorskip("dask.distributed")

#: Twelve punches on springs at N = 128 (about a second each on one core), so
#: that the kill lands while cases remain.
SWEEP = """
base = { halfspace = { contact_modulus = 1.0, work_of_adhesion = 1.0e-4 }, grid = { size = 1.0, elements = 128 }, indenter = { shape = "flat_punch", radius = 0.25, stiffness = 0.15 }, protocol = { method = "events", preload_displacement = 0.002 } }
mode = "product"
seed = 3

[sweep]
"indenter.stiffness" = [0.01, 0.02, 0.05, 0.1, 0.15, 0.2, 0.3, 0.5, 1.0, 2.0, 5.0, 10.0]
"""


def _command(name: str) -> list[str]:
    """The console script ``name`` of this interpreter's environment."""
    script = Path(sys.executable).with_name(name)
    found = str(script) if script.exists() else shutil.which(name)
    if found is None:
        pytest.skip(f"no {name} command next to the interpreter")
    return [found]


def _wait_for(predicate, timeout: float, what: str) -> None:
    deadline = time.monotonic() + timeout
    while not predicate():
        if time.monotonic() > deadline:
            raise AssertionError(f"timed out after {timeout} s waiting for {what}")
        time.sleep(0.1)


@pytest.mark.slow
def test_sweep_on_a_cluster_survives_a_killed_worker(tmp_path):
    sweep_path = tmp_path / "sweep.toml"
    sweep_path.write_text(SWEEP)
    scheduler_file = tmp_path / "scheduler.json"
    dask = _command("dask")
    env = {**os.environ, "OMP_NUM_THREADS": "1"}
    processes: list[subprocess.Popen] = []
    try:
        processes.append(subprocess.Popen(
            [*dask, "scheduler", "--scheduler-file", str(scheduler_file), "--host", "127.0.0.1", "--port", "0",
             "--no-dashboard"], env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
        _wait_for(scheduler_file.exists, 60, "the scheduler file")
        workers = []
        for _ in range(2):
            # --no-nanny: the process id is the worker's own (a nanny would restart it).
            worker = subprocess.Popen(
                [*dask, "worker", "--scheduler-file", str(scheduler_file), "--nthreads", "1", "--no-nanny",
                 "--no-dashboard", "--host", "127.0.0.1"], env=env,
                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            processes.append(worker)
            workers.append(worker)

        def registered() -> bool:
            from distributed import Client

            with Client(scheduler_file=str(scheduler_file), timeout=10) as client:
                return len(client.scheduler_info()["workers"]) == 2

        _wait_for(registered, 60, "two workers")
        out = tmp_path / "cluster"
        driver = subprocess.Popen(
            [*_command("brushbem"), "sweep", str(sweep_path), "--out", str(out),
             "--scheduler-file", str(scheduler_file), "--quiet"],
            env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        processes.append(driver)
        cases = out / "cases"
        _wait_for(lambda: cases.exists() and any(cases.glob("*.nc")), 120, "the first case file")
        written_at_kill = len(list(cases.glob("*.nc")))
        os.kill(workers[0].pid, signal.SIGKILL)
        _, stderr = driver.communicate(timeout=300)
        assert driver.returncode == 0, stderr
        assert written_at_kill < 12, "every case was done before the kill: the test proved nothing"
    finally:
        for process in reversed(processes):
            if process.poll() is None:
                process.kill()
                process.wait(timeout=30)

    # Every case exactly once (one file per case id, one summary row each), all finished.
    files = sorted(p.stem for p in cases.glob("*.nc"))
    record = json.loads((out / "sweep.json").read_text())
    assert files == sorted(case["case_id"] for case in record["cases"])
    summary = load_summary(out)
    assert len(summary) == 12 and summary["case_id"].is_unique
    assert set(summary["status"]) == {"finished"}
    # Equal to a local run, bit for bit.
    run_sweep(sweep_path, tmp_path / "local", workers=2)
    local = load_summary(tmp_path / "local")
    assert comparable(local).equals(comparable(summary))
    assert_bit_identical(tmp_path / "local", out)
