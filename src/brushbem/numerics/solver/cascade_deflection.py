"""The known tip deflection through a local cascade (`moved_deflection`).

A local cascade (`brushbem.numerics.solver.equilibria.local_cascade`) changes
the pressure on the pillars it peels only.  With ``KEEP_CASCADE_DEFLECTION``
the deflection known before it is moved by the deflection of that change (a
pressure on a few pillars, transformed on a short period), so that the next
solve starts from a known product instead of applying A_S to its start.
"""

from __future__ import annotations

from brushbem.numerics.operator import ContactOperator

__all__ = ["KEEP_CASCADE_DEFLECTION", "moved_deflection"]

#: Whether a local cascade keeps the known tip deflection of the state it starts from in step.
KEEP_CASCADE_DEFLECTION = True


def moved_deflection(operator: ContactOperator, deflection, before, after):
    """The tip deflection of ``after`` from ``deflection``, that of ``before`` (None: unknown or switched off)."""
    if deflection is None or not KEEP_CASCADE_DEFLECTION:
        return None
    change = after - before
    return deflection + operator.element_deflection(change, change != 0)
