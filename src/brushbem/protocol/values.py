"""The path's state and its known deflections as frozen values (no positional tuples).

`PathState` is the state of a pull-off as one value: the pressure and the
contact set (full grid), the working window the solves run on
(`brushbem.protocol.window.WorkingWindow`, itself a value: the window, its
operator and the tip heights), the values known of them without another
transform (the tip deflection of the pressure, the last unit response and
its deflection, the last cascade's pressure change), the connections' state
(`brushbem.protocol.connections.ConnectionState`, itself a value: the
viscoelastic memory, the pillar law's pieces and breaks) and, in a saved
state, its displacement.  The load paths hand it from step to step
(`brushbem.protocol.steps`: each step takes a state and returns the
next, never writes into it); a saved state is that value with its
``displacement``, which the paths go back to (`brushbem.protocol.steps.restored`): the force search of a fixed loading
(`brushbem.protocol.paths._reach_force`) and the events inside a fixed step
(`brushbem.protocol.events`).  A new state shares every array that did not
change with the one before (no copies).

`Known` is a value computed of one array on one working window (a tip
deflection, the cascade's pressure change), valid only while both are the
current ones: `Known.of` gives it back for that array (the same object) and
window, else None.  The arrays are held, not copied: the path replaces its
pressure and contact arrays, it never writes into them.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

from brushbem.numerics.operator import Window

__all__ = ["Known", "PathState"]


@dataclass(frozen=True)
class PathState:
    """The state of a pull-off (module docstring).

    Attributes
    ----------
    pressure, contact : arrays, full grid
        The equilibrium's pressure (compressive positive) and contact set.
    working : WorkingWindow
        The window the solves run on, its operator, the problem whose springs it sees and the tip heights
        (`brushbem.protocol.window.WorkingWindow`).  A saved state carries the one it was saved on.
    deflection : Known or None
        The tip deflection (half-space + springs) of ``pressure`` on the window it was computed on.
    unit : array, full grid, or None
        The last unit response a = A_S^-1 1 (the warm start of the next one, kept across windows).
    unit_deflection : Known or None
        The tip deflection of ``unit`` on its window.
    pressure_change : Known or None
        Of the contact set on the window: how the last cascade changed the pressure beyond the
        affine prediction, for the next unit response's guess (`brushbem.protocol.unit_guess.cascade_record`).
    connections : ConnectionState or None
        The connections' state (`brushbem.protocol.connections.ConnectionState`): the viscoelastic
        memory and the pillar law's pieces and breaks.
    displacement : float or None
        The base displacement of a saved state (None in a state being stepped).
    """

    pressure: Any
    contact: Any
    working: Any
    deflection: Known | None = None
    unit: Any = None
    unit_deflection: Known | None = None
    pressure_change: Known | None = None
    connections: Any = None
    displacement: float | None = None

    def known_deflection(self):
        """The tip deflection of ``pressure`` on the state's window if known (`Known.of`), else None."""
        return None if self.deflection is None else self.deflection.of(self.pressure, self.working.window)

    def replace(self, **changes) -> PathState:
        """The state with ``changes`` (its other fields, and their arrays, shared).

        `dataclasses.replace` without its per-call work (a path replaces its state a few times per
        event): the fields are copied as they are, each name checked.
        """
        if not changes.keys() <= _STATE_FIELDS:
            raise TypeError(f"PathState has no field {sorted(changes.keys() - _STATE_FIELDS)}")
        new = object.__new__(PathState)
        new.__dict__.update(self.__dict__)
        new.__dict__.update(changes)
        return new


@dataclass(frozen=True)
class Known:
    """``value``, computed of ``array`` on ``window`` (a tip deflection, a pressure change's record)."""

    array: Any
    window: Window
    value: Any

    def of(self, array, window: Window | None):
        """``value`` if it is of ``array`` (the same object) on ``window``, else None."""
        return self.value if array is self.array and window == self.window else None


_STATE_FIELDS = frozenset(field.name for field in dataclasses.fields(PathState))
