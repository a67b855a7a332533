"""The pillar model's events (``LoadPath.method = "pillars"``): from the first touch to separation.

The model and its state are described in `brushbem.pillars`.
"""

from __future__ import annotations

import math
from collections.abc import Iterator

import numpy as np

from brushbem.pillars.loading import press_rough
from brushbem.pillars.state import (PillarState, RasterCache, amplitudes, attached_together, cascade,
                                    element_penetration, force, force_rate, installed, on, peel_all, pressures,
                                    pressures_at, record, solved, tip_strengths, touch_candidates)
from brushbem.protocol.problem import LoadPath, State, detachment_slack, event_tie

__all__ = ["events"]


def events(cache: RasterCache, state: PillarState, path: LoadPath) -> Iterator[tuple[PillarState, State]]:
    """The states of the pull-off from ``state`` (nothing attached), from its first touch to separation: each as
    the path's value and its record.

    Everything is affine in d on a fixed state, so the next event - an
    element of an attached tip reaching the criterion, a free tip touching,
    the preload - is found in closed form, the state at it is yielded, and
    the cascade at that d (`brushbem.pillars.state.cascade`) gives the next equilibrium.
    Tips of unequal lengths are first pressed as the exact path presses
    them (`brushbem.pillars.loading.press_rough`).
    """
    model = cache.model
    lowest = float(model.g.min())
    d = lowest
    state = solved(cache, attached_together(cache, state, np.flatnonzero(
        model.g <= lowest + 1e-12 * max(abs(lowest), 1.0))))
    loading = True
    yield state, record(cache, state, d, True, "equilibrium", "first touch")
    if path.preload_displacement is not None and d >= path.preload_displacement:
        loading = False
    if float(np.ptp(model.g)) > 1e-12 * max(abs(lowest), 1.0):
        state, d = yield from press_rough(cache, state, path, lowest)
        loading = False
    steps = 0
    while True:
        steps += 1
        if steps > path.max_steps:
            yield state, record(cache, state, d, loading, "equilibrium", f"LoadPath.max_steps = {path.max_steps} "
                                "reached before the end of the branch", converged=False)
            return
        direction = 1.0 if loading else -1.0
        attached = on(state)
        t_detach, slack = _detachment_times(cache, state, path, d, direction)
        t_det = float(t_detach.min(initial=math.inf))
        t_target = _preload_distance(cache, state, path, d) if loading else math.inf
        rows, t_touch = _touch_times(cache, state, path, d, direction, min(t_det, t_target))
        t_attach = t_touch.min(axis=1) if rows.size else np.zeros(0)
        t_att = float(t_attach.min(initial=math.inf))
        t = min(t_det, t_att, t_target)
        if not math.isfinite(t):
            yield state, record(cache, state, d, loading, "equilibrium", "no event ahead on this branch (no pillar "
                                "touches or detaches)", converged=False)
            return
        t = max(t, 0.0)
        tie = event_tie(path, math.sqrt(model.h2))
        new_d = d + direction * t
        if loading and t_target <= t + tie and t_target + tie < min(t_det, t_att):
            d = new_d
            yield state, record(cache, state, d, True, "equilibrium", "preload reached")
            loading = False
            steps = 0
            continue
        x = amplitudes(state, new_d)
        yield state, record(cache, state, new_d, loading, "event", "event")
        d = new_d
        detaching = t_detach <= t + np.maximum(tie, slack)
        leaving = np.flatnonzero(detaching.any(axis=1)) if t_det <= t + tie else np.array([], int)
        state = peel_all(cache, state, [(int(attached[i]), detaching[i]) for i in leaving], x, d)
        if t_att <= t + tie:
            touching = t_attach <= t + tie
            masks = np.zeros(model.full.shape, dtype=bool)
            masks[rows] = t_touch <= t + tie
            state = installed(cache, state, masks, rows[touching])
        state = cascade(cache, state, d, loading)
        if not state.attached.any() and not loading:
            yield state, record(cache, state, d, False, "separated", "complete separation")
            return
        yield state, record(cache, state, d, loading, "equilibrium", "cascade")
        if loading and (force(cache, state, d) >= path.preload_force * (1 - 1e-9) if path.preload_force is not None
                        else d >= path.preload_displacement * (1 - 1e-12)):
            loading = False
            steps = 0


