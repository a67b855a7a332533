"""Mesh error bars: a case on two or three grids, Richardson-extrapolated (``brushbem run --refine``).

The Pohrt-Popov criterion converges at first order in the element size h
(the mesh criterion Sigma_c ~ h^-1/2 resolves the crack-tip field over one
element): JKR at a / h = 39 is still 4.4 % strong.  A single grid therefore
says little about its own error.  `refined_run` runs the configured case on
the grids N / 2^k, ..., N / 2, N (``grids`` of them, the configured one the
finest) and reports, for the adhesive force and the work of separation:

* ``values``: on each grid, coarse to fine;
* ``observed_order``: p = log2((f1 - f2) / (f2 - f3)) from three grids (None
  from two grids, or when the differences change sign: no asymptotic range);
* ``order`` and ``basis``: the order the extrapolation used.  The observed
  one (``basis = "observed order"``) when it lies in `ASYMPTOTIC_ORDERS`,
  the band around the formal first order in which the sequence is taken to
  be in its asymptotic range (JKR's sequences give 0.8); else the formal
  order 1, and ``basis`` says why (two grids observe no order; an order
  outside the band, e.g. 1.8 for a punch's work from r / h = 8, or
  differences of changing sign, mean the coarse grid is not yet asymptotic,
  and an observed order there would amplify that noise);
* ``extrapolated``: f* = f_N + (f_N - f_N/2) / (2^p - 1) with that order;
* ``error_estimate``: a bound on |f* - exact| from three grids (None from two:
  two grids cannot bound it, below), conservative by design: the
  largest of the Richardson correction |f_N - f*|, and with three grids the
  change of the formal-order extrapolation between the coarser and the finer
  pair and the difference between the observed-order and the formal-order
  extrapolations.  A rasterised circle's staircase adds an error that is not
  smooth in h (Kendall's punch: +2.0, +5.8, +6.3, +2.2, +0.5, +0.7 % at
  r / h = 2 to 64, `docs/reproduction/probe_refine.py`); the three-grid bound
  covers it where the extrapolation alone would not.  Two grids cannot see
  it (a punch of r / h = 32 and 64 extrapolates to +0.8 %, 5.5 times its own
  correction, further from Kendall than the fine grid): they give the
  formal-order extrapolation and no bound, which ``basis`` and a warning say.

Every grid must resolve the length that decides F_A (a punch's or pillar's
radius, a sphere's or spherical cap's JKR contact radius) by at least
`MIN_REFINE_ELEMENTS` elements: below that the sequence is not monotone
(the punch above rises from r / h = 2 to 8), and no two- or three-grid
estimate bounds the error (a punch at N = 16 and 8 gave an estimate 2.5
times too small).  A random layout is held fixed across the grids: its
``min_gap``, whose default is 2 h, is set to the finest grid's value, and
the grids' pillar centres and lengths are checked to be equal.

The pillar model (``protocol.method = "pillars"``) refines its tips alone
(`brushbem.pillars.tips`): the configured grid places the pillars, and the
tips run at q0, 2 q0 and 4 q0 elements per radius (``pillar_tip_resolution``;
the global grid subdivided f0, 2 f0, 4 f0 times), q0 the configured tips'
resolution, or the smallest multiple of the grid's that reaches
`MIN_REFINE_ELEMENTS`: a brush at the shipped 3-4 elements per radius
refines with no finer global grid.  Its result is the configured run's (the
tips as configured), with the refinement added; ``elements`` are the global
grids that would resolve the tips as much (N f), ``tip_elements_per_radius``
the tips'.  The exact paths hold their tips on the global grid and keep the
grid refinement above: below `MIN_REFINE_ELEMENTS` on the coarsest grid they
refuse, as no two- or three-grid estimate bounds their error there.

The tests check the bound on Kendall's and JKR's closed forms and on a punch
on a spring (``tests/test_refine.py``), and the tips' refinement of a brush on
its grid (``tests/test_pillar_tips.py``).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from typing import TYPE_CHECKING, Any

from brushbem.runs.assembly import parse_config
from brushbem.config import ConfigError, RunConfig, config_to_dict
from brushbem.results.refinement import FORMAL_ORDER, Extrapolation, Refinement
from brushbem.config.advice import deciding_length

if TYPE_CHECKING:
    from brushbem.runs.pulloff import PullOff

__all__ = ["ASYMPTOTIC_ORDERS", "FORMAL_ORDER", "MIN_REFINE_ELEMENTS", "Extrapolation", "Refinement",
           "refined_configs", "refined_run", "richardson"]

#: Observed orders taken as the asymptotic range of a first-order method: within a factor 2 of
#: FORMAL_ORDER at the low end (JKR: 0.8) and half an order above it (a punch's F_A from r / h = 8:
#: 1.27; its work from there, 1.8, is still pre-asymptotic and extrapolates 6 times worse than the
#: formal order).
ASYMPTOTIC_ORDERS = (0.5, 1.5)

#: Fewest elements across the length that decides F_A on every grid of a refinement (the
#: punch's F_A sequence is monotone from r / h = 8 on; module docstring).
MIN_REFINE_ELEMENTS = 8.0


def _extrapolate(fine: float, middle: float, ratio: float, order: float) -> float:
    return fine + (fine - middle) / (ratio**order - 1.0)


def richardson(values: Sequence[float], ratio: float = 2.0, order: float = FORMAL_ORDER) -> Extrapolation:
    """Richardson extrapolation of ``values`` on grids refined by ``ratio`` (coarse to fine; 2 or 3 values).

    ``order`` is the formal order; three values use the observed order instead
    when it lies in `ASYMPTOTIC_ORDERS` (scaled by ``order``).
    """
    values = [float(v) for v in values]
    if len(values) not in (2, 3) or not all(math.isfinite(v) for v in values):
        raise ValueError(f"richardson needs 2 or 3 finite values, got {values}")
    fine, middle = values[-1], values[-2]
    formal = _extrapolate(fine, middle, ratio, order)
    if len(values) == 2:
        # Two grids cannot tell the asymptotic range from the staircase of a rasterised edge: a punch of
        # r / h = 32 and 64 extrapolates 5.5 x its own correction away from Kendall.  No bound is claimed.
        return Extrapolation(values=values, extrapolated=formal, error_estimate=None,
                             observed_order=None, order=order, formal_order=order,
                             basis="formal order (two grids observe no order: no error bound)")
    coarse_pair = _extrapolate(middle, values[0], ratio, order)
    spread = abs(formal - coarse_pair)
    first, second = values[1] - values[0], values[2] - values[1]
    observed = None
    if first != 0 and second != 0 and (first > 0) == (second > 0):
        observed = math.log(first / second) / math.log(ratio)
    low, high = ASYMPTOTIC_ORDERS
    if observed is not None and low * order <= observed <= high * order:
        best = _extrapolate(fine, middle, ratio, observed)
        return Extrapolation(values=values, extrapolated=best, observed_order=observed, order=observed,
                             basis="observed order", formal_order=order,
                             error_estimate=max(abs(fine - best), abs(best - formal), spread))
    if second == 0:
        basis = "formal order (the two finest grids agree)"
    elif observed is None:
        basis = "formal order (the differences change sign: no asymptotic range)"
    else:
        basis = (f"formal order (observed {observed:.2f}, outside {low * order:g} to {high * order:g}: "
                 "no asymptotic range)")
    return Extrapolation(values=values, extrapolated=formal, error_estimate=max(abs(fine - formal), spread),
                         observed_order=observed, order=order, basis=basis, formal_order=order)


def refined_configs(config: RunConfig, grids: int, base_dir: Any = None) -> list[RunConfig]:
    """The configuration on ``grids`` grids N / 2^(grids-1), ..., N (coarse to fine), each validated.

    A random layout's default ``min_gap`` (2 h) is fixed at the finest grid's
    value, so every grid places the same pillars.

    Raises
    ------
    ConfigError
        If ``grids`` is not 2 or 3, N is not divisible by 2^(grids-1), a
        coarse grid is not a valid run (a pillar under 2 elements, a contact
        under resolved), the coarsest grid resolves the length that decides
        F_A by fewer than `MIN_REFINE_ELEMENTS` elements, or the grids'
        brushes differ (pillar centres or lengths): the message names the
        grid and the key.
    """
    if grids not in (2, 3):
        raise ConfigError([f"`--refine`: {grids} — must be 2 or 3 grids"])
    if config.protocol.method == "pillars":
        return tip_configs(config, grids)
    elements = config.grid.elements
    step = 2 ** (grids - 1)
    if elements % step:
        raise ConfigError([(f"`grid.elements`: {elements} — must be divisible by {step} to refine on {grids} grids "
                           f"(N / {step} is the coarsest)")])
    mapping = config_to_dict(config)
    indenter = dict(mapping["indenter"])
    if indenter.get("shape") == "brush" and indenter.get("layout") == "random" and indenter.get("min_gap") is None:
        indenter["min_gap"] = 2.0 * config.grid.element_size
    mapping = dict(mapping, indenter=indenter)
    out = []
    for k in range(grids - 1, -1, -1):
        coarse = dict(mapping, grid={**mapping["grid"], "elements": elements // 2**k})
        try:
            out.append(parse_config(coarse, base_dir))
        except ConfigError as exc:
            raise ConfigError([(f"the refinement's grid N = {elements // 2**k} (N / {2**k}) is not a valid run; "
                               f"use fewer grids or a finer grid.elements:"), *exc.problems]) from None
    _check_resolution(out[0], elements // step, step)
    _check_same_brush(out)
    return out


def tip_configs(config: RunConfig, grids: int) -> list[RunConfig]:
    """The pillar model's refinement (module docstring): the configuration with its tips at q0, 2 q0 (, 4 q0)
    elements per radius, on the configured grid."""
    from brushbem.runs.assembly import build_indenter

    per_radius = float(build_indenter(config).description.pillar_radius) / config.grid.element_size
    configured = config.protocol.pillar_tip_resolution
    first = 1 if configured is None else max(1, math.ceil(configured / per_radius * (1 - 1e-12)))
    if first * per_radius < MIN_REFINE_ELEMENTS:
        first = math.ceil(MIN_REFINE_ELEMENTS / per_radius * (1 - 1e-12))
    # Only the tips' resolution changes (>= MIN_REFINE_ELEMENTS, inside its range): the validated
    # configuration with that one key replaced.
    return [config.model_copy(update={"protocol": config.protocol.model_copy(
        update={"pillar_tip_resolution": first * 2**k * per_radius})}) for k in range(grids)]


def _check_resolution(coarsest: RunConfig, elements: int, step: int) -> None:
    pillar = None
    if coarsest.indenter.shape == "brush":
        from brushbem.runs.assembly import build_indenter

        pillar = float(build_indenter(coarsest).description.pillar_radius)  # as built (a clustered layout's)
    decided = deciding_length(coarsest, pillar)
    if decided is None:
        return
    key = decided.key if decided.what in ("punch radius", "pillar radius") else f"{decided.key} (its {decided.what})"
    length = decided.value
    spans = length / coarsest.grid.element_size
    if spans < MIN_REFINE_ELEMENTS:
        finer = math.ceil(MIN_REFINE_ELEMENTS / spans * elements) * step
        raise ConfigError([(
            f"`{key}`: {length:.4g} spans {spans:.3g} elements on the refinement's coarsest grid N = {elements} "
            f"(h = {coarsest.grid.element_size:g}); a refinement needs at least {MIN_REFINE_ELEMENTS:g} there, "
            "where the mesh error decreases steadily (below it no error estimate bounds the error): "
            f"use grid.elements >= {finer} or fewer grids")])


def _check_same_brush(configs: Sequence[RunConfig]) -> None:
    if configs[0].indenter.shape != "brush":
        return
    import numpy as np

    from brushbem.runs.assembly import build_indenter

    geometries = [build_indenter(cfg).description for cfg in configs]
    finest = geometries[-1]
    for cfg, geometry in zip(configs[:-1], geometries[:-1], strict=True):
        same = (geometry.centres.shape == finest.centres.shape
                and np.allclose(geometry.centres, finest.centres, rtol=0, atol=1e-12 * cfg.grid.size)
                and np.allclose(geometry.offsets, finest.offsets, rtol=0, atol=1e-12 * cfg.grid.size))
        if not same:
            raise ConfigError([(
                f"`indenter.layout`: {cfg.indenter.layout!r} — the brush on the refinement's grid "
                f"N = {cfg.grid.elements} differs from the one on N = {configs[-1].grid.elements} (pillar centres "
                "or lengths): a refinement must compare the same brush; give the layout explicitly "
                "(e.g. min_gap, lengths_file) or refine without it")])


def refined_run(config: RunConfig, grids: int = 3, *, run: Callable | None = None,
                progress: Callable[[float, str], None] | None = None,
                stop: Callable[[], bool] | None = None) -> PullOff:
    """Run ``config`` on ``grids`` grids; the finest (configured) result with ``summary.refinement`` added.

    Returns the `PullOff` of the configured grid, as `brushbem.runs.case.run_case`
    does, with the ``config`` as given.  ``run`` (`brushbem.runs.case.run_case` by
    default) is called as ``run(config, progress=...)``, with ``stop=`` too
    where ``stop`` is given.  A coarse grid's run that does not converge makes
    the refinement ``converged = False`` (and the extrapolation is still
    reported, marked so).
    """
    import dataclasses

    from brushbem.runs import case as case_module

    run = case_module.run_case if run is None else run
    configs = refined_configs(config, grids)
    tips = config.protocol.method == "pillars"
    # The pillar model refines its tips: the configured run too, where it is none of the refinement's.
    runs = [*configs, config] if tips and config not in configs else configs
    results = []
    for index, cfg in enumerate(runs):
        label = (f"tips at {_tip_resolution(cfg):.3g} elements per radius" if tips
                 else f"grid N = {cfg.grid.elements}")

        def report(fraction, message, index=index, label=label):
            if progress is not None:
                progress((index + fraction) / len(runs), f"{label}: {message}")
        results.append(run(cfg, progress=report) if stop is None else run(cfg, progress=report, stop=stop))
    finest = results[runs.index(config)] if tips else results[-1]
    summaries = [pulled.result.summary for pulled in results[:len(configs)]]
    converged = all(bool(s.get("converged")) for s in summaries)
    per_radius = [_tip_resolution(cfg) for cfg in configs] if tips else None
    refinement = Refinement(
        elements=[cfg.grid.elements * (_tip_factor(cfg) if tips else 1) for cfg in configs],
        adhesive_force=richardson([s["adhesive_force"] for s in summaries]),
        work_of_separation=richardson([s["work_of_separation"] for s in summaries]),
        converged=converged,
        tip_elements_per_radius=per_radius,
    )
    # The configuration as given (the finest grid's may fix a random layout's min_gap): what the files record.
    return dataclasses.replace(finest, result=_with_refinement(finest.result, refinement), config=config)


def _tip_resolution(config: RunConfig) -> float:
    """The tips' elements per radius of a pillar-model run (`brushbem.pillars.tips`)."""
    from brushbem.runs.assembly import build_indenter

    per_radius = float(build_indenter(config).description.pillar_radius) / config.grid.element_size
    return _tip_factor(config) * per_radius


def _tip_factor(config: RunConfig) -> int:
    """How many times the tips subdivide the grid in a pillar-model run."""
    from brushbem.runs.assembly import build_indenter

    resolution = config.protocol.pillar_tip_resolution
    if resolution is None:
        return 1
    per_radius = float(build_indenter(config).description.pillar_radius) / config.grid.element_size
    return max(1, math.ceil(resolution / per_radius * (1 - 1e-12)))


def _with_refinement(result, refinement: Refinement):
    import dataclasses

    summary = result.summary
    if isinstance(summary, Mapping) and hasattr(summary, "__dataclass_fields__"):
        notes = [f"--refine: {label}: extrapolated with the {entry.basis}"
                 for label, entry in (("F_A", refinement.adhesive_force),
                                      ("work of separation", refinement.work_of_separation))
                 if entry.basis != "observed order"]
        if len(refinement.elements) == 2:
            notes = ["--refine 2: two grids observe no order of convergence and bound no error (the "
                     "extrapolation assumes the formal first order, which a rasterised edge's staircase breaks): "
                     "refine on three grids (--refine 3) for an error bound"]
        summary = dataclasses.replace(summary, refinement=refinement, warnings=[*summary.warnings, *notes])
    return dataclasses.replace(result, summary=summary)
