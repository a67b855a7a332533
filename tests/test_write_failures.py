"""Writes that fail after the free-space check: a result too large to render in memory is streamed through
Python, so that a failed write (a quota, a disk another writer filled, a file-size limit) is an ``OSError``
and exit 4, never a crash inside HDF5; a figure that cannot be written says so, and that the results were.

No test writes a large file: the in-memory limit is lowered to 0 bytes, so that every result takes the
streaming path, and the failure is injected (a failing file, or a file-size limit in a subprocess)."""

from __future__ import annotations

import errno
import io
import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest
from click.testing import CliRunner

import brushbem.io as bio
import brushbem.io.writing as bio_writing  # where IN_MEMORY_LIMIT and open are read
from brushbem.runs.assembly import parse_config
from brushbem.runs.case import run_case
from brushbem.cli import main

PUNCH = textwrap.dedent("""
    [halfspace]
    contact_modulus = 1.0
    work_of_adhesion = 1e-3
    [grid]
    size = 1.0
    elements = 32
    [indenter]
    shape = "flat_punch"
    radius = 0.25
    [protocol]
    method = "events"
    preload_displacement = 0.01
""")


@pytest.fixture(scope="module")
def punch():
    config = parse_config({
        "halfspace": {"contact_modulus": 1.0, "work_of_adhesion": 1e-3}, "grid": {"size": 1.0, "elements": 32},
        "indenter": {"shape": "flat_punch", "radius": 0.25}, "protocol": {"preload_displacement": 0.01},
    })
    return run_case(config).result, config


def _leftovers(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir() if p.name.endswith(".tmp"))


def test_the_streaming_path_writes_the_same_file(punch, tmp_path, monkeypatch):
    result, config = punch
    bio.write_case(result, tmp_path / "memory", config=config)
    monkeypatch.setattr(bio_writing, "IN_MEMORY_LIMIT", 0)
    bio.write_case(result, tmp_path / "streamed", config=config)
    memory, streamed = bio.read_case(tmp_path / "memory"), bio.read_case(tmp_path / "streamed")
    for name in ("force", "pressure", "contact"):
        assert (memory[name].values == streamed[name].values).all()
    assert _leftovers(tmp_path / "streamed") == []


class _FailingFile(io.FileIO):
    """A file whose writes fail with ENOSPC once ``budget`` bytes are written (a disk filled by another writer)."""

    budget = 4096

    def write(self, data):
        if self.tell() + len(memoryview(data)) > self.budget:
            raise OSError(errno.ENOSPC, "No space left on device")
        return super().write(data)


def test_a_failed_streamed_write_is_an_oserror_and_leaves_nothing(punch, tmp_path, monkeypatch):
    result, config = punch
    monkeypatch.setattr(bio_writing, "IN_MEMORY_LIMIT", 0)
    monkeypatch.setattr(bio_writing, "open",
                        lambda path, mode="r", buffering=-1: _FailingFile(path, mode.replace("b", "")), raising=False)
    target = tmp_path / "result.nc"
    with pytest.raises(OSError) as caught:
        bio.write_dataset(result, target, config=config)
    assert caught.value.errno == errno.ENOSPC and caught.value.filename == str(target)
    assert not target.exists() and _leftovers(tmp_path) == []


def _limited_run(tmp_path: Path, limit: int) -> subprocess.CompletedProcess:
    """``brushbem run`` in a process whose files may not exceed ``limit`` bytes (RLIMIT_FSIZE: EFBIG), every
    result streamed."""
    config = tmp_path / "punch.toml"
    config.write_text(PUNCH)
    script = textwrap.dedent(f"""
        import resource, signal, sys
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # a write past the limit fails with EFBIG instead
        import brushbem.io.writing as bio
        from brushbem.cli import main
        bio.IN_MEMORY_LIMIT = 0
        resource.setrlimit(resource.RLIMIT_FSIZE, ({limit}, resource.RLIM_INFINITY))
        main(["run", {str(config)!r}, "--out", {str(tmp_path / "out")!r}, "--quiet"])
    """)
    return subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120, check=False)


@pytest.mark.skipif(not hasattr(os, "fork") or sys.platform != "linux", reason="RLIMIT_FSIZE (Linux)")
def test_a_write_that_fails_inside_the_file_system_exits_4_not_a_crash(tmp_path):
    """The file-size limit fails result.nc's writes (where HDF5 writing the file itself crashed the process,
    exit 139): the run exits 4, names the failure, and leaves no result and no temporary."""
    done = _limited_run(tmp_path, 8192)
    assert done.returncode == 4, (done.returncode, done.stderr)
    assert "could not write the results" in done.stderr and "File too large" in done.stderr
    assert "Traceback" not in done.stdout + done.stderr
    out = tmp_path / "out"
    assert not (out / "result.nc").exists() and not (out / "summary.json").exists()
    assert _leftovers(out) == []


def test_a_figure_that_cannot_be_written_says_so_and_that_the_results_were(tmp_path, monkeypatch):
    config = tmp_path / "punch.toml"
    config.write_text(PUNCH)
    out = tmp_path / "out"
    assert CliRunner().invoke(main, ["run", str(config), "--out", str(out), "--quiet"]).exit_code == 0
    assert (out / "pulloff.png").exists()

    def full_disk(result, path, reference=None, **kwargs):
        raise OSError(errno.ENOSPC, "No space left on device", str(path))

    import brushbem.figures.plot

    monkeypatch.setattr(brushbem.figures.plot, "plot_pull_off", full_disk)
    done = CliRunner().invoke(main, ["run", str(config), "--out", str(out), "--quiet", "--overwrite"])
    assert done.exit_code == 4, done.output
    assert "could not write the figure pulloff.png (pulloff.png: No space left on device)" in done.output
    assert "summary.json and result.nc were written" in done.output
    assert "could not write the results" not in done.output
    # The results of this run are there and whole; the earlier run's figure is not left beside them.
    data = bio.read_case(out)
    assert data.attrs["run_id"] == json.loads((out / "summary.json").read_text())["run_id"]
    assert not (out / "pulloff.png").exists()


def test_a_signal_during_the_writing_of_a_complete_result_is_not_an_interruption(tmp_path, monkeypatch):
    """Ctrl-C (SIGINT) while a complete, converged result is written: the files are written whole and the
    run says so, exit 0 (it said "partial result" and exited 130 for a result that was not partial)."""
    import signal

    from brushbem.runs.pulloff import PullOff

    config = tmp_path / "punch.toml"
    config.write_text(PUNCH)
    save = PullOff.save

    def save_under_a_signal(self, *args, **kwargs):
        os.kill(os.getpid(), signal.SIGINT)  # the run's handler records it; the write goes on
        return save(self, *args, **kwargs)

    monkeypatch.setattr(PullOff, "save", save_under_a_signal)
    out = tmp_path / "out"
    done = CliRunner().invoke(main, ["run", str(config), "--out", str(out), "--quiet"])
    assert done.exit_code == 0, done.output
    assert "partial" not in done.output and "SIGINT arrived after the pull-off was computed" in done.output
    summary = json.loads((out / "summary.json").read_text())
    assert summary["converged"] and not summary["interrupted"]
