"""The public Python API: run a pull-off from a configuration or from built objects.

Everything a notebook needs is reachable from the package's top level::

    import brushbem

    result = brushbem.run("examples/default.toml")     # a file, a mapping or a RunConfig
    print(result.adhesive_force, result.work_of_separation)
    dataset = result.to_xarray()                        # the result.nc content, in memory
    figure = result.figure()                            # matplotlib Figure (no pyplot)

or, without a configuration file::

    grid = brushbem.Grid(size=1.0, elements=128)
    tips = brushbem.brush(grid, layout="square", pillars_per_side=8, pillar_radius=0.02,
                          contact_modulus=1.0, work_of_adhesion=1e-4, stiffness=0.01)
    result = brushbem.pull_off(grid, tips, contact_modulus=1.0, work_of_adhesion=1e-4,
                               preload_force=0.02)

Sign convention: d > 0 presses into the half-space, F > 0 is compressive; the
adhesive force is reported as a positive magnitude, F_A = -min F.
"""

from __future__ import annotations

import math

from collections.abc import Callable, Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from brushbem.runs.assembly import Assembly, parse
from brushbem.runs.assembly import load as load_assembly
from brushbem.config import ConfigError, RunConfig
from brushbem.runs.pulloff import PullOff

if TYPE_CHECKING:
    from brushbem.physics.structure import Grid, Indenter

__all__ = ["PullOff", "load", "pull_off", "run"]


def run(
    config: str | Path | Mapping[str, Any] | RunConfig | Assembly,
    *,
    progress: Callable[[float, str], None] | None = None,
    stop: Callable[[], bool] | None = None,
    refine: int | None = None,
) -> PullOff:
    """Run the pull-off of a configuration: a TOML file, a mapping of its tables, a `RunConfig` or an `Assembly`.

    A file or mapping is validated first (`brushbem.config.ConfigError` lists
    every problem).  Relative file names in a mapping resolve against the
    current directory.  ``progress(fraction, message)`` is called as the run
    advances; ``stop()``, polled after every state, ends it early (the result
    then holds the path so far, ``interrupted`` and not converged).
    ``refine`` (2 or 3, as ``brushbem run --refine``) also runs the coarser
    grids and adds the Richardson extrapolation (`brushbem.runs.refine.refined_run`).
    """
    built: RunConfig | Assembly
    if isinstance(config, (RunConfig, Assembly)):
        built = config
    elif isinstance(config, Mapping):
        built = parse(config)
    elif isinstance(config, (str, Path)):
        built = load_assembly(config)
    else:
        raise TypeError(f"config = {config!r}: expected a file path, a mapping of tables, a RunConfig or an Assembly")
    from brushbem.runs import case

    if refine is None:
        return case.run_case(built, progress=progress, stop=stop)
    from brushbem.runs.refine import refined_run

    return refined_run(built if isinstance(built, RunConfig) else built.config, refine, progress=progress, stop=stop)


def load(folder: str | Path) -> PullOff:
    """The `PullOff` a run saved into ``folder`` (``brushbem run --out``, `PullOff.save`), read back typed.

    The curve, the snapshots and the per-pillar arrays come from ``result.nc``;
    the summary from ``summary.json``, as the same `RunSummary` the run returned
    (its ``normalized``, ``theory`` and ``refinement`` records rebuilt), with the
    ``run_id`` and the ``provenance`` that saving recorded.  The configuration is
    the resolved one the provenance records, validated again; with it the
    closed-form reference curve of the figure is computed again (a
    rasterisation, no pull-off).  Neither exists for a run of built objects
    (`pull_off`), nor where the configuration no longer validates (a file it
    names has moved): ``config`` and ``reference`` are None then.

    Raises
    ------
    FileNotFoundError
        ``folder`` does not exist.
    brushbem.io.InconsistentCaseError
        Its two files come from different runs.
    ValueError
        Its ``summary.json`` is not a run's summary.
    """
    from brushbem.io import load_result
    from brushbem.runs.case import reference_for

    result = load_result(folder)
    provenance = getattr(result.summary, "provenance", None)
    stored = provenance.config if provenance is not None else None
    if not isinstance(stored, Mapping):
        return PullOff(result)
    try:
        assembly = parse(stored)
    except ConfigError:  # a file it names has moved since: the numbers stand, the configuration does not
        return PullOff(result)
    return PullOff(result, reference_for(assembly, result.summary), assembly.config)


