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
from brushbem.report.run import GENERATOR, is_run_folder
from brushbem.results.units import Units

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
    from brushbem.report.run import _theory_html

    reason = "the closed form is of a linear elastic spring; this spring is viscoelastic"
    summary = {
        "adhesive_force": 0.02, "pull_off_displacement": -0.2, "work_of_separation": 0.002,
        "theory": {"model": "Kendall flat punch", "adhesive_force": 0.0199, "pull_off_displacement": -0.17,
                   "work_of_separation": 0.0017, "ratios": {"adhesive_force": 0.02 / 0.0199},
                   "not_applicable": {"pull_off_displacement": reason, "work_of_separation": reason}},
    }
    table = _theory_html(summary, Units())
    rows = {row.split("</td>", 1)[0]: row for row in table.split("<tr><td>")[1:]}
    assert f"{0.02 / 0.0199:.6g}" in rows["adhesive force"]
    for key in ("base displacement at the adhesive force", "work of separation"):
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


# --------------------------------------------------------------------------- what the report shows (issue 62)

#: The default example's summary.json (examples/default.toml, N = 256): its closed forms and normalised numbers.
BRUSH_SUMMARY = {
    "adhesive_force": 0.008211341739678014, "pull_off_displacement": -0.008558367756609458,
    "work_of_separation": 3.77515055001635e-05,
    "normalized": {"force_by_compact_punch": 1.8385442711143785, "force_by_rigid_brush": 1.0932049642283554,
                   "force_by_ideal_sharing": 0.4596360677785946, "displacement_by_rigid_brush": -1.2856817281828976,
                   "separation_displacement_by_rigid_brush": -1.3140068131099445,
                   "max_displacement_by_rigid_brush": 0.300450217785977, "preload_by_rigid_brush": 0.2647600035200837,
                   "preload_by_compact_punch": 0.44527147572519843, "roughness_by_rigid_brush": 0.0,
                   "stiffness_ratio": 0.455, "level_stiffness_ratios": [0.455], "filling_factor": 0.125,
                   "pillars": 256, "attached_pillars_at_pull_off": 244, "profile_amplification": 0.0},
    "theory": {"model": "brush limits (thesis eq. 4.5-4.13, 5.3-5.5, 7.4)",
               "compact_punch_force": 0.004466219208690012, "rigid_brush_force": 0.007511255444649425,
               "ideal_sharing_force": 0.017864876834760048, "rigid_brush_displacement": -0.006656676819001948,
               "rigid_brush_enhancement": 1.681792830507429, "soft_brush_enhancement": 4.0,
               "ratios": {"adhesive_force_by_rigid_brush": 1.0932049642283554,
                          "adhesive_force_by_ideal_sharing": 0.4596360677785946}},
}


def _cells(table: str) -> list[list[str]]:
    import html
    import re

    return [[html.unescape(re.sub(r"<[^>]+>", "", cell)) for cell in re.findall(r"<td[^>]*>(.*?)</td>", row)]
            for row in re.findall(r"<tr>(.*?)</tr>", table) if "<td" in row]


def test_the_brush_report_shows_the_computed_value_and_ratio_beside_every_closed_form():
    from brushbem.report.run import _theory_html

    text = _theory_html(BRUSH_SUMMARY, Units())
    assert text.count("<table") == 1  # one table: no second table of ratios
    rows = _cells(text)
    assert len(rows) == 6
    ratios = {}
    for meaning, value, computed, ratio, _unit in rows:
        symbol, number = computed.split(" = ")
        ratios[meaning.split(":")[0]] = float(ratio)
        # The ratio is the computed number over the closed form shown beside it: 6 significant digits each, so
        # the quotient of the shown numbers agrees to within 3 half-units of the 6th digit (< 1e-5 relative).
        assert float(ratio) == pytest.approx(float(number) / float(value), rel=1e-5, abs=0.0), meaning
    assert ratios["F_c"] == pytest.approx(1.0932049642283554, rel=1e-5, abs=0.0)  # F_A / F_c, the stored ratio
    assert ratios["N_p F_K"] == pytest.approx(0.4596360677785946, rel=1e-5, abs=0.0)
    assert ratios["−|d_c|"] == pytest.approx(1.2856817281828976, rel=1e-5, abs=0.0)


def test_every_normalised_number_has_a_symbol_and_a_definition():
    from brushbem.report.run import NORMALISED, _summary_html

    text = _summary_html(BRUSH_SUMMARY, Units())
    section = text[text.index("Normalised"):]
    rows = _cells(section)
    assert len(rows) == len(BRUSH_SUMMARY["normalized"])
    for symbol, definition, _value in rows:
        assert symbol not in BRUSH_SUMMARY["normalized"] and definition != "—", symbol  # no bare JSON key
    assert set(BRUSH_SUMMARY["normalized"]) <= set(NORMALISED)


def _snapshot_result(scale_of_zero_force: float):
    import numpy as np

    from brushbem.results import CaseResult, Curve, Snapshot

    contact = np.zeros((8, 8), bool)
    contact[2:6, 2:6] = True
    fields = {"max_preload": 1.0, "zero_force": scale_of_zero_force, "adhesive_force": -0.5}
    snapshots = tuple(Snapshot(name, 0.0, 0.0, np.where(contact, value, 0.0), contact)
                      for name, value in fields.items())
    curve = Curve(displacement=np.zeros(2), force=np.zeros(2), contact_area=np.zeros(2),
                  cg_iterations=np.zeros(2, int), converged=np.ones(2, bool), loading=np.array([True, False]),
                  attached_pillars=np.zeros(2, int))
    return CaseResult(curve=curve, snapshots=snapshots, summary={}, attributes={}, element_size=0.125, pillars={})


