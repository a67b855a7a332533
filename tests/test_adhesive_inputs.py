"""A designer's adhesive as input: fibril geometry to the spring, nu = 0.5, and the checks on physical units."""

from __future__ import annotations

import math

import pytest

from brushbem.config import ConfigError, config_to_dict, parse_config
from brushbem.physics import theory
from brushbem.results import ResolutionRecord

# The PDMS fibril brush of the documentation ("From your adhesive to a run"): r = 5 um, l = 40 um,
# E_f = 2 MPa, a half-space of E = 2 MPa, nu = 0.5 (E* = 2.67 MPa) and dgamma = 40 mJ/m^2 = 0.04 MPa um.
E_FIBRIL, LENGTH, RADIUS = 2.0, 40.0, 5.0


PDMS_TOML = """
[halfspace]
youngs_modulus = 2.0
poisson_ratio = 0.5
work_of_adhesion = 0.04
[grid]
size = 160.0
elements = 128
[indenter]
shape = "brush"
layout = "square"
pillars_per_side = 4
pillar_radius = 5.0
region_size = 80.0
[indenter.fibril]
youngs_modulus = 2.0
length = 40.0
[protocol]
preload_displacement = 0.5
[units]
length = "um"
stress = "MPa"
"""


def fibril_brush(**fibril) -> dict:
    return {
        "halfspace": {"youngs_modulus": 2.0, "poisson_ratio": 0.5, "work_of_adhesion": 0.04},
        "grid": {"size": 160.0, "elements": 128},
        "indenter": {"shape": "brush", "layout": "square", "pillars_per_side": 4, "pillar_radius": RADIUS,
                     "region_size": 80.0, "fibril": {"youngs_modulus": E_FIBRIL, "length": LENGTH, **fibril}},
        "protocol": {"preload_displacement": 0.5},
        "units": {"length": "um", "stress": "MPa"},
    }


def test_fibril_stiffness_is_the_bar_in_tension():
    # pi r^2 E / l by hand: pi 25 um^2 2 MPa / 40 um = 3.92699 uN/um (the 3.93 uN/um).
    assert theory.fibril_stiffness(LENGTH, RADIUS, youngs_modulus=E_FIBRIL) == pytest.approx(
        1.25 * math.pi, rel=1e-15, abs=0)


@pytest.mark.parametrize(("ends", "factor"), [("clamped-free", 2.0), ("clamped-pinned", 0.699),
                                              ("clamped-clamped", 0.5)])
def test_euler_buckling_force(ends, factor):
    # P_cr = pi^2 E I / (K l)^2 with I = pi r^4 / 4 (Timoshenko and Gere ch. 2); by hand for clamped-free:
    # pi^2 2 (pi 625 / 4) / (80)^2 = 9.8696 x 2 x 490.874 / 6400 = 1.51398 uN.
    force = theory.euler_buckling_force(LENGTH, RADIUS, youngs_modulus=E_FIBRIL, ends=ends)
    assert force == pytest.approx(math.pi**3 * 2 * 625 / 4 / (factor * LENGTH) ** 2, rel=1e-14, abs=0)
    if ends == "clamped-free":
        assert force == pytest.approx(1.51398, rel=1e-5, abs=0)
    with pytest.raises(ValueError, match="ends"):
        theory.euler_buckling_force(LENGTH, RADIUS, youngs_modulus=E_FIBRIL, ends="free-free")


def test_fibril_gives_the_spring_and_reparses():
    config = parse_config(fibril_brush())
    assert config.indenter.stiffness == pytest.approx(1.25 * math.pi, rel=1e-15, abs=0)
    assert config.halfspace.effective_modulus == pytest.approx(8 / 3, rel=1e-15, abs=0)
    assert parse_config(config_to_dict(config)) == config  # the recorded configuration holds the derived k


def test_fibril_radius_apart_from_the_pillar():
    config = parse_config(fibril_brush(radius=2.5))
    assert config.indenter.stiffness == pytest.approx(1.25 * math.pi / 4, rel=1e-15, abs=0)


