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