def test_the_snapshot_panels_share_one_colour_scale_and_an_all_zero_field_has_none():
    from brushbem.report.run import snapshots_figure

    order = ["max_preload", "zero_force", "adhesive_force"]
    figure, largest = snapshots_figure(_snapshot_result(1e-17), Units(), order)
    images = [image for ax in figure.axes for image in ax.get_images()]
    assert len(images) == 3 and len(figure.axes) == 4  # three panels and one colour bar
    assert {image.get_clim() for image in images} == {(-1.0, 1.0)}  # the zero-force panel is not scaled to 1e-17
    assert largest == 1.0
    zero = _snapshot_result(0.0)
    zero = type(zero)(**{**zero.__dict__, "snapshots": tuple(
        type(s)(s.name, 0.0, 0.0, 0.0 * s.pressure, s.contact) for s in zero.snapshots)})
    figure, largest = snapshots_figure(zero, Units(), order)
    assert largest == 0.0 and len(figure.axes) == 3  # no colour bar for a field of zeros


def test_the_report_embeds_only_a_regular_png_of_the_run_folder(run_folder, tmp_path):
    import base64
    import os

    folder = tmp_path / "run"
    shutil.copytree(run_folder, folder)
    secret = tmp_path / "secret.png"
    secret.write_bytes(b"\x89PNG\r\n\x1a\n" + b"private data, not the run's figure" * 10)
    (folder / "pulloff.png").unlink()
    os.symlink(secret, folder / "pulloff.png")
    document = _report(folder)
    assert base64.b64encode(secret.read_bytes()).decode()[:40] not in document
    assert "pulloff.png is a link, not embedded" in document and "drawn from result.nc" in document
    (folder / "pulloff.png").unlink()
    os.link(secret, folder / "pulloff.png")  # a hard link to a file outside the folder
    document = _report(folder)
    assert base64.b64encode(secret.read_bytes()).decode()[:40] not in document and "hard link" in document
    (folder / "pulloff.png").unlink()
    (folder / "pulloff.png").write_text("<script>not a PNG</script>")
    assert "pulloff.png is not a PNG file" in _report(folder)


def test_the_report_computes_nothing_from_the_stored_configuration(run_folder, tmp_path, monkeypatch):
    import brushbem.runs.assembly as assembly

    def refuse(*args, **kwargs):
        raise AssertionError("the report validated the stored configuration")

    monkeypatch.setattr(assembly, "parse", refuse)
    folder = tmp_path / "run"
    shutil.copytree(run_folder, folder)
    (folder / "pulloff.png").unlink()
    assert "drawn from result.nc" in _report(folder)


@pytest.mark.parametrize("damage", ["provenance", "indenter", "pressure"])
def test_a_damaged_run_folder_is_reported_without_a_traceback(run_folder, tmp_path, damage):
    import xarray as xr

    folder = tmp_path / "run"
    shutil.copytree(run_folder, folder)
    summary = json.loads((folder / "summary.json").read_text())
    if damage == "provenance":
        summary["provenance"] = [1, 2]
    elif damage == "indenter":
        summary["provenance"]["config"]["indenter"] = [1, 2]
    else:
        dataset = xr.load_dataset(folder / "result.nc")
        dataset.drop_vars("pressure").to_netcdf(folder / "result.nc")
    (folder / "summary.json").write_text(json.dumps(summary))
    done = CliRunner().invoke(main, ["report", str(folder)])
    assert done.exception is None or isinstance(done.exception, SystemExit), done.exception
    assert done.exit_code == 0, done.output
    if damage == "pressure":
        assert "The result holds no snapshots" in (folder / "report.html").read_text()


def test_report_on_a_folder_that_is_no_results_folder_says_what_it_takes(run_folder, tmp_path):
    empty = tmp_path / "empty"
    empty.mkdir()
    done = CliRunner().invoke(main, ["report", str(empty)])
    assert done.exit_code == 2 and "is empty" in done.output and "run folder" in done.output
    design = tmp_path / "design"
    design.mkdir()
    (design / "design.json").write_text("{}")
    done = CliRunner().invoke(main, ["report", str(design)])
    assert done.exit_code == 2 and "design folder" in done.output
    half = tmp_path / "half"
    shutil.copytree(run_folder, half)
    (half / "result.nc").unlink()
    done = CliRunner().invoke(main, ["report", str(half)])
    assert done.exit_code == 2 and "did not finish writing" in done.output
    assert not (half / "report.html").exists()


def test_report_waits_for_no_run_writing_the_same_folder(run_folder, tmp_path):
    from brushbem.io import exclusive_folder

    folder = tmp_path / "run"
    shutil.copytree(run_folder, folder)
    (folder / "report.html").unlink(missing_ok=True)
    with exclusive_folder(folder):  # a `brushbem run --out` (here: this process's lock) writing the folder
        import subprocess
        import sys

        done = subprocess.run([sys.executable, "-m", "brushbem", "report", str(folder)], capture_output=True,
                              text=True, timeout=120, check=False)
    assert done.returncode == 2 and "another brushbem process" in done.stderr, done.stderr
    assert not (folder / "report.html").exists()
