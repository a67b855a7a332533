"""Viscoelastic pillars (thesis sec. 8.2, 3): Kelvin-Voigt and standard-linear-solid connections in time.

Checks, each against an independent result:

* the rate-independent limits: pulled very slowly, a connection is the
  elastic spring of its relaxed stiffness; very fast, the elastic spring of
  its instantaneous stiffness (Kelvin-Voigt: rigid); the error is first
  order in dt / tau;
* a flat punch on a connection stays in full contact until it detaches at
  its (mesh) Kendall force, whatever the speed, and in full contact it is a
  linear spring k_h: the pull-off is then a one-degree-of-freedom problem.
  Its implicit-Euler recursion, written out here in ten lines, must give the
  BEM's work of separation to the solver's tolerance; and its exact
  continuous-time solution (closed form: a linear ODE for the arm force on
  each branch, `_continuous_work`) is what the BEM converges to as the step
  shrinks, at first order;
* a brush pulled at three speeds, and bad input named by its key.

Grids are quick grids (N = 64): they test the machinery.
"""

from __future__ import annotations

import dataclasses
import functools
import itertools
import math
import textwrap

import pytest
from scipy.optimize import brentq

from brushbem.runs.assembly import load
from brushbem.config import ConfigError
from brushbem.errors import ParameterError
from brushbem.protocol import ContactProblem, LoadPath, indent, record_pull_off
from brushbem.protocol.recording import work_of_separation
from brushbem.physics.structure import Grid, brush, flat_punch
from brushbem.physics.viscoelastic import Viscoelastic, time_stepping_problems

GRID = Grid(1.0, 64)
RADIUS = 0.2
STIFFNESS = 0.2  # k_inf, ~ 0.5 x the punch's half-space stiffness 2 E* a
DGAMMA = 1e-3
PRELOAD = 0.01
TAU = 1.0
MODELS = {"kelvin_voigt": None, "standard_linear_solid": 3.0}


@functools.cache  # the elastic punch is the reference of several tests: pulled off once
def _run(rheology: Viscoelastic | None, speed: float | None, step: float = 5e-4, stiffness: float = STIFFNESS):
    punch = flat_punch(GRID, RADIUS, stiffness)
    if rheology is not None:
        punch = dataclasses.replace(punch, viscoelastic=rheology)
    problem = ContactProblem(GRID, punch, contact_modulus=1.0, work_of_adhesion=DGAMMA)
    record = record_pull_off(problem, LoadPath(method="fixed", preload_displacement=PRELOAD, step=step,
                                               speed=speed))
    assert record.summary["converged"], record.summary["reason"]
    return record.summary


@pytest.mark.parametrize("model", list(MODELS))
def test_slow_and_fast_limits_are_the_relaxed_and_the_instantaneous_spring(model):
    """Slow: the elastic punch on k_inf.  Fast: on k_0 = k_inf f (SLS) or rigid (KV); error ~ dt / tau.

    tau / dt is v / 5e-4: at v = 1e-10 the step is 5e6 relaxation times
    (implicit Euler's arm stiffness k_1 / (1 + dt / tau) is 2e-7 of k_1), at
    v = 1e3 and 1e5 dt / tau is 5e-7 and 5e-9.  Slow: F_A, the work and the
    pull-off displacement to 1e-7 (the arm's residue is 2e-7 k_1 in a
    series with a 10 x stiffer half-space).  The work's deviation from
    the instantaneous spring must shrink with dt / tau (first order: by 100
    between the two fast speeds, allowed 30 for the solver's noise) and be
    below 1e-4 at v = 1e3.
    """
    factor = MODELS[model]
    rheology = Viscoelastic(model, TAU, factor)
    relaxed = _run(None, None)
    slow = _run(rheology, 1e-10)
    for key in ("adhesive_force", "work_of_separation", "pull_off_displacement"):
        assert slow[key] == pytest.approx(relaxed[key], rel=1e-7)
    instantaneous = _run(None, None, stiffness=STIFFNESS * factor if factor else math.inf)
    errors = []
    for speed in (1e3, 1e5):
        fast = _run(rheology, speed)
        assert fast["adhesive_force"] == pytest.approx(instantaneous["adhesive_force"], rel=1e-6)
        errors.append(abs(fast["work_of_separation"] / instantaneous["work_of_separation"] - 1))
    assert errors[0] < 1e-4 and errors[1] < errors[0] / 30


def _punch_constants() -> tuple[float, float]:
    """The rasterised punch's half-space stiffness k_h (full contact) and its pull-off force F_K, from the BEM."""
    rigid = ContactProblem(GRID, flat_punch(GRID, RADIUS), contact_modulus=1.0, work_of_adhesion=0.0)
    k_h = indent(rigid, PRELOAD).force / PRELOAD
    return k_h, _run(None, None)["adhesive_force"]