def test_fibril_on_a_punch_takes_its_radius_and_a_sphere_needs_one():
    document = fibril_brush()
    document["indenter"] = {"shape": "flat_punch", "radius": 20.0,
                            "fibril": {"youngs_modulus": E_FIBRIL, "length": LENGTH}}
    assert parse_config(document).indenter.stiffness == pytest.approx(math.pi * 400 * 2 / 40, rel=1e-15, abs=0)
    document["indenter"] = {"shape": "sphere", "radius": 20.0, "fibril": {"youngs_modulus": E_FIBRIL, "length": LENGTH}}
    with pytest.raises(ConfigError) as caught:
        parse_config(document)
    assert any("`indenter.fibril.radius`: missing" in line for line in caught.value.problems), caught.value.problems


def test_fibril_beside_a_stiffness_is_refused():
    document = fibril_brush()
    document["indenter"]["stiffness_ratio"] = 0.1
    with pytest.raises(ConfigError) as caught:
        parse_config(document)
    (line,) = caught.value.problems
    assert "`indenter.fibril`" in line and "not both" in line and "3.92699" in line


def test_buckling_gives_euler_law_through_the_pillar_law():
    document = fibril_brush(buckling="clamped-pinned")
    with pytest.raises(ConfigError) as caught:  # a pillar law is followed in fixed steps
        parse_config(document)
    assert any("fibril.buckling" in line and "fixed" in line for line in caught.value.problems)
    document["protocol"].update(method="fixed", step=0.01)
    law = parse_config(document).indenter.pillar_law
    assert law.forces == pytest.approx(
        (theory.euler_buckling_force(LENGTH, RADIUS, youngs_modulus=E_FIBRIL, ends="clamped-pinned"),), rel=1e-15)
    assert law.factors == (1.0, 0.01)
    document["indenter"]["fibril"]["post_buckling_factor"] = 0.1
    assert parse_config(document).indenter.pillar_law.factors == (1.0, 0.1)


# --- plausibility: a slip of units warns, naming the likely meaning ---------------------------------------


def warnings_of(document: dict) -> list[str]:
    from brushbem.config import advice

    return advice.plausibility_warnings(parse_config(document))


def test_physical_inputs_give_no_plausibility_warning():
    assert warnings_of(fibril_brush()) == []


def test_work_of_adhesion_typed_in_millijoules_warns():
    document = fibril_brush()
    document["halfspace"]["work_of_adhesion"] = 40.0  # 40 mJ/m^2 typed where MPa um (= J/m^2) belongs
    (warning,) = warnings_of(document)
    assert warning.startswith("halfspace.work_of_adhesion = 40 MPa·µm = 40 J/m²")
    assert "did you mean 0.04 MPa·µm = 40 mJ/m²?" in warning


@pytest.mark.parametrize(("key", "value", "meant"), [
    ("youngs_modulus", 2.0e6, "did you mean 2 MPa = 2e+06 Pa?"),     # pascals typed where MPa belongs
    ("youngs_modulus", 2.0e-4, "did you mean 0.2 MPa = 0.0002 GPa?"),  # below 1 kPa: typed as if in GPa
])
def test_a_modulus_outside_1_kpa_to_1_tpa_warns(key, value, meant):
    document = fibril_brush()
    document["halfspace"][key] = value
    warnings = warnings_of(document)
    assert any(w.startswith(f"halfspace.{key} = {value:g} MPa") and meant in w for w in warnings), warnings


def test_fibril_modulus_and_a_sub_nanometre_radius_warn():
    document = fibril_brush()
    document["units"] = {"length": "nm", "stress": "MPa"}  # millimetres typed where nanometres are declared
    document["indenter"]["fibril"]["youngs_modulus"] = 2.0e7  # pascals typed where MPa are declared
    document["grid"]["size"], document["indenter"]["region_size"] = 0.16, 0.08
    document["indenter"]["pillar_radius"], document["indenter"]["fibril"]["length"] = 0.005, 0.04
    document["halfspace"]["work_of_adhesion"], document["protocol"]["preload_displacement"] = 4e-5, 5e-4
    warnings = warnings_of(document)
    assert any(w.startswith("indenter.fibril.youngs_modulus = 2e+07 MPa") and "did you mean 20 MPa = 2e+07 Pa?" in w
               for w in warnings), warnings
    assert any(w.startswith("indenter.pillar_radius = 0.005 nm") and "did you mean 5e+03 nm = 0.005 mm?" in w
               for w in warnings), warnings


