"""Cost before compute: the expected time of a whole sweep from a few of its cases, and of one run.

``estimate_sweep(sweep, samples=3)`` runs ``samples`` cases of the sweep, one
after the other in this process, spread evenly over its expansion order (the
first and the last case and equally spaced ones between, so that every swept
axis is visited at its ends), and extrapolates: the expected CPU time of the
whole sweep is the number of cases times the mean sampled time, with the
standard error of that mean; the wall time on W workers is that over
min(W, cases) (a worker runs one case at a time, and the cases of one
sweep cost roughly alike except where a swept key changes the grid or the
brush, which the spread of the samples then shows).  Nothing is written.

``estimate_run(config)`` (``brushbem run CONFIG --estimate``) computes the
first states of one run's path for a couple of seconds, which measures the
cost of a state on its grid, and counts the states of the whole path from
the load path (fixed steps: the displacement range over the step; event
paths: the sampled loading extrapolated in d, about one event per pillar on
a brush's pull-off); its peak memory is `brushbem.config.resources.memory_estimate`.
Nothing is written either.
"""

from __future__ import annotations

import math
import statistics
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from brushbem.sweep import Sweep, compute_case

__all__ = ["RunEstimate", "SweepEstimate", "estimate_run", "estimate_sweep", "sample_indices", "too_large_to_sample"]


@dataclass(frozen=True)
class SweepEstimate:
    """The sampled cost of a sweep.

    Attributes
    ----------
    cases : int
        Cases of the whole sweep.
    sampled : tuple of str
        Case ids that were run.
    seconds : tuple of float
        Their wall times (each alone in this process), in seconds.
    statuses : tuple of str
        Their outcomes ("finished", "unconverged", "failed").
    """

    cases: int
    sampled: tuple[str, ...]
    seconds: tuple[float, ...]
    statuses: tuple[str, ...]

    @property
    def mean_seconds(self) -> float:
        return statistics.fmean(self.seconds) if self.seconds else 0.0

    @property
    def cpu_hours(self) -> float:
        """Expected time of the whole sweep on one worker, in hours."""
        return self.cases * self.mean_seconds / 3600.0

    @property
    def cpu_hours_error(self) -> float | None:
        """Standard error of ``cpu_hours`` from the spread of the samples (None for one sample: no spread)."""
        if len(self.seconds) < 2:
            return None
        return self.cases * statistics.stdev(self.seconds) / math.sqrt(len(self.seconds)) / 3600.0

    def wall_hours(self, workers: int) -> float:
        """Expected wall time on ``workers`` workers, in hours."""
        if workers < 1:
            raise ValueError(f"workers = {workers} must be >= 1")
        return self.cpu_hours / min(workers, max(self.cases, 1))


def sample_indices(cases: int, samples: int) -> list[int]:
    """``samples`` distinct case indices spread evenly from the first to the last case."""
    if cases <= 0:
        return []
    samples = max(1, min(samples, cases))
    return sorted({round(x) for x in np.linspace(0, cases - 1, samples)})


def estimate_sweep(
    sweep: Sweep,
    samples: int = 3,
    progress: Callable[[str], None] | None = None,
) -> SweepEstimate:
    """Run ``samples`` cases of ``sweep`` (spread over it) and return the estimate."""
    if samples < 1:
        raise ValueError(f"samples = {samples} must be >= 1")
    chosen = [sweep.cases[i] for i in sample_indices(len(sweep.cases), samples)]
    seconds, statuses = [], []
    for k, case in enumerate(chosen, 1):
        if progress is not None:
            progress(f"sample {k}/{len(chosen)}: case {case.case_id}")
        start = time.perf_counter()
        outcome = compute_case(case.config)
        seconds.append(time.perf_counter() - start)
        statuses.append(outcome.status)
    return SweepEstimate(
        cases=len(sweep.cases),
        sampled=tuple(case.case_id for case in chosen),
        seconds=tuple(seconds),
        statuses=tuple(statuses),
    )


# ---------------------------------------------------------------------- one run

#: Wall time (seconds) that `estimate_run` spends on the first states of the path.
SAMPLE_SECONDS = 2.0


