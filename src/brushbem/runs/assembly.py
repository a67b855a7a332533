"""Assembly: a validated configuration in, the problem and the load path out.

The layers import one way: `brushbem.config` (the schema: fields and the rules
between keys) <- this module <- `brushbem.runs.case`, `brushbem.sweep`,
`brushbem.cli`.  Here the configured indenter is rasterised, the rules that
need the rasterised structure run on it (`Rules`: a layout that cannot be
built, a preload that never reaches the lowest element, a spring coupling
that does not apply), structure errors are named by their configuration keys,
and the problem is built from the same rasterisation: a run rasterises its
indenter once.

`load_config` and `parse_config` are the complete check (the schema's with
these rules); `load` and `parse` also return the built `Assembly`.  Nothing
here imports the solver: ``brushbem validate`` loads neither it nor SciPy
(but for a concave profile, whose offsets come from `brushbem.physics.theory`).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from brushbem import config as schema
from brushbem.config import (
    MAX_PRELOAD_DOMAIN_SIZES,
    ConfigError,
    GridConfig,
    HalfSpaceConfig,
    IndenterConfig,
    Problem,
    RunConfig,
    show_value,
)
from brushbem.config.limits import SPRING_RESOLUTION_MARGIN, SPRING_ROUNDING_FLOOR
from brushbem.config.rules import PARAMETER_KEYS, configuration_key, configuration_text, parameter_problems
from brushbem.errors import ParameterError
from brushbem.physics.scales import stiffness_of_ratio
from brushbem.physics.structure import (
    Grading,
    Grid,
    Indenter,
    Level,
    Profile,
    StructureError,
    Tilt,
    Tip,
    brush,
    flat_punch,
    height_map,
    sphere,
)

if TYPE_CHECKING:
    from brushbem.protocol import ContactProblem, LoadPath

__all__ = [
    "PARAMETER_KEYS",
    "Assembly",
    "Rules",
    "assemble",
    "build_brush",
    "build_indenter",
    "build_path",
    "build_problem",
    "configuration_errors",
    "configuration_text",
    "load",
    "load_config",
    "parse",
    "parse_config",
]


@contextmanager
def configuration_errors() -> Iterator[None]:
    """Re-raise a numerics `ParameterError` as a `ConfigError` naming the configuration keys.

    For building or running from a configuration: every ``Owner.parameter`` of `PARAMETER_KEYS` in the
    message reads as its key, and the line starts with the key of the parameter at fault.  A
    `StructureError` passes unchanged (the rules on the structure report it by key before a run).
    """
    try:
        yield
    except StructureError:
        raise
    except ParameterError as exc:
        message = configuration_text(str(exc))
        key = configuration_key(exc)
        if key is not None and key not in message:
            message = f"{key}: {message}"
        raise ConfigError([message]) from exc


def brush_side(grid_config: GridConfig, indenter_config: IndenterConfig) -> float:
    """L of k~ = k / (E* L) (thesis eq. 4.13): the brush's side, ``indenter.region_size`` (a circle's diameter).

    The thesis's L is the side of the "square area L x L" the pillars are distributed in (L736), which is
    its whole domain; a domain padded around the brush keeps the brush's k~.  Without ``region_size`` the
    brush fills the domain and L = ``grid.size``, as in every committed study (their k~ are unchanged).
    """
    region_size = getattr(indenter_config, "region_size", None)
    return float(region_size) if region_size is not None else float(grid_config.size)


def build_brush(grid_config: GridConfig, indenter_config: IndenterConfig,
                halfspace_config: HalfSpaceConfig) -> Indenter:
    """The brush of the configuration sections (``shape = "brush"``).

    Converts the stiffness ratios k~ = k / (E* L), L the brush's side
    (``indenter.region_size``, by default ``grid.size``; eq. 4.13), to
    stiffnesses; a `StructureError` names the ``indenter`` key it comes from.
    A clustered layout (``layout = "clustered"``) derives its pillar radius
    from ``filling_factors`` and records the filling factor of every level as
    rasterised (`brushbem.physics.structure.BrushGeometry.level_filling_factors`).
    """
    spec = indenter_config
    grid = Grid(grid_config.size, grid_config.elements)
    modulus = halfspace_config.effective_modulus
    side = brush_side(grid_config, indenter_config)
    levels = tuple(
        Level(lv.cluster, lv.stiffness if lv.stiffness is not None
              else stiffness_of_ratio(lv.stiffness_ratio, modulus, side),
              _grading(lv.grading))
        for lv in (spec.levels or ())
    )
    lengths = np.load(spec.lengths_file, allow_pickle=False) if spec.lengths_file else None
    profile = None
    if spec.profile is not None:
        profile = Profile(spec.profile.amplification, spec.profile.reference_stress)
    try:
        return brush(
            grid,
            layout=spec.layout,
            pillar_radius=spec.pillar_radius,
            contact_modulus=modulus,
            work_of_adhesion=halfspace_config.work_of_adhesion,
            # k~ goes to the builder, which converts it once (k = k~ E* L, L its region's side = `brush_side`).
            stiffness=spec.stiffness if spec.stiffness_ratio is None else math.inf,
            stiffness_ratio=spec.stiffness_ratio,
            region=spec.region or "square",
            region_size=spec.region_size,
            pillars_per_side=spec.pillars_per_side,
            spacing=spec.spacing,
            pillar_count=spec.pillar_count,
            min_gap=spec.min_gap,
            seed=spec.seed or 0,
            roughness=spec.roughness.sigma if spec.roughness is not None else 0.0,
            profile=profile,
            lengths=lengths,
            levels=levels,
            tip=_tip(spec.tip),
            tilt=Tilt(spec.tilt.angle, spec.tilt.azimuth) if spec.tilt is not None else None,
            grading=_grading(spec.grading),
            filling_factors=spec.filling_factors,
        )
    except StructureError as exc:
        named = _named_file(exc, spec)
        if named is not None:  # name the file, not only its count
            raise named from None
        raise


def _named_file(exc: StructureError, spec: IndenterConfig) -> StructureError | None:
    """``exc`` about a file's values (lengths, per-pillar tips, grading factors) as one naming the file's key and name."""
    if exc.key == "lengths_file":
        return StructureError("lengths_file", spec.lengths_file, f"{exc.allowed} ({spec.lengths_file})")
    if exc.key == "tip" and spec.tip is not None:
        key = "radius" if spec.tip.shape == "spherical_cap" else "depth"
        file = getattr(spec.tip, key, None)
        if isinstance(file, str):
            return StructureError(f"tip.{key}", file, f"{exc.allowed} ({file})")
    tables = {"grading.file": spec.grading}
    tables.update({f"levels.{i}.grading.file": lv.grading for i, lv in enumerate(spec.levels or ())})
    grading = tables.get(exc.key)
    if grading is not None and grading.file is not None:
        return StructureError(exc.key, grading.file, f"{exc.allowed} ({grading.file})")
    return None


def _grading(spec) -> Grading | None:
    """The `Grading` of a ``grading`` table (None without one)."""
    if spec is None:
        return None
    if spec.rule == "file":
        return Grading("factors", factors=np.load(spec.file, allow_pickle=False))
    return Grading(spec.rule, spec.amplitude, 1.0 if spec.exponent is None else spec.exponent,
                   0.0 if spec.azimuth is None else spec.azimuth)


def _tip(spec) -> Tip | list[Tip] | None:
    """The `Tip` (or one per pillar, where the parameter is a file) of a ``tip`` table."""
    if spec is None or spec.shape == "flat":
        return None
    if spec.shape == "profile":
        return Tip("profile", profile=np.load(spec.file, allow_pickle=False))
    key = "radius" if spec.shape == "spherical_cap" else "depth"
    value = getattr(spec, key)
    if isinstance(value, str):
        return [Tip(spec.shape, **{key: float(v)}) for v in np.load(value, allow_pickle=False).ravel()]
    return Tip(spec.shape, **{key: float(value)})


def _rasterise(grid_config: GridConfig, spec: IndenterConfig, halfspace_config: HalfSpaceConfig) -> Indenter:
    return _with_rheology(_rasterise_shape(grid_config, spec, halfspace_config), spec)


def _with_rheology(indenter: Indenter, spec: IndenterConfig) -> Indenter:
    """The rasterised shape with the pillars' viscoelastic connection or nonlinear law of ``spec``."""
    if spec.viscoelastic is not None:
        from brushbem.physics.viscoelastic import Viscoelastic

        v = spec.viscoelastic
        indenter = dataclasses.replace(indenter, viscoelastic=Viscoelastic(v.model, v.relaxation_time,
                                                                           v.instantaneous_factor))
    if spec.pillar_law is not None:
        from brushbem.physics.pillar_laws import PiecewiseLinear

        law = spec.pillar_law
        indenter = dataclasses.replace(indenter, pillar_law=PiecewiseLinear(law.forces, law.factors,
                                                                            law.tension_limit))
    return indenter


