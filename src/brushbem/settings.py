"""The numerical switches of brushbem as one frozen value, at the floor of the package.

`Switches` holds every choice that a test or a benchmark turns off to
measure what it buys (each default is the measured better one): whether the
solver keeps and reuses what it computed, how the pillar model solves, and
where a cheaper equivalent path is taken.  Nothing sets a module attribute:
the switches in force are a frozen value, `switches()`, replaced for a block
with `using`::

    from brushbem import settings

    with settings.using(single_products=False, kept_pillars=16):
        record = record_pull_off(problem, path)   # every solve of this run sees them

A value set by `using` holds in the thread (and the asyncio task) that set it,
for the generators consumed inside the block too; worker processes of a sweep
start from the defaults.  `kept_pillars` also sets how much memory the pillar
model needs, so the memory rule of the configuration (`brushbem.config.resources`)
reads it here, and validating a file loads no solver.
"""

from __future__ import annotations

import contextlib
import dataclasses
from collections.abc import Iterator
from contextvars import ContextVar
from dataclasses import dataclass

__all__ = ["DEFAULT", "Switches", "switches", "using"]


@dataclass(frozen=True)
class Switches:
    """The numerical switches in force (one frozen value; `using` replaces it for a block).

    Attributes
    ----------
    kept_pillars : int or None
        Attached pillars of a lattice brush beyond which the pillar model solves by CG (`LatticeCG`)
        instead of the kept inverse (n^2 numbers: 8 GB at 3 x 10^4, and O(n^3) to refactorise); None:
        always the kept inverse.  Level chapter-5 brushes, k~ = 1e-2, CPU seconds: 32 x 32 2.4-2.7 with a
        limit of 512 against 2.7-3.1 kept (equal: the limit keeps the inverse there); 64 x 64 12.6 against
        39.4 kept, 100 x 100 42 against 356 (``benchmarks/large_brush.py --sizes 64 100 --sigma 0
        --exact-max 0 --kept-baseline``).
    kept_partial : int or None
        An explicit limit in place of ``kept_partial_bytes``: while the attached pillars are at most half of
        the lattice (a rough brush's partial contact), the pillar model keeps its inverse up to this many of
        them.  None (the default): up to as many as ``kept_partial_bytes`` allows.
    kept_partial_bytes : int
        The memory budget of the kept inverse on a partial set (attached pillars at most half of the
        lattice): it is kept while its estimated peak (`brushbem.config.resources.pillar_kept_bytes`, 9 n^2
        numbers) fits in these bytes, and at run time in half of the memory at hand too (the solver's cap,
        with a warning).  2 GiB: up to 5461 attached pillars (`brushbem.config.resources.kept_partial_count`).
        The circulant preconditioner of `LatticeCG` fits a full lattice, and on such a set it took 22-32
        iterations a solve instead of 8-9 (64 x 64 chapter-5 brush, sigma~ = 0.5, 978 attached at the
        preload; its loading 60 CPU s by CG, 10 s kept; 9.1 s with the near-field preconditioner,
        `near_preconditioner`).  The 316 x 316 brush (sigma~ = 0.5, 4270 attached at the preload) loaded in
        179 CPU s kept up to 16384 (peak 6.4 GB: the dense blocks of a join of 9618 pillars; 133 CPU s and
        6.8 GB measured again with the switch held, `brushbem.pillars`), in 359-376
        CPU s kept up to 4096 (CG beyond, peak 2.8 GB), whose pull-off by CG took 1.07 CPU s a state; the
        budget keeps its 4270 (1.3 GB estimated), so that its pull-off runs on the kept inverse: 15575 states,
        pull-off 1572 CPU s, 1917 in all, peak 2.9 GB (`brushbem.pillars`).
    pillar_cg_iterations : int
        Iterations of the pillar model's CG before its solve is declared not converged.
    near_preconditioner : bool
        Whether the pillar model's CG preconditions a scattered contact set (most attached pillars with a
        detached neighbour, `brushbem.pillars.cg.boundary_share`) by its near field
        (`brushbem.pillars.cg.LatticeCG.near_factor`) instead of the circulant: the 64 x 64 chapter-5 brush at
        sigma~ = 0.5 loaded by CG in 10 iterations a solve on average instead of 21.
    recycled_vectors : int
        Most Ritz vectors the pillar model's CG keeps from solve to solve for its two-level preconditioner
        on scattered sets (`brushbem.pillars.recycle`); 0: none (the near field alone).
    recycled_stale : float
        The share of the attached pillars that may leave, join or peel after the kept vectors' products were
        made before they are made afresh (`brushbem.pillars.recycle.Recycler.refresh`, k columns of products).
    single_pillar_products : bool
        Whether the pillar model's CG on a lattice takes the far field of its late iterations' products in
        single precision (`brushbem.pillars.cg.LatticeCG.solve`: while the error that adds stays within half
        its tolerance; the true residual is checked at the end).
    radiate_uniform : bool
        Whether the pillar model's uniform amplitudes answer the higher modes' near field too (one global
        solve a round).  Without it the concave 16 x 16 brush of ``tests/test_pillars_method.py`` keeps its
        F_A +9.7 % error.
    radiate_while_pressing : bool
        Whether the higher modes' near field is fed back while a brush of unequal tips is pressed
        (`brushbem.pillars.loading.press_rough`).
    press_local_release : bool
        Whether a pillar that releases slots in a round of the pillar-level press goes on releasing on its
        own in that round (`brushbem.pillars.loading`): the chapter-5 brush's loading in 59 solves
        instead of 80, the same contact and F_A.
    reuse_set_solver : bool
        Whether a solve on the set of the operator's last pillar-block solve reuses its system and
        preconditioner.
    single_products : bool
        Whether a pillar-block solve given a `ProductLedger` takes its late iterations' products in single
        precision (`BlockDeflection.apply_single`, ``conjugate_gradient``'s ``inexact``).
    keep_solution_deflection : bool
        Whether a pillar-block solve keeps its solution's tip deflection on the window (`BlockDeflection`).
    keep_cascade_deflection : bool
        Whether a local cascade keeps the known tip deflection of the state it starts from in step.
    coarse_update_rank : int
        Most pillars by which T^-1 + H may differ from the last factorised one (pillars that left the
        contact set, or whose stiffness fell) for a solve through that factor and a correction of this
        rank (`_CoarseBase`); more, and it is factorised afresh.  0: every matrix is factorised.
    skip_empty_rows : bool
        Whether `brushbem.backend.padded_convolution` of a 2-D array transforms along the rows only the
        rows that are not zero.
    snap_periods : bool
        Whether `halfspace_on_support` rounds the shorter periods up with `snapped_period`.
    symmetric_products : bool
        Whether `unit_guess` forms the Galerkin system through the symmetry of A and its block on the
        elements that left (one transform per cascade) instead of transforming A a_E and A p_E (two).
    compact_event_search : bool
        Whether `_events_ahead` works on the footprint elements of the window only (NumPy): no element off
        the footprint is in contact or can touch, so the events are the same, with a sixth of the array
        work of the window's arrays for a brush of phi = 0.16.
    preload_model : bool
        Whether the search for a preload force extrapolates below the target with the independent
        pillars' model (`_IndependentPillars`) instead of the secant of F (5 contact problems instead of 8
        on the chapter-5 brush; the preload state moves within the solver's tolerance).
    """

    kept_pillars: int | None = 1024
    kept_partial: int | None = None
    kept_partial_bytes: int = 2 * 2**30
    pillar_cg_iterations: int = 2000
    near_preconditioner: bool = True
    recycled_vectors: int = 40
    recycled_stale: float = 0.02
    single_pillar_products: bool = True
    radiate_uniform: bool = True
    radiate_while_pressing: bool = True
    press_local_release: bool = True
    reuse_set_solver: bool = True
    single_products: bool = True
    keep_solution_deflection: bool = True
    keep_cascade_deflection: bool = True
    coarse_update_rank: int = 64
    skip_empty_rows: bool = True
    snap_periods: bool = True
    symmetric_products: bool = True
    compact_event_search: bool = True
    preload_model: bool = True


#: The defaults: every switch at its measured better setting.
DEFAULT = Switches()

_CURRENT: ContextVar[Switches] = ContextVar("brushbem_switches", default=DEFAULT)


def switches() -> Switches:
    """The switches in force here (`DEFAULT` outside every `using` block)."""
    return _CURRENT.get()


@contextlib.contextmanager
def using(**changes) -> Iterator[Switches]:
    """The switches in force with ``changes`` (field = value) for the block; the previous ones after it.

    Raises
    ------
    TypeError
        A name that is no field of `Switches`.
    """
    value = dataclasses.replace(_CURRENT.get(), **changes)
    token = _CURRENT.set(value)
    try:
        yield value
    finally:
        _CURRENT.reset(token)
