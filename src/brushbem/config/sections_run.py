"""The tables of how a run proceeds: `ProtocolConfig` (the load path), `SolverConfig` and `UnitsConfig`."""

from __future__ import annotations

from typing import ClassVar, Literal

from pydantic import Field, field_validator

from brushbem.config.errors import _show
from brushbem.config.rules import Problem
from brushbem.config.sections_base import _MODEL_CONFIG, _Model, _Section
from brushbem.physics.pillar_model_domain import default_tip_peel


class ProtocolConfig(_Section):
    """The pull-off load path: press to a preload, then retract until separation.

    Attributes
    ----------
    method : {"events", "element_events", "fixed", "pillars"}
        ``"events"`` follows the exact path: it jumps from one contact
        change to the next, and presses a brush (two or more pillars) as
        non-adhesive contact problems, which is the same branch checked on
        its samples (``brushbem.protocol``); ``"element_events"`` takes
        every element event on the loading branch too (the reference, and
        today's path of single bodies); ``"fixed"`` retracts by constant
        steps (the thesis's method, L648; the step is ours: the thesis
        states none), locating every detachment (and a
        pillar law's break) inside each step; ``"pillars"`` is the
        pillar-level model of a brush of flat tips (a few modes per tip,
        events exact in the reduced model; ``brushbem.pillars``).
    preload_displacement : float or None
        Press until the base displacement reaches this value, units of length;
        at most `MAX_PRELOAD_DOMAIN_SIZES` (1000) x grid.size.
    preload_force : float or None
        Press until the compressive force reaches this value, units of force;
        at most the force that presses the stiffest contact the domain allows
        (2 E* L / sqrt(2)) that deep.  Exactly one of the two preloads is given.
    step : float
        Displacement step of ``"fixed"``, in units of length: at most
        grid.size, and at least the preload's depth / max_steps.
    max_steps : int
        Most steps (events, or fixed displacement steps) on each branch,
        loading and unloading; a branch that needs more ends the run, which
        reports not converged.
    speed : float or None
        Pulling (and pressing) speed of viscoelastic pillars, in units of
        length per time: each ``step`` is the time step step / speed.  Needs
        ``indenter.viscoelastic``, ``method = "fixed"`` and
        ``preload_displacement``.
    event_window : float
        Which events of the event paths ("events", "element_events",
        "pillars") are taken together, in one cascade: every element whose
        pressure is within event_window x Sigma_c of the criterion at the
        first detachment, and every event within event_window x h along the
        path (h = grid.size / grid.elements); dimensionless, in [0, 1e-3].
        Independent of ``solver.tolerance`` and of the depth of the path.
        The default 1e-7 changes F_A by < 1e-6 against 1e-12 on the
        validation families.
    pillar_modes : {"quadratic", "tilt", "uniform"}
        ``method = "pillars"`` only: the pressure modes of every tip.
    pillar_near : float or None
        ``method = "pillars"`` only: centres closer than this many pillar
        radii are coupled exactly (default 8).
    pillar_solve : {"auto", "kept", "cg"}
        ``method = "pillars"`` only: the kept inverse up to a limit of
        attached pillars and CG on the lattice's FFT beyond, always the kept
        inverse, or always CG (pillars on a lattice).
    pillar_tip_resolution : float or None
        ``method = "pillars"`` only: every tip on a raster of its own with at
        least this many elements per pillar radius (>= 2; the grid subdivided
        by the smallest integer that gives it); None: the grid's own.
    pillar_tip_calibration : bool
        ``method = "pillars"`` only: every tip's critical stress scaled so that
        the tip alone on its raster comes off at Kendall's force (removes a
        lone tip's discretisation error, not a brush's; measured in
        ``docs/pillars/calibration.csv``); false: the raster's own.
    pillar_tip_peel : bool or None
        ``method = "pillars"`` only: every whole tip leaves at its continuum
        capacity (its first point raised by its stable peel's gain, from its
        K(theta) read off its modes, `brushbem.pillars.peel`); false: the
        tips peel on their rasters element by element (the exact path's
        criterion on the same raster; the thesis's studies pin it); not true
        with ``pillar_tip_calibration``.  Unset (None): the default,
        `brushbem.physics.pillar_model_domain.default_tip_peel` (true for
        the pillar model unless its tips are calibrated); `tip_peel` is the
        value the run takes.
    """

    model_config = _MODEL_CONFIG
    #: Keys of which exactly one is required (the message for a missing [protocol] names them).
    REQUIRED_ONE_OF: ClassVar[tuple[str, ...]] = ("preload_displacement", "preload_force")

    method: Literal["events", "element_events", "fixed", "pillars"] = "events"
    preload_displacement: float | None = Field(None, gt=0, allow_inf_nan=False)
    preload_force: float | None = Field(None, gt=0, allow_inf_nan=False)
    step: float = Field(1e-4, gt=0, allow_inf_nan=False)
    max_steps: int = Field(200_000, gt=0, le=1_000_000_000)
    speed: float | None = Field(None, gt=0, allow_inf_nan=False)
    event_window: float = Field(1e-7, ge=0, le=1e-3, allow_inf_nan=False)
    pillar_modes: Literal["quadratic", "tilt", "uniform"] = "quadratic"
    pillar_near: float | None = Field(None, gt=0, allow_inf_nan=False)
    pillar_solve: Literal["auto", "kept", "cg"] = "auto"
    pillar_tip_resolution: float | None = Field(None, ge=2, allow_inf_nan=False)
    pillar_tip_calibration: bool = False
    pillar_tip_peel: bool | None = None

    @property
    def tip_peel(self) -> bool:
        """Whether the run's tips leave at their continuum capacity: ``pillar_tip_peel``, or its default where unset."""
        if self.pillar_tip_peel is not None:
            return self.pillar_tip_peel
        return default_tip_peel(self.method, self.pillar_tip_calibration)

    def _rule_problems(self) -> list[Problem]:
        if (self.preload_displacement is None) == (self.preload_force is None):
            given = (
                f"preload_displacement = {_show(self.preload_displacement)}, "
                f"preload_force = {_show(self.preload_force)}"
            )
            return [Problem("", given, "give exactly one of preload_displacement or preload_force")]
        return []


