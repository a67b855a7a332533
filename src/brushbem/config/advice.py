"""What a valid configuration is warned of before it runs: inputs far outside the physical range, and the
discretisation error its resolution carries.

Neither refuses a run: `brushbem validate` prints the warnings after "ok", `brushbem run` prints them and
records them in ``summary.json`` (``warnings``), and every run records its `Resolution` (``resolution``).

* `plausibility_warnings`: with ``[units]``, a work of adhesion above 1 J/m^2 (van der Waals and
  hydrogen-bonded adhesion lie between about 1 mJ/m^2 and 0.1 J/m^2), a modulus below 1 kPa or above
  1 TPa (the softest gels and diamond), a pillar, punch or fibril radius under 1 nm: each names the
  likely slip of units ("did you mean 0.04 MPa um = 40 mJ/m^2?").  The bounds are ours (the thesis
  states none): a factor 10 or more beyond any adhesive a designer builds.
* `resolution`: the elements across the length that decides F_A (a flat punch's or a pillar's radius,
  a sphere's or a spherical cap's JKR contact radius at pull-off) and the discretisation error of F_A
  and the work at that resolution, read from the measured table ``brushbem/data/resolution_error.csv``
  (`benchmarks/resolution_error.py`: a flat punch on a spring against Kendall, at the radius typed), and
  for a sphere or a spherical cap from ``sphere_resolution_error.csv`` (a rigid JKR sphere against JKR; it
  converges at first order, +20 % at 8 and +6.4 % at 24 elements across a_JKR); a brush's F_A from
  ``brush_resolution_error.csv`` (the flat 8 x 8 brush against the continuum limit, ``docs/pillars/limit.py``:
  +3.7 % at 3.6, +1.8 % at 14.4, +1.4 % at 28.9, +1.2 % at 39.7 elements per radius, where a lone punch is
  +1 % at 32; beyond its finest row, that row's).
  Below `MIN_ELEMENTS_PER_RADIUS` `resolution_warnings` warns with the estimate and the fix.
"""

from __future__ import annotations

import csv
import functools
import math
from dataclasses import dataclass
from importlib.resources import files
from typing import TYPE_CHECKING, Any

from brushbem.physics.scales import jkr_contact_radius
from brushbem.results.design import ResolutionRecord

if TYPE_CHECKING:
    from brushbem.config.schema import RunConfig

__all__ = ["MIN_ELEMENTS_PER_RADIUS", "DecidingLength", "Resolution", "advice", "deciding_length", "fibril_radius", "plausibility_warnings", "resolution",
           "resolution_warnings"]

#: Fewest elements across the deciding radius without a warning: ours (the thesis states none).  At 8 the
#: measured F_A error of a flat punch lies between -0.6 % and +7.1 % by where the circle's staircase falls
#: (``resolution_error.csv``), at 4 between -9 % and +13 %, at 16 between +0.9 % and +3.3 %.
MIN_ELEMENTS_PER_RADIUS = 8.0

#: Physical ranges (SI) beyond which an input is taken for a slip of units: ours (the thesis states none).
WORK_OF_ADHESION_MAX = 1.0       # J/m^2
MODULUS_RANGE = (1e3, 1e12)      # Pa
RADIUS_MIN = 1e-9                # m

_LENGTH_EXPONENT = {"m": 0, "cm": -2, "mm": -3, "um": -6, "nm": -9}
_STRESS_EXPONENT = {"Pa": 0, "kPa": 3, "MPa": 6, "GPa": 9}
_SHOWN_LENGTH = {"um": "µm"}


#: The resolution of the deciding length and its estimated error: the ``resolution`` record of ``summary.json``.
Resolution = ResolutionRecord


