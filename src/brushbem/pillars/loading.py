"""The pillar model's loading of tips of unequal lengths: `press`, `press_rough` (``method = "pillars"``).

The exact path presses a brush whose tips are not level as the
non-adhesive contact problem at every d (`brushbem.protocol.contact_loading`);
here that problem is solved at the pillar level (`press`: an active set of
footprint slots), at the preload displacement or at the displacement of the
preload force (`press_rough`), with the higher modes' near field fed back
once the active set has settled (`brushbem.pillars.solver.radiate`).  The
model is described in `brushbem.pillars`.

A round of `press` solves the pillar-level system on the current set; two
things keep the rounds few without moving where they end.  A pillar that
releases slots goes on releasing on its own in the same round, the others
held (`_release_locally`), instead of shedding one ring of edge slots a
round; and a set the press has solved before is not solved again: the
rounds from it are replayed from what they asked for (`_Rounds`), which
runs a cycle of edge slots through to the flip limit without solves.  On
the chapter-5 brush (32 x 32, N = 512, k~ = 0.01, sigma~ = 1) the loading
took 86 solves before, 80 with the replay alone and 59 with both, to the
same contact at every sample and the same F_A and work to 2e-15.  And a
press at nearly the d of the last starts with the slots whose joins that
press spent spent (``PillarState.spent``): the preload search's last
Newton steps ran the same cycle of edge slots to the flip limit each time
(100 x 100, sigma~ = 0.5: 17 rounds at each of its last three presses, now
17, 4 and 1; the same F_A to 1e-14).
"""

from __future__ import annotations

import math
from collections.abc import Generator

import numpy as np

from brushbem import settings
from brushbem.pillars.state import (PillarState, RasterCache, amplitudes, element_penetration, force, force_rate,
                                    installed, local_amplitudes, on, pressures_at, record, solved, touch_candidates)
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

def press(cache: RasterCache, state: PillarState, d: float) -> tuple[PillarState, int]:
    """The non-adhesive contact problem at d: its state and the rounds it took (solves of the pillar-level system).

    Rounds of an active set at element level: an element in tension
    leaves, a footprint slot that the tip penetrates joins, until neither
    happens (a primal-dual active-set method; the solution of the convex
    problem is unique, so the state does not depend on where it starts,
    except where the flip limit ends a cycle of edge slots: a slot that has
    joined `_FLIPS` times stays off).  A set it has solved before in the
    same phase is not solved again: the rounds that follow it are replayed
    from what they asked for (`_Rounds`).  Near the last press's d the slots
    that press spent start spent, so that pressing again at its d is one
    round to its state.
    """
    model = cache.model
    tolerance = 1e-10 * max(abs(d), float(np.max(np.abs(model.g))), 1e-300)
    # The active set settles without the higher modes' near field first (cheap rounds), then with it
    # (`press_radiates`: a few rounds more, from near the answer).  From the settled state of a press at
    # nearly the same d (the preload search's last Newton steps) it starts with the field: the set without it
    # lies farther from there (25-34 rounds a press instead of a few, 64 x 64 chapter-5 brush, sigma~ = 0.5).
    near = state.pressed is not None and abs(d - state.pressed) <= _NEAR_PRESS * max(abs(d - float(model.g.min())),
                                                                                     1e-300)
    phases = ([True] if near else [False, True]) if state.press_radiates and model.m > 1 else [False]
    flips = np.zeros(model.full.shape, dtype=np.int64)
    if near and state.spent is not None:
        flips[state.spent] = _FLIPS
    state = state.replace(pressed=None, spent=None)
    rounds = 0

    def answer():
        nonlocal state
        state = solved(cache, state)
        return _answer(cache, state, d, tolerance)

    def install(new, held):
        nonlocal state
        state = installed(cache, state, new, np.flatnonzero((new != held).any(axis=1)))

    for radiating in phases:
        state = state.replace(radiate=radiating)
        rounds += _settle(answer, install, flips, cache.check_stop, d)
    if state.radiate:
        state = state.replace(pressed=d, spent=flips >= _FLIPS)
    return state, rounds


