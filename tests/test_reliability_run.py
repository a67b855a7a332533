"""`brushbem run` attacked from outside: signals, a busy, read-only or full output folder, a
writer killed between its two files, and inputs whose scales the numerics cannot resolve.

Every test goes through the command line (a subprocess where a signal or a crash must be
seen as the user sees it) and asserts the promise: a named refusal or a readable result,
never a traceback, a crash, or a half-written file that a reader takes for a result.
"""

from __future__ import annotations

import json
import math
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from brushbem import protocol
from brushbem.runs.assembly import parse_config
from brushbem.runs.case import run_case
from brushbem.cli import main
from brushbem.io import InconsistentCaseError, read_case

ROOT = Path(__file__).resolve().parents[1]
BRUSHBEM = [sys.executable, "-m", "brushbem"]

# A brush on the element path at N = 512: tens of seconds, so that a signal sent a
# second after the run took its folder always arrives mid-computation.
LONG_RUN = textwrap.dedent("""
    [halfspace]
    contact_modulus = 1.0
    work_of_adhesion = 1.0e-4
    [grid]
    size = 1.0
    elements = 512
    [indenter]
    shape = "brush"
    layout = "square"
    region = "square"
    pillars_per_side = 16
    pillar_radius = 0.0122
    stiffness_ratio = 0.455
    [protocol]
    method = "element_events"
    preload_displacement = 0.002
""")

PUNCH = textwrap.dedent("""
    [halfspace]
    contact_modulus = {modulus}
    work_of_adhesion = 1e-3
    [grid]
    size = 1.0
    elements = {elements}
    [indenter]
    shape = "flat_punch"
    radius = 0.25
    stiffness = {stiffness}
    [protocol]
    method = "events"
    preload_displacement = 0.01
""")


def _punch(tmp_path: Path, modulus: float = 1.0, stiffness: float | str = "inf", elements: int = 32) -> Path:
    path = tmp_path / "punch.toml"
    path.write_text(PUNCH.format(modulus=modulus, stiffness=stiffness, elements=elements))
    return path