#: The measured tables: a flat punch's (``resolution_error.csv``) and a JKR sphere's.
PUNCH_TABLE, SPHERE_TABLE = "resolution_error.csv", "sphere_resolution_error.csv"
#: A brush's own F_A error (``brush_resolution_error.csv``, ``docs/pillars/limit.py``): the flat 8 x 8 brush at
#: k~ = 1e-5 against the continuum limit, where it is known to 1.0 % (``docs/pillars/limit.py``: the tips' first-order
#: continuum peel below, ``front_brush.csv``, the edge tips' capacity at 80 elements per radius above).  A brush's
#: F_A converges more slowly than a lone punch's (its tips peel in their neighbours' field): at 28.9 elements per
#: radius +1.6 % (the punch's +1 %), so a brush's F_A error is read from it.
BRUSH_TABLE = "brush_resolution_error.csv"
#: The same brush with its tips leaving at their continuum capacity (``protocol.pillar_tip_peel``,
#: ``brush_peel_error.csv``, ``docs/pillars/peel.py``), and the coarsest tips it was measured at: there its
#: placements' mean is the limit's middle (0.0 %), every placement within -1.2 .. +0.7 % between the limit's bounds
#: (1.0 % apart), so no warning at or above it.
PEEL_TABLE, PEEL_MIN_ELEMENTS = "brush_peel_error.csv", 3.6
#: A rough brush's (``rough_error.csv``, ``docs/pillars/rough.py``): the rough 8 x 8 family at k~ = 10 .. 1e-5
#: against the ends of its limit (the option's tips at 28.9 elements per radius below, the raster's finest above).
#: Where F_A is a tenth to a quarter of F_c (k~ = 1, 0.1) the tips move it by several per cent at every
#: resolution measured, so a rough brush's range is the union of the flat brush's and this one, and the option's
#: 3.6 elements per radius do not resolve it (the warning stays below `MIN_ELEMENTS_PER_RADIUS`).
ROUGH_TABLE = "rough_error.csv"


@functools.cache
def _table(name: str = PUNCH_TABLE) -> tuple[dict[str, float], ...]:
    text = files("brushbem.data").joinpath(name).read_text(encoding="utf-8")
    rows = csv.DictReader(line for line in text.splitlines() if not line.startswith("#"))
    return tuple({key: float(value) for key, value in row.items() if value != ""} for row in rows)


def _interpolated(elements: float, column: str, name: str = PUNCH_TABLE) -> float:
    """The table's ``column`` at ``elements`` per radius: linear in log q inside, first order in h beyond (the
    brush's table: its last row beyond, its error falling with no order established)."""
    rows = _table(name)
    first, last = rows[0], rows[-1]
    if elements <= first["elements_per_radius"]:
        return first[column]
    if elements >= last["elements_per_radius"]:
        return last[column] if name in (BRUSH_TABLE, ROUGH_TABLE) else \
            last[column] * last["elements_per_radius"] / elements
    for low, high in zip(rows, rows[1:], strict=False):
        if low["elements_per_radius"] <= elements <= high["elements_per_radius"]:
            t = (math.log(elements / low["elements_per_radius"])
                 / math.log(high["elements_per_radius"] / low["elements_per_radius"]))
            return (1 - t) * low[column] + t * high[column]
    raise AssertionError("unreachable: the table's rows are increasing")


@dataclass(frozen=True)
class DecidingLength:
    """The length that decides F_A's resolution: what it is, the key it comes from, its value (units of length)."""

    what: str
    key: str
    value: float


def deciding_length(config: RunConfig, pillar_radius: float | None = None) -> DecidingLength | None:
    """The length that decides F_A's resolution, stated once (the run's `resolution`, the refinement's check).

    A flat punch's radius; a sphere's JKR contact radius at pull-off (eq. 2.20b; None without adhesion);
    a brush's pillar radius (``pillar_radius``: as built, where known, which a clustered layout derives;
    else from ``indenter.filling_factors``), or with spherical-cap tips the smaller of it and the cap's JKR
    radius (the smallest cap of a per-pillar file); None for a height map.
    """
    indenter, halfspace = config.indenter, config.halfspace
    modulus, dgamma = halfspace.effective_modulus, halfspace.work_of_adhesion

    def jkr(radius: float) -> float:  # eq. 2.20b
        return jkr_contact_radius(radius, modulus, dgamma)

    if indenter.shape == "flat_punch" and indenter.radius is not None:
        return DecidingLength("punch radius", "indenter.radius", float(indenter.radius))
    if indenter.shape == "sphere" and indenter.radius is not None:
        return DecidingLength("JKR contact radius at pull-off", "indenter.radius", jkr(float(indenter.radius))) \
            if dgamma > 0 else None
    if indenter.shape != "brush":
        return None
    radius, key = pillar_radius, "indenter.pillar_radius"
    if radius is None:
        radius = indenter.pillar_radius
    if radius is None and indenter.filling_factors and indenter.pillars_per_side:
        region = indenter.region_size or config.grid.size
        radius = region / indenter.pillars_per_side * math.sqrt(math.prod(indenter.filling_factors) / math.pi)
        key = "indenter.filling_factors"
    if radius is None:
        return None
    tip = indenter.tip
    if tip is not None and tip.shape == "spherical_cap" and tip.radius is not None and dgamma > 0:
        cap = jkr(_smallest_cap(tip.radius))
        if cap < radius:
            return DecidingLength("JKR contact radius of the tip at pull-off", "indenter.tip.radius", cap)
    return DecidingLength("pillar radius", key, float(radius))


