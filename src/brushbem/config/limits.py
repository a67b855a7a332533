"""The bounds on a run configuration and a sweep file: magnitudes, size, nesting, case count,
and how much is echoed back.

Each bound keeps hostile or mistaken input (random bytes, a pasted array, a
number of 1e300, a sweep of millions of cases) from reaching the numerics,
exhausting memory or recursion, or flooding the problem report.
"""

from __future__ import annotations

__all__ = ["MAGNITUDE_RANGE", "MAX_CONFIG_BYTES", "MAX_PRELOAD_DOMAIN_SIZES", "MAX_SWEEP_BYTES", "MAX_SWEEP_CASES",
           "MAX_SWEEP_DEPTH", "SPRING_RESOLUTION_MARGIN", "SPRING_ROUNDING_FLOOR"]


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

# Deepest base displacement a preload may reach, in domain sizes (grid.size).  Beyond one domain size
# a run already warns that the strains leave the linear half-space's range; a thousand is a unit
# mistake (micrometres for metres), and the displacement's rounding (2.2e-16 d) starts to swamp the
# pull-off's displacements: a punch pressed to 1e29 L gave F_A = 0 "converged", one pressed by a
# force to 8.7e12 L was 0.5 % off.  A preload force is bounded by the same depth at the stiffest
# contact the domain allows (`brushbem.config.schema.RunConfig`).
MAX_PRELOAD_DOMAIN_SIZES = 1e3

# The solver's rounding floor (`brushbem.numerics.solver.cg.ROUNDING_FLOOR`, kept equal by a test): a solve
# whose half-space part is below this fraction of its right-hand side, times solver.tolerance, cannot
# be resolved in double precision.  Validation refuses a spring whose estimated fraction lies a
# margin below that (`brushbem.runs.assembly.Rules`), where the run could only fail, or, where its
# residual happens to round to zero, report a result that double precision did not resolve.
SPRING_ROUNDING_FLOOR = 16 * 2.0**-52
SPRING_RESOLUTION_MARGIN = 10.0

# Deepest nesting of tables and arrays a configuration may have: the schema
# needs 4 (``indenter.levels[i].cluster``); a deeper document is a mistake and
# would exhaust the recursion of the TOML reader and the validators.
_MAX_DEPTH = 32

# Largest configuration file read: a run configuration is a few kB.
MAX_CONFIG_BYTES = 1 << 20

# Largest sweep file read, checked before it is parsed.  The largest shipped
# sweep file, ``studies/sweeps/rough_brush.preload.toml`` (1380 zipped points
# of 4 keys), is 58 kB; 1 MiB is 18 times that, and still parses in a fraction
# of a second.
MAX_SWEEP_BYTES = 1 << 20

# Deepest nesting of a sweep file: a run configuration's own limit
# (`_MAX_DEPTH`) one level down under ``base``, or three levels down as a swept
# value (``sweep`` > key > list > value), so that any value a configuration
# takes can be swept.  A shipped sweep file nests at most 5.
MAX_SWEEP_DEPTH = _MAX_DEPTH + 3

# Most cases one sweep may expand to (the product of its lists' lengths, or
# their common length with mode "zip", times the realizations), checked
# before any case is built.  The largest shipped sweep,
# ``rough_brush.preload``, has 13 800 (1380 points x 10 realizations); the
# limit leaves seven times that.  Expanding a sweep validates every case (a
# few ms to tens of ms each) and records it in ``sweep.json`` (about 2 kB
# each), so 100 000 cases already take minutes to expand and some 200 MB to
# record before the first one runs; a larger study is split into several
# sweep files.
MAX_SWEEP_CASES = 100_000

# Most problem lines reported for one document; the rest are counted.
_MAX_PROBLEMS = 100