def _rasterise_shape(grid_config: GridConfig, spec: IndenterConfig, halfspace_config: HalfSpaceConfig) -> Indenter:
    grid = Grid(grid_config.size, grid_config.elements)
    if spec.shape == "flat_punch":
        return flat_punch(grid, spec.radius, spec.stiffness)
    if spec.shape == "sphere":
        return sphere(grid, spec.radius, spec.stiffness)
    if spec.shape == "height_map":
        return height_map(grid, np.load(spec.file, allow_pickle=False), spec.stiffness)
    if spec.shape == "brush":
        return build_brush(grid_config, spec, halfspace_config)
    raise ValueError(f"indenter.shape = {spec.shape!r} is not known")


class Rules:
    """The rules on the rasterised structure (`brushbem.config.StructureRules`), and what they built.

    The indenter rasterised for the rules is kept (for the sections it was
    built from) and handed to `assemble`, so validating and running a
    configuration rasterise it once.
    """

    def __init__(self) -> None:
        self._built: tuple[tuple[int, int, int], Indenter] | None = None

    def shape(self, grid: GridConfig, indenter: IndenterConfig, halfspace: HalfSpaceConfig) -> Indenter:
        """The rasterised shape of these sections, springs included (built once; raises `StructureError`).

        Without the pillars' rheology (`indenter`): a rule between sections (a law on rigid pillars) names
        its keys, which the rasterisation's error would not.
        """
        key = (id(grid), id(indenter), id(halfspace))
        if self._built is None or self._built[0] != key:
            self._built = (key, _rasterise_shape(grid, indenter, halfspace))
        return self._built[1]

    def indenter(self, grid: GridConfig, indenter: IndenterConfig, halfspace: HalfSpaceConfig) -> Indenter:
        """The rasterised indenter of these sections (the shape built once; raises `StructureError`)."""
        return _with_rheology(self.shape(grid, indenter, halfspace), indenter)

    def structure_problems(self, grid: GridConfig, indenter: IndenterConfig,
                           halfspace: HalfSpaceConfig) -> list[Problem]:
        """A brush layout that cannot be built (overlapping, sub-resolved or untileable) as config errors."""
        if not indenter.is_brush:
            return []
        try:
            self.shape(grid, indenter, halfspace)
        except StructureError as exc:
            return [Problem(f"indenter.{exc.key}", show_value(exc.value), exc.allowed)]
        except ValueError as exc:  # a structure no key-named check caught: still a refusal, not a traceback
            return [Problem("indenter", show_value(indenter.layout), f"cannot be built: {exc}")]
        return []

    def rasterised_problems(self, config: RunConfig) -> list[Problem]:
        """The preload must reach the rasterised indenter; the spring coupling must apply to it."""
        try:
            indenter = self.indenter(config.grid, config.indenter, config.halfspace)
        except (StructureError, ValueError, OSError):
            return []  # reported by the rules on the sections
        problems = []
        preload = config.protocol.preload_displacement
        lowest = indenter.lowest_height
        if preload is not None and not indenter.preload_reaches(preload):
            deepest = MAX_PRELOAD_DOMAIN_SIZES * config.grid.size
            problems.append(Problem(
                "protocol.preload_displacement", show_value(preload),
                f"must be > {lowest:.6g} (and at most {deepest:g}): {lowest:.6g} is the height of the indenter's "
                "lowest element on this grid (where it first touches); a smaller preload never reaches the surface",
            ))
        problems.extend(_unresolvable_spring_problems(config, indenter))
        if config.protocol.method == "pillars":
            # The pillar model's domain, checked here on the rasterised brush and not first at run time (its rule
            # alone: neither the model nor SciPy is loaded to validate).
            from brushbem.physics.pillar_model_domain import pillar_model_problems

            problems.extend(parameter_problems(pillar_model_problems(
                indenter, work_of_adhesion=config.halfspace.work_of_adhesion, speed=config.protocol.speed)))
        if config.solver.coupling == "discriminant":
            from brushbem.numerics.operator import (
                discriminant_half_width,  # the transforms: only for this coupling
            )

            for level in indenter.elastic_levels:
                if not level.uniform:
                    problems.append(Problem(
                        "solver.coupling", show_value(config.solver.coupling),
                        "needs one stiffness per spring level; a graded or per-pillar stiffness needs "
                        "coupling = 'segments'",
                    ))
                    break
                try:
                    discriminant_half_width(np.asarray(indenter.element_clusters(level)))
                except ValueError as exc:
                    problems.append(Problem("solver.coupling", show_value(config.solver.coupling), str(exc)))
                    break
        return problems