def _arms(model: str) -> tuple[float, float]:
    """(k_1, eta) of the connection: the Maxwell arm's spring and dashpot (Kelvin-Voigt: k_1 = inf)."""
    factor = MODELS[model]
    if factor is None:
        return math.inf, STIFFNESS * TAU
    k1 = STIFFNESS * (factor - 1.0)
    return k1, k1 * TAU


def _discrete_work(model: str, speed: float, step: float, k_h: float, f_k: float) -> float:
    """The one-degree-of-freedom punch, stepped exactly as the BEM steps the connection (implicit Euler)."""
    k1, eta = _arms(model)
    dt = step / speed
    arm = eta / dt if math.isinf(k1) else k1 / (1.0 + k1 * dt / eta)
    keep = 0.0 if math.isinf(k1) else arm / k1
    k_eff = STIFFNESS + arm
    s = f1 = 0.0
    n = round(PRELOAD / step)
    ds = [j * step for j in range(1, n + 1)] + [PRELOAD - j * step for j in range(1, 100 * n)]
    points, previous = [], (PRELOAD, None)
    for j, d in enumerate(ds):
        b = (arm * s - keep * f1) / k_eff
        force = k_h * (d - b) / (1.0 + k_h / k_eff)  # F = k_h (d - s), s = F / k_eff + b
        if j >= n:  # unloading
            d0, f0 = previous
            if force < -f_k:  # detaches inside the step, where F reaches -F_K (the BEM's first crossing)
                tau = (f0 + f_k) / (f0 - force)
                return work_of_separation([*points, (d0 - tau * step, -f_k)])
            points.append((d, force))
        else:
            points = [(d, force)]
        previous = (d, force)
        s_new = force / k_eff + b
        f1 = arm * (s_new - s) + keep * f1
        s = s_new
    raise AssertionError("the lumped punch never detached")


def _continuous_work(model: str, speed: float, k_h: float, f_k: float) -> float:
    """The exact work of separation of the one-degree-of-freedom punch pulled at ``speed`` (closed form).

    With F = k_h (d - s) = k_inf s + F_1 and the arm ds/dt = dF_1/dt / k_1 +
    F_1 / eta, the arm force obeys dF_1/dt = A dd/dt - B F_1, A = k_1 k_h /
    (k_h + k_inf + k_1), B = k_1 (k_h + k_inf) / (eta (k_h + k_inf + k_1))
    (Kelvin-Voigt: k_1 -> inf, A = k_h, B = (k_h + k_inf) / eta), and F =
    k_h (k_inf d + F_1) / (k_h + k_inf).  On each branch dd/dt = +-v is
    constant: F_1 relaxes exponentially to +-A v / B.  The work is the
    integral of -F dd from the zero crossing of F to F = -F_K (a vertical
    drop after), both located by root finding on the closed form.
    """
    k1, eta = _arms(model)
    k_inf = STIFFNESS
    if math.isinf(k1):
        a, b = k_h, (k_h + k_inf) / eta
    else:
        a, b = k1 * k_h / (k_h + k_inf + k1), k1 * (k_h + k_inf) / (eta * (k_h + k_inf + k1))
    t_load = PRELOAD / speed
    f1_max = a * speed / b * (1.0 - math.exp(-b * t_load))  # from rest, dd/dt = +v

    def arm(t):  # unloading, t from the preload
        target = -a * speed / b
        return target + (f1_max - target) * math.exp(-b * t)

    def force(t):
        return k_h * (k_inf * (PRELOAD - speed * t) + arm(t)) / (k_h + k_inf)

    def impulse(t):  # integral of F dt from 0 to t
        target = -a * speed / b
        arm_integral = target * t + (f1_max - target) * (1.0 - math.exp(-b * t)) / b
        return k_h * (k_inf * (PRELOAD * t - 0.5 * speed * t * t) + arm_integral) / (k_h + k_inf)

    horizon = 100 * PRELOAD / speed
    t0 = brentq(force, 0.0, horizon, xtol=1e-15, rtol=1e-14)
    t1 = brentq(lambda t: force(t) + f_k, t0, horizon, xtol=1e-15, rtol=1e-14)
    return -(impulse(t1) - impulse(t0)) * speed  # dd = -v dt