def _detachment_times(cache: RasterCache, state: PillarState, path: LoadPath, d: float,
                      direction: float) -> tuple[np.ndarray, np.ndarray]:
    """How far the base moves before each slot of each attached pillar (`brushbem.pillars.state.on`) reaches the
    criterion:
    (n, width), inf where its tension does not grow; and how much further each stays within the event
    window (`brushbem.protocol.problem.detachment_slack`)."""
    model = cache.model
    p = pressures_at(cache, state, d)
    rate = direction * pressures(cache, state, state.alpha)
    rows = on(state)
    grows = np.take(state.raster, rows, axis=0) & (rate < 0)
    critical = model.critical[rows]
    t_detach = np.where(grows, (p + critical) / np.where(grows, -rate, 1.0), np.inf)
    slack = detachment_slack(path, critical, grows, rate)
    if model.continuum_peel:
        _whole_tip_times(cache, state, d, direction, rows, t_detach, slack, path)
    return np.maximum(t_detach, 0.0), slack


def _whole_tip_times(cache: RasterCache, state: PillarState, d: float, direction: float, rows: np.ndarray,
                     t_detach: np.ndarray, slack: np.ndarray, path: LoadPath) -> None:
    """Where whole tips leave at their continuum capacity: their rows of ``t_detach`` and ``slack`` (in place)
    from their force against their strength (`brushbem.pillars.state.tip_strengths`), in their first slot.
    A strength moves with d: it is read again at the first detachment found."""
    model = cache.model
    force = model.h2 * model.force[rows] * (d * state.alpha[rows, 0] - state.beta[rows, 0])
    rate = direction * model.h2 * model.force[rows] * state.alpha[rows, 0]
    pulled = rate < 0
    t_event = d
    for _ in range(2):
        strength = tip_strengths(cache, state, t_event)[rows]
        tip = np.isfinite(strength)
        if not tip.any():
            return
        t_tip = np.where(tip & pulled, (force + strength) / np.where(pulled, -rate, 1.0), np.inf)
        t_detach[tip] = np.inf
        t_detach[tip, 0] = t_tip[tip]
        first = float(t_detach.min(initial=math.inf))
        if not math.isfinite(first):
            break
        t_event = d + direction * max(first, 0.0)
    slack[tip] = 0.0
    slack[tip, 0] = np.where(pulled[tip], path.event_window * strength[tip] / np.where(pulled[tip], -rate[tip], 1.0),
                             0.0)


def _preload_distance(cache: RasterCache, state: PillarState, path: LoadPath, d: float) -> float:
    """How far the base presses on before the preload (a displacement, or a force on the fixed state)."""
    if path.preload_displacement is not None:
        return path.preload_displacement - d
    rate = force_rate(cache, state)
    return (path.preload_force - force(cache, state, d)) / rate if rate > 0 else math.inf


def _touch_times(cache: RasterCache, state: PillarState, path: LoadPath, d: float, direction: float,
                 window: float) -> tuple[np.ndarray, np.ndarray]:
    """(rows, t_touch (rows, width)): how far the base moves before each footprint slot of the free pillars
    ``rows`` touches; only those that may touch within ``window`` or with the event there (within its
    tie; by `brushbem.pillars.state.touch_candidates`) are looked at, all of them when ``window`` is infinite."""
    model = cache.model
    tolerance = 1e-10 * max(abs(d), float(np.max(np.abs(model.g))), 1e-300)
    if math.isfinite(window):
        window = max(window, 0.0)
        window += event_tie(path, math.sqrt(model.h2)) + tolerance
        candidates = touch_candidates(cache, state, d, d + direction * window, tolerance)
    else:
        candidates = ~state.attached
    rows, penetration, slope = element_penetration(cache, state, d, candidates)
    closing = np.isfinite(penetration) & (direction * slope > 0)
    t_touch = np.where(closing, -penetration / np.where(closing, direction * slope, 1.0), np.inf)
    return rows, np.maximum(t_touch, 0.0)