def _smallest_cap(radius: float | str) -> float:
    """A cap radius, or the smallest of a per-pillar file's."""
    if not isinstance(radius, str):
        return float(radius)
    import numpy as np

    return float(np.min(np.load(radius, allow_pickle=False)))


def fibril_radius(config: RunConfig) -> float | None:
    """The radius of ``indenter.fibril``: its own, or the pillar's or punch's it takes by default."""
    from brushbem.config.sections_indenter import _fibril_default_radius

    fibril = config.indenter.fibril
    if fibril is None:
        return None
    return fibril.radius or _fibril_default_radius(config.indenter)


def _record(what: str, key: str, value: float, elements: float, force: float, force_range: tuple[float, float],
            work: float | None, work_range: tuple[float, float] | None, basis: str,
            minimum: float = MIN_ELEMENTS_PER_RADIUS) -> ResolutionRecord:
    return ResolutionRecord(length=what, key=key, value=value, elements=elements, minimum_elements=minimum,
                            force_error_estimate=force, force_error_range=list(force_range), work_error_estimate=work,
                            work_error_range=None if work_range is None else list(work_range), basis=basis)


def resolution(config: RunConfig) -> ResolutionRecord | None:
    """The resolution of the deciding length and its estimated error, or None where none decides."""
    found = deciding_length(config) if config.halfspace.work_of_adhesion > 0 else None
    if found is None:
        return None
    what, key, value = found.what, found.key, found.value
    elements = value / config.grid.element_size * _tip_factor(config, value)
    if what.startswith("JKR"):
        error = _interpolated(elements, "force_error", SPHERE_TABLE)
        work = _interpolated(elements, "work_error", SPHERE_TABLE) if what == "JKR contact radius at pull-off" \
            else None
        return _record(what, key, value, elements, error, (error, error), work,
                       None if work is None else (work, work),
                       "a rigid JKR sphere at this many elements across a_JKR against JKR (eq. 2.20, 2.37; "
                       "benchmarks/resolution_error.py --sphere)")
    if what == "pillar radius" and _rough(config):
        smooth = _smooth_resolution(config, what, key, value, elements)
        column = "peel" if _tips_peel(config) else "raster"
        low = _interpolated(elements, f"{column}_force_error_min", ROUGH_TABLE)
        high = _interpolated(elements, f"{column}_force_error_max", ROUGH_TABLE)
        return _record(
            what, key, value, elements, smooth.force_error_estimate,
            (min(low, smooth.force_error_range[0]), max(high, smooth.force_error_range[1])),
            smooth.work_error_estimate,
            None if smooth.work_error_range is None else tuple(smooth.work_error_range),
            f"{smooth.basis}; the range with a rough brush's: the rough 8 x 8 family (sigma~ = 1) at k~ = 10 .. 1e-5 "
            f"between its limit's ends, {_percent(low)} .. {_percent(high)} at this resolution (docs/pillars/rough.py)")
    return _smooth_resolution(config, what, key, value, elements)


def _rough(config: RunConfig) -> bool:
    """Whether the brush's pillars have lengths of their own (roughness, or a lengths file)."""
    indenter = config.indenter
    return indenter.shape == "brush" and (
        (indenter.roughness is not None and indenter.roughness.sigma > 0) or indenter.lengths_file is not None)


