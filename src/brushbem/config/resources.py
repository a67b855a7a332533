"""What a run needs from the machine: memory and the size of its result file.

`memory_estimate` gives the peak resident memory of ``brushbem run`` for a
configuration, from a model fitted to measured peaks
(``benchmarks/memory.py``); `available_memory` what this machine (or the
``BRUSHBEM_MEMORY_LIMIT`` environment variable) allows.  Validation refuses a
configuration whose estimate exceeds it, before anything is computed
(`memory_problem`).
"""

from __future__ import annotations

import math
import os
import re
from pathlib import Path
from typing import TYPE_CHECKING

from brushbem import settings

if TYPE_CHECKING:
    from brushbem.config import RunConfig

__all__ = [
    "MEMORY_LIMIT_VARIABLE",
    "available_memory",
    "format_bytes",
    "kept_pillar_count",
    "memory_estimate",
    "memory_problem",
    "parse_bytes",
    "pillar_kept_bytes",
    "pillar_recycled_bytes",
    "result_size_estimate",
]

#: Environment variable that sets the memory a run may use, in bytes or with
#: a unit (``"16G"``, ``"512MiB"``, ``"2.5GB"``; powers of 1024), or ``"off"``
#: to skip the check.  Unset: the memory the operating system reports
#: available.
MEMORY_LIMIT_VARIABLE = "BRUSHBEM_MEMORY_LIMIT"

# Peak RSS = interpreter and imports + bytes per element of the N x N grid,
# times a margin.  Fitted to the peaks of benchmarks/memory.py (N = 256 ...
# 1024 for single bodies, 256 and 512 for the 16 x 16 brush, whose pillar,
# spring and contact-problem arrays cost more per element); the estimate lies
# above every measured peak.  At N = 4096 and 8192 single bodies were measured
# at 2.6 GB and 9.5 GB, about half the estimate: the margin grows with N.
_BASE_BYTES = 250e6
_BYTES_PER_ELEMENT = {"flat_punch": 270.0, "sphere": 270.0, "height_map": 270.0, "brush": 700.0}
_MARGIN = 1.1

# The pillar model (protocol.method = "pillars") keeps no element-level operator: per element the
# indenter's maps and the recorded snapshots, per pillar its bases and couplings (N = 16 n in the
# measured families, so both scale alike).  Measured peaks (benchmarks/large_brush.py, the size study):
# 0.36 GB (level, 10^4 pillars, N = 1600), 0.66 GB (rough, 10^4), 3.1-3.2 GB (level, 10^5, N = 5056),
# 3.5 GB (rough, 10^5; 5.8 GB sampled in a sweep's worker); 6.7 GB estimated at 10^5.  The size study's
# sigma~ = 0.1 brush: at 10^4 0.89 GB unrecorded (benchmarks/large_brush.py, inverse kept on 4818 attached)
# and 0.97 GB recorded (`brushbem run`: five snapshots of the N x N pressure and contact, about 30 bytes an
# element more), 2.9 GB estimated; at 10^5 2.15 GB unrecorded through its loading and first 105 pull-off
# states (18179 attached, by CG: no kept inverse; 2.32 GB through 100 states), so about 3 GB recorded, 9.2 GB
# estimated (the kept inverse of 5461 pillars that a rough brush may keep counted, 2.4 GB with the margin:
# this brush's measured peaks leave no room for it, but a brush whose contact grows through that size keeps
# it, as the 10^4 brush keeps 4818; and the CG's 40 kept Ritz vectors, 0.14 GB).  Off a lattice it
# keeps dense couplings of every mode and the inverse, (m + 2) M^2 numbers for M pillars (m = 6 modes).
_PILLARS_BYTES_PER_ELEMENT = 230.0
_PILLAR_MODES = 6

# The pillar model's kept inverse of n attached pillars (`brushbem.pillars.solver.Solver`) at its peak, in
# numbers of n^2: the inverse with room to grow (its array doubles: up to 4 n^2) and the temporaries of a
# refactorisation or of a large join (the block of G00 and the springs' block, the factor and the inverse with
# its two triangles: about 5 n^2).  Measured: a peak of 6.4 GB at n = 10312 (316 x 316 rough brush,
# kept_partial = 16384), 4.2 GB (4.9 n^2) beyond the model's 2.2 GB; counted as 9 (the doubled array).  On a
# partial set the inverse is kept while this fits in Switches.kept_partial_bytes (`kept_partial_count`).
_KEPT_NUMBERS = 9.0

# Bytes per element of result.nc, per recorded snapshot (pressure as float64,
# contact as one byte), and the number of snapshots a pull-off records
# (max_preload, zero_force, adhesive_force, half_detached, before_separation).
_RESULT_BYTES_PER_ELEMENT = 9.0
_SNAPSHOTS = 5

_UNITS = {"": 1, "k": 1 << 10, "m": 1 << 20, "g": 1 << 30, "t": 1 << 40}