def _material(name: str, given: float | None, indenter: Indenter) -> float:
    """``given``, or the value ``indenter`` was built with; ValueError if they differ or neither exists."""
    recorded = getattr(indenter.description, name, None) if indenter.description is not None else None
    if given is None:
        if recorded is None:
            allowed = ("dgamma >= 0, energy per area (0: no adhesion)" if name == "work_of_adhesion"
                       else "E* > 0, in units of stress")
            raise ValueError(f"{name} is required: {allowed}")
        return float(recorded)
    if recorded is not None and not math.isclose(float(given), float(recorded), rel_tol=1e-12):
        raise ValueError(f"{name} = {given!r} differs from the {name} = {recorded!r} the brush was built with "
                         "(one material per run: give it once, to brushbem.brush, or the same value to both)")
    return float(given)


def pull_off(
    grid: Grid,
    indenter: Indenter,
    *,
    contact_modulus: float | None = None,
    work_of_adhesion: float | None = None,
    preload_displacement: float | None = None,
    preload_force: float | None = None,
    method: str = "events",
    step: float = 1e-4,
    tolerance: float = 1e-8,
    speed: float | None = None,
    xp: Any = np,
    progress: Callable[[float, str], None] | None = None,
) -> PullOff:
    """Press ``indenter`` into the half-space and pull it off (no configuration file).

    Parameters
    ----------
    grid : Grid
        The N x N domain (`brushbem.Grid`).
    indenter : Indenter
        From `brushbem.flat_punch`, `brushbem.sphere`, `brushbem.height_map`
        or `brushbem.brush` on the same grid.
    contact_modulus : float
        E*, in units of stress.  Optional for a brush, which records the E* it was
        built with (`brushbem.brush`); a different value is refused.
    work_of_adhesion : float
        dgamma, energy per area (0: no adhesion, given explicitly).  Optional for a
        brush, like ``contact_modulus``; required otherwise.

    Raises
    ------
    ValueError
        A material is missing, or differs from the one the brush was built with.
    preload_displacement, preload_force : float
        Exactly one: press to this base displacement or until this force.
    method : {"events", "element_events", "fixed", "pillars"}
        The load path (docs/site/configuration.md, `[protocol]`); ``step`` is the fixed method's step.
        ``"pillars"`` is the pillar-level model of a brush of flat, untilted tips, level or of
        unequal lengths (`brushbem.pillars`); it refuses, naming the parameter, any other indenter.
    tolerance : float
        Relative residual of every CG solve.
    speed : float, optional
        Pulling speed of viscoelastic pillars (``dataclasses.replace(indenter,
        viscoelastic=brushbem.Viscoelastic(...))``), with ``method="fixed"``.
    xp : array namespace
        NumPy (default) or a GPU namespace such as CuPy.
    """
    from brushbem.runs.case import run_problem
    from brushbem.protocol import ContactProblem, LoadPath

    contact_modulus = _material("contact_modulus", contact_modulus, indenter)
    work_of_adhesion = _material("work_of_adhesion", work_of_adhesion, indenter)
    problem = ContactProblem(grid, indenter, contact_modulus, work_of_adhesion, xp=xp)
    path = LoadPath(method=method, preload_displacement=preload_displacement, preload_force=preload_force,
                    step=step, tolerance=tolerance, speed=speed)
    return run_problem(problem, path, progress=progress)
