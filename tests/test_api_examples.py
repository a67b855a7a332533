"""The Python API page's examples (docs/site/api.md) run as written, and the public API is what it says."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import brushbem

ROOT = Path(__file__).resolve().parents[1]
API_PAGE = ROOT / "docs" / "site" / "api.md"


def _first_python_block(heading: str, page: Path = API_PAGE) -> str:
    text = page.read_text(encoding="utf-8")
    section = text[text.index(heading):]
    match = re.search(r"```python\n(.*?)```", section, re.DOTALL)
    assert match, f"no python block under {heading!r}"
    return match.group(1)


def test_readme_python_example_runs_as_written():
    namespace: dict = {}
    exec(compile(_first_python_block("# Python API"), "api.md", "exec"), namespace)  # noqa: S102
    result = namespace["result"]
    assert result.converged
    # The returned views agree with the summary and the curve they come from.
    assert result.adhesive_force == pytest.approx(-float(np.min(result.curve.force)), rel=1e-12)
    assert result.adhesive_force > 0 and result.work_of_separation > 0
    dataset = namespace["dataset"]
    np.testing.assert_array_equal(dataset["force"].values, result.curve.force)
    assert namespace["figure"].axes


def test_run_from_a_file_and_from_a_mapping_agree(tmp_path):
    """brushbem.run takes a path or a mapping; save writes the files of ``brushbem run``."""
    config = {
        "halfspace": {"contact_modulus": 1.0, "work_of_adhesion": 1e-3},
        "grid": {"size": 1.0, "elements": 64},
        "indenter": {"shape": "flat_punch", "radius": 0.25, "stiffness": 0.15},
        "protocol": {"preload_displacement": 0.01},
    }
    path = tmp_path / "punch.toml"
    path.write_text(
        "[halfspace]\ncontact_modulus = 1.0\nwork_of_adhesion = 1e-3\n[grid]\nsize = 1.0\nelements = 64\n"
        "[indenter]\nshape = \"flat_punch\"\nradius = 0.25\nstiffness = 0.15\n"
        "[protocol]\npreload_displacement = 0.01\n",
        encoding="utf-8",
    )
    from_mapping = brushbem.run(config)
    from_file = brushbem.run(path)
    assert from_file.adhesive_force == from_mapping.adhesive_force
    assert from_file.summary["theory"] == from_mapping.summary["theory"]
    out = from_file.save(tmp_path / "out")
    assert {p.name for p in out.iterdir()} >= {"summary.json", "result.nc", "pulloff.png"}
    with pytest.raises(brushbem.ConfigError, match="grid.elements"):
        brushbem.run({**config, "grid": {"size": 1.0, "elements": 3}})
    with pytest.raises(TypeError, match="config = 3"):
        brushbem.run(3)


def test_import_brushbem_loads_no_numerics():
    """``import brushbem`` (and the CLI's validate) stays light: the names load on first use."""
    code = "import sys, brushbem; print(any(m.startswith(('scipy', 'brushbem.numerics.solver')) for m in sys.modules))"
    assert subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.strip() == "False"
    assert set(brushbem.__all__) >= {"run", "pull_off", "brush", "Grid", "ConfigError"}
    with pytest.raises(AttributeError):
        brushbem.not_a_name  # noqa: B018


@pytest.mark.docs
def test_readme_beyond_the_thesis_example_runs_as_written():
    """The API page's block on tip shapes, gradients, tilt, viscoelastic and nonlinear pillars runs and converges."""
    block = _first_python_block("Tip shapes, gradients, tilt, viscoelastic and nonlinear pillars")
    namespace: dict = {}
    exec(compile(block, "api.md", "exec"), namespace)  # noqa: S102
    for name in ("graded", "pulled", "pressed"):
        assert namespace[name].converged, (name, namespace[name].summary["reason"])
    assert namespace["pressed"].summary["preload_force"] > 0
    assert namespace["graded"].adhesive_force > 0 and namespace["pulled"].work_of_separation > 0