@dataclass(frozen=True)
class RunEstimate:
    """The expected cost of one run (`estimate_run`), with the basis of every number.

    Attributes
    ----------
    elements : int
        N of the N x N grid.
    method : str
        ``protocol.method``.
    states : int
        Recorded states the path is expected to take (both branches).
    sampled_states : int
        States of the path computed for the estimate.
    setup_seconds : float
        Building the problem and the first state of the path (measured).
    seconds_per_state : float
        Mean wall time of the sampled states after the first (measured).
    seconds : float
        Expected wall time of the computation (without writing the files and
        the figure, a few seconds more).
    complete : bool
        The sample ran the whole path: ``seconds`` is measured, not extrapolated.
    basis : tuple of str
        How ``states`` was counted, one line per branch.
    kind : str
        ``"measured"`` (the sample ran the whole path), ``"about"`` (fixed
        steps to a closed-form end), ``"at least"`` (fixed steps where no
        closed form gives the tensile part, or an event path whose states cost more than the sampled
        ones: `_unpriced_cost`) or ``"up to about"`` (event paths:
        a cascade that takes several events at once makes fewer states; a
        brush's pull-off counted from its attached pillars: measured to hold to
        100 x 100 pillars, not at 316 x 316, `ATTACHED_STATES_MEASURED`).
    stops : str or None
        Why the run would stop before separation (a branch needs more steps
        than ``protocol.max_steps``: the run ends there, not converged).
    memory_bytes, result_bytes : int
        Peak memory (`brushbem.config.resources.memory_estimate`) and the
        uncompressed size of ``result.nc``.
    loading_seconds : float or None
        The loading branch as measured, where the sample ran it whole (the
        pillar model's contact problems); ``seconds_per_state`` is then the
        unloading states' mean.
    """

    elements: int
    method: str
    states: int
    sampled_states: int
    setup_seconds: float
    seconds_per_state: float
    seconds: float
    complete: bool
    basis: tuple[str, ...]
    kind: str
    stops: str | None
    memory_bytes: int
    result_bytes: int
    loading_seconds: float | None = None


#: The largest grid (N) and the most pillars whose first states `estimate_run` computes: beyond either, building
#: the brush alone takes tens of seconds (10^6 pillars at N = 8192: a minute to rasterise, before any state),
#: so the estimate gives the run's size and memory from the configuration, and says it cannot give its time.
SAMPLE_MAX_ELEMENTS = 2048
SAMPLE_MAX_PILLARS = 100_000


def configured_pillars(config) -> int:
    """How many pillars the configuration asks for, from its keys alone (1 for a punch, sphere or height map)."""
    spec = config.indenter
    if spec.shape != "brush":
        return 1
    if spec.pillar_count is not None:
        return int(spec.pillar_count)
    per_side = int(spec.pillars_per_side or 1)
    clusters = 1
    if spec.layout == "clustered":  # pillars_per_side sub-pillars per side in every cluster of every level
        for level in spec.levels or ():
            clusters *= max(int(getattr(level, "cluster", 1) or 1), 1) ** 2
    return per_side**2 * clusters


def too_large_to_sample(config) -> str | None:
    """Why ``estimate_run`` would compute something the size of the run (None: it samples in seconds)."""
    elements, pillars = config.grid.elements, configured_pillars(config)
    if elements > SAMPLE_MAX_ELEMENTS:
        return f"grid.elements = {elements} is beyond {SAMPLE_MAX_ELEMENTS}"
    if pillars > SAMPLE_MAX_PILLARS:
        return f"{pillars:,} pillars are beyond {SAMPLE_MAX_PILLARS:,}"
    return None


def _branch_end(problem, path) -> tuple[float, str] | None:
    """The closed-form displacement at which the pull-off ends roughly, and what it is; None without one."""
    from brushbem.runs.case import theory_for

    try:
        closed = theory_for(problem, {}, path)[0]
    except (ValueError, ArithmeticError, AttributeError, KeyError, TypeError):
        return None
    for key, label in (("pull_off_displacement", "the closed-form pull-off displacement"),
                       ("rigid_brush_displacement", "-|d_c| of the rigid brush (eq. 4.12)")):
        value = closed.get(key) if hasattr(closed, "get") else None
        if value is not None and math.isfinite(value):
            return -abs(float(value)), label
    return None


def _pillar_groups(problem, pillars: np.ndarray | None = None) -> int:
    """Pillars that detach together on a symmetric brush: alike in distance from the centre, offset and footprint.

    ``pillars``: count only these (a boolean mask or indices; None: all).  Every pillar its own group where the
    structure does not say (a brush without its geometry record).
    """
    chosen = np.arange(problem.indenter.n_pillars) if pillars is None else np.asarray(pillars)
    if chosen.dtype == bool:
        chosen = np.flatnonzero(chosen)
    info = problem.indenter.description
    try:
        centres = np.asarray(info.centres, dtype=float)
        offsets = np.asarray(info.offsets, dtype=float)
        elements = np.asarray(info.pillar_elements, dtype=float)
    except AttributeError:
        return int(chosen.size)
    if chosen.size == 0:
        return 0
    middle = centres.mean(axis=0)
    distance = np.hypot(*(centres - middle).T)
    h = problem.grid.element_size
    keys = np.column_stack([np.round(distance / (1e-6 * h)), np.round(offsets / (1e-9 * h)), elements])
    return int(len(np.unique(keys[chosen], axis=0)))


