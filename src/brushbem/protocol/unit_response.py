"""The event path's unit response a = A_S^-1 1 as steps of the path's state (`unit_response`).

On a fixed contact set S the pressure is affine in d along a (dp/dd), and
the tip deflection along its deflection: the event path
(`brushbem.protocol.events`) predicts the next event from both.  Each
function here takes the path's state (`brushbem.protocol.values.PathState`)
and returns the next with what it computed: `unit_response` (the solve,
warm-started from the last response, `brushbem.protocol.unit_guess`),
`unit_deflection` (its one transform on the window) and
`with_pressure_change` (what a cascade changed, for the next response's
guess).  The state keeps each with the array and the window it is of
(`brushbem.protocol.values.Known`).
"""

from __future__ import annotations

import dataclasses

from brushbem.numerics.operator import Window
from brushbem.numerics.solver import solve_on_set, tip_deflection
from brushbem.protocol.unit_guess import cascade_record, unit_guess
from brushbem.protocol.values import Known, PathState

__all__ = ["unit_deflection", "unit_response", "with_pressure_change"]


def unit_response(context, state: PathState):
    """a = A_S^-1 1 on the state's window (dp/dd for its contact set), and the state that holds it.

    ``context`` (`brushbem.protocol.steps.PathContext`): the path's tolerance and the unit responses' ledger.
    """
    xp = context.xp
    working = state.working
    sl = working.window.slices
    contact = state.contact[sl]
    block, operator = working.cache.sub_operator(working.operator, contact)
    block_contact = contact[block]
    ones = xp.astype(block_contact, xp.float64)
    initial, product = _unit_guess(state, contact)
    result = solve_on_set(
        operator, block_contact, ones,
        initial=None if initial is None else initial[block],
        initial_product=None if product is None else product[block],
        tolerance=context.path.tolerance, max_iterations=context.path.max_iterations, ledger=context.ledgers[1],
        cache=working.cache,
    )
    solution = xp.zeros(contact.shape, dtype=ones.dtype)
    solution[block] = result.solution
    result = dataclasses.replace(result, solution=solution)
    unit = None
    if result.converged:
        unit = xp.zeros_like(state.pressure)
        unit[sl] = solution
    return state.replace(unit=unit), result


def unit_deflection(state: PathState):
    """The state that knows the tip deflection of its unit response on its window, and that deflection.

    Transformed once per response.
    """
    window = state.working.window
    known = None if state.unit_deflection is None else state.unit_deflection.of(state.unit, window)
    if known is not None:
        return state, known
    deflection = tip_deflection(state.working.operator, state.unit[window.slices], state.working.cache)
    return state.replace(unit_deflection=Known(state.unit, window, deflection)), deflection


def with_pressure_change(state: PathState, predicted, predicted_deflection, window: Window) -> PathState:
    """``state`` remembering dp = p - predicted on the contact and what its product needs, after a cascade at fixed d.

    ``predicted`` is the affine prediction the cascade started from (full
    grid) and ``predicted_deflection`` its tip deflection on ``window``.
    For a single element k leaving S the new unit response is exactly
    a|S' + (a_k / p_k) dp (both corrections are A_S'^-1 A_S'k times a
    scalar), so dp is the natural second direction of the next unit
    response's starting guess (`unit_response`, `brushbem.protocol.unit_guess`).
    What is kept of it: `brushbem.protocol.unit_guess.cascade_record`.
    """
    state = state.replace(pressure_change=None)
    deflection = state.known_deflection()
    if deflection is None or window != state.working.window:
        return state
    sl = window.slices
    record = cascade_record(state.working.operator, state.contact[sl], predicted[sl], state.pressure[sl],
                            deflection, predicted_deflection)
    if record is None:
        return state
    return state.replace(pressure_change=Known(state.contact, window, record))


def _unit_guess(state: PathState, contact):
    """Starting guess for A_S^-1 1 on the window and its deflection (None where unknown).

    The previous response restricted to S, its deflection kept in step by
    dropping the elements that left (no transform for a few of them).
    After a cascade the guess is the Galerkin (energy-optimal) combination
    of that and the cascade's pressure change dp (`with_pressure_change`),
    exact for a single element leaving (`brushbem.protocol.unit_guess`).
    """
    window = state.working.window
    if state.unit is None:
        return None, None
    previous = state.unit[window.slices]
    known = None if state.unit_deflection is None else state.unit_deflection.of(state.unit, window)
    if known is None:
        return state.working.problem.xp.where(contact, previous, 0.0), None
    change = None if state.pressure_change is None else state.pressure_change.of(state.contact, window)
    return unit_guess(state.working.operator, contact, previous, known, change)