def _smooth_resolution(config: RunConfig, what: str, key: str, value: float, elements: float) -> ResolutionRecord:
    """`resolution`'s record from the level brush's (or the lone punch's) tables."""
    if what == "pillar radius" and _tips_peel(config):
        return _record(
            what, key, value, elements, _interpolated(elements, "force_error_mean", PEEL_TABLE),
            (_interpolated(elements, "force_error_min", PEEL_TABLE), _interpolated(elements, "force_error_max", PEEL_TABLE)),
            _interpolated(elements, "work_error_mean", PEEL_TABLE),
            (_interpolated(elements, "work_error_min", PEEL_TABLE), _interpolated(elements, "work_error_max", PEEL_TABLE)),
            "F_A: the flat 8 x 8 brush at k~ = 1e-5, its tips leaving at their continuum capacity, at this many "
            "elements per pillar radius against the continuum limit (its middle; the range: every placement of the "
            "lattice on the raster between the limit's bounds; at k~ = 10 -0.75 .. +1.04 % at 3.6; a random layout "
            "within 1 % of both ends of its continuum limit, +0.33 / -0.87 %: docs/pillars/peel.py); the work: its "
            "placements against their mean at 14.4 elements per radius",
            minimum=PEEL_MIN_ELEMENTS)
    work = _interpolated(elements, "work_error_mean")
    if what == "pillar radius":
        return _record(
            what, key, value, elements, _interpolated(elements, "force_error_mean", BRUSH_TABLE),
            (_interpolated(elements, "force_error_min", BRUSH_TABLE),
             _interpolated(elements, "force_error_max", BRUSH_TABLE)), work,
            (_interpolated(elements, "work_error_min"), _interpolated(elements, "work_error_max")),
            "F_A: the flat 8 x 8 brush at k~ = 1e-5 at this many elements per pillar radius against the continuum "
            "limit (its middle; the range: every placement of the lattice on the raster between the limit's bounds; "
            "docs/pillars/limit.py); the work: a flat punch on a spring against eq. 2.18-2.19 "
            "(benchmarks/resolution_error.py)")
    force = _interpolated(elements, "force_error_mean")
    return _record(
        what, key, value, elements, force,
        (_interpolated(elements, "force_error_min"), _interpolated(elements, "force_error_max")), work,
        (_interpolated(elements, "work_error_min"), _interpolated(elements, "work_error_max")),
        "a flat punch on a spring at this many elements per radius against Kendall (eq. 2.4, 2.18-2.19), "
        "mean and range over radii within 10 % (benchmarks/resolution_error.py)")


def _tips_peel(config: RunConfig) -> bool:
    """Whether the tips leave at their continuum capacity (``protocol.pillar_tip_peel``)."""
    return config.protocol.method == "pillars" and config.protocol.tip_peel


def _tip_factor(config: RunConfig, length: float) -> int:
    """How many times the pillar model subdivides the grid for its tips (``protocol.pillar_tip_resolution``,
    `brushbem.pillars.tips`): 1 for every other method and by default."""
    tips = config.protocol.pillar_tip_resolution if config.protocol.method == "pillars" else None
    if tips is None:
        return 1
    return max(1, math.ceil(tips / (length / config.grid.element_size) * (1 - 1e-12)))


def _percent(value: float) -> str:
    return f"{100 * value:+.2g} %"


def resolution_warnings(config: RunConfig) -> list[str]:
    """A warning with the estimated error and the fix where the deciding length spans < 8 elements."""
    found = resolution(config)
    if found is None or found.resolved:
        return []
    needed = math.ceil(config.grid.elements * MIN_ELEMENTS_PER_RADIUS / found.elements)
    if _tips_peel(config):
        fix = (f"set protocol.pillar_tip_resolution = {found.minimum_elements:g} or more (the tips on a raster of "
               "their own, measured there)")
    elif config.protocol.method == "pillars":
        # The pillar model resolves its tips apart from the grid.
        fix = ("leave protocol.pillar_tip_peel unset or true (the default: the tips leave at their continuum "
               "capacity; the flat brush within 1 % of its limit at 3.6 elements per radius, docs/pillars/peel.py), or "
               f"protocol.pillar_tip_resolution = {2 * MIN_ELEMENTS_PER_RADIUS:g} or more (the tips on a raster "
               "of their own; the grid only places the pillars), or run with --refine 3 for an extrapolated F_A "
               "with its error bar (the tips alone refined)")
    else:
        fix = (f"raise grid.elements to {needed} or more, or to {2 * needed} with --refine 2 for an extrapolated "
               f"F_A with its error bar (its coarser grid needs {MIN_ELEMENTS_PER_RADIUS:g} per radius too)")
    low, high = found.force_error_range
    spread = "" if low == high else f", between {_percent(low)} and {_percent(high)} by where the circle's staircase falls"
    work = ("" if found.work_error_estimate is None
            else f"; the work of separation about {_percent(found.work_error_estimate)}")
    return [f"{found.key}: the {found.length}, {found.value:.4g}, spans {found.elements:.3g} elements (h = "
            f"{config.grid.element_size:.4g}), under {MIN_ELEMENTS_PER_RADIUS:g}: F_A carries a discretisation error of "
            f"about {_percent(found.force_error_estimate)}{spread}{work} ({found.basis}); {fix}"]


