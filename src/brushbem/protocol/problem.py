"""What a pull-off is asked to do: the contact problem, the load path, and the states it records.

Sign convention: d > 0 presses into the half-space, F and p > 0 are compressive.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from brushbem.errors import ParameterError
from brushbem.physics.adhesion import critical_stress
from brushbem.physics.pillar_model_domain import default_tip_peel
from brushbem.physics.structure import Grid, Indenter

__all__ = ["ContactProblem", "LoadPath", "NotConvergedError", "PressedElements", "State", "check_preload",
           "detachment_slack", "event_tie"]


class NotConvergedError(RuntimeError):
    """A solve did not converge; the path stops and the record says why."""


@dataclass(frozen=True)
class ContactProblem:
    """An indenter on springs against an elastic half-space.

    Parameters
    ----------
    grid : Grid
    indenter : Indenter
    contact_modulus : float
        E*, in units of stress.
    work_of_adhesion : float
        dgamma, energy per unit area (0: no adhesion).
    coupling : {"segments", "discriminant"}
        How the spring sums are evaluated (see ``brushbem.numerics.operator``).
    """

    grid: Grid
    indenter: Indenter
    contact_modulus: float
    work_of_adhesion: float
    coupling: str = "segments"
    xp: object = np

    def __post_init__(self):
        if not (math.isfinite(self.contact_modulus) and self.contact_modulus > 0):
            raise ValueError(f"contact_modulus = {self.contact_modulus} must be finite and > 0")
        if not (math.isfinite(self.work_of_adhesion) and self.work_of_adhesion >= 0):
            raise ValueError(f"work_of_adhesion = {self.work_of_adhesion} must be finite and >= 0")

    @property
    def critical_stress(self) -> float:
        """Sigma_c of the mesh (eq. 2.14); 0 without adhesion."""
        return critical_stress(self.contact_modulus, self.work_of_adhesion, self.grid.element_size)


#: The widest event window allowed (a fraction of the element size): events a thousandth of an element apart
#: are distinct events of any pull-off we resolve.
MAX_EVENT_WINDOW = 1e-3


def event_tie(path: LoadPath, element_size: float) -> float:
    """The distance along the path within which two events are one (``path.event_window`` x h), a length.

    Events equal by symmetry differ by rounding, and events computed from a converged solve by its
    residual: taking those together saves steps of no length.  The window is a length of the grid (and,
    for detachments, a margin of stress, `detachment_slack`), not of the tolerance or of the
    displacement d, so a looser CG or a deeper preload does not merge events that are apart.  The
    default 1e-7 changes F_A by < 1e-6 against 1e-12 on the validation families
    (`docs/reproduction/probe_event_window.py`).
    """
    return path.event_window * element_size + 1e-300


def detachment_slack(path: LoadPath, critical: float, grows, rate, xp=np):
    """How much further along the path each detaching element stays within the event window, a length.

    An element whose pressure falls at ``rate`` per unit of the path (< 0 where ``grows``) is taken with
    the first detachment while its pressure is within ``path.event_window`` x Sigma_c of the criterion:
    event_window x Sigma_c / |rate|.  A margin of stress, so the same for every CG tolerance and depth;
    on soft springs (a small rate) it spans the longer way that the same stress margin takes.
    """
    return xp.where(grows, (path.event_window * critical) / xp.where(grows, -rate, 1.0), 0.0)


#: The pillar model's choices of modes (`brushbem.pillars.basis.MODES`) and of its pillar-level solve.
PILLAR_MODES = ("quadratic", "tilt", "uniform")
PILLAR_SOLVES = ("auto", "kept", "cg")


@dataclass(frozen=True)
class LoadPath:
    """How the indenter is pressed and pulled off.

    Parameters
    ----------
    method : {"events", "element_events", "fixed", "pillars"}
    preload_displacement, preload_force : float or None
        Exactly one: press to this base displacement, or until this force.
    step : float
        Displacement step of the "fixed" method, in units of length.
    max_steps : int
        Bound on the recorded states of each branch (a path that needs more is
        reported as not converged).
    tolerance : float
        Relative residual of every CG solve (nothing else).
    max_iterations : int
        Bound on the iterations of one CG solve.
    window_margin : float
        Margin of the working window around the contact, as a fraction of its
        size (at least 4 elements).
    cascade : {"local", "global"}
        How the detachment rounds of a brush run (`brushbem.numerics.solver.equilibria`).
    speed : float or None
        Pulling speed v of a time-stepped path (viscoelastic pillars, method
        "fixed"): every displacement step is the time step dd / v, in the
        time units of the pillars' relaxation time.
    event_window : float
        Which events of the event paths ("events", "element_events",
        "pillars") are taken together, in one cascade: at the first, every
        element whose pressure is within ``event_window`` x Sigma_c of the
        criterion (`detachment_slack`), and every event within
        ``event_window`` x h along the path (h the element size,
        `event_tie`).  Dimensionless, in [0, 1e-3] (0: only exact ties); a
        margin of stress and of the grid's length, so the same for every CG
        tolerance and every depth |d| of the path.
    pillar_modes : {"quadratic", "tilt", "uniform"}
        Method "pillars" only: the pressure modes of every tip (`brushbem.pillars`).
    pillar_near : float or None
        Method "pillars" only: centres closer than this many pillar radii are
        coupled exactly (None: `brushbem.pillars.basis.NEAR_RADII`).
    pillar_solve : {"auto", "kept", "cg"}
        Method "pillars" only: the pillar-level solve - the kept inverse up to
        a limit of attached pillars and CG on the lattice's FFT beyond
        (``"auto"``), always the kept inverse, or always CG (a lattice only).
    pillar_tip_resolution : float or None
        Method "pillars" only: every tip on a raster of its own with at
        least this many elements per pillar radius, the global grid
        subdivided by the smallest integer that gives it
        (`brushbem.pillars.tips`); None: the global grid's.
    pillar_tip_calibration : bool
        Method "pillars" only: every tip's critical stress scaled so that the
        tip alone on its raster comes off at Kendall's force
        (`brushbem.pillars.calibration`); False: the raster's own Sigma_c.
    pillar_tip_peel : bool or None
        Method "pillars" only: every whole tip leaves, whole, at its
        continuum capacity - its first point raised by its stable peel's
        gain, both from its K(theta) read off its modes
        (`brushbem.pillars.peel`); False: the tips peel on their rasters,
        element by element (the exact path's criterion on the same raster,
        which the thesis's studies use).  Not with
        ``pillar_tip_calibration`` (a whole tip's criterion is its own; tips
        in part contact keep the raster's Sigma_c).  None (the default):
        `brushbem.physics.pillar_model_domain.default_tip_peel` - True for
        the pillar model unless its tips are calibrated, False otherwise;
        `tip_peel` is the value the path takes.
    """

    method: str = "events"
    preload_displacement: float | None = None
    preload_force: float | None = None
    step: float = 1e-4
    max_steps: int = 200000
    tolerance: float = 1e-8
    max_iterations: int = 20000
    window_margin: float = 0.25
    cascade: str = "local"
    speed: float | None = None
    event_window: float = 1e-7
    pillar_modes: str = "quadratic"
    pillar_near: float | None = None
    pillar_solve: str = "auto"
    pillar_tip_resolution: float | None = None
    pillar_tip_calibration: bool = False
    pillar_tip_peel: bool | None = None

    def __post_init__(self):
        if self.method not in ("events", "element_events", "fixed", "pillars"):
            raise ParameterError("LoadPath", "method", f"LoadPath.method = {self.method!r} must be 'events', "
                                 "'element_events', 'fixed' or 'pillars'")
        if self.cascade not in ("local", "global"):
            raise ParameterError("LoadPath", "cascade", f"LoadPath.cascade = {self.cascade!r} must be 'local' or 'global'")
        if (self.preload_displacement is None) == (self.preload_force is None):
            raise ParameterError("LoadPath", "preload_displacement", "exactly one of LoadPath.preload_displacement "
                                 "and LoadPath.preload_force is required")
        for name in ("preload_displacement", "preload_force"):
            value = getattr(self, name)
            if value is not None and not (math.isfinite(value) and value > 0):
                raise ParameterError("LoadPath", name, f"LoadPath.{name} = {value} must be finite and > 0")
        if not (math.isfinite(self.step) and self.step > 0):
            raise ParameterError("LoadPath", "step", f"LoadPath.step = {self.step} must be finite and > 0")
        if not (math.isfinite(self.event_window) and 0 <= self.event_window <= MAX_EVENT_WINDOW):
            raise ParameterError("LoadPath", "event_window", f"LoadPath.event_window = {self.event_window} must be "
                                 f"in [0, {MAX_EVENT_WINDOW:g}] (a fraction of the element size)")
        if self.speed is not None and not (math.isfinite(self.speed) and self.speed > 0):
            raise ParameterError("LoadPath", "speed", f"LoadPath.speed = {self.speed} must be finite and > 0")
        self._check_pillar_options()

    @property
    def tip_peel(self) -> bool:
        """Whether the tips leave at their continuum capacity: ``pillar_tip_peel``, or `default_tip_peel` where it
        is None (so that a path replaced with another method or calibration takes that one's default)."""
        if self.pillar_tip_peel is not None:
            return self.pillar_tip_peel
        return default_tip_peel(self.method, self.pillar_tip_calibration)

    def _check_pillar_options(self) -> None:
        """The pillar model's options: their values, and none but the defaults with another method."""
        if self.pillar_modes not in PILLAR_MODES:
            raise ParameterError("LoadPath", "pillar_modes", f"LoadPath.pillar_modes = {self.pillar_modes!r} must "
                                 f"be one of {', '.join(map(repr, PILLAR_MODES))}")
        if self.pillar_near is not None and not (math.isfinite(self.pillar_near) and self.pillar_near > 0):
            raise ParameterError("LoadPath", "pillar_near", f"LoadPath.pillar_near = {self.pillar_near} must be "
                                 "finite and > 0 (pillar radii)")
        if self.pillar_tip_resolution is not None and not (math.isfinite(self.pillar_tip_resolution)
                                                           and self.pillar_tip_resolution >= 2):
            raise ParameterError("LoadPath", "pillar_tip_resolution", "LoadPath.pillar_tip_resolution = "
                                 f"{self.pillar_tip_resolution} must be finite and >= 2 (elements per pillar radius)")
        if self.pillar_solve not in PILLAR_SOLVES:
            raise ParameterError("LoadPath", "pillar_solve", f"LoadPath.pillar_solve = {self.pillar_solve!r} must "
                                 f"be one of {', '.join(map(repr, PILLAR_SOLVES))}")
        if self.pillar_tip_peel and self.pillar_tip_calibration:
            raise ParameterError("LoadPath", "pillar_tip_calibration", "LoadPath.pillar_tip_calibration = True with "
                                 "pillar_tip_peel = True: the continuum peel carries its own (per-element) "
                                 "calibration; remove pillar_tip_calibration")
        if self.method != "pillars":
            for name, default in (("pillar_modes", "quadratic"), ("pillar_near", None), ("pillar_solve", "auto"),
                                  ("pillar_tip_resolution", None), ("pillar_tip_calibration", False)):
                if getattr(self, name) != default:
                    raise ParameterError("LoadPath", name, f"LoadPath.{name} = {getattr(self, name)!r} applies to "
                                         f"method = 'pillars' only (method = {self.method!r}); remove it")
            if self.tip_peel:  # unset or False: no tips of its own to peel
                raise ParameterError("LoadPath", "pillar_tip_peel", "LoadPath.pillar_tip_peel = True applies to "
                                     f"method = 'pillars' only (method = {self.method!r}); remove it")


@dataclass(frozen=True)
class PressedElements:
    """A state's contact as its elements: the flat indices (row-major) of the contact elements of its N x N grid,
    each once, and their pressures.

    The elements of every pillar come in ascending order (a sum over a pillar's elements adds them in the
    order of the full grid's, to the last bit); ``grids`` gives the (pressure, contact) arrays.  A path that
    knows its contact element by element (the pillar model) records it so: its states' grids are built
    only when read (`State`), not for every state.
    """

    side: int
    elements: np.ndarray
    pressure: np.ndarray

    def grids(self) -> tuple[np.ndarray, np.ndarray]:
        """(pressure, contact) on the N x N grid: the pressures where the elements are, 0 and False elsewhere."""
        n = self.side
        # Zeroed arrays written at the contact elements only: the others stay untouched pages.
        pressure, contact = np.zeros(n * n), np.zeros(n * n, dtype=bool)
        pressure[self.elements] = self.pressure
        contact[self.elements] = True
        return pressure.reshape(n, n), contact.reshape(n, n)


class _Grid:
    """A `State` field holding an N x N array, or None where the state's ``pressed`` (`PressedElements`) holds
    its contact: then the array is built from it when first read, and kept.

    A descriptor as the field's default (a "descriptor-typed field" of `dataclasses`): the constructor, and
    `dataclasses.replace`, write through `__set__`; an omitted field is None.
    """

    def __set_name__(self, owner, name):
        self.slot = "_" + name

    def __get__(self, state, owner=None):
        if state is None:
            return None  # the field's default
        value = state.__dict__[self.slot]
        if value is None and state.pressed is not None:
            state.__dict__["_pressure"], state.__dict__["_contact"] = state.pressed.grids()
            value = state.__dict__[self.slot]
        return value

    def __set__(self, state, value):
        state.__dict__[self.slot] = value


@dataclass(frozen=True)
class State:
    """One recorded equilibrium of the load path.

    Attributes
    ----------
    displacement : float
        Base displacement d.
    force : float
        F = h^2 sum p, compressive positive.
    contact_area : float
        h^2 times the number of contact elements.
    attached_pillars : int
    loading : bool
        True while pressing, False while pulling off.
    kind : str
        "equilibrium" (after any cascade), "event" (a state on the threshold
        of the next event, before elements leave or join) or "separated".
    trial_force : float
        Force of the fixed-set solution at this d before the cascade (equal to
        ``force`` when nothing changed); the path passes through it.
    cg_iterations, n_solves : int
        Spent to reach this state.
    converged : bool
    reason : str
    pressure : ndarray, shape (N, N)
    contact : ndarray of bool, shape (N, N)
    pressed : PressedElements or None
        The contact element by element, where the path records it so (the
        pillar model): ``pressure`` and ``contact`` are then given as None
        and built from it when first read (its full-grid arrays are not
        made for every state of a pull-off).  None: the grids are given.
    """

    displacement: float
    force: float
    contact_area: float
    attached_pillars: int
    loading: bool
    kind: str
    trial_force: float
    cg_iterations: int
    n_solves: int
    converged: bool
    reason: str
    pressure: object = _Grid()
    contact: object = _Grid()
    pressed: PressedElements | None = None


def check_preload(indenter: Indenter, path: LoadPath) -> None:
    """Raise `ParameterError` (of ``LoadPath.preload_displacement``) where the preload does not reach the
    indenter (`Indenter.preload_reaches`)."""
    if path.preload_displacement is not None and not indenter.preload_reaches(path.preload_displacement):
        raise ParameterError(
            "LoadPath", "preload_displacement",
            f"LoadPath.preload_displacement = {path.preload_displacement:g} must be > {indenter.lowest_height:.6g}, "
            "the height of the indenter's lowest element (where it first touches)"
        )