def _attached_pillars(problem, state) -> np.ndarray:
    """The pillars with contact in ``state`` (boolean, one per pillar), from its contact elements."""
    from brushbem.backend import to_numpy

    labels = np.asarray(to_numpy(problem.indenter.pillar)).ravel()
    if state.pressed is not None:
        contact = np.asarray(state.pressed.elements)
    else:
        contact = np.flatnonzero(np.asarray(to_numpy(state.contact)).ravel())
    owners = labels[contact]
    owners = owners[owners >= 0]
    return np.bincount(owners, minlength=problem.indenter.n_pillars)[:problem.indenter.n_pillars] > 0


def _steps(length: float, step: float) -> float:
    """Fixed steps of ``step`` over ``length`` (a float: it may exceed any integer of interest)."""
    return max(math.ceil(length / step - 1e-9), 1) if length > 0 else 1


def estimate_run(config, *, sample_seconds: float = SAMPLE_SECONDS) -> RunEstimate:
    """The expected wall time and peak memory of ``brushbem run`` for ``config``, without running it.

    The first states of the real path are computed for about
    ``sample_seconds`` (at least one; never written), which measures the cost
    of a state at this grid; the number of states is counted from the load
    path:

    * ``method = "fixed"``: the loading takes preload / step steps (a brush
      pressed as contact problems: its few samples), the unloading
      (preload - d_end) / step, d_end the closed-form pull-off displacement
      of a punch or a sphere, -|d_c| of a brush, or 0 where no closed form
      applies; each branch at most ``protocol.max_steps`` (where it needs
      more, the run stops there, not converged, which ``stops`` says);
    * the event methods: the loading's events as sampled, extrapolated
      linearly in d where the sample did not reach the preload; on a
      brush's pull-off two states (the threshold and the equilibrium after
      it) per detachment of a group of alike pillars (`_pillar_groups`; a
      cascade that takes several groups at once makes fewer), counting only
      the pillars attached at the end of the loading where the sample reached
      it (the pillar model's: a rough brush's short tips never touch;
      `ATTACHED_STATES_MEASURED`), on a single
      body at most as many events as the loading (the contact shrinks
      through the element rings it grew through, many at once in a
      cascade): an upper count.

    Where the sample finishes the whole path, the time is the measured one.
    """
    from brushbem.runs.assembly import Assembly, assemble
    from brushbem.config.resources import memory_estimate, result_size_estimate

    start = time.perf_counter()
    built = config if isinstance(config, Assembly) else assemble(config)
    config, problem, path = built.config, built.problem, built.path
    sampled, times, setup, complete = _sample_path(problem, path, start, sample_seconds,
                                                   through_loading=path.method == "pillars")
    unloading_times = [t for t, state in zip(times, sampled[1:]) if not state.loading]
    common = {"elements": config.grid.elements, "method": path.method, "sampled_states": len(sampled),
              "setup_seconds": setup,
              "seconds_per_state": statistics.fmean(unloading_times or times) if times else setup,
              "memory_bytes": memory_estimate(config), "result_bytes": result_size_estimate(config)}
    if complete:
        last = sampled[-1] if sampled else None
        stops = None if last is None or last.converged else last.reason
        return RunEstimate(states=len(sampled), seconds=setup + sum(times), complete=True, kind="measured",
                           basis=(f"the sample ran the whole path ({len(sampled)} states)",), stops=stops, **common)
    count = _fixed_states if path.method == "fixed" else _event_states
    n_loading, n_unloading, basis, kind = count(problem, path, sampled)
    unpriced = _unpriced_cost(problem, path, sampled)
    if unpriced is not None:
        kind = "at least"
        basis = [*basis, unpriced]
    stops = None
    if max(n_loading, n_unloading) > path.max_steps:
        branch = "loading" if n_loading > path.max_steps else "unloading"
        stops = (f"the {branch} branch needs about {max(n_loading, n_unloading):.3g} "
                 f"{'steps' if path.method == 'fixed' else 'states'}, more than protocol.max_steps = "
                 f"{path.max_steps}: the run stops there, not converged"
                 + (' (raise protocol.step, or use method = "events")' if path.method == "fixed" else ""))
    total = max(min(n_loading, path.max_steps) + min(n_unloading, path.max_steps), float(len(sampled)))
    seconds = setup + (total - 1) * common["seconds_per_state"]
    loading_seconds = None
    if unloading_times:
        # The loading was sampled whole: its measured time, and the unloading's states at their own cost.
        loading_seconds = setup + sum(t for t, state in zip(times, sampled[1:]) if state.loading)
        seconds = loading_seconds + min(n_unloading, path.max_steps) * common["seconds_per_state"]
    return RunEstimate(states=int(round(total)), seconds=seconds, complete=False, basis=tuple(basis), kind=kind,
                       stops=stops, loading_seconds=loading_seconds, **common)


