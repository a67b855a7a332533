"""The documentation site: it builds with warnings as errors, its tutorial runs as written, its gallery renders.

The site is MkDocs (``mkdocs.yml``; ``make docs``): pages drawn from the
README's sections by ``docs/site/hooks.py``, the API reference from the
numpydoc docstrings (mkdocstrings), the gallery from ``docs/figures``.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
TUTORIAL = ROOT / "docs" / "site" / "tutorial.md"


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("site")
    build = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(out)],
                           cwd=ROOT, capture_output=True, text=True, timeout=600, check=False)
    assert build.returncode == 0, build.stdout[-3000:] + build.stderr[-3000:]
    return out


def test_the_site_builds_with_warnings_as_errors(site):
    for page in ("index.html", "site/tutorial/index.html", "site/configuration/index.html",
                 "site/gallery/index.html", "site/api/index.html", "thesis-comparison/index.html"):
        assert (site / page).is_file(), page
    configuration = (site / "site/configuration/index.html").read_text()
    assert "stiffness_ratio" in configuration and "pillar_law" in configuration  # every key
    assert "record_pull_off" in (site / "site/api/index.html").read_text() or \
        "pull_off" in (site / "site/api/index.html").read_text()


@pytest.mark.slow
def test_the_tutorial_runs_as_written(tmp_path):
    text = TUTORIAL.read_text(encoding="utf-8")
    shell = re.findall(r"```sh\n(.*?)```", text, re.DOTALL)
    python = re.findall(r"```python\n(.*?)```", text, re.DOTALL)
    assert shell and python
    env = dict(os.environ, PATH=f"{Path(sys.executable).parent}{os.pathsep}{os.environ.get('PATH', '')}")
    for block in shell:
        for line in block.strip().splitlines():
            done = subprocess.run(line, shell=True, cwd=tmp_path, env=env, capture_output=True, text=True,
                                  timeout=600, check=False)
            assert done.returncode == 0, (line, done.stdout[-2000:], done.stderr[-2000:])
    assert (tmp_path / "tutorial" / "out" / "summary.json").is_file()
    namespace: dict = {}
    exec(compile(python[0], str(TUTORIAL), "exec"), namespace)  # noqa: S102
    assert namespace["result"].converged and namespace["figure"].axes


def test_the_gallery_renders_its_figures_in_headless_chromium(site, tmp_path):
    from test_studies_framework import _browser, _chromium

    binary = _chromium()
    page = site / "site" / "gallery" / "index.html"
    dumped = _browser(binary, "--virtual-time-budget=10000", "--dump-dom", page.resolve().as_uri(), cwd=tmp_path)
    assert dumped.returncode == 0, dumped.stderr[-2000:]
    images = re.findall(r"<img [^>]*>", dumped.stdout)
    assert len(images) >= 5
    assert all('data-loaded="true"' in image for image in images), [i for i in images if "true" not in i][:3]