def _unresolvable_spring_problems(config: RunConfig, indenter: Indenter) -> list[Problem]:
    """Springs too soft for double precision to resolve the half-space's part of a solve.

    Under a spring of stiffness k whose footprint (a pillar, a cluster's pillars, a punch) of area A is
    in contact, the half-space carries the fraction k / (k + K) of the deflection, K >= 2 E* sqrt(A / pi)
    (of all contacts of an area the disc is the least stiff).  The solver needs that fraction times
    solver.tolerance above its rounding floor (`brushbem.numerics.solver.cg.ROUNDING_FLOOR`); below it a run
    fails, or, where its residual rounds to zero, reports what it could not resolve (a pillar graded by
    1e-9 failed, by 1e-12 "converged").  Refused here with a margin (`SPRING_RESOLUTION_MARGIN`), for
    every value below alike.  Checked where the footprints are in full contact at the preload (flat
    tips, no tilt: a pillar, a cluster, a punch); the run's own check covers curved contacts, and a
    viscoelastic or nonlinear pillar is checked at its stiffest (the standard linear solid's
    instantaneous stiffness, the law's largest factor; a Kelvin-Voigt dashpot has no bound).
    """
    spec = config.indenter
    if spec.shape not in ("flat_punch", "brush"):
        return []
    if (spec.tip is not None and spec.tip.shape != "flat") or (spec.tilt is not None and spec.tilt.angle > 0):
        return []
    limit = SPRING_ROUNDING_FLOOR / config.solver.tolerance / SPRING_RESOLUTION_MARGIN
    h2 = config.grid.element_size**2
    modulus = config.halfspace.effective_modulus
    problems = []
    for i, level in enumerate(indenter.levels):
        if level.rigid:
            continue
        stiffest = 1.0
        if i == 0 and spec.viscoelastic is not None:
            if spec.viscoelastic.instantaneous_factor is None:
                continue
            stiffest = spec.viscoelastic.instantaneous_factor
        if i == 0 and spec.pillar_law is not None:
            stiffest = max(spec.pillar_law.factors)
        labels = indenter.element_clusters(level)
        area = np.bincount(labels[labels >= 0], minlength=level.n_clusters) * h2
        contact = 2.0 * modulus * np.sqrt(area / np.pi)
        k = level.stiffnesses * stiffest
        fraction = k / (k + contact)
        n = int(np.argmin(fraction))
        if fraction[n] >= limit:
            continue
        needed = limit / (1.0 - limit) * contact[n] / stiffest
        key, value, scale = _spring_key(config, i)
        which = "" if level.n_clusters == 1 else f" (spring {n} of {level.n_clusters})"
        factor = f"; a factor of at least {needed / scale:.3g}" if scale is not None else ""
        problems.append(Problem(
            key, show_value(value),
            f"too soft to resolve: the softest spring{which}, k = {level.stiffnesses[n]:.3g}, leaves the half-space "
            f"{fraction[n]:.2g} of its deflection (2 E* sqrt(A / pi) = {contact[n]:.3g} under its footprint), and "
            f"double precision resolves a solve with solver.tolerance = {config.solver.tolerance:g} only above "
            f"{limit:.3g}: every spring must have k >= {needed:.3g}{factor} (or raise solver.tolerance)",
        ))
    return problems


