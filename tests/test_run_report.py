"""`brushbem report DIR` on one run's folder: a self-contained report.html with the curve, the snapshots, the
summary with units, the closed-form comparison and the provenance, every text escaped."""

from __future__ import annotations

import json
import shutil
import textwrap
from html.parser import HTMLParser
from pathlib import Path

import pytest
from click.testing import CliRunner

from brushbem.cli import main
from brushbem.workflow.run_report import GENERATOR, is_run_folder
from brushbem.workflow.units import Units

#: A flat punch on a spring at N = 32 (a tenth of a second): Kendall's closed forms apply, with ratios.
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
    stiffness = 0.15
    [protocol]
    method = "events"
    preload_displacement = 0.01
    [units]
    length = "mm"
    stress = "MPa"
""")

#: Tags a run report may hold: nothing that runs or fetches anything.
ALLOWED_TAGS = {"html", "head", "meta", "title", "style", "body", "h1", "h2", "h3", "p", "b", "span", "div", "ul",
                "li", "table", "tr", "th", "td", "figure", "img", "figcaption", "dl", "dt", "dd", "pre"}


class _Tags(HTMLParser):
    def __init__(self) -> None:
        super().__init__()
        self.tags: list[tuple[str, dict]] = []
        self.text: list[str] = []

    def handle_starttag(self, tag, attrs):
        self.tags.append((tag, dict(attrs)))

    def handle_data(self, data):
        self.text.append(data)


def _parse(document: str) -> _Tags:
    parser = _Tags()
    parser.feed(document)
    return parser


@pytest.fixture(scope="module")
def run_folder(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("report")
    config = folder / "punch.toml"
    config.write_text(PUNCH)
    out = folder / "run"
    done = CliRunner().invoke(main, ["run", str(config), "--out", str(out), "--quiet"])
    assert done.exit_code == 0, done.output
    return out


def _report(folder: Path, *args: str) -> str:
    done = CliRunner().invoke(main, ["report", str(folder), *args])
    assert done.exit_code == 0, done.output
    assert done.output.strip() == str(folder / "report.html")
    return (folder / "report.html").read_text(encoding="utf-8")


def test_a_run_folder_gets_a_self_contained_report(run_folder, tmp_path):
    folder = tmp_path / "run"
    shutil.copytree(run_folder, folder)
    document = _report(folder)
    summary = json.loads((folder / "summary.json").read_text())
    parsed = _parse(document)
    images = {attrs.get("alt"): attrs["src"] for tag, attrs in parsed.tags if tag == "img"}
    # The curve (the run's pulloff.png, embedded byte for byte) and the snapshots: PNG data URIs, nothing fetched.
    import base64

    curve = images["force against base displacement"]
    assert curve.startswith("data:image/png;base64,")
    assert base64.b64decode(curve.split(",", 1)[1]) == (folder / "pulloff.png").read_bytes()
    assert images["contact pressure at every stage"].startswith("data:image/png;base64,")
    assert all(not value.startswith(("http:", "https:", "//", "file:")) for _, attrs in parsed.tags
               for value in attrs.values() if value)
    assert {tag for tag, _ in parsed.tags} <= ALLOWED_TAGS
    text = " ".join(parsed.text)
    # The summary with its units ([units] mm and MPa: forces in N, works in mJ).
    assert "adhesive force F_A" in text and "N" in text.split("adhesive force F_A", 1)[1].split("pull-off")[0]
    assert f"{summary['adhesive_force']:.6g}" in text and "mJ" in text and "mm" in text
    # The closed forms: Kendall's value, the computed one and their ratio.
    ratio = summary["theory"]["ratios"]["adhesive_force"]
    assert "Kendall flat punch" in text and f"{ratio:.6g}" in text
    # The snapshots table names every stage reached.
    for stage in ("max_preload", "adhesive_force"):
        assert stage in text
    # Provenance: version, commit, creation time, run id and the configuration.
    provenance = summary["provenance"]
    assert provenance["created"] in text and summary["run_id"] in text
    assert (provenance["commit"] or "not recorded") in text
    assert "&quot;flat_punch&quot;" in document  # the configuration, escaped JSON
    assert f'<meta name="generator" content="{GENERATOR}">' in document


def test_every_text_from_the_files_is_escaped(run_folder, tmp_path):
    folder = tmp_path / "run"
    shutil.copytree(run_folder, folder)
    summary = json.loads((folder / "summary.json").read_text())
    attack = '<script>alert("x")</script><img src=x onerror=alert(1)> & \'q\''
    summary["warnings"] = [attack]
    summary["reason"] = attack
    summary["theory"]["model"] = attack
    summary["stages_not_reached"] = {"half_detached": attack}
    summary["provenance"]["config"]["indenter"]["shape"] = attack
    (folder / "summary.json").write_text(json.dumps(summary))
    document = _report(folder)
    assert "<script" not in document and "onerror=" not in document.replace("onerror=alert(1)&gt;", "")
    assert "&lt;script&gt;alert(&quot;x&quot;)&lt;/script&gt;" in document
    parsed = _parse(document)
    assert {tag for tag, _ in parsed.tags} <= ALLOWED_TAGS
    assert sum(tag == "img" for tag, _ in parsed.tags) == 2  # the two figures, not the injected one
    assert attack in " ".join(parsed.text)  # shown as text


def test_without_pulloff_png_the_curve_is_drawn_from_result_nc(run_folder, tmp_path):
    folder = tmp_path / "run"
    shutil.copytree(run_folder, folder)
    (folder / "pulloff.png").unlink()
    document = _report(folder)
    assert "drawn from result.nc" in document
    assert 'id="curve"><img alt="force against base displacement" src="data:image/png;base64,' in document


def test_a_closed_form_that_does_not_apply_is_named_as_such():
    from brushbem.workflow.run_report import _theory_html

    reason = "the closed form is of a linear elastic spring; this spring is viscoelastic"
    summary = {
        "adhesive_force": 0.02, "pull_off_displacement": -0.2, "work_of_separation": 0.002,
        "theory": {"model": "Kendall flat punch", "adhesive_force": 0.0199, "pull_off_displacement": -0.17,
                   "work_of_separation": 0.0017, "ratios": {"adhesive_force": 0.02 / 0.0199},
                   "not_applicable": {"pull_off_displacement": reason, "work_of_separation": reason}},
    }
    table = _theory_html(summary, Units())
    rows = {row.split("</td>", 1)[0]: row for row in table.split("<tr><td>")[1:]}
    assert f"{0.02 / 0.0199:.6g}" in rows["adhesive_force"]
    for key in ("pull_off_displacement", "work_of_separation"):
        assert f"not applicable: {reason}" in rows[key]
        assert f"{0.2 / 0.17:.6g}" not in rows[key] and f"{0.002 / 0.0017:.6g}" not in rows[key]
    assert "No closed form applies" in _theory_html({"theory": {}}, Units())


def test_a_run_folder_of_two_runs_or_a_sweep_folder_is_not_reported_as_a_run(run_folder, tmp_path):
    folder = tmp_path / "run"
    shutil.copytree(run_folder, folder)
    summary = json.loads((folder / "summary.json").read_text())
    summary["run_id"] = "another run"
    (folder / "summary.json").write_text(json.dumps(summary))
    done = CliRunner().invoke(main, ["report", str(folder)])
    assert done.exit_code == 2 and "different runs" in done.output
    assert not (folder / "report.html").exists()
    (folder / "sweep.json").write_text("{}")
    assert not is_run_folder(folder)  # a sweep folder goes to the sweep report


@pytest.mark.slow  # over 3 s on 2 cores: `make test` runs it, `make test-fast` does not
def test_a_rerun_removes_the_earlier_runs_report(run_folder, tmp_path):
    folder = tmp_path / "run"
    shutil.copytree(run_folder, folder)
    _report(folder)
    config = tmp_path / "punch.toml"
    config.write_text(PUNCH)
    done = CliRunner().invoke(main, ["run", str(config), "--out", str(folder), "--quiet", "--overwrite"])
    assert done.exit_code == 0, done.output
    assert not (folder / "report.html").exists()  # it described the results just replaced
    (folder / "report.html").write_text("<p>my own notes</p>")
    done = CliRunner().invoke(main, ["run", str(config), "--out", str(folder), "--quiet", "--overwrite"])
    assert done.exit_code == 0, done.output
    assert (folder / "report.html").read_text() == "<p>my own notes</p>"  # not brushbem's: left alone