def _slip(value: float, unit: str, factor: float, meant: str) -> str:
    return f"did you mean {value * factor:.3g} {unit} = {value:g} {meant}?"


def plausibility_warnings(config: RunConfig) -> list[str]:
    """Inputs in ``[units]`` far outside the physical range, each with the likely slip of units.

    Without ``[units]`` the numbers have no unit to judge them by, and nothing is said.
    """
    units = config.units
    if units.length is None or units.stress is None:
        return []
    length, stress = units.length, units.stress
    metres, pascals = 10.0 ** _LENGTH_EXPONENT[length], 10.0 ** _STRESS_EXPONENT[stress]
    shown = f"{stress}·{_SHOWN_LENGTH.get(length, length)}"
    warnings = []
    dgamma = config.halfspace.work_of_adhesion
    if dgamma * pascals * metres > WORK_OF_ADHESION_MAX:
        si = dgamma * pascals * metres
        warnings.append(
            f"halfspace.work_of_adhesion = {dgamma:g} {shown} = {si:.3g} J/m², above the {WORK_OF_ADHESION_MAX:g} J/m² "
            "of any adhesion by surface forces (about 1 mJ/m² to 0.1 J/m²): "
            f"{_slip(dgamma, shown, 1e-3 / (pascals * metres), 'mJ/m²')} (energy per area in these units is "
            f"{stress} × {_SHOWN_LENGTH.get(length, length)}; 1 {shown} = {pascals * metres:g} J/m²)")
    moduli = [("halfspace.contact_modulus", config.halfspace.contact_modulus),
              ("halfspace.youngs_modulus", config.halfspace.youngs_modulus)]
    fibril = config.indenter.fibril
    if fibril is not None:
        moduli.append(("indenter.fibril.youngs_modulus", fibril.youngs_modulus))
    low, high = MODULUS_RANGE
    for key, value in moduli:
        if value is None:
            continue
        si = value * pascals
        if low <= si <= high:
            continue
        meant = min(_STRESS_EXPONENT, key=lambda unit: abs(math.log10(value * 10.0 ** _STRESS_EXPONENT[unit]) - 6))
        side = f"below {low:g} Pa (the softest gels)" if si < low else f"above {high:g} Pa (diamond)"
        warnings.append(f"{key} = {value:g} {stress} = {si:.3g} Pa, {side}: "
                        f"{_slip(value, stress, 10.0 ** _STRESS_EXPONENT[meant] / pascals, meant)}")
    radii = [("indenter.radius", config.indenter.radius if config.indenter.shape == "flat_punch" else None),
             ("indenter.pillar_radius", config.indenter.pillar_radius),
             ("indenter.fibril.radius", fibril.radius if fibril is not None else None)]
    shown_length = _SHOWN_LENGTH.get(length, length)
    for key, value in radii:
        if value is None or value * metres >= RADIUS_MIN:
            continue
        # The slip is a number typed in a larger unit than [units] names: the one that puts it nearest 1 um.
        larger = [unit for unit, exponent in _LENGTH_EXPONENT.items() if exponent > _LENGTH_EXPONENT[length]]
        meant = min(larger, key=lambda unit: abs(math.log10(value * 10.0 ** _LENGTH_EXPONENT[unit]) + 6), default=None)
        slip = ("check units.length" if meant is None else
                _slip(value, shown_length, 10.0 ** _LENGTH_EXPONENT[meant] / metres, _SHOWN_LENGTH.get(meant, meant)))
        warnings.append(f"{key} = {value:g} {shown_length} = {value * metres:.3g} m, under {RADIUS_MIN:g} m (a few "
                        f"atoms): {slip}")
    return warnings


def advice(config: RunConfig) -> list[str]:
    """Every warning of a valid configuration: `plausibility_warnings`, then `resolution_warnings`."""
    return [*plausibility_warnings(config), *resolution_warnings(config)]