def _answer(cache: RasterCache, state: PillarState, d: float,
            tolerance: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The solved ``state`` at d: (its slots, slots in tension, slots off it that the tip penetrates)."""
    pressure = pressures_at(cache, state, d)
    held = state.attached[:, None] & state.raster
    release = np.zeros_like(held)
    floor = -1e-10 * max(float(np.max(np.abs(pressure), initial=0.0)), 1e-300)
    release[on(state)] = held[on(state)] & (pressure < floor)
    if settings.switches().press_local_release:
        _release_locally(cache, state, d, held, release, floor)
    rows, penetration, _ = element_penetration(cache, state, d, touch_candidates(cache, state, d, d, tolerance)
                                               | state.attached)
    wanted = np.zeros_like(held)
    wanted[rows] = ~held[rows] & (penetration > tolerance)
    return held, release, wanted


def _release_locally(cache: RasterCache, state: PillarState, d: float, held: np.ndarray, release: np.ndarray,
                     floor: float) -> None:
    """Each pillar that releases slots this round goes on releasing on its own: ``release`` extended in place.

    With the other pillars held at this round's amplitudes (`local_amplitudes`, as a peel holds them) the
    pillar's own modes on its smaller raster may put more of its slots below ``floor`` (tension): they are
    released in the same round, until none is.  Most of a press's later rounds were a few pillars shedding
    their edge slots a round at a time after joining whole (the chapter-5 brush's loading: 80 solves, 59 with
    this; the same contact at every sample and the same F_A and work, ``tests/test_pillar_loading.py``).
    The settled set is the press's own test, so what this changes is only the way there.
    """
    x = amplitudes(state, d)
    frozen = state.attached
    for p in np.flatnonzero(release.any(axis=1)):
        mask = held[p] & ~release[p]
        while mask.any():
            a, basis = local_amplitudes(cache, state, p, mask, frozen, x, d)
            tense = basis.phi @ a < floor
            if not tense.any():
                break
            mask = mask.copy()
            mask[np.flatnonzero(mask)[tense]] = False
        release[p] = held[p] & ~mask


def _settle(answer, install, flips: np.ndarray, check_stop, d: float) -> int:
    """Rounds of the active set from the current one until it settles: the solves they took.

    ``answer()`` solves the current set: (its slots, those to release, those that penetrate); the slots
    that penetrate join unless their ``flips`` (advanced here) are spent; ``install(new, on)`` makes ``new``
    the current set.  A set solved before is not solved again (`_Rounds.replay`).
    """
    seen = _Rounds()
    for solves in range(1, 4 * _FLIPS + 101):
        check_stop()
        on, release, wanted = answer()
        join = wanted & (flips < _FLIPS)
        if not (release.any() or join.any()):
            return solves
        seen.add(on, release, wanted)
        new = (on & ~release) | join
        flips += new != on
        install(seen.replay(new, flips), on)
    raise RuntimeError(f"the pillar-level contact problem at d = {d:.6g} did not settle")


class _Rounds:
    """The active sets a press has solved in one phase and what their solves asked for: slots to release, slots
    that penetrate (joining unless their flips are spent).

    Both are functions of the set alone, so when a round's new set is one solved before (a cycle of a few
    edge slots that only the flip limit ends: two pillars of the chapter-5 brush swapped 4 sets for 8 rounds
    at the preload) the rounds that follow are known without solving: `replay` steps through the recorded
    answers, counting flips as the rounds would, until a set not solved before (a join the flip limit now
    blocks) or a set that asks for nothing more; the press solves on from there.  The same sets and flips as
    solving every round, without the solves.
    """

    def __init__(self):
        self._answers: dict[bytes, tuple[np.ndarray, np.ndarray]] = {}

    def add(self, on: np.ndarray, release: np.ndarray, wanted: np.ndarray) -> None:
        self._answers[np.packbits(on).tobytes()] = (np.flatnonzero(release), np.flatnonzero(wanted))

    def replay(self, new: np.ndarray, flips: np.ndarray) -> np.ndarray:
        """The set the press goes on from after ``new`` (``flips`` advanced in place by the rounds replayed)."""
        while (answer := self._answers.get(np.packbits(new).tobytes())) is not None:
            release, wanted = answer
            step = new.copy()
            step.flat[release] = False
            step.flat[wanted[flips.flat[wanted] < _FLIPS]] = True
            if np.array_equal(step, new):  # the set the press settles on: solved once more as the last round
                break
            flips += step != new
            new = step
        return new


def press_rough(cache: RasterCache, state: PillarState, path: LoadPath,
                lowest: float) -> Generator[tuple[PillarState, State], None, tuple[PillarState, float]]:
    """The loading branch of a brush whose tips are not level, as the exact path presses it: its states (each
    as the path's value and its record), and the state and d at the preload.

    The exact path's loading branch of such a brush is the non-adhesive
    contact problem at every d (`brushbem.protocol.contact_loading`): tips
    that have just touched are in partial contact.  Here it is solved at the
    pillar level (`press`) at the preload displacement, or at the
    displacement of the preload force, found from below (the indentation at
    most doubling) and then by Newton steps on the affine F(d) of a fixed
    contact set inside a bracket (exact once the set does not change); then at ``LOADING_SAMPLES - 1`` evenly
    spaced displacements below it for the loading curve, from which the path returns to the preload's state.
    """
    model = cache.model
    state = state.replace(press_radiates=settings.switches().radiate_while_pressing)
    samples: list[float] = []
    if path.preload_displacement is not None:
        target = float(path.preload_displacement)
        state, _ = press(cache, state, target)
    else:
        goal = float(path.preload_force)
        low, high = lowest, math.inf
        # From below: the tips that touch first are few, and pressing far past the preload would attach
        # every pillar (a dense pillar-level matrix of all of them).  Below the goal a step at most doubles
        # the indentation; above it, F being convex in d, Newton steps approach the goal from above.
        d = lowest + float(np.ptp(model.g)) / 16.0
        for _ in range(200):
            state, _ = press(cache, state, d)
            total = force(cache, state, d)
            if abs(total - goal) <= 1e-10 * goal:
                break
            if total < goal:
                low = max(low, d)
            else:
                high = min(high, d)
            rate = force_rate(cache, state)
            step = d + (goal - total) / rate if rate > 0 else math.inf
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
    kept = state
    for k in range(1, LOADING_SAMPLES):
        samples.append(lowest + (target - lowest) * k / LOADING_SAMPLES)
    for d in samples:
        state, _ = press(cache, state, d)
        yield state, record(cache, state, d, True, "equilibrium", "contact problem (pillar level)")
    # Back to the preload's contact set (a saved state: the next step brings the cache to its rasters).  The
    # pull-off feeds back no higher modes: on the contact set found, the preload force's displacement without
    # them (F is affine in d on a fixed set).
    state = solved(cache, kept.replace(press_radiates=False, radiate=False))
    if path.preload_displacement is None:
        target += (float(path.preload_force) - force(cache, state, target)) / force_rate(cache, state)
    yield state, record(cache, state, target, True, "equilibrium", "contact problem (pillar level): preload reached")
    return state, target
