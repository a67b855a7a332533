"""The pillar model's loading of tips of unequal lengths: `press`, `press_rough` (``method = "pillars"``).

The exact path presses a brush whose tips are not level as the
non-adhesive contact problem at every d (`brushbem.protocol.contact_loading`);
here that problem is solved at the pillar level (`press`: an active set of
footprint slots), at the preload displacement or at the displacement of the
preload force (`press_rough`), with the higher modes' near field fed back
once the active set has settled (`brushbem.pillars.solver.radiate`).  The
model is described in `brushbem.pillars`.
"""

from __future__ import annotations

import math
from collections.abc import Generator

import numpy as np

from brushbem import settings
from brushbem.pillars.state import PillarState
from brushbem.protocol.contact_loading import LOADING_SAMPLES
from brushbem.protocol.problem import LoadPath, State

__all__ = ["press", "press_rough"]

#: How often a footprint slot may join or leave in one contact problem (`press`).  The fit of the
#: neighbours' field across a tip is not exact, so a slot at a contact's edge can penetrate while off and
#: be in tension while on; after this many changes it stays off (out of contact, as without tension).
_FLIPS = 6

#: A press starts from the last one's settled set with the near field fed back when its d is this close
#: (relative to the indentation d - lowest tip).
_NEAR_PRESS = 0.02

def press(run: PillarState, d: float) -> int:
    """The non-adhesive contact problem at d: the rounds it took (solves of the pillar-level system).

    Rounds of an active set at element level: an element in tension
    leaves, a footprint slot that the tip penetrates joins, until neither
    happens (a primal-dual active-set method; the solution of the convex
    problem is unique, so the state does not depend on where it starts).
    """
    model = run.model
    tolerance = 1e-10 * max(abs(d), float(np.max(np.abs(model.g))), 1e-300)
    flips = np.zeros(model.full.shape, dtype=np.int64)
    # The active set settles without the higher modes' near field first (cheap rounds), then with it
    # (`press_radiates`: a few rounds more, from near the answer).  From the settled state of a press at
    # nearly the same d (the preload search's last Newton steps) it starts with the field: the set without it
    # lies farther from there (25-34 rounds a press instead of a few, 64 x 64 chapter-5 brush, sigma~ = 0.5).
    near = run.pressed is not None and abs(d - run.pressed) <= _NEAR_PRESS * max(abs(d - float(model.g.min())), 1e-300)
    phases = ([True] if near else [False, True]) if run.press_radiates and model.m > 1 else [False]
    run.pressed = None
    rounds = 0
    for radiate in phases:
        run.radiate = radiate
        for _ in range(4 * _FLIPS + 100):
            run.check_stop()
            rounds += 1
            run.solve()
            pressure = run.pressures_at(d)
            on = run.attached[:, None] & model.raster
            release = np.zeros_like(on)
            release[run.on()] = on[run.on()] & (pressure < -1e-10 * max(float(np.max(np.abs(pressure), initial=0.0)),
                                                                         1e-300))
            rows, penetration, _ = run.element_penetration(d, run.touch_candidates(d, d, tolerance) | run.attached)
            join = np.zeros_like(on)
            join[rows] = ~on[rows] & (penetration > tolerance) & (flips[rows] < _FLIPS)
            if not (release.any() or join.any()):
                break
            new = (on & ~release) | join
            flips += new != on
            run.install(new, np.flatnonzero((new != on).any(axis=1)))
        else:
            raise RuntimeError(f"the pillar-level contact problem at d = {d:.6g} did not settle")
    if run.radiate:
        run.pressed = d
    return rounds


def press_rough(run: PillarState, path: LoadPath, lowest: float) -> Generator[State, None, float]:
    """The loading branch of a brush whose tips are not level, as the exact path presses it.

    The exact path's loading branch of such a brush is the non-adhesive
    contact problem at every d (`brushbem.protocol.contact_loading`): tips
    that have just touched are in partial contact.  Here it is solved at the
    pillar level (`press`) at the preload displacement, or at the
    displacement of the preload force, found from below (the indentation at
    most doubling) and then by Newton steps on the affine F(d) of a fixed
    contact set inside a bracket (exact once the set does not change); then at ``LOADING_SAMPLES - 1`` evenly spaced displacements
    below it for the loading curve.
    """
    model = run.model
    run.press_radiates = settings.switches().radiate_while_pressing
    samples: list[float] = []
    if path.preload_displacement is not None:
        target = float(path.preload_displacement)
        press(run, target)
    else:
        goal = float(path.preload_force)
        low, high = lowest, math.inf
        # From below: the tips that touch first are few, and pressing far past the preload would attach
        # every pillar (a dense pillar-level matrix of all of them).  Below the goal a step at most doubles
        # the indentation; above it, F being convex in d, Newton steps approach the goal from above.
        d = lowest + float(np.ptp(model.g)) / 16.0
        for _ in range(200):
            press(run, d)
            force = run.force(d)
            if abs(force - goal) <= 1e-10 * goal:
                break
            if force < goal:
                low = max(low, d)
            else:
                high = min(high, d)
            rate = model.h2 * float(np.sum(np.where(run.attached, model.force * run.alpha[:, 0], 0.0)))
            step = d + (goal - force) / rate if rate > 0 else math.inf
            if not math.isfinite(high):
                step = min(step, lowest + 2.0 * (d - lowest))
            elif not low < step < high:
                step = 0.5 * (low + high)
            if abs(step - d) <= 1e-13 * max(abs(d), 1.0):
                break
            d = step
        else:
            raise RuntimeError(f"the preload force {goal:g} was not found on the loading branch")
        target = d
    kept = (run.attached.copy(), model.raster.copy())
    for k in range(1, LOADING_SAMPLES):
        samples.append(lowest + (target - lowest) * k / LOADING_SAMPLES)
    for d in samples:
        press(run, d)
        yield run.state(d, True, "equilibrium", "contact problem (pillar level)")
    attached, raster = kept
    masks = np.where(attached[:, None], raster, False)
    run.install(masks, np.flatnonzero((masks != (run.attached[:, None] & model.raster)).any(axis=1)
                                      | (attached != run.attached)))
    # The pull-off feeds back no higher modes: on the contact set found, the preload force's displacement
    # without them (F is affine in d on a fixed set).
    run.press_radiates = run.radiate = False
    run.solve()
    if path.preload_displacement is None:
        rate = model.h2 * float(np.sum(np.where(run.attached, model.force * run.alpha[:, 0], 0.0)))
        target += (float(path.preload_force) - run.force(target)) / rate
    yield run.state(target, True, "equilibrium", "contact problem (pillar level): preload reached")
    return target