@pytest.mark.parametrize("model, steps", [
    ("standard_linear_solid", (1e-3, 5e-4, 2.5e-4)),
    ("kelvin_voigt", (2e-3, 1e-3, 5e-4)),
])
@pytest.mark.slow
def test_a_punch_on_a_connection_is_the_one_degree_of_freedom_model(model, steps):
    """At a speed where the connection relaxes during the pull-off (the path lasts 2 tau), three checks.

    F_A is the elastic punch's at every speed (it detaches at its own
    Kendall force; 1e-7: the crossing is located on pressures solved to the
    CG tolerance 1e-8, measured 2e-8).  For the standard linear solid the
    BEM's work equals the stepped one-degree-of-freedom recursion to 1e-6
    (the same scheme; what is left is the solver's tolerance), and as the
    step halves twice it approaches the exact continuous-time value with an
    observed order > 0.8 (implicit Euler is first order), the finest step
    within 1 % of it.

    The one-degree-of-freedom model assumes that the punch comes off in one
    cascade.  A Kelvin-Voigt connection is stiff at the step (k_eff = k (1 +
    tau / dt): 8.2 = 20 k_h at tau / dt = 40), and with every event of a step
    located, the mesh holds the punch partly peeled after its first ring
    leaves (the event path's state, which the lumped model does not have):
    the work is above the recursion's, by +1.7, +1.1, +0.67 % of the
    continuous value at steps 2e-3, 1e-3, 5e-4.  What must hold for it is that
    the work approaches the continuous value as the step shrinks and is within
    1 % of it at the finest step.
    """
    rheology = Viscoelastic(model, TAU, MODELS[model])
    k_h, f_k = _punch_constants()
    speed = 0.01  # the whole path lasts 2 PRELOAD / v = 2 tau
    exact = _continuous_work(model, speed, k_h, f_k)
    errors = []
    for step in steps:
        summary = _run(rheology, speed, step)
        assert summary["adhesive_force"] == pytest.approx(f_k, rel=1e-7)
        if model == "standard_linear_solid":
            assert summary["work_of_separation"] == pytest.approx(_discrete_work(model, speed, step, k_h, f_k),
                                                                  rel=1e-6)
        errors.append(abs(summary["work_of_separation"] / exact - 1))
    assert errors[-1] < 0.01, errors
    assert all(e1 < e0 for e0, e1 in itertools.pairwise(errors)), errors
    if model == "standard_linear_solid":
        orders = [math.log(e0 / e1) / math.log(2) for e0, e1 in itertools.pairwise(errors)]
        assert min(orders) > 0.8, (errors, orders)
        # Rate dependence is real: the viscous work differs from the relaxed spring's by 4 %.
        relaxed = _run(None, None, steps[-1])["work_of_separation"]
        assert abs(exact / relaxed - 1) > 0.02


@pytest.mark.slow
def test_a_brush_pulled_at_three_speeds():
    """A 4 x 4 brush of SLS connections: F_A rises from the relaxed towards the instantaneous brush with speed.

    A stiffer brush shares the load worse (thesis ch. 4: soft pillars raise
    F_A), so the order is not assumed; what must hold is that every speed
    converges, and the slowest and fastest equal the relaxed and the
    instantaneous elastic brushes (1e-6, as in the punch's limits).
    """
    per_side, radius = 4, math.sqrt(0.16 / math.pi) / 4

    def make(stiffness, rheology=None):
        indenter = brush(GRID, layout="square", pillars_per_side=per_side, pillar_radius=radius,
                         contact_modulus=1.0, work_of_adhesion=1e-4, stiffness=stiffness, roughness=1e-3, seed=2)
        return dataclasses.replace(indenter, viscoelastic=rheology)

    def run(indenter, speed=None):
        problem = ContactProblem(GRID, indenter, contact_modulus=1.0, work_of_adhesion=1e-4)
        record = record_pull_off(problem, LoadPath(method="fixed", preload_displacement=0.006, step=2e-4,
                                                   speed=speed))
        assert record.summary["converged"], record.summary["reason"]
        return record.summary

    rheology = Viscoelastic("standard_linear_solid", 1.0, 10.0)
    relaxed, instantaneous = run(make(0.01)), run(make(0.1))
    results = {speed: run(make(0.01, rheology), speed) for speed in (1e-7, 1e-3, 1e5)}
    assert results[1e-7]["adhesive_force"] == pytest.approx(relaxed["adhesive_force"], rel=1e-6)
    assert results[1e5]["adhesive_force"] == pytest.approx(instantaneous["adhesive_force"], rel=1e-6)
    middle = results[1e-3]["work_of_separation"]
    assert min(relaxed["work_of_separation"], instantaneous["work_of_separation"]) * 0.5 < middle


