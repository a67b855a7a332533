"""The pillar-level loading's rounds (`brushbem.pillars.loading`): a set solved before is replayed, not solved.

`_settle` runs the active-set rounds of a press; when a round's new set is
one it has solved before (a cycle of edge slots that only the flip limit
ends) it replays the recorded answers instead of solving.  Held here against
the rounds solved one by one on answers drawn at random for every set of a
few slots: the same final set, the same flips, never more solves.
"""

from __future__ import annotations

import numpy as np
import pytest

from brushbem.pillars import loading


def _oracle(seed: int, slots: int):
    """Answers (release, wanted) as functions of the set alone, drawn once per set: many cycles."""
    rng = np.random.default_rng(seed)
    table = {}

    def answer(on: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        key = on.tobytes()
        if key not in table:
            settled = rng.random() < 0.15
            release = on & (rng.random(on.shape) < 0.5) & (not settled)
            wanted = ~on & (rng.random(on.shape) < 0.5) & (not settled)
            table[key] = (release, wanted)
        return table[key]

    return answer, np.zeros((2, slots), dtype=bool)


def _solved_every_round(answer, start: np.ndarray) -> tuple[np.ndarray, np.ndarray, int]:
    """The reference: every round solved (the press's rounds without a replay)."""
    on, flips = start.copy(), np.zeros(start.shape, dtype=np.int64)
    for solves in range(1, 10_000):
        release, wanted = answer(on)
        join = wanted & (flips < loading._FLIPS)
        if not (release.any() or join.any()):
            return on, flips, solves
        new = (on & ~release) | join
        flips += new != on
        on = new
    raise AssertionError("the reference did not settle")


def _replayed(answer, start: np.ndarray) -> tuple[np.ndarray, np.ndarray, int]:
    """The press's rounds (`loading._settle`) on ``answer``: the final set, its flips, the solves."""
    state = {"on": start.copy(), "solves": 0}

    def ask():
        state["solves"] += 1
        return (state["on"].copy(), *answer(state["on"]))

    def install(new, on):
        assert np.array_equal(on, state["on"])
        state["on"] = new.copy()

    flips = np.zeros(start.shape, dtype=np.int64)
    solves = loading._settle(ask, install, flips, lambda: None, 0.0)
    assert solves == state["solves"]
    return state["on"], flips, solves


@pytest.mark.parametrize("seed", range(40))
def test_a_replayed_cycle_ends_where_solving_every_round_ends(seed):
    answer, start = _oracle(seed, slots=3)
    expected, expected_flips, expected_solves = _solved_every_round(answer, start)
    on, flips, solves = _replayed(answer, start)
    assert np.array_equal(on, expected)
    assert np.array_equal(flips, expected_flips)
    assert solves <= expected_solves


def test_the_replay_saves_solves_on_cycles():
    """Some of the drawn presses cycle, and there the replay solves fewer rounds (else the test above would not
    test it)."""
    saved = []
    for seed in range(40):
        answer, start = _oracle(seed, slots=3)
        saved.append(_solved_every_round(answer, start)[2] - _replayed(answer, start)[2])
    assert sum(saved) > 0 and sum(1 for s in saved if s > 0) >= 5, saved


def _touched(problem, force):
    """The cache and state of a pull-off of ``problem`` with its lowest tips attached, pressing with the near field
    fed back; and the lowest tip's height."""
    from brushbem import pillars
    from brushbem.pillars import state as pillar_state
    from brushbem.protocol import LoadPath

    model = pillars.PillarModel(problem)
    cache, state = pillar_state.begin(model, LoadPath(method="pillars", preload_force=force))
    lowest = float(model.g.min())
    state = pillar_state.attached_together(cache, state, np.flatnonzero(model.g <= lowest + 1e-12))
    return cache, state.replace(press_radiates=True), lowest


def test_local_release_finds_the_same_contact_in_fewer_rounds(switches):
    """A pillar that releases slots goes on releasing on its own in the same round (``press_local_release``):
    on a rough 6 x 6 brush (N = 96, k~ = 1e-2, sigma~ = 1) pressed in two steps the contact is the same slot
    for slot as without, in fewer rounds (measured 8 + 3 without, 5 + 3 with)."""
    from test_pillars_method import _brush

    problem, force = _brush(96, 6, 1e-2, 1.0)
    found = {}
    for local in (False, True):
        switches(press_local_release=local)
        cache, state, lowest = _touched(problem, force)
        d = lowest + 0.6 * float(np.ptp(cache.model.g)) + 0.02
        state, first = loading.press(cache, state, lowest + 0.5 * (d - lowest))
        state, second = loading.press(cache, state, d)
        found[local] = [first, second], state.attached[:, None] & state.raster
    assert np.array_equal(found[True][1], found[False][1])
    assert found[True][1].sum() > 1000  # many pillars in partial contact
    assert sum(found[True][0]) < sum(found[False][0])


def test_a_press_at_the_same_displacement_keeps_the_spent_slots_spent():
    """A slot whose joins the last press spent (the flip limit) starts the next press at nearly its d spent: a
    press again at the same d is one round to the same set (rough 8 x 8, N = 128, k~ = 1e-2, sigma~ = 1, one
    slot spent), where with every slot's flips afresh it ran the cycle again (3 rounds; on a 16 x 16 brush
    an end one slot off the first)."""
    from test_pillars_method import _brush

    problem, force = _brush(128, 8, 1e-2, 1.0)
    cache, state, lowest = _touched(problem, force)
    d = lowest + 0.3 * float(np.ptp(cache.model.g)) + 0.01
    pressed, _ = loading.press(cache, state, d)
    first = pressed.attached[:, None] & pressed.raster
    assert pressed.spent.any()
    again, rounds = loading.press(cache, pressed, d)
    assert rounds == 1
    assert np.array_equal(again.attached[:, None] & again.raster, first)
    _, rounds = loading.press(cache, pressed.replace(spent=None), d)  # every slot's flips afresh: the cycle again
    assert rounds > 1
