"""The starting guess of the event path's next unit response after a cascade (`unit_guess`).

After a cascade at fixed d, the next unit response a' = A_S'^-1 1 starts from
the Galerkin (energy-optimal) combination of the previous response restricted
to the new set, a|S', and the cascade's pressure change dp (exact for a
single element leaving S).  The 2 x 2 system needs the products A a|S' and
A dp.  Of those, the path's state knows A a (the previous response's deflection)
and A Delta for Delta = p - p_pred (the cascade's deflection minus the
prediction's); the rest are products with the pressures a_E and p_E that the
elements E that left carried.  With ``settings.Switches.symmetric_products`` the inner
products of the 2 x 2 system take those through the symmetry of A and its
dense block A_EE on E (a few pillars' elements), and only the one combination
that the starting product needs is transformed; without it, A a_E and A p_E
are transformed one by one (the same numbers to round-off).
"""

from __future__ import annotations

import numpy as np

from brushbem import backend, settings
from brushbem.numerics.operator import ContactOperator

__all__ = ["cascade_record", "unit_guess"]

#: Most elements that left for the dense block A_EE (beyond, A a_E and A p_E are transformed).
_BLOCK_ELEMENTS = 2048


def cascade_record(operator: ContactOperator, contact, before, pressure, deflection, predicted_deflection):
    """What `unit_guess` keeps of a cascade on the window: (dp, A dp, None) or (dp, None, (p_pred, A Delta, Delta)).

    ``before`` is the prediction p_pred the cascade started from, ``pressure``
    its result p on the set ``contact`` and the two deflections theirs; None
    when the cascade did not change the pressure on the set.
    """
    xp = operator.xp
    change = pressure - xp.where(contact, before, 0.0)
    if not bool(xp.any(change != 0)):
        return None
    if settings.switches().symmetric_products:
        return change, None, (before, deflection - predicted_deflection, pressure - before)
    return change, deflection - predicted_deflection + operator.element_deflection(before, ~contact), None


def unit_guess(operator: ContactOperator, contact, previous, unit_product, change):
    """Starting guess for A_S^-1 1 on the window and its tip deflection (the product None where unknown).

    ``contact`` is the new set S' (window), ``previous`` the last unit response
    a (window, on the old set), ``unit_product`` its tip deflection A a or
    None, and ``change`` the cascade's record or None: (dp, A dp) or, with
    the symmetric products, (dp, None, (p_pred, A Delta, Delta)) on the
    window (`brushbem.protocol.unit_response.with_pressure_change`).
    """
    xp = operator.xp
    guess = xp.where(contact, previous, 0.0)
    if unit_product is None:
        return guess, None
    if change is None:
        return guess, unit_product - operator.element_deflection(previous, ~contact)
    dp, dp_product, symmetric = change
    if symmetric is not None:
        combined = _symmetric_guess(operator, contact, previous, guess, unit_product, dp, symmetric)
        if combined is not None:
            return combined
        before, delta_product, _ = symmetric
        dp_product = delta_product + operator.element_deflection(before, ~contact)
    product = unit_product - operator.element_deflection(previous, ~contact)

    def inner(a, b) -> float:  # both vanish outside S, so this is the inner product on S
        return float(xp.sum(a * b))

    g11 = inner(guess, product)
    g12 = 0.5 * (inner(guess, dp_product) + inner(dp, product))
    g22 = inner(dp, dp_product)
    coefficients = _solve_2x2(g11, g12, g22, float(xp.sum(guess)), float(xp.sum(dp)))
    if coefficients is None:
        return guess, product
    c1, c2 = coefficients
    return c1 * guess + c2 * dp, c1 * product + c2 * dp_product


def _solve_2x2(g11: float, g12: float, g22: float, f1: float, f2: float) -> tuple[float, float] | None:
    determinant = g11 * g22 - g12 * g12
    if not (g11 > 0 and g22 > 0 and determinant > 1e-12 * g11 * g22):
        return None
    return (f1 * g22 - f2 * g12) / determinant, (g11 * f2 - g12 * f1) / determinant


def _symmetric_guess(operator: ContactOperator, contact, previous, guess, unit_product, dp, symmetric):
    """`unit_guess`'s combination with one transform, or None where it does not apply.

    With a_1 = a|S', dp = Delta + p_E and U = A a (E the elements off S'
    that carried a or p_pred):

        <a_1, A a_1> = <a_1, U> - <U_E, a_E> + a_E . A_EE a_E,
        <a_1, A dp>  = <a_1, A Delta> + <U_E, p_E> - a_E . A_EE p_E,
        <dp, A dp>   = <Delta, A Delta> + 2 <p_E, (A Delta)_E> + p_E . A_EE p_E,

    and the guess's product c1 A a_1 + c2 A dp = c1 U + c2 A Delta + A (c2 p_E - c1 a_E).
    """
    xp = operator.xp
    if not backend.is_numpy_namespace(xp):
        return None
    before, delta_product, delta = symmetric
    off = ~contact
    left = off & ((previous != 0) | (before != 0))
    rows, cols = np.nonzero(left)
    if rows.size > _BLOCK_ELEMENTS:
        return None
    a_e, p_e, u_e = previous[rows, cols], before[rows, cols], unit_product[rows, cols]
    block = (operator.halfspace.block_matrix(np.stack([rows, cols], axis=1)) if rows.size
             else np.zeros((0, 0)))
    if operator.springs:
        flat = rows * contact.shape[1] + cols
        for lv in operator.springs.levels:
            labels = lv.labels[flat]
            block = block + lv.padded[labels][:, None] * (labels[:, None] == labels[None, :])
    block_a, block_p = block @ a_e, block @ p_e
    g11 = float(np.sum(guess * unit_product)) - float(u_e @ a_e) + float(a_e @ block_a)
    g12 = float(np.sum(guess * delta_product)) + float(u_e @ p_e) - float(a_e @ block_p)
    g22 = (float(np.sum(delta * delta_product)) + 2.0 * float(p_e @ delta_product[rows, cols])
           + float(p_e @ block_p))
    coefficients = _solve_2x2(g11, g12, g22, float(np.sum(guess)), float(np.sum(dp)))
    if coefficients is None:
        return None
    c1, c2 = coefficients
    values = np.zeros_like(previous)
    values[rows, cols] = c2 * p_e - c1 * a_e
    product = c1 * unit_product + c2 * delta_product + operator.element_deflection(values, left)
    return c1 * guess + c2 * dp, product