def test_time_stepping_needs_speed_fixed_steps_and_a_displacement():
    punch = dataclasses.replace(flat_punch(GRID, RADIUS, STIFFNESS), viscoelastic=Viscoelastic("kelvin_voigt", 1.0))
    problem = ContactProblem(GRID, punch, contact_modulus=1.0, work_of_adhesion=DGAMMA)
    for path, message in (
        (LoadPath(method="fixed", preload_displacement=PRELOAD), "LoadPath.speed"),
        (LoadPath(method="events", preload_displacement=PRELOAD, speed=1.0), "method = 'fixed'"),
        (LoadPath(method="fixed", preload_force=1e-3, speed=1.0), "preload_displacement"),
    ):
        with pytest.raises(ValueError, match=message):
            record_pull_off(problem, path)
    elastic = ContactProblem(GRID, flat_punch(GRID, RADIUS, STIFFNESS), contact_modulus=1.0, work_of_adhesion=DGAMMA)
    with pytest.raises(ParameterError, match="LoadPath.speed") as refused:
        record_pull_off(elastic, LoadPath(method="fixed", preload_displacement=PRELOAD, speed=1.0))
    assert (refused.value.owner, refused.value.parameter) == ("LoadPath", "speed")
    with pytest.raises(ValueError, match="relaxation_time"):
        Viscoelastic("kelvin_voigt", -1.0)
    with pytest.raises(ValueError, match="instantaneous_factor"):
        Viscoelastic("standard_linear_solid", 1.0, 0.5)
    with pytest.raises(ParameterError, match="must be finite with Indenter.viscoelastic") as refused:
        dataclasses.replace(flat_punch(GRID, RADIUS), viscoelastic=Viscoelastic("kelvin_voigt", 1.0))
    # One rule (`elastic_connection_problems`) for the indenter and the path rule the configuration names by key.
    [expected] = time_stepping_problems(True, method="fixed", speed=1.0, preload_displacement=PRELOAD,
                                        stiffness=math.inf)
    assert (refused.value.owner, refused.value.parameter, refused.value.message) == (
        expected.owner, expected.parameter, expected.message)


def test_config_names_every_bad_viscoelastic_key(tmp_path):
    path = tmp_path / "case.toml"
    path.write_text(textwrap.dedent("""
        [halfspace]
        contact_modulus = 1.0
        work_of_adhesion = 1e-3
        [grid]
        size = 1.0
        elements = 64
        [indenter]
        shape = "flat_punch"
        radius = 0.2
        stiffness = 0.2
        viscoelastic = {model = "kelvin_voigt", relaxation_time = -1.0, instantaneous_factor = 2.0}
        [protocol]
        preload_displacement = 0.01
        speed = -1.0
        """))
    with pytest.raises(ConfigError) as info:
        load(path)
    message = str(info.value)
    for key in ("indenter.viscoelastic.relaxation_time", "indenter.viscoelastic.instantaneous_factor",
                "protocol.speed"):
        assert key in message, message
    path.write_text(path.read_text().replace("relaxation_time = -1.0, instantaneous_factor = 2.0",
                                             "relaxation_time = 1.0").replace("speed = -1.0", "speed = 0.01"))
    with pytest.raises(ConfigError, match="protocol.method"):
        load(path)
    path.write_text(path.read_text().replace("speed = 0.01", 'speed = 0.01\nmethod = "fixed"\nstep = 5e-4'))
    built = load(path)
    assert built.problem.indenter.viscoelastic == Viscoelastic("kelvin_voigt", 1.0)
    assert built.path.speed == 0.01


def test_the_memory_is_a_value():
    """The connections' history (`Memory`) is a frozen value: a step's offsets and its commit give new ones and leave
    the old as it was, with the implicit Euler update of the module docstring."""
    import numpy as np

    from brushbem.physics.viscoelastic import Memory

    indenter = dataclasses.replace(flat_punch(GRID, RADIUS, STIFFNESS),
                                   viscoelastic=Viscoelastic("standard_linear_solid", 1.0, 3.0))
    start = Memory.start(indenter, 1e-4, 1e-3)  # dt = 0.1 tau
    committed = start.advance().commit(np.array([2e-3]))
    assert start.compression.tolist() == [0.0] and start.arm_force.tolist() == [0.0] and start.offset.tolist() == [0.0]
    # From rest b = 0: s = F / k_eff, and F_1 = k_1' s.
    assert committed.compression[0] == pytest.approx(2e-3 / committed.stiffness[0], rel=1e-15)
    assert committed.arm_force[0] == pytest.approx(committed.arm[0] * committed.compression[0], rel=1e-15)
    following = committed.advance()
    assert committed.offset.tolist() == [0.0] and following.offset[0] != 0.0
    with pytest.raises(dataclasses.FrozenInstanceError):
        start.offset = following.offset
