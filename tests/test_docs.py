"""The documentation site: it builds with warnings as errors, its tutorial prints what it shows, its gallery renders.

The site is MkDocs (``mkdocs.yml``; ``make docs``): pages drawn from the
README's sections by ``docs/site/hooks.py``, the API reference from the
numpydoc docstrings (mkdocstrings), the physics page's equations rendered by
MathJax (pymdownx.arithmatex).  The tutorial's outputs are checked number by
number; the gallery's values beside the thesis's are the rows of
``docs/thesis-comparison.md`` and its figures every committed one under
``docs/figures`` and ``docs/beyond/figures``; the robustness tables are the
committed cases; N_p, never N, counts pillars.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = pytest.mark.docs  # the documents against the code: `make test`, not `make test-fast`

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
    for page in ("index.html", "site/tutorial.html", "site/configuration.html",
                 "site/gallery.html", "site/api.html", "thesis-comparison.html"):
        assert (site / page).is_file(), page
    configuration = (site / "site/configuration.html").read_text()
    assert "stiffness_ratio" in configuration and "pillar_law" in configuration  # every key
    assert "record_pull_off" in (site / "site/api.html").read_text() or \
        "pull_off" in (site / "site/api.html").read_text()
    # The physics page's equations are rendered mathematics (arithmatex output for MathJax).
    physics = (site / "site/physics.html").read_text()
    assert physics.count('class="arithmatex"') > 100 and "mathjax" in physics.lower()
    assert "$" not in re.sub(r"<(script|code|pre)[^>]*>.*?</\1>", "", physics, flags=re.DOTALL)


# The tutorial's outputs (docs/site/tutorial.md): every number of a ```text block that follows a
# ```sh or ```python block must be what that block prints, to this relative tolerance.  The rows that
# measure the machine or the solver rather than the result are not compared.
TUTORIAL_TOLERANCE = 1e-3
UNCHECKED = {"time (s)", "CG iterations per solve"}
NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"


def _tutorial_blocks() -> list[tuple[str, str, str]]:
    """(language, code, expected output) of every code block of the tutorial followed by a ```text block."""
    text = TUTORIAL.read_text(encoding="utf-8")
    blocks = re.findall(r"```(\w+)\n(.*?)```", text, re.DOTALL)
    return [(language, code, blocks[index + 1][1]) for index, (language, code) in enumerate(blocks[:-1])
            if language in ("sh", "python") and blocks[index + 1][0] == "text"]


def _printed_numbers(output: str) -> dict[str, float]:
    """Label -> number of every table row ``| label | number |`` and every ``label = number`` of ``output``."""
    found: dict[str, float] = {}
    for line in output.splitlines():
        cells = [cell.strip() for cell in re.split(r"[│┃|]", line) if cell.strip()]
        if len(cells) == 2 and re.fullmatch(NUMBER, cells[1]):
            found[cells[0]] = float(cells[1])
        for label, value in re.findall(rf"(\S+) = ({NUMBER})(?![\w.])", line):
            found[label] = float(value)
    return {label: value for label, value in found.items() if label not in UNCHECKED}


def _assert_same_numbers(printed: dict[str, float], shown: dict[str, float], where: str) -> None:
    assert shown, f"the tutorial shows no numbers for {where}"
    assert set(printed) == set(shown), (where, sorted(set(printed) ^ set(shown)))
    wrong = {label: (shown[label], printed[label]) for label in shown
             if printed[label] != pytest.approx(shown[label], rel=TUTORIAL_TOLERANCE, abs=1e-300)}
    assert not wrong, (f"{where}: numbers in tutorial.md (shown, printed) differ by more than "
                       f"{TUTORIAL_TOLERANCE:g}: {wrong}")


#: The rows of the `brushbem run` table that read from summary.json's ``design`` and ``resolution``.
_DESIGN_ROWS = {"adhesion strength F_A / A0": ("design", "adhesion_strength"),
                "apparent area A0": ("design", "apparent_area"),
                "spring k (indenter.stiffness)": ("design", "spring", "stiffness"),
                "elements per punch radius": ("resolution", "elements")}


def _summary_numbers(summary: dict, table: dict[str, float]) -> dict[str, float]:
    """The summary.json value behind every row of the `brushbem run` table (``theory: x`` is ``theory.x``)."""
    values = {}
    for label in table:
        if label in _DESIGN_ROWS:
            value = summary
            for key in _DESIGN_ROWS[label]:
                value = value[key]
            values[label] = float(value)
            continue
        head, _, key = label.partition(": ")
        value = summary[head][key] if key else summary[re.sub(r"[ -]", "_", label)]
        values[label] = float(value)
    return values


def test_the_tutorial_shows_an_output_for_each_of_its_blocks():
    languages = [language for language, _, _ in _tutorial_blocks()]
    assert languages == ["sh", "python"], languages


def test_the_tutorial_python_prints_what_it_shows(tmp_path, monkeypatch):
    """The tutorial's Python block, run as written, prints the numbers shown below it (fast)."""
    import contextlib
    import io

    import matplotlib.pyplot as plt

    (code, expected), = [(code, expected) for language, code, expected in _tutorial_blocks() if language == "python"]
    monkeypatch.chdir(tmp_path)
    namespace: dict = {}
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        exec(compile(code, str(TUTORIAL), "exec"), namespace)  # noqa: S102
    try:
        assert namespace["result"].converged and namespace["figure"].axes
        _assert_same_numbers(_printed_numbers(printed.getvalue()), _printed_numbers(expected), "the Python block")
    finally:
        plt.close("all")


def test_the_tutorial_command_line_numbers_are_what_the_run_computes(tmp_path):
    """The numbers of the `brushbem run` table shown in the tutorial are those of its configuration (fast).

    The configuration is the one `brushbem init punch_spring` writes; the run goes through
    `brushbem.run`, the computation behind `brushbem run`, without the files and the figure.
    The slow test below runs the commands themselves.
    """
    from click.testing import CliRunner

    import brushbem
    from brushbem.cli import main

    (code, expected), = [(code, expected) for language, code, expected in _tutorial_blocks() if language == "sh"]
    init = next(line for line in code.strip().splitlines() if line.startswith("brushbem init "))
    written = CliRunner().invoke(main, [*init.split()[1:3], "--out", str(tmp_path)])
    assert written.exit_code == 0, written.output
    shown = _printed_numbers(expected)
    summary = brushbem.run(next(tmp_path.glob("*.toml"))).summary
    _assert_same_numbers(_summary_numbers(summary, shown), shown, "`brushbem run` (through brushbem.run)")


@pytest.mark.slow
def test_the_tutorial_commands_print_what_it_shows(tmp_path):
    """The tutorial's shell commands, run as written, print the numbers shown below them (about 5 s)."""
    (code, expected), = [(code, expected) for language, code, expected in _tutorial_blocks() if language == "sh"]
    env = dict(os.environ, COLUMNS="80",
               PATH=f"{Path(sys.executable).parent}{os.pathsep}{os.environ.get('PATH', '')}")
    output = []
    for line in code.strip().splitlines():
        done = subprocess.run(line, shell=True, cwd=tmp_path, env=env, capture_output=True, text=True,
                              timeout=600, check=False)
        assert done.returncode == 0, (line, done.stdout[-2000:], done.stderr[-2000:])
        output.append(done.stdout)
    assert (tmp_path / "tutorial" / "out" / "summary.json").is_file()
    _assert_same_numbers(_printed_numbers("".join(output)), _printed_numbers(expected), "the shell commands")


GALLERY = ROOT / "docs" / "site" / "gallery.md"
COMPARISON = ROOT / "docs" / "thesis-comparison.md"


def _table_rows(text: str, header: str) -> list[list[str]]:
    """The cells of the rows of every Markdown table in ``text`` whose header line starts with ``header``."""
    rows, inside = [], False
    for line in text.splitlines():
        if line.startswith(header):
            inside = True
        elif inside and line.startswith("| ") and not line.startswith("| ---"):
            rows.append([cell.strip() for cell in re.split(r"(?<!\\)\|", line)[1:-1]])
        elif not line.startswith("|"):
            inside = False
    return rows


def _comparison_rows() -> dict[str, list[list[str]]]:
    """Study -> rows (quantity, where, thesis, ours, standard error, deviation, verdict) of the comparison."""
    rows: dict[str, list[list[str]]] = {}
    for section in re.split(r"^## ", COMPARISON.read_text(encoding="utf-8"), flags=re.MULTILINE)[1:]:
        study = re.match(r"`(\w+)`", section)
        if study:
            found = _table_rows(section, "| quantity | where | thesis | ours |")
            rows[study.group(1)] = [row[:6] + [re.match(r"\*\*[^*]+\*\*", row[6]).group(0)] for row in found]
    return rows


def test_the_gallery_shows_every_comparison_row_with_the_comparisons_numbers():
    """Our values beside the thesis's in the gallery are the rows of docs/thesis-comparison.md, all of them.

    The gallery names rows by quantity (``{{ rows: STUDY ... }}``) and the site's hook fills in the
    comparison's cells as they are regenerated; a quantity the comparison no longer has is an error.
    """
    import importlib.util

    spec = importlib.util.spec_from_file_location("brushbem_site_hooks", ROOT / "docs" / "site" / "hooks.py")
    hooks = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(hooks)
    gallery = hooks.render_rows(GALLERY.read_text(encoding="utf-8"))
    assert "{{ rows" not in gallery
    shown = _table_rows(gallery, "| quantity | where | thesis | ours |")
    assert shown
    expected = [row for rows in _comparison_rows().values() for row in rows]
    missing = [row for row in expected if row not in shown]
    stale = [row for row in shown if row not in expected]
    assert not missing and not stale, (missing, stale)
    # Each row sits under its study's heading.
    for study, rows in _comparison_rows().items():
        section = re.search(rf"^## [^\n]*`{study}`\)$(.*?)(?=^## |\Z)", gallery, re.MULTILINE | re.DOTALL)
        assert section, study
        assert all(row in _table_rows(section.group(1), "| quantity | where |") for row in rows), study


def test_the_gallery_shows_every_committed_figure():
    gallery = GALLERY.read_text(encoding="utf-8")
    linked = set(re.findall(r"!\[[^\]]*\]\(\.\./([^)]+)\)", gallery))
    committed = {path.relative_to(ROOT / "docs").as_posix()
                 for folder in ("figures", "beyond/figures") for path in (ROOT / "docs" / folder).rglob("*.png")}
    assert linked == committed, (sorted(committed - linked), sorted(linked - committed))


def test_the_robustness_tables_are_the_committed_cases():
    """The robustness table of the gallery and of design.md: mean (standard error) of the committed cases."""
    import pandas as pd

    tables = ROOT / "docs" / "beyond" / "robustness"
    frames = {part: pd.read_csv(tables / f"{part}.csv") for part in ("roughness", "tilt")}

    def brush(frame):
        designed = frame["indenter.lengths_file"] != "robustness.flat.npy"
        concave = frame["indenter.profile.amplification"] > 0
        return designed.map({True: "designed", False: ""}).where(
            designed, concave.map({True: "concave", False: "flat"}))

    for page in (GALLERY, ROOT / "docs" / "site" / "design.md"):
        text = page.read_text(encoding="utf-8")
        header = next(line for line in text.splitlines() if re.match(r"\| (k~|\$\\tilde k\$) \| brush \|", line))
        columns, kind = [], None
        for cell in [cell.strip() for cell in header.split("|")[3:-1]]:
            kind = "tilt" if cell.startswith("tilt") else "roughness" if "sigma" in cell or "σ" in cell else kind
            columns.append((kind, float(re.search(NUMBER, cell.split("=")[-1].replace("tilt", "")).group(0))))
        rows = _table_rows(text, header)
        assert len(rows) == 6, page
        for row in rows:
            stiffness, name = float(row[0]), row[1]
            for (kind, x), cell in zip(columns, row[2:], strict=True):
                frame = frames[kind]
                key = "normalized.roughness_by_rigid_brush" if kind == "roughness" else "indenter.tilt.angle"
                chosen = frame[(frame["indenter.stiffness_ratio"] == stiffness) & (brush(frame) == name)
                               & ((frame[key] - x).abs() < 1e-3)]["normalized.force_by_ideal_sharing"]
                assert len(chosen) >= 1, (page.name, row[:2], kind, x)
                mean, error = re.fullmatch(rf"({NUMBER})(?: \(({NUMBER})\))?", cell).groups()
                assert abs(float(mean) - chosen.mean()) <= 5e-4 + 1e-12, (page.name, row[:2], kind, x, chosen.mean())
                shown_error = float(error) if error else 0.0
                true_error = chosen.sem() if len(chosen) > 1 else 0.0
                assert abs(shown_error - true_error) <= 5e-4 + 1e-12, (page.name, row[:2], kind, x, true_error)


def test_one_notation_across_the_pages():
    """N is the grid's elements per side everywhere; the number of pillars is N_p (notation table of physics.md)."""
    physics = (ROOT / "docs" / "site" / "physics.md").read_text(encoding="utf-8")
    assert "## Notation" in physics and "| symbol | meaning | config key (or output) | unit |" in physics
    for page in [*(ROOT / "docs" / "site").glob("*.md"), ROOT / "docs" / "index.md"]:
        text = page.read_text(encoding="utf-8")
        assert not re.search(r"\(N F_K\)|/ \(N\s+F_K\)|N \* F_K", text), page.name


def test_the_gallery_renders_its_figures_in_headless_chromium(site, tmp_path):
    from test_studies_framework import _browser, _chromium

    binary = _chromium()
    page = site / "site" / "gallery.html"
    dumped = _browser(binary, "--virtual-time-budget=10000", "--dump-dom", page.resolve().as_uri(), cwd=tmp_path)
    assert dumped.returncode == 0, dumped.stderr[-2000:]
    images = re.findall(r"<img [^>]*>", dumped.stdout)
    assert len(images) >= 5
    assert all('data-loaded="true"' in image for image in images), [i for i in images if "true" not in i][:3]


# The site from disk with no network (README: "open out/site/index.html"): no page loads anything from
# another host, every navigation link names a page file (a directory URL opens a folder listing from
# file://), and in headless Chromium with every host unresolvable the physics page's equations are
# typeset by the local MathJax.  The screenshot of that page is kept as the test's artefact.
ARTEFACTS = ROOT / "out" / "artefacts"
OFFLINE = ("--host-resolver-rules=MAP * ~NOTFOUND", "--proxy-server=http://127.0.0.1:9", "--proxy-bypass-list=<-loopback>")


def test_no_page_loads_anything_from_another_host(site):
    remote = re.compile(r'<(?:script|link|img|iframe)\b[^>]*\b(?:src|href)="(?:https?:)?//[^"]*"')
    for page in site.rglob("*.html"):
        found = remote.findall(page.read_text(encoding="utf-8"))
        assert not found, (page.relative_to(site), found[:3])
    assert not (site / "search").exists()  # no search box: its index cannot be fetched from file://


def test_the_site_opened_from_disk_offline_renders_equations_and_follows_links(site, tmp_path):
    from urllib.parse import unquote, urljoin, urlparse

    from test_studies_framework import _browser, _chromium

    binary = _chromium()
    index = (site / "index.html").resolve().as_uri()
    home = _browser(binary, *OFFLINE, "--virtual-time-budget=10000", "--dump-dom", index, cwd=tmp_path)
    assert home.returncode == 0, home.stderr[-2000:]
    navigation = re.search(r'<div id="navbar-collapse".*?</ul>', home.stdout, re.DOTALL)
    assert navigation, home.stdout[:2000]
    links = re.findall(r'<a href="([^"#]+)" class="nav-link', navigation.group(0))
    assert len(links) >= 10
    for href in links:  # each navigation link, followed from the page's file:// address, is a page file
        target = Path(unquote(urlparse(urljoin(index, href)).path))
        assert target.is_file() and target.suffix == ".html", (href, target)
    physics_link = next(href for href in links if href.endswith("physics.html"))
    physics = urljoin(index, physics_link)
    page = _browser(binary, *OFFLINE, "--virtual-time-budget=20000", "--dump-dom", physics, cwd=tmp_path)
    assert page.returncode == 0, page.stderr[-2000:]
    dom = page.stdout
    assert "<title>Physics" in dom  # the link opened the page, not a folder listing
    # Every equation the page holds is typeset: one MathJax container (an SVG) per arithmatex span or
    # block, no raw TeX delimiters left, no MathJax error node.
    equations = len(re.findall(r'class="arithmatex"', dom))
    typeset = re.findall(r"<mjx-container[^>]*>\s*<svg", dom)
    assert equations > 100 and len(typeset) == equations, (equations, len(typeset))
    assert "\\(" not in re.sub(r"<(script|code|pre)[^>]*>.*?</\1>", "", dom, flags=re.DOTALL)
    assert not re.search(r'<g [^>]*data-mml-node="merror"', dom)  # (the stylesheet names merror too)

    ARTEFACTS.mkdir(parents=True, exist_ok=True)
    screenshot = ARTEFACTS / "docs-physics-offline.png"
    shot = _browser(binary, *OFFLINE, "--virtual-time-budget=20000", f"--screenshot={screenshot}",
                    "--window-size=1280,1600", physics, cwd=tmp_path)
    assert shot.returncode == 0, shot.stderr[-2000:]
    assert screenshot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and screenshot.stat().st_size > 10_000


def test_the_test_times_are_stated_once():
    """The suite's count and time are stated in one place (the README's "Getting started"); the other pages
    point there instead of each keeping its own measurement (three pages stated 77, 92 and 103 s)."""
    stated = re.compile(r"\b\d+ s on 2 (?:idle )?cores|\b\d{3,5} tests\b")
    for page in [*(ROOT / "docs" / "site").glob("*.md"), ROOT / "docs" / "index.md"]:
        assert not stated.findall(page.read_text(encoding="utf-8")), page.name
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    assert len(re.findall(r"\d+\s+tests\s+in\s+\d+\s+s\s+on\s+2", readme)) == 2  # make test-fast and make test
