"""Recording a pull-off: the curve, the snapshots at the marked moments, the summary numbers."""

from __future__ import annotations

import dataclasses
import itertools
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from brushbem.results import Curve, PullOffSummary, Snapshot
from brushbem.protocol.paths import pull_off
from brushbem.protocol.problem import ContactProblem, LoadPath, State

__all__ = ["PullOffRecord", "record_pull_off", "work_of_separation"]


@dataclass(frozen=True)
class PullOffRecord:
    """The curve, the snapshots and the summary numbers of one pull-off."""

    curve: Curve
    snapshots: tuple[Snapshot, ...]
    summary: PullOffSummary
    pillars: dict = field(default_factory=dict)


def record_pull_off(
    problem: ContactProblem,
    path: LoadPath,
    progress: Callable[[float, str], None] | None = None,
    stop: Callable[[], bool] | None = None,
) -> PullOffRecord:
    """Run ``pull_off`` and collect the curve, snapshots and summary.

    Summary fields: adhesive_force (-min F on the pull-off, >= 0),
    pull_off_displacement, separation_displacement (last d with contact),
    work_of_separation (work against the tensile force from the zero-force
    crossing of the unloading branch to separation, along the path, cascades
    vertical), preload_force, max_displacement, converged, reason,
    interrupted, n_solves, n_cg_iterations, n_states, wall_time_s.

    ``stop`` is polled after every state: when it returns True the path
    ends there, and the record holds what was computed, with
    ``interrupted = True`` and ``converged = False`` (a partial pull-off is
    not a result).  A summary number that comes out non-finite (an overflow
    of extreme inputs) makes the run not converged, with the reason.
    """
    start = time.perf_counter()
    recorder = _Recorder(problem)
    last = None
    for state in pull_off(problem, path, stop=stop):
        if not recorder.add(state):
            break
        last = state
        if progress is not None:
            progress(_progress_fraction(state, path, recorder.max_area),
                     f"d = {state.displacement:.4g}, F = {state.force:.4g}")
        if not state.converged:
            break
        if stop is not None and stop():
            recorder.interrupt(state)
            break
    else:
        # The pillar model ends its path inside a step when asked to stop: interrupted, not "ended early".
        if stop is not None and last is not None and last.kind != "separated" and stop():
            recorder.interrupt(last)
    return recorder.finish(path, time.perf_counter() - start)


def _progress_fraction(state: State, path: LoadPath, max_area: float) -> float:
    """How far the pull-off has come: 30 % for the loading, 70 % for the contact area lost since."""
    if state.loading:
        target = path.preload_displacement
        fraction = 0.3 * (state.displacement / target if target else min(state.force / path.preload_force, 1))
    else:
        fraction = 0.3 + 0.7 * (1.0 - state.contact_area / max_area if max_area else 1.0)
    return min(max(fraction, 0.0), 1.0)