def memory_estimate(config: RunConfig) -> int:
    """Peak resident memory of ``brushbem run`` for ``config``, in bytes.

    Parameters
    ----------
    config : RunConfig

    Returns
    -------
    int
        The estimate: the interpreter and its imports plus a cost per element
        of the N x N grid that depends on the indenter's shape (brushes keep
        pillar and spring maps beside the elastic arrays), with a margin over
        the peaks measured by ``benchmarks/memory.py``; for the pillar model
        (``protocol.method = "pillars"``) a smaller cost per element and its
        dense pillar-level matrices instead.
    """
    elements = config.grid.elements**2
    if config.protocol.method == "pillars" and config.indenter.shape == "brush":
        return int(_MARGIN * (_BASE_BYTES + _PILLARS_BYTES_PER_ELEMENT * elements + _pillar_matrices(config)))
    per_element = _BYTES_PER_ELEMENT[config.indenter.shape]
    return int(_MARGIN * (_BASE_BYTES + per_element * elements))


def _pillar_matrices(config: RunConfig) -> float:
    """Bytes of the pillar model's dense matrices: the kept inverse on a lattice (`pillar_kept_bytes` of at most
    ``Switches.kept_pillars`` attached, or on a brush of unequal tips, whose contact may be partial, of
    `kept_partial_count` up to half of the lattice) and, on such a brush where more pillars may attach than that,
    the CG's kept Ritz vectors (`pillar_recycled_bytes`); every mode's couplings and the inverse off a lattice."""
    indenter = config.indenter
    if indenter.layout == "random":
        pillars = indenter.pillar_count or 0
        return 8.0 * (_PILLAR_MODES + 2) * pillars**2
    kept = kept_pillar_count(config)
    pillars = (indenter.pillars_per_side or 0) ** 2
    # The Ritz vectors serve scattered contact sets only (the near-field preconditioner): tips of unequal lengths.
    scattered = _unequal_tips(indenter) and pillars > kept
    return pillar_kept_bytes(kept) + (pillar_recycled_bytes(pillars) if scattered else 0.0)


def _unequal_tips(indenter) -> bool:
    """Whether the brush's tips may differ in length (its contact may be partial and scattered)."""
    return (indenter.roughness is not None and indenter.roughness.sigma > 0) or indenter.profile is not None \
        or indenter.lengths_file is not None


def pillar_recycled_bytes(pillars: int) -> float:
    """Peak bytes of the Ritz vectors that the pillar model's CG keeps on a lattice of ``pillars``
    (`brushbem.pillars.recycle`: W and A W, ``Switches.recycled_vectors`` columns over every pillar, and their
    copies while they are made afresh: 4 k M numbers; 128 MB at 10^5 pillars and 40 vectors)."""
    return 8.0 * 4 * settings.switches().recycled_vectors * pillars


