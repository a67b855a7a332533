"""The path's saved states and its known deflections as frozen values (no positional tuples).

`PathPoint` is a state of the path that the paths go back to: the force
search of a fixed loading (`brushbem.protocol.paths._reach_force`) and the
events inside a fixed step (`brushbem.protocol.events`), which restore its
pressure and contact set and, under a pillar law, its pieces and breaks.
`Known` is a value computed of one array on one working window (a tip
deflection, the cascade's pressure change), valid only while both are the
current ones: `Known.of` gives it back for that array (the same object) and
window, else None.  The arrays are held, not copied: the path replaces its
pressure and contact arrays, it never writes into them.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from brushbem.numerics.operator import Window

__all__ = ["Known", "PathPoint"]


@dataclass(frozen=True)
class PathPoint:
    """A state the path returns to.

    Attributes
    ----------
    displacement : float or None
        The base displacement of the state (None where the caller keeps it).
    pressure, contact : arrays, full grid
        The equilibrium's pressure and contact set.
    pieces : object or None
        The pillar law's pieces and breaks (`brushbem.protocol.connections.ConnectionState.saved`),
        None without a law.
    """

    displacement: float | None
    pressure: Any
    contact: Any
    pieces: Any = None


@dataclass(frozen=True)
class Known:
    """``value``, computed of ``array`` on ``window`` (a tip deflection, a pressure change's record)."""

    array: Any
    window: Window
    value: Any

    def of(self, array, window: Window | None):
        """``value`` if it is of ``array`` (the same object) on ``window``, else None."""
        return self.value if array is self.array and window == self.window else None