class _Recorder:
    """What `record_pull_off` keeps of the states of one pull-off, as they come."""

    def __init__(self, problem: ContactProblem):
        from brushbem.backend import to_numpy

        self.to_numpy = to_numpy
        self.labels = np.asarray(to_numpy(problem.indenter.pillar)).ravel()
        self.n_pillars = problem.indenter.n_pillars
        self.h2 = problem.grid.element_size**2
        self.last_attached_d = np.full(self.n_pillars, np.nan)
        self.max_tension = np.zeros(self.n_pillars)
        self.max_tension_d = np.full(self.n_pillars, np.nan)
        self.attached_at_preload = 0
        # The states without their arrays: keeping every State would keep two
        # full-grid arrays per state alive (1.4 GB for the N = 256 JKR benchmark,
        # and a page fault for every fresh page of every new array), or its elements.
        self.rows: list[State] = []
        self.path_points: list[tuple[float, float, bool]] = []  # (d, F, loading), cascades included
        self.snapshots: dict[str, Snapshot] = {}
        #: Stages (snapshot names) that the path does not pass through, with the reason.
        self.not_reached: dict[str, str] = {}
        self.last_contact_state: State | None = None
        self.last_loading_state: State | None = None
        self.best: State | None = None
        self.converged = True
        self.reason = "complete separation"
        self.n_solves = self.n_iterations = 0
        self.max_area = 0.0
        self.separated = False
        self.interrupted = False

    def pillar_forces(self, state: State) -> tuple[np.ndarray, np.ndarray]:
        if state.pressed is not None:  # its elements, each pillar's in the grid's order: the same sums
            contact, pressure = state.pressed.elements, state.pressed.pressure
        else:
            contact = np.flatnonzero(np.asarray(self.to_numpy(state.contact)).ravel())
            pressure = np.asarray(self.to_numpy(state.pressure)).ravel()[contact]
        force = self.h2 * np.bincount(self.labels[contact], weights=pressure, minlength=self.n_pillars)
        attached = np.bincount(self.labels[contact], minlength=self.n_pillars) > 0
        return force, attached

    def _take(self, name: str, state: State) -> None:
        self.snapshots[name] = _snapshot(name, state, self.to_numpy, self.pillar_forces)

    def add(self, state: State) -> bool:
        """Keep what is needed of ``state``; False when the path ended with it (separation)."""
        self.n_solves += state.n_solves
        self.n_iterations += state.cg_iterations
        if not state.converged:
            self.converged = False
            self.reason = state.reason
        if state.kind == "separated":
            self.separated = True
            self.path_points.append((state.displacement, state.trial_force, False))
            self.path_points.append((state.displacement, 0.0, False))
            self.rows.append(dataclasses.replace(state, pressure=None, contact=None, pressed=None))
            return False
        if state.trial_force != state.force:
            self.path_points.append((state.displacement, state.trial_force, state.loading))
        self.path_points.append((state.displacement, state.force, state.loading))
        self.rows.append(dataclasses.replace(state, pressure=None, contact=None, pressed=None))
        if state.loading:
            self.last_loading_state = state
            self.attached_at_preload = state.attached_pillars
        elif state.contact_area > 0:
            previous = self.last_contact_state or self.last_loading_state
            self.last_contact_state = state
            forces, attached = self.pillar_forces(state)
            self.last_attached_d[attached] = state.displacement
            larger = -forces > self.max_tension
            self.max_tension[larger] = -forces[larger]
            self.max_tension_d[larger] = state.displacement
            if self.best is None or state.force < self.best.force:
                self.best = state
            if "zero_force" not in self.snapshots and "zero_force" not in self.not_reached and state.force <= 0:
                self._zero_force(previous, state)
            if ("half_detached" not in self.snapshots and self.n_pillars > 1
                    and 2 * state.attached_pillars <= self.attached_at_preload):
                self._take("half_detached", state)
        self.max_area = max(self.max_area, state.contact_area)
        return True

    def _zero_force(self, previous: State | None, state: State) -> None:
        """The zero-force stage: interpolated where F crosses 0 on one contact set, else not reached.

        Between two states with the same contact set the pressure is affine
        in d, so the state at F = 0 is their exact interpolation.  Where the
        force jumps across 0 in a detachment cascade (at one d), no
        equilibrium has zero force: the stage is recorded as not reached.
        """
        if state.force == 0.0:
            self._take("zero_force", state)
            return
        if previous is None or not previous.force > 0:
            self.not_reached["zero_force"] = "the unloading starts in tension: no state at zero force"
            return
        same_set = previous.displacement != state.displacement and bool(np.array_equal(
            np.asarray(self.to_numpy(previous.contact)), np.asarray(self.to_numpy(state.contact))))
        if not same_set:
            self.not_reached["zero_force"] = (
                f"the force jumps from {previous.force:.6g} to {state.force:.6g} at d = {state.displacement:.6g} "
                "(the contact set changes there): no equilibrium at zero force")
            return
        t = previous.force / (previous.force - state.force)
        pressure = previous.pressure + t * (state.pressure - previous.pressure)
        zero = dataclasses.replace(
            state, displacement=previous.displacement + t * (state.displacement - previous.displacement),
            force=float(self.h2 * np.sum(np.asarray(self.to_numpy(pressure)))), pressure=pressure,
            contact=state.contact, pressed=None, kind="event",
            reason="zero-force crossing, interpolated on a fixed contact set")
        self._take("zero_force", zero)

    def interrupt(self, state: State) -> None:
        self.interrupted = True
        self.converged = False
        self.reason = f"interrupted at d = {state.displacement:.6g} after {len(self.rows)} states"

    def finish(self, path: LoadPath, wall_time: float) -> PullOffRecord:
        """The record of the states seen: snapshots, curve, summary, per-pillar numbers."""
        if not self.separated and self.converged:
            self.converged = False
            self.reason = "the path ended before complete separation"
        loading = self.last_loading_state
        if self.last_contact_state is None and loading is not None and loading.contact_area > 0:
            # The first unloading step already separated: the unloading branch
            # starts at the preload, which is its last state with contact and the
            # least compressive one.
            self.last_contact_state = self.best = loading
            _, attached = self.pillar_forces(loading)
            self.last_attached_d[attached] = loading.displacement
        for name, state in (("max_preload", loading), ("adhesive_force", self.best),
                            ("before_separation", self.last_contact_state)):
            if state is not None:
                self._take(name, state)
        order = ("max_preload", "zero_force", "adhesive_force", "half_detached", "before_separation")
        snapshots = tuple(self.snapshots[name] for name in order if name in self.snapshots)
        if self.n_pillars > 1 and "half_detached" not in self.snapshots and self.separated:
            last = self.last_contact_state
            attached = last.attached_pillars if last is not None else 0
            self.not_reached["half_detached"] = (
                f"the attached pillars go from {attached} (of {self.attached_at_preload} at the preload) to 0 in one "
                "detachment cascade: no state with half of them attached")
        pillars = {"separation_displacement": self.last_attached_d, "max_tension": self.max_tension,
                   "max_tension_displacement": self.max_tension_d}
        return PullOffRecord(curve=_curve(self.rows), snapshots=snapshots,
                             summary=self._summary(path, wall_time), pillars=pillars)

    def _summary(self, path: LoadPath, wall_time: float) -> PullOffSummary:
        rows, best, last = self.rows, self.best, self.last_contact_state
        loading_states = [s for s in rows if s.loading]
        # The unloading path starts at the end of the loading branch.
        start_point = [(loading_states[-1].displacement, loading_states[-1].force)] if loading_states else []
        if path.method == "fixed":
            unloading = start_point + _fixed_unloading_path([s for s in rows if not s.loading])
        else:
            unloading = start_point + [(d, f) for d, f, load in self.path_points if not load]
        adhesive = max(0.0, -best.force) if best is not None else 0.0
        # A trial force beyond the largest tension of an equilibrium is a fixed step's overshoot past the
        # criterion (or a pillar law's break): the work counts no tension the pull-off never held, so
        # that F_A > 0 exactly when W > 0.
        unloading = [(d, max(f, -adhesive)) for d, f in unloading]
        summary = {
            "adhesive_force": adhesive,
            "pull_off_displacement": best.displacement if best is not None else None,
            "separation_displacement": last.displacement if last is not None else None,
            "work_of_separation": work_of_separation(unloading),
            "preload_force": loading_states[-1].force if loading_states else 0.0,
            "max_displacement": loading_states[-1].displacement if loading_states else 0.0,
            "converged": bool(self.converged),
            "reason": self.reason,
            "interrupted": self.interrupted,
            "n_solves": int(self.n_solves),
            "n_cg_iterations": int(self.n_iterations),
            "mean_cg_iterations_per_solve": self.n_iterations / self.n_solves if self.n_solves else 0.0,
            "attached_pillars_at_pull_off": best.attached_pillars if best is not None else 0,
            "n_states": len(rows),
            "wall_time_s": wall_time,
            "stages_not_reached": dict(self.not_reached) or None,
        }
        overflowed = [key for key in _FINITE_SUMMARY if summary[key] is not None and not math.isfinite(summary[key])]
        if overflowed and summary["converged"]:
            summary["converged"] = False
            summary["reason"] = (
                f"non-finite {', '.join(overflowed)}: the inputs' scales overflow double precision "
                "(e.g. work_of_adhesion or the preload far from contact_modulus x Grid.size)"
            )
        return PullOffSummary(**summary)