def kept_pillar_count(config: RunConfig) -> int:
    """The most attached pillars of a lattice brush whose inverse the pillar model keeps (module comments)."""
    indenter = config.indenter
    pillars = (indenter.pillars_per_side or 0) ** 2
    switches = settings.switches()
    if switches.kept_pillars is None:
        return pillars
    kept = min(pillars, switches.kept_pillars)
    return max(kept, min(pillars // 2, kept_partial_count(switches))) if _unequal_tips(indenter) else kept


def kept_partial_count(switches: settings.Switches) -> int:
    """The most attached pillars of a partial contact set (at most half of the lattice) whose inverse the pillar
    model keeps: ``switches.kept_partial`` where set, else the most whose `pillar_kept_bytes` fit in
    ``switches.kept_partial_bytes`` (5461 in the default 2 GiB).

    Raises
    ------
    ValueError
        If ``kept_partial`` is negative, or ``kept_partial_bytes`` is not a positive number of bytes.
    """
    if switches.kept_partial is not None:
        if switches.kept_partial < 0:
            raise ValueError(f"Switches.kept_partial must be None or at least 0 attached pillars "
                             f"(got {switches.kept_partial})")
        return int(switches.kept_partial)
    budget = switches.kept_partial_bytes
    if not (isinstance(budget, (int, float)) and math.isfinite(budget) and budget > 0):
        raise ValueError(f"Switches.kept_partial_bytes must be a positive, finite number of bytes (got {budget!r})")
    return math.isqrt(int(budget // pillar_kept_bytes(1)))


def pillar_kept_bytes(attached: int) -> float:
    """Peak bytes of the pillar model's kept inverse of ``attached`` pillars (``_KEPT_NUMBERS`` n^2 numbers)."""
    return 8.0 * _KEPT_NUMBERS * attached**2


def result_size_estimate(config: RunConfig) -> int:
    """Size of the ``result.nc`` of ``config``, in bytes (its snapshots dominate)."""
    return int(_SNAPSHOTS * _RESULT_BYTES_PER_ELEMENT * config.grid.elements**2)


def parse_bytes(text: str) -> int:
    """Bytes of ``text``: a number with an optional unit k, M, G or T (powers of 1024).

    ``"8G"``, ``"8 GB"``, ``"8GiB"`` and ``"8589934592"`` are the same.

    Raises
    ------
    ValueError
        If ``text`` is not a finite, positive amount.
    """
    match = re.fullmatch(r"\s*([0-9]*\.?[0-9]+(?:[eE][+-]?[0-9]+)?)\s*([kKmMgGtT]?)(?:i?[bB])?\s*", text)
    if match is None:
        raise ValueError("must be a number of bytes, optionally with a unit k, M, G or T (e.g. 16G), or off")
    amount = float(match.group(1)) * _UNITS[match.group(2).lower()]
    if not (math.isfinite(amount) and amount >= 1):
        raise ValueError(f"must be at least one byte (got {text.strip()!r}, {amount:g} bytes)")
    return int(amount)


def available_memory() -> tuple[int | None, str]:
    """The memory a run may use, in bytes, and where that figure comes from.

    Returns
    -------
    bytes : int or None
        ``BRUSHBEM_MEMORY_LIMIT`` if set; else the smaller of ``MemAvailable``
        (``/proc/meminfo``, or ``os.sysconf`` available pages) and the room
        left under a cgroup memory limit (a container or a batch job); None
        where none of them can be read or the variable is ``off`` (no check).
    source : str
        Where the figure comes from, for messages.

    Raises
    ------
    ValueError
        If ``BRUSHBEM_MEMORY_LIMIT`` is set but is not an amount of bytes.
    """
    setting = os.environ.get(MEMORY_LIMIT_VARIABLE)
    if setting is not None and setting.strip():
        if setting.strip().lower() in ("off", "none", "unlimited"):
            return None, f"{MEMORY_LIMIT_VARIABLE}=off"
        return parse_bytes(setting), f"{MEMORY_LIMIT_VARIABLE}={setting.strip()}"
    found: list[tuple[int, str]] = []
    meminfo = _meminfo_available()
    if meminfo is not None:
        found.append((meminfo, "available memory (MemAvailable)"))
    else:
        try:
            pages = os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
        except (AttributeError, ValueError, OSError):
            pages = -1
        if pages > 0:
            found.append((pages, "available physical memory"))
    cgroup = _cgroup_room()
    if cgroup is not None:
        found.append((cgroup, "room under the cgroup memory limit"))
    if not found:
        return None, "unknown"
    return min(found)


def memory_problem(config: RunConfig) -> str | None:
    """Why ``config`` cannot run in the available memory, or None.

    The estimate (`memory_estimate`) is compared with `available_memory`;
    no check where the available memory is unknown or the limit is ``off``.

    Raises
    ------
    ValueError
        If ``BRUSHBEM_MEMORY_LIMIT`` is not an amount of bytes.
    """
    limit, source = available_memory()
    if limit is None:
        return None
    need = memory_estimate(config)
    if need <= limit:
        return None
    kept = ""
    if config.protocol.method == "pillars" and config.indenter.shape == "brush" and config.indenter.layout != "random":
        count = kept_pillar_count(config)
        kept = (f" ({format_bytes(_MARGIN * pillar_kept_bytes(count))} of it the pillar model's kept inverse of "
                f"up to {count} attached pillars: lower Switches.kept_pillars or kept_partial_bytes (or set "
                "kept_partial), beyond which it solves by CG)")
    return (
        f"a run on {config.grid.elements} x {config.grid.elements} elements needs about {format_bytes(need)} "
        f"of memory{kept}, more than the {format_bytes(limit)} of {source}: lower grid.elements, or set "
        f"{MEMORY_LIMIT_VARIABLE} (bytes, e.g. 64G, or off) where more memory is at hand"
    )


def format_bytes(count: float) -> str:
    """``count`` bytes in GiB, MiB or KiB with three significant digits."""
    for unit, size in (("GiB", 1 << 30), ("MiB", 1 << 20), ("KiB", 1 << 10)):
        if count >= size:
            return f"{count / size:.3g} {unit}"
    return f"{int(count)} B"


def _meminfo_available() -> int | None:
    try:
        text = Path("/proc/meminfo").read_text()
    except OSError:
        return None
    match = re.search(r"^MemAvailable:\s+(\d+)\s*kB", text, flags=re.MULTILINE)
    return int(match.group(1)) * 1024 if match else None


def _cgroup_room() -> int | None:
    """Limit minus usage of this process's cgroup (v2), or None without a limit."""
    try:
        limit = Path("/sys/fs/cgroup/memory.max").read_text().strip()
        usage = Path("/sys/fs/cgroup/memory.current").read_text().strip()
    except OSError:
        return None
    if not limit.isdigit() or not usage.isdigit():  # "max": no limit
        return None
    return max(int(limit) - int(usage), 0)
