"""Viscoelastic pillar connections: Kelvin-Voigt and the standard linear solid, stepped in time (thesis sec. 8.2, 3).

The pillars' own springs (level 1) become rheological connections, pulled at
a constant speed v, so that a displacement step dd is the time step dt = dd / v:

* **Kelvin-Voigt**: a spring k and a dashpot eta in parallel, F = k s + eta
  ds/dt (s: the connection's compression, F: its force, compressive
  positive).  Retardation time tau = eta / k.
* **Standard linear solid** (Zener): a spring k_inf in parallel with a
  Maxwell arm (spring k_1 in series with a dashpot eta), F = k_inf s + F_1
  with ds/dt = dF_1/dt / k_1 + F_1 / eta.  Relaxed stiffness k_inf,
  instantaneous stiffness k_0 = k_inf + k_1, relaxation time tau = eta / k_1.

Both are integrated by the implicit Euler method, which turns every step
into an elastic connection with an affine law

    s = F / k_eff + b,    k_eff = k_inf + k_1',    k_1' = k_1 / (1 + dt / tau)

(Kelvin-Voigt: k_1' = eta / dt = k tau / dt), where the history term b =
(k_1' s_old - q F_1,old) / k_eff, q = k_1' / k_1 (0 for Kelvin-Voigt), comes
from the previous step.  With a constant step, k_eff is the same at every
step: the solve is the elastic brush's with the pillar stiffness k_eff, and b
enters as a length offset of each pillar's tip (the penetration is d - height
- s - u).  After each step, s and F_1 follow from the pillars' forces.  The
limits are exact: dt >> tau gives k_eff -> k_inf and b -> 0 (the relaxed,
elastic brush); dt << tau gives the instantaneous stiffness k_inf + k_1 (and
for Kelvin-Voigt a rigid connection), with b -> 0 from rest.  The scheme is
first order in dt / tau.

Only the pillars' own connections are viscoelastic; the levels above them
and the half-space are elastic.  A viscoelastic half-space would need the
history of the surface displacements (a hereditary integral over the whole
contact), which this time stepping does not carry.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from brushbem.errors import ParameterProblem
from brushbem.physics.structure import Indenter, SpringLevel, elastic_connection_problems

__all__ = ["MODELS", "Memory", "Viscoelastic", "time_stepping_problems"]

MODELS = ("kelvin_voigt", "standard_linear_solid")


@dataclass(frozen=True)
class Viscoelastic:
    """The rheology of the pillars' own connections (module docstring).

    Attributes
    ----------
    model : {"kelvin_voigt", "standard_linear_solid"}
    relaxation_time : float
        tau, in units of time (those of the path's speed): eta / k for
        Kelvin-Voigt, eta / k_1 for the standard linear solid.
    instantaneous_factor : float, optional
        k_0 / k_inf > 1 of the standard linear solid (its instantaneous over
        its relaxed stiffness); the pillar's ``stiffness`` is k_inf (or the
        Kelvin-Voigt spring k).
    """

    model: str
    relaxation_time: float
    instantaneous_factor: float | None = None

    def __post_init__(self):
        if self.model not in MODELS:
            raise ValueError(f"viscoelastic.model = {self.model!r} must be one of {', '.join(map(repr, MODELS))}")
        if not (math.isfinite(self.relaxation_time) and self.relaxation_time > 0):
            raise ValueError(f"viscoelastic.relaxation_time = {self.relaxation_time} must be finite and > 0")
        if self.model == "standard_linear_solid":
            factor = self.instantaneous_factor
            if factor is None or not (math.isfinite(factor) and factor > 1):
                raise ValueError(
                    f"viscoelastic.instantaneous_factor = {factor} must be finite and > 1 for the standard linear "
                    "solid (k_0 / k_inf)"
                )
        elif self.instantaneous_factor is not None:
            raise ValueError("viscoelastic.instantaneous_factor is only used with model = 'standard_linear_solid'")

    def step_stiffness(self, relaxed: np.ndarray, dt: float) -> tuple[np.ndarray, np.ndarray]:
        """(k_eff, k_1') of every connection for the time step ``dt``."""
        ratio = self.relaxation_time / dt
        if self.model == "kelvin_voigt":
            arm = relaxed * ratio
        else:
            k1 = relaxed * (self.instantaneous_factor - 1.0)
            arm = k1 * ratio / (1.0 + ratio)
        return relaxed + arm, arm


@dataclass(frozen=True)
class Memory:
    """The state of the connections along a time-stepped path, as a value: compression s and Maxwell-arm force F_1.

    Make the first with `Memory.start`; `advance` and `commit` give the next ones (a value is never
    changed: a saved path state holds it as it was).

    Attributes
    ----------
    rheology : Viscoelastic
    dt : float
        The time step, step / speed.
    stiffness, arm, keep : ndarray, one per pillar
        k_eff and k_1' of the step, and q = k_1' / k_1 (the share of the old arm force kept; 0 for
        Kelvin-Voigt).
    compression, arm_force, offset : ndarray, one per pillar
        s and F_1 after the last committed step, and the history offset b of the current step.
    stepped : Indenter
        The indenter whose pillar springs have the step's stiffness k_eff.
    """

    rheology: Viscoelastic
    dt: float
    stiffness: np.ndarray
    arm: np.ndarray
    keep: np.ndarray
    compression: np.ndarray
    arm_force: np.ndarray
    offset: np.ndarray
    stepped: Indenter

    @classmethod
    def start(cls, indenter: Indenter, step: float, speed: float) -> Memory:
        """The connections at rest at the start of a path of displacement ``step`` at ``speed`` (dt = step / speed).

        ``indenter`` has ``viscoelastic`` set and an elastic pillar level.
        """
        rheology = indenter.viscoelastic
        level = indenter.levels[0]
        dt = step / speed
        relaxed = np.array(level.stiffnesses, dtype=np.float64)
        stiffness, arm = rheology.step_stiffness(relaxed, dt)
        keep = (np.zeros_like(relaxed) if rheology.model == "kelvin_voigt"
                else np.full_like(relaxed, 1.0 / (1.0 + dt / rheology.relaxation_time)))
        stepped = dataclasses.replace(indenter, levels=(SpringLevel(stiffness, level.cluster), *indenter.levels[1:]))
        zero = np.zeros_like(relaxed)
        return cls(rheology, dt, stiffness, arm, keep, zero, zero, zero, stepped)

    def advance(self) -> Memory:
        """Before the next step: its history offsets b (``offset``, one per pillar, units of length)."""
        offset = (self.arm * self.compression - self.keep * self.arm_force) / self.stiffness
        return dataclasses.replace(self, offset=offset)

    def commit(self, forces: np.ndarray) -> Memory:
        """The step's equilibrium with the pillar forces ``forces`` (compressive positive) accepted."""
        compression = forces / self.stiffness + self.offset
        arm_force = self.arm * (compression - self.compression) + self.keep * self.arm_force
        return dataclasses.replace(self, compression=compression, arm_force=arm_force)


def time_stepping_problems(viscoelastic: bool, *, method: str, speed: float | None,
                           preload_displacement: float | None, preload_force: float | None = None,
                           stiffness: float | None = None) -> list[ParameterProblem]:
    """The rule of viscoelastic pillars, stated once: they and the pulling speed go together, on fixed steps
    (a step is the time step times the speed) to a preload displacement, with a finite (relaxed) stiffness.

    ``viscoelastic``: whether the pillars are (`Indenter.viscoelastic`); ``stiffness``: the pillars' stiffness
    where it is known before the indenter is built (None: not checked; an `Indenter` refuses a rigid one: the
    rigid-pillar rule is `brushbem.physics.structure.elastic_connection_problems`).
    Returns every problem; the load path raises the first, the configuration names them all by key.
    """
    if not viscoelastic:
        if speed is None:
            return []
        return [ParameterProblem("LoadPath", "speed", speed,
                                 "only applies to viscoelastic pillars (Indenter.viscoelastic); remove it")]
    problems = []
    if speed is None:
        problems.append(ParameterProblem("LoadPath", "speed", None,
                                         "required with Indenter.viscoelastic: the pulling speed (> 0)"))
    if method != "fixed":
        problems.append(ParameterProblem("LoadPath", "method", method,
                                         "needs method = 'fixed' with Indenter.viscoelastic (the path is stepped in "
                                         "time: dt = step / speed)"))
    if preload_displacement is None:
        problems.append(ParameterProblem("LoadPath", "preload_force", preload_force,
                                         "viscoelastic pillars (Indenter.viscoelastic) are pressed to "
                                         "LoadPath.preload_displacement instead (a force target would need steps of "
                                         "changing length)"))
    if stiffness is not None:
        problems.extend(elastic_connection_problems(stiffness, viscoelastic=True, pillar_law=None))
    return problems
