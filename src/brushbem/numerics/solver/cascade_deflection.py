"""The known tip deflection through a local cascade (`moved_deflection`).

A local cascade (`brushbem.numerics.solver.equilibria.local_cascade`) changes
the pressure on the pillars it peels only.  With ``Switches.keep_cascade_deflection``
the deflection known before it is moved by the deflection of that change (a
pressure on a few pillars, transformed on a short period), so that the next
solve starts from a known product instead of applying A_S to its start.
"""

from __future__ import annotations

from brushbem import settings
from brushbem.numerics.operator import ContactOperator

__all__ = ["moved_deflection"]


def moved_deflection(operator: ContactOperator, deflection, before, after):
    """The tip deflection of ``after`` from ``deflection``, that of ``before`` (None: unknown or switched off)."""
    if deflection is None or not settings.switches().keep_cascade_deflection:
        return None
    change = after - before
    return deflection + operator.element_deflection(change, change != 0)