def _start(config: Path, out: Path) -> subprocess.Popen:
    return subprocess.Popen([*BRUSHBEM, "run", str(config), "--out", str(out), "--quiet"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def _wait_for_lock(out: Path, process: subprocess.Popen, limit: float = 60.0) -> None:
    """Until the run holds its folder (the configuration is valid and the computation starts)."""
    deadline = time.monotonic() + limit
    while not (out / ".brushbem.lock").exists():
        assert process.poll() is None, process.communicate()
        assert time.monotonic() < deadline, "the run never took its folder"
        time.sleep(0.05)


def _no_leftovers(out: Path) -> None:
    """No temporary file that a reader could mistake, and no result without its partner."""
    assert not list(out.glob(".*.tmp")), list(out.iterdir())
    assert (out / "summary.json").exists() == (out / "result.nc").exists(), list(out.iterdir())


# ------------------------------------------------------------------ signals


@pytest.mark.slow
@pytest.mark.parametrize(("number", "status"), [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_interrupted_run_keeps_a_readable_partial_result(tmp_path, number, status):
    config = tmp_path / "long.toml"
    config.write_text(LONG_RUN)
    out = tmp_path / "out"
    process = _start(config, out)
    _wait_for_lock(out, process)
    time.sleep(1.5)
    process.send_signal(number)
    stdout, stderr = process.communicate(timeout=120)
    assert process.returncode == status, stderr
    assert "Traceback" not in stdout + stderr
    assert "partial result" in stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["interrupted"] is True and summary["converged"] is False
    assert summary["reason"].startswith("interrupted at d =")
    dataset = read_case(out)  # the pair is consistent and readable
    assert dataset.sizes["step"] == summary["n_states"] > 0
    assert not bool(dataset["converged"].values.all()) or summary["n_states"] > 0
    _no_leftovers(out)


# ------------------------------------------------------------------ output folders


@pytest.mark.slow
def test_second_run_into_a_busy_folder_is_refused(tmp_path):
    config = tmp_path / "long.toml"
    config.write_text(LONG_RUN)
    out = tmp_path / "out"
    first = _start(config, out)
    try:
        _wait_for_lock(out, first)
        second = subprocess.run(check=False, args=[*BRUSHBEM, "run", str(_punch(tmp_path)), "--out", str(out), "--quiet"],
                                capture_output=True, text=True, timeout=120)
        assert second.returncode == 2, second.stderr
        assert f"pid {first.pid}" in second.stderr and str(out) in second.stderr
        assert "Traceback" not in second.stdout + second.stderr
        assert not (out / "summary.json").exists()  # the refused run wrote nothing
    finally:
        first.kill()
        first.communicate()  # waits, and closes its pipes
    # The kernel dropped the killed run's lock: the folder is usable again.
    rerun = CliRunner().invoke(main, ["run", str(_punch(tmp_path)), "--out", str(out), "--quiet"])
    assert rerun.exit_code == 0, rerun.output
    _no_leftovers(out)


def test_out_that_is_a_file_is_refused(tmp_path):
    target = tmp_path / "taken"
    target.write_text("not a folder")
    result = CliRunner().invoke(main, ["run", str(_punch(tmp_path)), "--out", str(target)])
    assert result.exit_code == 2
    assert "taken" in result.output and "Traceback" not in result.output
    assert target.read_text() == "not a folder"


def _mount_tmpfs(where: Path, options: str) -> bool:
    where.mkdir()
    if os.geteuid() != 0:
        return False
    done = subprocess.run(check=False, args=["mount", "-t", "tmpfs", "-o", options, "tmpfs", str(where)], capture_output=True)
    return done.returncode == 0


def _unmount(where: Path) -> None:
    subprocess.run(check=False, args=["umount", str(where)], capture_output=True)


def test_read_only_out_is_refused_before_computing(tmp_path):
    out = tmp_path / "ro"
    if _mount_tmpfs(out, "ro,size=64k"):
        try:
            result = CliRunner().invoke(main, ["run", str(_punch(tmp_path)), "--out", str(out)])
        finally:
            _unmount(out)
    elif os.geteuid() != 0:
        out.chmod(0o555)
        result = CliRunner().invoke(main, ["run", str(_punch(tmp_path)), "--out", str(out)])
    else:
        pytest.skip("root without mount: no read-only folder can be made")
    assert result.exit_code == 2, result.output
    assert "--out" in result.output and "cannot write" in result.output
    # Refused before the computation: no progress, no summary table.
    assert "pull-off summary" not in result.output
    assert result.exception is None or isinstance(result.exception, SystemExit)


@pytest.mark.slow
def test_full_disk_is_a_message_not_a_crash(tmp_path):
    out = tmp_path / "tiny"
    if not _mount_tmpfs(out, "size=64k"):
        pytest.skip("cannot mount a tiny tmpfs here (needs root)")
    try:
        done = subprocess.run(check=False, args=[*BRUSHBEM, "run", str(_punch(tmp_path)), "--out", str(out / "o"), "--quiet"],
                              capture_output=True, text=True, timeout=300)
        assert done.returncode == 4, (done.returncode, done.stderr)  # 139 was a segfault in HDF5
        assert "Traceback" not in done.stdout + done.stderr
        assert "no space left" in done.stderr.lower()
        assert not (out / "o" / "summary.json").exists() and not (out / "o" / "result.nc").exists()
        _no_leftovers(out / "o")

        # Past the free-space check (space taken after it), the in-memory rendering makes
        # the disk's refusal an OSError of Python's write, never a crash inside HDF5.
        script = textwrap.dedent(f"""
            import errno, sys
            import brushbem.io.writing as io
            from brushbem.runs.case import run_case
            from brushbem.runs.assembly import load_config
            io._check_free_space = lambda folder, needed: None
            config = load_config({str(_punch(tmp_path))!r})
            result = run_case(config).result
            import os, shutil
            os.makedirs({str(out / "o")!r}, exist_ok=True)
            # Another writer takes the space after the check: all but 2 kB, less than any result file.
            with open({str(out / "filler")!r}, "wb") as filler:
                filler.write(bytes(max(shutil.disk_usage({str(out)!r}).free - 2048, 0)))
            try:
                io.write_case(result, {str(out / "o")!r}, config=config)
            except OSError as exc:
                sys.exit(10 if exc.errno == errno.ENOSPC else 11)
        """)
        done = subprocess.run(check=False, args=[sys.executable, "-c", script], capture_output=True, text=True, timeout=300)
        assert done.returncode == 10, (done.returncode, done.stderr)
        _no_leftovers(out / "o")
    finally:
        _unmount(out)


@pytest.mark.slow
def test_writer_killed_between_its_two_files(tmp_path):
    """A run killed after result.nc but before summary.json: the pair is refused, a rerun repairs it."""
    out = tmp_path / "out"
    config = _punch(tmp_path)
    first = CliRunner().invoke(main, ["run", str(config), "--out", str(out), "--quiet"])
    assert first.exit_code == 0
    old_summary = (out / "summary.json").read_text()
    script = textwrap.dedent(f"""
        import os
        import brushbem.io.writing as io
        from brushbem.runs.case import run_case
        from brushbem.runs.assembly import load_config
        original = io.write_dataset
        def write_then_die(*args, **kwargs):
            original(*args, **kwargs)
            open({str(out / ".summary.json.killed.tmp")!r}, "w").write("{{ half")
            os._exit(9)  # as SIGKILL: no cleanup
        io.write_dataset = write_then_die
        config = load_config({str(config)!r})
        io.write_case(run_case(config).result, {str(out)!r}, config=config)
    """)
    done = subprocess.run(check=False, args=[sys.executable, "-c", script], capture_output=True, text=True, timeout=300)
    assert done.returncode == 9
    assert (out / "summary.json").read_text() == old_summary  # the old summary beside a new dataset
    with pytest.raises(InconsistentCaseError, match="different runs"):
        read_case(out)
    rerun = CliRunner().invoke(main, ["run", str(config), "--out", str(out), "--quiet", "--overwrite"])
    assert rerun.exit_code == 0, rerun.output
    read_case(out)
    _no_leftovers(out)


# ------------------------------------------------------------------ numerics


def _punch_summary(tmp_path: Path, **values) -> dict:
    config = parse_config({
        "halfspace": {"contact_modulus": values.get("modulus", 1.0), "work_of_adhesion": 1e-3},
        "grid": {"size": 1.0, "elements": 64},
        "indenter": {"shape": "flat_punch", "radius": 0.25, "stiffness": values["stiffness"]},
        "protocol": {"method": "events", "preload_displacement": 0.01},
    })
    return run_case(config).result.summary


def test_soft_springs_solve_the_half_space_part_to_the_tolerance(tmp_path):
    """F_A of a punch does not depend on its spring (Kendall, thesis ch. 2): the solves must
    resolve the half-space's part of the right-hand side, however soft the spring.

    Measured against ||rhs||, a residual of 1e-8 left F_A 3 % high at k = 1e-9 (k / (2 E* a) =
    2e-9).  Down to k / (2 E* a) = 2e-6 the half-space's part is 2e-6 of the rhs, a relative
    residual of 2e-14 on it is still resolved, and F_A agrees with the stiff spring's to 1e-7
    (the tolerance 1e-8 times the conditioning of the set's solve).
    """
    stiff = _punch_summary(tmp_path, stiffness=0.15)
    assert stiff["converged"]
    for stiffness in (1e-3, 1e-6):
        soft = _punch_summary(tmp_path, stiffness=stiffness)
        assert soft["converged"], soft["reason"]
        assert soft["adhesive_force"] == pytest.approx(stiff["adhesive_force"], rel=1e-7)


@pytest.mark.parametrize(("modulus", "stiffness"), [(1.0, 1e-9), (1e12, 0.15)])
def test_unresolvable_spring_is_refused_before_the_run(tmp_path, modulus, stiffness):
    """k / (2 E* a) = 2e-9 and 3e-13: the tip's displacement lies below the rounding of d.

    Before, both ran to "converged" with F_A / Kendall = 1.03 and 1.0077 (4.4 at E* = 1e12,
    k = 1e-9); then the run said why it could not solve them, but only while its residual had not
    already rounded to zero.  Now every spring that far below the solver's floor is refused at
    validation, naming the key and the least stiffness that resolves.
    """
    result = CliRunner().invoke(main, ["run", str(_punch(tmp_path, modulus, stiffness)), "--out",
                                       str(tmp_path / "out"), "--quiet"])
    assert result.exit_code == 2, result.output
    assert "`indenter.stiffness`" in result.output and "too soft to resolve" in result.output
    assert "k >= " in result.output and "Traceback" not in result.output
    assert not (tmp_path / "out" / "summary.json").exists()


def test_a_spring_near_the_floor_is_run_and_reported_not_converged(tmp_path):
    """k / (2 E* a) = 2e-7: above the validation's margin, below what the solver resolves at
    solver.tolerance = 1e-8: the run says why it cannot be solved (exit 3)."""
    result = CliRunner().invoke(main, ["run", str(_punch(tmp_path, 1.0, 1e-7, elements=16)), "--out",
                                       str(tmp_path / "out"), "--quiet"])
    assert result.exit_code == 3, result.output
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert summary["converged"] is False
    assert "double precision" in summary["reason"]


def test_non_finite_summary_is_never_converged(tmp_path, monkeypatch):
    """The last guard: a number that overflows makes the run unconverged, with the reason."""
    monkeypatch.setattr(protocol.recording, "work_of_separation", lambda points: math.inf)
    summary = _punch_summary(tmp_path, stiffness=math.inf)
    assert summary["converged"] is False
    assert "non-finite work_of_separation" in summary["reason"]


def test_fixed_steps_beyond_the_pull_off_still_find_it(tmp_path):
    """Steps of 2.5x to 25 000x the pull-off displacement: the first detachment inside the
    step is located exactly, so F_A is the event path's (it was 0 with W > 0 before)."""
    base = {
        "halfspace": {"contact_modulus": 1.0, "work_of_adhesion": 1e-9},
        "grid": {"size": 1.0, "elements": 64},
        "indenter": {"shape": "flat_punch", "radius": 0.25, "stiffness": math.inf},
    }
    events = run_case(parse_config({**base, "protocol": {"method": "events", "preload_displacement": 0.01}}))
    reference = events.result.summary["adhesive_force"]
    for step in (1e-4, 1e-3, 1e-2):
        fixed = run_case(parse_config({**base, "protocol": {
            "method": "fixed", "step": step, "preload_displacement": 0.01}})).result.summary
        assert fixed["converged"]
        # A rigid punch detaches at once: the crossing is exact on the full contact set.
        assert fixed["adhesive_force"] == pytest.approx(reference, rel=1e-6)
        assert fixed["work_of_separation"] > 0.0
    assert np.isfinite(reference) and reference > 0


SPHERE = textwrap.dedent("""
    [halfspace]
    contact_modulus = 1.0
    work_of_adhesion = {dgamma}
    [grid]
    size = 1.0
    elements = 128
    [indenter]
    shape = "sphere"
    radius = {radius}
    [protocol]
    method = "events"
    preload_displacement = 0.001
""")


@pytest.mark.parametrize(("radius", "dgamma"), [(0.1 / 128, 1e-4), (1.0, 1e-12)])
def test_unresolved_sphere_is_refused(tmp_path, radius, dgamma):
    """R = 0.1 h gave F_A = 34.5 x JKR, dgamma = 1e-12 at R = 1 gave 852 x, both "converged":
    a JKR contact of a fraction of an element is not resolved by the mesh criterion."""
    path = tmp_path / "sphere.toml"
    path.write_text(SPHERE.format(radius=radius, dgamma=dgamma))
    result = CliRunner().invoke(main, ["validate", str(path)])
    assert result.exit_code == 2, result.output
    assert "`indenter.radius`" in result.output and "JKR contact radius" in result.output
    # A resolved sphere on the same grid passes: a_JKR = 0.071, 9 elements.
    path.write_text(SPHERE.format(radius=1.0, dgamma=1e-4))
    assert CliRunner().invoke(main, ["validate", str(path)]).exit_code == 0


def test_fixed_step_beyond_the_domain_is_refused(tmp_path):
    """A step of 1e30 located the pull-off to the rounding of 1e30 (d_A 250 x off, "converged")."""
    path = _punch(tmp_path)
    path.write_text(path.read_text().replace('method = "events"', 'method = "fixed"\nstep = 1e30'))
    result = CliRunner().invoke(main, ["validate", str(path)])
    assert result.exit_code == 2, result.output
    assert "`protocol.step`" in result.output and "grid.size" in result.output


# ------------------------------------------------------------------ the lock file and the folder's other files


def _lock_as(kind: str, lock: Path, victim: Path) -> None:
    """Put a hostile or foreign file where the run's lock goes."""
    if kind == "symlink":  # in a shared folder, aimed at someone else's file
        lock.symlink_to(victim)
    elif kind == "dangling symlink":  # would create the file it names
        lock.symlink_to(victim.parent / "created-through-the-link")
    elif kind == "hard link":
        os.link(victim, lock)
    elif kind == "folder":
        lock.mkdir()
    elif kind == "fifo":  # opening it for writing would block
        os.mkfifo(lock)
    elif kind == "foreign file":  # a regular file that brushbem did not write
        lock.write_text("my notes\n")


@pytest.mark.parametrize("kind", ["symlink", "dangling symlink", "hard link", "folder", "fifo", "foreign file"])
def test_a_lock_that_is_a_link_or_not_brushbems_is_refused_and_left_untouched(tmp_path, kind):
    """A lock that is a symlink (or a hard link, a folder, a FIFO, a file brushbem did not write) is
    refused with exit 2 naming its path, before anything is computed, and its target is untouched:
    the lock used to be opened through links, truncated and overwritten with a pid."""
    out = tmp_path / "out"
    out.mkdir()
    victim = tmp_path / "someone-elses-file"
    victim.write_text("precious\n")
    lock = out / ".brushbem.lock"
    _lock_as(kind, lock, victim)
    before = lock.read_text() if kind == "foreign file" else None

    result = CliRunner().invoke(main, ["run", str(_punch(tmp_path, elements=16)), "--out", str(out), "--quiet"])
    assert result.exit_code == 2, result.output
    assert "Traceback" not in result.output and str(lock) in result.output, result.output
    assert "lock" in result.output
    assert victim.read_text() == "precious\n"
    assert not (tmp_path / "created-through-the-link").exists()
    assert not (out / "summary.json").exists()  # refused before the computation
    if kind == "foreign file":
        assert lock.read_text() == before


class _Computed(Exception):
    """Raised where the computation would start: what the run did to its folder before is final."""


def test_only_the_runs_own_temporaries_are_removed(tmp_path, monkeypatch):
    """A killed run's temporaries (``.<result file>.<random>.tmp``) are removed; other hidden
    ``*.tmp`` files in --out (an editor's swap file, another program's temporaries) are kept:
    every hidden ``*.tmp`` used to be deleted, in the working folder with ``--out .``.  The lock a
    killed run left (its pid) is taken over."""
    from brushbem.runs import case

    def stop(*args, **kwargs):
        raise _Computed

    monkeypatch.setattr(case, "run_case", stop)
    monkeypatch.chdir(tmp_path)
    config = _punch(tmp_path, elements=16)
    ours = [".summary.json.k2x9_abc.tmp", ".result.nc.zz01ab3c.tmp", ".pulloff.png.q7w8e9r0.tmp",
            ".write-check.a1b2c3d4.tmp"]
    theirs = [".vimswap.tmp", ".notes.json.a1b2c3d4.tmp", ".summary.json.tmp", ".result.nc.Upper.tmp"]
    for name in ours + theirs:
        (tmp_path / name).write_text("x")
    (tmp_path / ".result.nc.link0001.tmp").symlink_to(tmp_path / ".vimswap.tmp")
    (tmp_path / ".brushbem.lock").write_text("4711")

    result = CliRunner().invoke(main, ["run", str(config), "--out", ".", "--quiet"])
    assert isinstance(result.exception, _Computed), result.output
    left = {path.name for path in tmp_path.iterdir()}
    assert not left & set(ours), left
    assert set(theirs) | {".result.nc.link0001.tmp"} <= left
    assert all((tmp_path / name).read_text() == "x" for name in theirs)
    assert (tmp_path / ".brushbem.lock").read_text() == str(os.getpid())


def test_an_empty_out_is_refused(tmp_path, monkeypatch):
    """``--out ""`` (almost surely an unset variable) is refused with exit 2, and nothing is written
    into the working folder it used to stand for."""
    monkeypatch.chdir(tmp_path)
    config = _punch(tmp_path, elements=16)
    before = sorted(tmp_path.iterdir())
    result = CliRunner().invoke(main, ["run", str(config), "--out", "", "--quiet"])
    assert result.exit_code == 2, result.output
    assert "--out" in result.output and "empty path" in result.output
    assert sorted(tmp_path.iterdir()) == before


def test_a_second_ctrl_c_while_writing_ends_at_once_and_removes_the_temporary(tmp_path):
    """The second SIGINT lands while the writer holds a non-reentrant lock (as xarray's does while result.nc
    is written) whose cleanup takes it again: raising KeyboardInterrupt there hung the process.  Under
    `_Stop.writing` it removes the temporary and exits 130 at once."""
    script = tmp_path / "write.py"
    script.write_text(textwrap.dedent(f"""
        import os, signal, threading, time
        from pathlib import Path
        from brushbem.cli.common import _Stop
        from brushbem.io import atomic_path

        out = Path({str(tmp_path / "out")!r})
        out.mkdir()
        lock = threading.Lock()
        with _Stop() as stop, stop.writing(out, ("result.nc",)):
            with atomic_path(out / "result.nc") as temporary:
                temporary.write_bytes(b"half a file")
                lock.acquire()
                try:
                    os.kill(os.getpid(), signal.SIGINT)  # the first: stop after the current state
                    os.kill(os.getpid(), signal.SIGINT)  # the second, inside the library's lock
                    time.sleep(5)
                finally:
                    lock.acquire()  # the library's cleanup under its own lock: never returns
    """))
    done = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=60, check=False,
                          env={**os.environ, "PYTHONPATH": str(Path(__file__).resolve().parents[1] / "src")})
    assert done.returncode == 130, (done.returncode, done.stderr[-2000:])
    assert "aborted while writing" in done.stderr and "Traceback" not in done.stderr
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == []  # the temporary removed, nothing written