def _spring_key(config: RunConfig, index: int) -> tuple[str, Any, float | None]:
    """The key that sets spring level ``index`` (0: the pillars' own), its value, and the ungraded k of a file."""
    spec = config.indenter
    if spec.shape != "brush":
        return "indenter.stiffness", spec.stiffness, None
    table, prefix = (spec, "indenter") if index == 0 else (spec.levels[index - 1], f"indenter.levels.{index - 1}")
    ratio = table.stiffness_ratio
    base = table.stiffness if ratio is None else ratio
    if table.grading is not None:
        grading = table.grading
        ungraded = (table.stiffness if ratio is None
                    else stiffness_of_ratio(ratio, config.halfspace.effective_modulus, brush_side(config.grid, spec)))
        if grading.rule == "file":
            return f"{prefix}.grading.file", grading.file, ungraded
        return f"{prefix}.grading.amplitude", grading.amplitude, None
    return (f"{prefix}.stiffness_ratio" if ratio is not None else f"{prefix}.stiffness"), base, None


@dataclass(frozen=True)
class Assembly:
    """A validated configuration with its built problem and load path."""

    config: RunConfig
    problem: ContactProblem
    path: LoadPath


def build_indenter(config: RunConfig) -> Indenter:
    """Rasterise the configured indenter on the configured grid."""
    with configuration_errors():
        return _rasterise(config.grid, config.indenter, config.halfspace)


