"""``brushbem init``: the examples shipped inside the package are the repository's, and each one validates."""

from __future__ import annotations

from pathlib import Path

import pytest
from click.testing import CliRunner

from brushbem.runs.assembly import load_config
from brushbem.cli import EXAMPLES, main
from brushbem.sweep import load_sweep

REPO_EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


@pytest.mark.parametrize("name", list(EXAMPLES))
def test_init_writes_an_example_that_validates(name, tmp_path):
    result = CliRunner().invoke(main, ["init", name, "--out", str(tmp_path)])
    assert result.exit_code == 0, result.output
    written = tmp_path / EXAMPLES[name][0]
    if name == "sweep":
        assert len(load_sweep(written).cases) > 1
        repo = (REPO_EXAMPLES / "sweeps" / "punch_stiffness.toml").read_text()
        # The same sweep, its base beside it instead of one folder up.
        assert written.read_text() == repo.replace('base = "../punch_spring.toml"', 'base = "punch_spring.toml"')
    else:
        load_config(written)
        assert written.read_text() == (REPO_EXAMPLES / written.name).read_text()
    again = CliRunner().invoke(main, ["init", name, "--out", str(tmp_path)])
    assert again.exit_code == 2 and "--force" in again.output
    assert CliRunner().invoke(main, ["init", name, "--out", str(tmp_path), "--force"]).exit_code == 0


# --------------------------------------------------------------------------- init under abuse (issues 61, 62)


def test_the_next_hint_names_the_out_folder_the_tutorial_runs_into(tmp_path):
    result = CliRunner().invoke(main, ["init", "punch_spring", "--out", str(tmp_path / "tutorial")])
    assert result.exit_code == 0, result.output
    assert result.output.splitlines()[-1].endswith(f"--out {tmp_path / 'tutorial' / 'out'}")


def test_init_onto_a_folder_named_like_the_example_is_a_message(tmp_path):
    (tmp_path / "default.toml").mkdir()
    for force in ([], ["--force"]):
        result = CliRunner().invoke(main, ["init", "default", "--out", str(tmp_path), *force])
        assert result.exit_code == 2 and "is a folder" in result.output, result.output
        assert result.exception is None or isinstance(result.exception, SystemExit)


def test_init_force_replaces_a_link_and_never_writes_through_it(tmp_path):
    outside = tmp_path / "outside.txt"
    outside.write_text("not brushbem's")
    out = tmp_path / "out"
    out.mkdir()
    (out / "default.toml").symlink_to(outside)
    refused = CliRunner().invoke(main, ["init", "default", "--out", str(out)])
    assert refused.exit_code == 2 and "--force" in refused.output
    result = CliRunner().invoke(main, ["init", "default", "--out", str(out), "--force"])
    assert result.exit_code == 0, result.output
    assert outside.read_text() == "not brushbem's"  # the link's target is untouched
    assert not (out / "default.toml").is_symlink() and "[indenter]" in (out / "default.toml").read_text()


def test_init_into_a_read_only_folder_is_a_message(tmp_path):
    import os
    import subprocess

    out = tmp_path / "ro"
    out.mkdir()
    mounted = False
    if os.geteuid() == 0:
        mounted = subprocess.run(["mount", "-t", "tmpfs", "-o", "ro,size=64k", "tmpfs", str(out)],
                                 capture_output=True, check=False).returncode == 0
        if not mounted:
            pytest.skip("root without mount: no read-only folder can be made")
    else:
        out.chmod(0o555)
    try:
        result = CliRunner().invoke(main, ["init", "default", "--out", str(out)])
    finally:
        if mounted:
            subprocess.run(["umount", str(out)], capture_output=True, check=False)
    assert result.exit_code == 2 and "cannot write" in result.output, result.output
    assert result.exception is None or isinstance(result.exception, SystemExit)