def test_without_units_nothing_is_judged():
    document = fibril_brush()
    del document["units"]
    document["halfspace"]["work_of_adhesion"] = 40.0
    assert warnings_of(document) == []


# --- the resolution of the deciding length and the error it carries ------------------------------------


def test_resolution_reads_the_measured_table():
    from brushbem.config import advice

    document = fibril_brush()  # r = 5 on h = 160 / 128 = 1.25: 4 elements per radius
    found = advice.resolution(parse_config(document))
    assert (found.length, found.key, found.elements) == ("pillar radius", "indenter.pillar_radius", 4.0)
    # A brush's F_A error is the brush's own (brush_resolution_error.csv, against the continuum limit), between
    # its rows at 3.6 and 7.2 per radius; the work's the punch's (resolution_error.csv).
    low, high = advice._table(advice.BRUSH_TABLE)[:2]
    assert low["elements_per_radius"] < 4.0 < high["elements_per_radius"]
    t = math.log(4.0 / low["elements_per_radius"]) / math.log(high["elements_per_radius"] / low["elements_per_radius"])
    for got, column in ((found.force_error_estimate, "force_error_mean"), (found.force_error_range[0], "force_error_min"),
                        (found.force_error_range[1], "force_error_max")):
        assert got == pytest.approx((1 - t) * low[column] + t * high[column], rel=1e-12)
    row = next(r for r in advice._table() if r["elements_per_radius"] == 4.0)
    assert found.work_error_estimate == row["work_error_mean"]
    assert "continuum limit" in found.basis
    assert isinstance(found, ResolutionRecord) and not found.resolved  # the summary's record itself
    (warning,) = advice.resolution_warnings(parse_config(document))
    assert "spans 4 elements" in warning and "raise grid.elements to 256" in warning and "--refine" in warning
    document["grid"]["elements"] = 256  # 8 elements per radius: resolved, no warning, the error still reported
    resolved = parse_config(document)
    assert advice.resolution_warnings(resolved) == [] and advice.resolution(resolved).elements == 8.0


