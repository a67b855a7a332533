"""Numerical settings that more than one layer reads, stated once at the floor of the package.

`KEPT_PILLARS` decides how the pillar-level model (``protocol.method =
"pillars"``) solves, and so how much memory it needs: the model
(`brushbem.protocol.pillar_solver`) and the memory rule of the configuration
(`brushbem.config.resources`) both read it here, so that validating a file
loads no solver.
"""

from __future__ import annotations

__all__ = ["KEPT_PILLARS"]

#: Attached pillars of a lattice brush beyond which the solve is CG (`LatticeCG`) instead of the kept
#: inverse (n^2 numbers: 8 GB at 3 x 10^4, and O(n^3) to refactorise); None: always the kept inverse.
#: Level chapter-5 brushes, k~ = 1e-2, CPU seconds: 32 x 32 2.4-2.7 with a limit of 512 against 2.7-3.1
#: kept (equal: the limit keeps the inverse there); 64 x 64 12.6 against 39.4 kept, 100 x 100 42 against
#: 356 (``benchmarks/large_brush.py --sizes 64 100 --sigma 0 --exact-max 0 --kept-baseline``).
KEPT_PILLARS: int | None = 1024
