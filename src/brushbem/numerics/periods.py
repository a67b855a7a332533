"""Shorter periods for the transform of a pressure on part of a window (`halfspace_on_support`).

The half-space convolution of a pressure that vanishes outside a box well
inside the window needs a period of only about the window plus the box, not
twice the window (`brushbem.physics.halfspace.HalfSpace.wrapped_spectrum`).
Each period needs its own wrapped spectrum (a kernel evaluation and a
transform, cached in the half-space); with ``Switches.snap_periods`` the periods are
rounded up to a short ladder, so the pillars of a brush share a few of them
instead of making one per support.
"""

from __future__ import annotations

from brushbem import backend, settings
from brushbem.physics.halfspace import HalfSpace

__all__ = ["halfspace_on_support", "snapped_period"]

#: The ladder's step: the window's side divided by this.
_PERIOD_STEPS = 4


def snapped_period(needed: int, side: int) -> int:
    """The smallest fast length >= ``needed`` on the ladder of multiples of ``side / _PERIOD_STEPS``."""
    step = -(-side // _PERIOD_STEPS)
    return backend.smooth_length(-(-needed // step) * step)


def halfspace_on_support(halfspace: HalfSpace, pressure, support):
    """K p on the window for a pressure that vanishes outside the box ``support`` (None: anywhere).

    ``HalfSpace.apply(pressure, support=support)``, with the period rounded
    up by `snapped_period` under ``Switches.snap_periods``: the same convolution up
    to round-off.
    """
    if not settings.switches().snap_periods or support is None:
        return halfspace.apply(pressure, support=support)
    rows, cols = pressure.shape[-2:]
    r0, r1, c0, c1 = support
    long_rows = snapped_period(max(rows, 2 * max(r1 - 1, rows - 1 - r0)), rows)
    long_cols = snapped_period(max(cols, 2 * max(c1 - 1, cols - 1 - c0)), cols)
    if long_rows * long_cols < 0.9 * (4 * rows * cols):
        return backend.padded_convolution(halfspace.xp, pressure, halfspace.wrapped_spectrum(long_rows, long_cols),
                                          (long_rows, long_cols))
    return halfspace.apply(pressure)