def _curve(rows: list[State]) -> Curve:
    """The curve of the recorded states (a separation's force is 0)."""
    return Curve(
        displacement=np.array([s.displacement for s in rows]),
        force=np.array([s.force if s.kind != "separated" else 0.0 for s in rows]),
        contact_area=np.array([s.contact_area for s in rows]),
        cg_iterations=np.array([s.cg_iterations for s in rows], dtype=np.int64),
        converged=np.array([s.converged for s in rows], dtype=bool),
        loading=np.array([s.loading for s in rows], dtype=bool),
        attached_pillars=np.array([s.attached_pillars for s in rows], dtype=np.int64),
    )


#: Summary numbers that a converged run reports finite.
_FINITE_SUMMARY = ("adhesive_force", "pull_off_displacement", "separation_displacement", "work_of_separation",
                   "preload_force", "max_displacement")


def _snapshot(name: str, state: State, to_numpy, pillar_forces) -> Snapshot:
    return Snapshot(
        name=name,
        displacement=state.displacement,
        force=state.force,
        pressure=np.array(to_numpy(state.pressure)),
        contact=np.array(to_numpy(state.contact)),
        pillar_force=pillar_forces(state)[0],
    )


def _fixed_unloading_path(rows: list[State]) -> list[tuple[float, float]]:
    """The unloading path (d, F) of fixed steps, cascades placed where they start.

    A step whose first detachment was located (a ``kind == "event"`` state
    from `_first_crossing`) follows its contact set's line exactly to that
    point; the cascade is then taken there, as the event path does, down to
    the line of the contact set the step ended with, which passes through the
    step's equilibrium with the slope of the next step's first solve (the
    same contact set: exact where nothing else happened in the step).  A
    step that ends in separation drops to zero at its crossing.  Elsewhere
    the path goes through every state, cascades vertical at the step's end.
    """
    points: list[tuple[float, float]] = []
    crossing: State | None = None
    for i, state in enumerate(rows):
        if state.kind == "event":
            crossing = state
            points.append((state.displacement, state.force))
            continue
        force = 0.0 if state.kind == "separated" else state.force
        if crossing is not None:
            after = force
            following = rows[i + 1] if i + 1 < len(rows) else None
            if state.kind != "separated" and following is not None and following.displacement != state.displacement:
                # The next step's first solve is on this step's contact set.
                reached = following.force if following.kind == "event" else following.trial_force
                slope = (reached - force) / (following.displacement - state.displacement)
                after = force + slope * (crossing.displacement - state.displacement)
            points.append((crossing.displacement, after))
            crossing = None
        elif state.trial_force != force:
            points.append((state.displacement, state.trial_force))
        points.append((state.displacement, force))
    return points


def work_of_separation(points: list[tuple[float, float]]) -> float:
    """Work against the tensile force along an unloading path (d decreasing).

    ``points`` is the path (d, F) in order, cascades as vertical segments; each
    segment is linear (exact for the event-driven path).  The work is the area
    of the tensile part of the curve, -F dd where F < 0: it starts at the
    first zero crossing of F and ends at separation.  Where F turns
    compressive again on the way (a cascade that leaves compressed contacts
    behind, as on a rough brush), that stretch is pushed by the half-space,
    not pulled against its adhesion, and adds nothing - so the work is never
    negative.
    """
    work = 0.0
    for (d0, f0), (d1, f1) in itertools.pairwise(points):
        run = d0 - d1  # >= 0 along the unloading
        if run == 0.0 or (f0 >= 0.0 and f1 >= 0.0):
            continue
        if f0 <= 0.0 and f1 <= 0.0:
            work += 0.5 * (-f0 - f1) * run
        else:  # F changes sign inside the segment: the tensile triangle
            tension = -min(f0, f1)
            work += 0.5 * tension * run * tension / (abs(f0) + abs(f1))
    return float(work)