#: What two states per attached group is worth, measured (pull-off states per pillar attached at the end of the
#: loading, k~ = 0.01, pillar model): sigma~ = 0.5 rough brushes 1.42 (32 per side), 1.55 (48), 1.75 (64), 2.07
#: (100), 3.6 (316); the size study's sigma~ = 0.1 brush 0.19 (48: 356 states, 1876 attached) and 0.22 (100:
#: 1052 states, 4818 attached), where the last state takes most pillars at once (3335 of 4818 at 100).  An upper
#: count to 100 per side (2.07 against 2), no factor: the one larger brush measured takes 1.8 x more.
ATTACHED_STATES_MEASURED = ("an upper count as measured to 100 x 100 pillars (0.19 to 2.07 states per attached "
                            "pillar on rough brushes: 10 x fewer at sigma~ = 0.1, where the last state detaches most "
                            "pillars at once), but 3.6 at 316 x 316 (sigma~ = 0.5): 1.8 x more states there")


#: Pillar radius in elements from which a brush's detachments are priced by no sampled state: each cascade
#: peels a tip ring by ring (of the order of its radius in solves, each of its size), where the sample's
#: states are single solves.  Measured: 2 x 2 pillars of 32 elements' radius took 19 s where the states
#: priced it at 2.3 s (the default example's 3.1 elements: 10.6 s against 13 s).
RING_PEELING_ELEMENTS = 8.0


def _unpriced_cost(problem, path, sampled: list) -> str | None:
    """Why the sampled states under-price the rest of an event path (the estimate is then a lower bound)."""
    if path.method == "fixed":
        return None
    info = problem.indenter.description
    h = problem.grid.element_size
    radius = getattr(info, "pillar_radius", None)
    if problem.indenter.n_pillars >= 2 and radius is not None and radius / h >= RING_PEELING_ELEMENTS:
        return (f"each detachment's cascade peels a tip of {radius / h:.3g} elements' radius ring by ring, which "
                "no sampled state prices: the run can take several times longer (not known before it runs)")
    unloading = [state for state in sampled if not state.loading]
    if problem.indenter.n_pillars < 2 and not unloading:
        return ("the sampled states are the loading's first, at a small contact; a state costs more as the "
                "contact grows (a sphere on a spring: 5 x by the preload): the run can take longer (not known "
                "before it runs)")
    return None


def _sample_path(problem, path, start: float, sample_seconds: float,
                 through_loading: bool = False) -> tuple[list, list[float], float, bool]:
    """The first states of the path, computed for about ``sample_seconds`` since ``start`` (at least one).

    ``through_loading``: and at least to the first unloading state, then ``sample_seconds`` more (the
    pillar model presses in a few contact problems whose cost is not that of an unloading state).

    Returns the states, the wall time of each after the first, the time from
    ``start`` to the first (building the problem and the path's set-up
    included), and whether the path ended within the sample.
    """
    from brushbem.protocol import pull_off

    states = pull_off(problem, path)
    sampled: list = []
    times: list[float] = []
    setup = 0.0
    try:
        while True:
            begin = time.perf_counter()
            try:
                state = next(states)
            except StopIteration:
                return sampled, times, setup, True
            now = time.perf_counter()
            if sampled:
                times.append(now - begin)
            else:
                setup = now - start
            sampled.append(state)
            if not state.converged or state.kind == "separated":
                return sampled, times, setup, True
            if through_loading and state.loading:
                continue
            if through_loading and sum(not s.loading for s in sampled) == 1:
                start = now
            if now - start >= sample_seconds:
                return sampled, times, setup, False
    finally:
        states.close()


