"""The bounds on a run configuration: magnitudes, size, nesting, and how much is echoed back.

Each bound keeps hostile or mistaken input (random bytes, a pasted array, a
number of 1e300) from reaching the numerics or flooding the problem report.
"""

from __future__ import annotations

__all__ = ["MAGNITUDE_RANGE", "MAX_CONFIG_BYTES"]


# Longest value representation echoed back in a problem line; random or
# pasted input can be arbitrarily long and the line must stay readable.
_MAX_SHOWN = 60

# Every nonzero finite number of a configuration must have a magnitude in this
# range.  The numerics form products and quotients of a few inputs (E* h,
# dgamma / (E* h), r^2 / R, areas h^2 N^2, works F d); inside this range they
# stay far from overflow (1e308) and from the subnormal range (1e-308), so no
# input can turn into an inf, a 0 or a division by zero downstream.  Any
# consistent set of units (SI, or E* = L = 1) keeps physical inputs in it.
MAGNITUDE_RANGE = (1e-30, 1e30)

# Deepest nesting of tables and arrays a configuration may have: the schema
# needs 4 (``indenter.levels[i].cluster``); a deeper document is a mistake and
# would exhaust the recursion of the TOML reader and the validators.
_MAX_DEPTH = 32

# Largest configuration file read: a run configuration is a few kB.
MAX_CONFIG_BYTES = 1 << 20

# Most problem lines reported for one document; the rest are counted.
_MAX_PROBLEMS = 100
