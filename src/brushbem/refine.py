"""Mesh error bars: a case on two or three grids, Richardson-extrapolated (``brushbem run --refine``).

The Pohrt-Popov criterion converges at first order in the element size h
(the mesh criterion Sigma_c ~ h^-1/2 resolves the crack-tip field over one
element): JKR at a / h = 39 is still 4.4 % strong.  A single grid therefore
says little about its own error.  `refined_run` runs the configured case on
the grids N / 2^k, ..., N / 2, N (``grids`` of them, the configured one the
finest) and reports, for the adhesive force and the work of separation:

* ``values``: on each grid, coarse to fine;
* ``observed_order``: log2((f1 - f2) / (f2 - f3)) from three grids (None
  from two, or when the differences change sign: no asymptotic range);
* ``extrapolated``: f* = f_N + (f_N - f_N/2) / (2^p - 1) with the formal
  order p = 1.  The formal order, not the observed one: the observed order
  of these sequences is far from steady on affordable grids (JKR from a / h
  = 10, 21, 42: 0.5 and 0.2), and extrapolating with it would amplify that
  noise; first-order extrapolation is what the criterion's analysis
  supports;
* ``error_estimate``: a bound on |f* - exact|, conservative by design: the
  larger of the Richardson correction |f_N - f*| (the fine grid's own error
  estimate) and, with three grids, the change of f* between the coarser and
  the finer pair.  A rasterised circle's staircase adds an error that is not
  smooth in h (Kendall's punch: 3.7, 1.5, 0.3, 0.5 % at r / h = 8 to 64);
  the bound covers it where the extrapolation alone would not.

The tests check the bound on Kendall's and JKR's closed forms and on a punch
on a spring (``tests/test_refine.py``).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from .assembly import parse_config
from .config import ConfigError, RunConfig, config_to_dict
from .records import MappingRecord

__all__ = ["FORMAL_ORDER", "Extrapolation", "Refinement", "refined_configs", "refined_run", "richardson"]

#: The order in h of the Pohrt-Popov criterion's error.
FORMAL_ORDER = 1.0


@dataclass(frozen=True, kw_only=True)
class Extrapolation(MappingRecord):
    """One quantity on the refined grids (module docstring)."""

    values: list
    extrapolated: float
    error_estimate: float
    observed_order: float | None
    formal_order: float = FORMAL_ORDER


@dataclass(frozen=True, kw_only=True)
class Refinement(MappingRecord):
    """``summary.json``'s ``refinement``: the grids and the extrapolated quantities."""

    elements: list
    adhesive_force: Extrapolation
    work_of_separation: Extrapolation
    converged: bool


def richardson(values: Sequence[float], ratio: float = 2.0, order: float = FORMAL_ORDER) -> Extrapolation:
    """Richardson extrapolation of ``values`` on grids refined by ``ratio`` (coarse to fine; 2 or 3 values)."""
    values = [float(v) for v in values]
    if len(values) not in (2, 3) or not all(math.isfinite(v) for v in values):
        raise ValueError(f"richardson needs 2 or 3 finite values, got {values}")
    factor = ratio**order - 1.0
    fine, middle = values[-1], values[-2]
    extrapolated = fine + (fine - middle) / factor
    error = abs(fine - extrapolated)
    observed = None
    if len(values) == 3:
        coarse_pair = middle + (middle - values[0]) / factor
        error = max(error, abs(extrapolated - coarse_pair))
        first, second = values[1] - values[0], values[2] - values[1]
        if first != 0 and second != 0 and (first > 0) == (second > 0):
            observed = math.log(first / second) / math.log(ratio)
    return Extrapolation(values=values, extrapolated=extrapolated, error_estimate=error, observed_order=observed,
                         formal_order=order)


def refined_configs(config: RunConfig, grids: int, base_dir: Any = None) -> list[RunConfig]:
    """The configuration on ``grids`` grids N / 2^(grids-1), ..., N (coarse to fine), each validated.

    Raises
    ------
    ConfigError
        If ``grids`` is not 2 or 3, N is not divisible by 2^(grids-1), or a
        coarse grid is not a valid run (a pillar under 2 elements, a contact
        under resolved): the message names the grid.
    """
    if grids not in (2, 3):
        raise ConfigError([f"`--refine`: {grids} — must be 2 or 3 grids"])
    elements = config.grid.elements
    step = 2 ** (grids - 1)
    if elements % step:
        raise ConfigError([(f"`grid.elements`: {elements} — must be divisible by {step} to refine on {grids} grids "
                           f"(N / {step} is the coarsest)")])
    mapping = config_to_dict(config)
    out = []
    for k in range(grids - 1, -1, -1):
        coarse = dict(mapping, grid={**mapping["grid"], "elements": elements // 2**k})
        try:
            out.append(parse_config(coarse, base_dir))
        except ConfigError as exc:
            raise ConfigError([(f"the refinement's grid N = {elements // 2**k} (N / {2**k}) is not a valid run; "
                               f"use fewer grids or a finer grid.elements:"), *exc.problems]) from None
    return out


def refined_run(config: RunConfig, grids: int = 3, *, run: Callable | None = None,
                progress: Callable[[float, str], None] | None = None):
    """Run ``config`` on ``grids`` grids; the finest (configured) result with ``summary.refinement`` added.

    Returns ``(result, reference)`` as `brushbem.case.run_case` does, for the
    configured grid.  A coarse grid's run that does not converge makes the
    refinement ``converged = False`` (and the extrapolation is still
    reported, marked so).
    """
    from . import case as case_module

    run = case_module.run_case if run is None else run
    configs = refined_configs(config, grids)
    results = []
    for index, cfg in enumerate(configs):
        def report(fraction, message, index=index, elements=cfg.grid.elements):
            if progress is not None:
                progress((index + fraction) / len(configs), f"grid N = {elements}: {message}")
        results.append(run(cfg, progress=report))
    finest, reference = results[-1]
    summaries = [result.summary for result, _ in results]
    converged = all(bool(s.get("converged")) for s in summaries)
    refinement = Refinement(
        elements=[cfg.grid.elements for cfg in configs],
        adhesive_force=richardson([s["adhesive_force"] for s in summaries]),
        work_of_separation=richardson([s["work_of_separation"] for s in summaries]),
        converged=converged,
    )
    return _with_refinement(finest, refinement), reference


def _with_refinement(result, refinement: Refinement):
    import dataclasses

    summary = result.summary
    if isinstance(summary, Mapping) and hasattr(summary, "__dataclass_fields__"):
        summary = dataclasses.replace(summary, refinement=refinement)
    return dataclasses.replace(result, summary=summary)