def build_problem(config: RunConfig, indenter: Indenter | None = None, xp: Any = np) -> ContactProblem:
    """The contact problem of a validated configuration (``indenter``: its rasterisation, if built)."""
    from brushbem.protocol import ContactProblem

    indenter = build_indenter(config) if indenter is None else indenter
    with configuration_errors():
        return ContactProblem(
            grid=Grid(config.grid.size, config.grid.elements),
            indenter=indenter,
            contact_modulus=config.halfspace.effective_modulus,
            work_of_adhesion=config.halfspace.work_of_adhesion,
            coupling=config.solver.coupling,
            xp=xp,
        )


def build_path(config: RunConfig) -> LoadPath:
    """The load path of a validated configuration."""
    from brushbem.protocol import LoadPath

    p = config.protocol
    with configuration_errors():
        return LoadPath(
            method=p.method,
            preload_displacement=p.preload_displacement,
            preload_force=p.preload_force,
            step=p.step,
            max_steps=p.max_steps,
            speed=p.speed,
            event_window=p.event_window,
            pillar_modes=p.pillar_modes,
            pillar_near=p.pillar_near,
            pillar_solve=p.pillar_solve,
            pillar_tip_resolution=p.pillar_tip_resolution,
            pillar_tip_calibration=p.pillar_tip_calibration,
            pillar_tip_peel=p.pillar_tip_peel,
            tolerance=config.solver.tolerance,
            max_iterations=config.solver.max_iterations,
            cascade=config.solver.cascade,
        )


def assemble(config: RunConfig, rules: Rules | None = None, xp: Any = np) -> Assembly:
    """The problem and the load path of a validated configuration.

    ``rules``: the `Rules` that validated it, whose rasterisation is reused.
    """
    with configuration_errors():
        indenter = None if rules is None else rules.indenter(config.grid, config.indenter, config.halfspace)
    return Assembly(config, build_problem(config, indenter, xp), build_path(config))


def parse_config(mapping: Mapping[str, Any], base_dir: str | Path | None = None) -> RunConfig:
    """`brushbem.config.parse_config` with the rules on the rasterised structure: the complete check."""
    return schema.parse_config(mapping, base_dir, rules=Rules())


def load_config(path: str | Path) -> RunConfig:
    """`brushbem.config.load_config` with the rules on the rasterised structure: the complete check."""
    return schema.load_config(path, rules=Rules())


def parse(mapping: Mapping[str, Any], base_dir: str | Path | None = None) -> Assembly:
    """Validate a configuration mapping completely and build it (one rasterisation)."""
    rules = Rules()
    return assemble(schema.parse_config(mapping, base_dir, rules=rules), rules)


def load(path: str | Path) -> Assembly:
    """Read, validate completely and build a TOML configuration (one rasterisation)."""
    rules = Rules()
    return assemble(schema.load_config(path, rules=rules), rules)