def _preload(path, loading: list, unloading: list) -> tuple[float, str]:
    """The preload displacement (sampled, given, or where the force target is reached) and how it is known."""
    if unloading and loading:
        return loading[-1].displacement, f"the preload d = {loading[-1].displacement:.4g}"
    if path.preload_displacement is not None:
        return path.preload_displacement, f"the preload d = {path.preload_displacement:.4g}"
    # A force target: F taken proportional to d from the first touch (F grows faster where the contact grows,
    # so the preload comes sooner: an upper count).
    touched = [state for state in loading if state.force > 0]
    if touched and touched[-1].displacement > 0:
        preload = touched[-1].displacement * max(path.preload_force / touched[-1].force, 1.0)
    else:
        preload = max((state.displacement for state in loading), default=0.0) or path.step
    return preload, f"the preload force, reached near d = {preload:.4g} (F taken proportional to d)"


def _contact_loading(loading: list) -> bool:
    """Whether the sampled loading is a brush's contact problems (a few states, not steps or events)."""
    return bool(loading) and loading[0].reason.startswith("contact problem")


def _counted_loading(loading: list, unloading: list) -> float | None:
    """The loading's states where the sample counted them (it reached the unloading, or solved a brush's
    contact problems, one more to come), else None."""
    if unloading:
        return float(len(loading))
    return float(len(loading) + 1) if _contact_loading(loading) else None


def _fixed_states(problem, path, sampled: list) -> tuple[float, float, list[str], str]:
    """States of a fixed-step path on each branch (floats: they may exceed any integer of interest), the basis,
    and the kind of the count (`RunEstimate.kind`)."""
    loading = [state for state in sampled if state.loading]
    unloading = [state for state in sampled if not state.loading]
    preload, preload_text = _preload(path, loading, unloading)
    basis = []
    counted = _counted_loading(loading, unloading)
    if counted is not None:
        n_loading = counted
        basis.append(f"loading: {int(n_loading)} states ({'sampled' if unloading else 'contact problems'})")
    else:
        n_loading = float(_steps(preload, path.step))
        basis.append(f"loading: {n_loading:.3g} fixed steps of {path.step:g} to {preload_text}")
    end = _branch_end(problem, path)
    end_d, end_text = end if end is not None else (0.0, "d = 0 (no closed form for the tensile part: at least)")
    n_unloading = float(_steps(preload - end_d, path.step))
    basis.append(f"unloading: {n_unloading:.3g} fixed steps of {path.step:g} from the preload to {end_text}")
    return n_loading, n_unloading, basis, "about" if end is not None else "at least"


def _event_states(problem, path, sampled: list) -> tuple[float, float, list[str], str]:
    """States of an event path on each branch, the basis, and the kind of the count (`RunEstimate.kind`)."""
    loading = [state for state in sampled if state.loading]
    unloading = [state for state in sampled if not state.loading]
    preload, preload_text = _preload(path, loading, unloading)
    basis = []
    counted = _counted_loading(loading, unloading)
    if counted is not None:
        n_loading = counted
        basis.append(f"loading: {int(n_loading)} states ({'sampled' if unloading else 'contact problems'})")
    else:
        first, last = loading[0].displacement, loading[-1].displacement
        covered = (last - first) / (preload - first) if preload > first and last > first else 0.0
        n_loading = len(loading) / covered if covered > 0 else float(len(loading) + 1)
        basis.append(f"loading: {n_loading:.3g} events ({len(loading)} sampled over {covered:.1%} of the way "
                     f"to {preload_text}, extrapolated linearly in d)")
    pillars = problem.indenter.n_pillars
    if pillars >= 2 and unloading and loading:
        # Only the pillars attached at the end of the loading ever detach (a rough brush's short tips never touch).
        attached = _attached_pillars(problem, loading[-1])
        groups = _pillar_groups(problem, attached)
        n_unloading = float(max(2 * groups + 1, len(unloading)))
        basis.append(f"unloading: two states (threshold, equilibrium) per group of alike pillars among the "
                     f"{int(attached.sum())} of {pillars} attached at the end of the loading ({groups} groups: equal "
                     f"distance from the centre, length and footprint); {ATTACHED_STATES_MEASURED}")
    elif pillars >= 2:
        groups = _pillar_groups(problem)
        n_unloading = float(max(2 * groups + 1, len(unloading)))
        basis.append(f"unloading: two states (threshold, equilibrium) per detachment event, one event per group "
                     f"of alike pillars ({groups} groups of the {pillars} pillars: equal distance from the "
                     "centre, length and footprint); a cascade that takes several groups at once makes fewer")
    else:
        n_unloading = float(max(n_loading, len(unloading)))
        basis.append("unloading: at most as many events as the loading (the contact shrinks through the "
                     "element rings it grew through; a cascade takes many at once, so usually far fewer)")
    return n_loading, n_unloading, basis, "up to about"