def test_the_table_says_what_the_punch_measures():
    """The committed table against a fresh run of its first rows (benchmarks/resolution_error.py)."""
    import importlib.util
    from pathlib import Path

    from brushbem.config import advice

    path = Path(__file__).parents[1] / "benchmarks" / "resolution_error.py"
    spec = importlib.util.spec_from_file_location("resolution_error", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    row = next(r for r in advice._table() if r["elements_per_radius"] == 8.0)
    measured = [module.errors(8.0 * (1 + s)) for s in module.SHIFTS]
    forces, works = [m[0] for m in measured], [m[1] for m in measured]
    # The table holds 5 significant digits of the same deterministic runs.
    assert row["force_error_mean"] == pytest.approx(sum(forces) / len(forces), rel=1e-4, abs=0)
    assert (row["force_error_min"], row["force_error_max"]) == pytest.approx((min(forces), max(forces)), rel=1e-4,
                                                                              abs=0)
    assert row["work_error_mean"] == pytest.approx(sum(works) / len(works), rel=1e-4, abs=0)


def test_the_sphere_table_says_what_the_sphere_measures():
    """The committed sphere table's row at 3 elements across a_JKR against a fresh run (5 significant digits)."""
    import importlib.util
    from pathlib import Path

    from brushbem.config import advice

    path = Path(__file__).parents[1] / "benchmarks" / "resolution_error.py"
    spec = importlib.util.spec_from_file_location("resolution_error", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    row = next(r for r in advice._table(advice.SPHERE_TABLE) if r["elements_per_radius"] == 3.0)
    force, work, _ = module.sphere(3.0)
    assert row["force_error"] == pytest.approx(force, rel=1e-4, abs=0)
    assert row["work_error"] == pytest.approx(work, rel=1e-4, abs=0)


@pytest.mark.parametrize(("indenter", "length"), [
    ({"shape": "flat_punch", "radius": 10.0}, "punch radius"),
    ({"shape": "sphere", "radius": 400.0}, "JKR contact radius at pull-off"),
])
def test_every_indenter_names_its_deciding_length(indenter, length):
    """a_JKR = (9 pi dgamma R^2 / (8 E*))^(1/3) = 13.4 um for R = 400 um: 10.7 elements of h = 1.25 um."""
    from brushbem.config import advice

    document = fibril_brush()
    document["indenter"] = indenter
    found = advice.resolution(parse_config(document))
    assert found.length == length
    if length.startswith("JKR"):  # eq. 2.20b, and the sphere's own measured table
        a_jkr = (9 * math.pi * 0.04 * 400.0**2 / (8 * 8 / 3)) ** (1 / 3)
        assert found.value == pytest.approx(a_jkr, rel=1e-14, abs=0)
        assert "--sphere" in found.basis
        rows = advice._table(advice.SPHERE_TABLE)
        assert min(r["force_error"] for r in rows) <= found.force_error_estimate <= max(r["force_error"] for r in rows)


# --- a run: the fibril's spring in the physics, what a designer reports, curve.csv ------------------------


def test_punch_on_its_fibril_separates_with_the_work_of_eq_2_19(tmp_path):
    """k = pi r_f^2 E_f / l enters the run: the work of separation is eq. 2.18-2.19's at that k.

    A punch of r = 20 um at 32 elements per radius on a fibril of r_f = 10 um, l = 100 um, E_f = 2 MPa:
    k = 6.28 uN/um, k~ = k / (2 E* r) = 0.0589.  The tolerance is the measured error of the work at 32
    elements per radius, +1.1 % to +3.4 % (resolution_error.csv), with a margin.
    """
    import brushbem

    h = 20.0 / 32
    document = fibril_brush()
    document["grid"] = {"size": 70 * h, "elements": 70}
    document["indenter"] = {"shape": "flat_punch", "radius": 20.0,
                            "fibril": {"youngs_modulus": 2.0, "length": 100.0, "radius": 10.0}}
    pulled = brushbem.run(document)
    k = math.pi * 100 * 2 / 100
    spring = pulled.summary["design"]["spring"]
    assert spring["stiffness"] == pytest.approx(k, rel=1e-15, abs=0) and spring["from"].startswith("indenter.fibril")
    # k~ = k / (2 E* r) as the run normalises it: at the footprint's radius, 0.17 % above the radius typed.
    assert spring["stiffness_ratio"] == pulled.summary["theory"]["normalized_stiffness"]
    assert spring["stiffness_ratio"] == pytest.approx(k / (2 * 8 / 3 * 20.0), rel=3e-3, abs=0)
    work = theory.punch_spring_work_of_separation(20.0, k, contact_modulus=8 / 3, work_of_adhesion=0.04)
    assert 1.0 < pulled.work_of_separation / work < 1.045
    assert pulled.summary["design"]["adhesion_strength"] == pytest.approx(
        pulled.adhesive_force / (math.pi * 400), rel=1e-15, abs=0)
    assert pulled.summary["resolution"]["elements"] == pytest.approx(32.0, rel=1e-14, abs=0)


def test_a_rigid_indenter_has_no_spring_to_report():
    """`spring_numbers` gives (k, k~) of a spring and None for a rigid indenter, whose design has no ``spring``:
    the run hands the pair on without reading it."""
    from brushbem.physics.comparison import spring_numbers
    from brushbem.runs.assembly import parse

    punch = {"halfspace": {"contact_modulus": 1.0, "work_of_adhesion": 1e-4}, "grid": {"size": 1.0, "elements": 32},
             "indenter": {"shape": "flat_punch", "radius": 0.25, "stiffness": "inf"},
             "protocol": {"method": "events", "preload_displacement": 1e-3}}
    assert spring_numbers(parse(punch).problem) is None
    punch["indenter"]["stiffness"] = 0.1
    stiffness, ratio = spring_numbers(parse(punch).problem)
    assert stiffness == 0.1 and ratio is not None and math.isfinite(ratio)


def test_brush_reports_strength_per_pillar_and_writes_the_curve(tmp_path):
    import csv

    import brushbem

    pulled = brushbem.run(fibril_brush())
    design = pulled.summary["design"]
    assert design["apparent_area"] == 80.0**2 and design["pillars"] == 16
    assert design["adhesion_strength"] == pytest.approx(pulled.adhesive_force / 6400, rel=1e-15, abs=0)
    assert design["adhesive_force_per_pillar"] == pytest.approx(pulled.adhesive_force / 16, rel=1e-15, abs=0)
    # A brush's spring k~ is its normalisation's (k / (E* L), L the brush's side), the same number.
    assert design.spring.stiffness_ratio == pulled.summary.normalized.stiffness_ratio is not None
    assert design["units"]["adhesion_strength"] == "MPa" and design["units"]["adhesive_force_per_pillar"] == "uN"
    assert any("spans 4 elements" in warning for warning in pulled.summary["warnings"])
    pulled.save(tmp_path, figure=False)
    with open(tmp_path / "curve.csv", encoding="utf-8") as handle:
        rows = list(csv.reader(handle))
    assert rows[0] == ["displacement [um]", "force [uN]", "contact_area [um2]", "attached_pillars", "loading",
                       "converged"]
    curve = pulled.curve
    assert len(rows) == len(curve.displacement) + 1
    assert [float(r[1]) for r in rows[1:]] == list(curve.force)  # exactly the doubles of result.nc
    assert [int(r[4]) for r in rows[1:]] == [int(v) for v in curve.loading]
    assert -min(float(r[1]) for r in rows[1:]) == pulled.adhesive_force


def test_terminal_summary_carries_units_and_designer_numbers(tmp_path):
    from click.testing import CliRunner

    from brushbem.cli import main

    path = tmp_path / "pdms.toml"
    path.write_text(PDMS_TOML, encoding="utf-8")
    result = CliRunner().invoke(main, ["run", str(path), "--out", str(tmp_path / "out")])
    assert result.exit_code == 0, result.output
    for text in ("adhesion strength F_A / A0", "kPa", "F_A per pillar (N_p = 16)", "µN", "spring k (indenter.fibril)",
                 "3.927 N/m", "elements per pillar radius", "F_A discretisation error (est.)"):
        assert text in result.output, text
    assert (tmp_path / "out" / "curve.csv").is_file()


def test_buckled_fibrils_carry_euler_force_and_pull_off_as_before():
    """Pressed 3 um, every fibril (clamped-free, P_cr = 1.514 uN) buckles: each carries at least P_cr and at most
    P_cr + 0.01 k (3 um - P_cr / k), the plateau's slope over the largest compression the base allows.  The
    pull-off happens in tension, where the law is the linear spring: F_A is the linear brush's (the event path's,
    which the fixed path's located detachments reproduce; rel 1e-6 leaves room for the located events' rounding).
    """
    import brushbem

    document = fibril_brush(buckling="clamped-free")
    document["protocol"] = {"method": "fixed", "step": 0.05, "preload_displacement": 3.0}
    buckled = brushbem.run(document)
    linear = brushbem.run(fibril_brush())
    assert buckled.converged and linear.converged
    k = 1.25 * math.pi
    p_cr = theory.euler_buckling_force(LENGTH, RADIUS, youngs_modulus=E_FIBRIL, ends="clamped-free")
    assert buckled.summary["design"]["spring"]["buckling_force"] == pytest.approx(p_cr, rel=1e-15, abs=0)
    assert 16 * p_cr < buckled.summary["preload_force"] <= 16 * (p_cr + 0.01 * k * (3.0 - p_cr / k))
    assert buckled.adhesive_force == pytest.approx(linear.adhesive_force, rel=1e-6, abs=0)


def test_the_table_applies_to_the_pillar_models_tips():
    """A lone pillar of the pillar model detaches as the exact path's punch (to 1e-7 at 4 to 32 elements per radius,
    measured), so its tips carry the resolution table's error: here at 8 elements per radius, rel 1e-6."""
    import brushbem

    h = 1.0 / 8
    found = {}
    for method in ("pillars", "events"):
        found[method] = brushbem.run({
            "halfspace": {"contact_modulus": 1.0, "work_of_adhesion": 1e-3},
            "grid": {"size": 22 * h, "elements": 22},
            "indenter": {"shape": "brush", "layout": "square", "pillars_per_side": 1, "pillar_radius": 1.0,
                         "region_size": 2.0 + 2 * h, "stiffness": 2.0},
            "protocol": {"method": method, "preload_displacement": 0.01, "pillar_tip_peel": False}}).adhesive_force
    assert found["pillars"] == pytest.approx(found["events"], rel=1e-6, abs=0)