class SolverConfig(_Model):
    """Inner linear solver (preconditioned conjugate gradients).

    Attributes
    ----------
    tolerance : float
        Relative residual at which a solve counts as converged, dimensionless.
    max_iterations : int
        Iterations allowed per solve before it is reported as not converged.
    coupling : {"segments", "discriminant"}
        How the spring sums enter the operator: segment sums over the
        element-to-pillar incidence (exact for any layout), or the thesis's
        discriminant-matrix convolution (eq. 3.13-3.17; refused where its size
        condition does not hold).
    cascade : {"local", "global"}
        How a brush's detachment cascade at fixed d runs: the pillars that
        peel solved on their own between global solves ("local"), or a global
        solve for every round (the thesis's loop, "global").
    """

    model_config = _MODEL_CONFIG

    tolerance: float = Field(1e-8, ge=1e-15, lt=1e-2, allow_inf_nan=False)
    max_iterations: int = Field(20_000, gt=0, le=1_000_000_000)
    coupling: Literal["segments", "discriminant"] = "segments"
    cascade: Literal["local", "global"] = "local"


class UnitsConfig(_Section):
    """The unit system of the inputs (`brushbem.results.units`): names only, the numbers do not change.

    Attributes
    ----------
    length : {"m", "cm", "mm", "um", "nm"} or None
        The unit of ``grid.size`` and every length; ``"µm"``, ``"micron"``
        and ``"micrometre"`` are read as ``"um"``.
    stress : {"Pa", "kPa", "MPa", "GPa"} or None
        The unit of E* and every stress; forces, works and the work of
        adhesion follow.  Both or neither; neither (the default) is
        dimensionless.
    """

    model_config = _MODEL_CONFIG

    length: Literal["m", "cm", "mm", "um", "nm"] | None = None
    stress: Literal["Pa", "kPa", "MPa", "GPa"] | None = None

    #: Other names of the micrometre, read as "um" (UDUNITS-2's name, which result.nc writes).
    LENGTH_ALIASES: ClassVar[dict[str, str]] = {"µm": "um", "μm": "um", "micron": "um", "microns": "um",
                                                "micrometre": "um", "micrometer": "um"}

    @field_validator("length", mode="before")
    @classmethod
    def _micrometre(cls, value: object) -> object:
        return cls.LENGTH_ALIASES.get(value, value) if isinstance(value, str) else value

    def _rule_problems(self) -> list[Problem]:
        length, stress = getattr(self, "length", None), getattr(self, "stress", None)
        if (length is None) == (stress is None):
            return []
        missing = "stress" if stress is None else "length"
        return [Problem(missing, "missing", "give units.length and units.stress together, or neither "
                                            "(dimensionless)")]
