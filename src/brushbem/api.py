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
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .assembly import Assembly, load, parse
from .config import RunConfig

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.figure import Figure

    from .results import CaseResult, Curve, ReferenceCurve, Snapshot
    from .structure import Grid, Indenter

__all__ = ["PullOff", "pull_off", "run"]


@dataclass(frozen=True)
class PullOff:
    """The result of one pull-off: the curve, the snapshots, the summary, and views of them.

    Attributes
    ----------
    result : CaseResult
        The typed record (curve, snapshots, summary, provenance, per-pillar arrays).
    reference : ReferenceCurve or None
        The closed-form reference curve of the figure (``displacement``,
        ``force``, ``label``), where one applies.
    config : RunConfig or None
        The configuration it ran from (None for `pull_off` on built objects).
    """

    result: CaseResult
    reference: ReferenceCurve | None = None
    config: RunConfig | None = None

    @property
    def curve(self) -> Curve:
        """Every recorded state: ``displacement``, ``force``, ``contact_area``, ``loading``, ... (arrays)."""
        return self.result.curve

    @property
    def snapshots(self) -> dict[str, Snapshot]:
        """The marked moments (``max_preload``, ``adhesive_force``, ...) by name."""
        return {snapshot.name: snapshot for snapshot in self.result.snapshots}

    @property
    def summary(self) -> dict[str, Any]:
        """The ``summary.json`` contract (docs/site/outputs.md): F_A, d_A, work, convergence, theory ratios, warnings."""
        return self.result.summary

    @property
    def converged(self) -> bool:
        return bool(self.summary.get("converged", False))

    @property
    def adhesive_force(self) -> float:
        """F_A = -min F over the pull-off (a positive magnitude), in units of force."""
        return _number(self.summary.get("adhesive_force"))

    @property
    def work_of_separation(self) -> float:
        """The area of the tensile part of the unloading curve, in units of energy."""
        return _number(self.summary.get("work_of_separation"))

    @property
    def pull_off_displacement(self) -> float:
        """d_A, the base displacement at the adhesive force, in units of length."""
        return _number(self.summary.get("pull_off_displacement"))

    def _headline(self) -> list[tuple[str, str]]:
        """The few numbers a reader wants first: (label, value with unit words), in order."""
        from .units import Units

        summary = self.summary
        units = Units.from_config(self.config) if self.config is not None else Units()

        def unit(dimension: str) -> str:
            return "" if units.dimensionless else f" {units.of(dimension)}"

        rows = [
            ("adhesive force F_A", f"{self.adhesive_force:.6g}{unit('force')}"),
            ("pull-off displacement d_A", f"{self.pull_off_displacement:.6g}{unit('length')}"),
            ("work of separation W", f"{self.work_of_separation:.6g}{unit('energy')}"),
            ("converged", f"{self.converged} ({summary.get('reason', '')})"),
            ("states recorded", f"{len(self.curve.displacement)}"),
        ]
        if summary.get("warnings"):
            rows.append(("warnings", f"{len(summary['warnings'])}"))
        return rows

    def __repr__(self) -> str:
        """One line per headline number (the arrays are in ``curve`` and ``snapshots``)."""
        return "PullOff(" + ", ".join(f"{label}={value}" for label, value in self._headline()) + ")"

    def _repr_html_(self) -> str:
        """A small table for notebooks."""
        from html import escape

        rows = "".join(f"<tr><th style='text-align:left'>{escape(label)}</th><td>{escape(value)}</td></tr>"
                       for label, value in self._headline())
        return f"<table><caption>brushbem pull-off</caption>{rows}</table>"

    def to_xarray(self) -> xr.Dataset:
        """The ``result.nc`` content as an in-memory `xarray.Dataset`."""
        from .io import to_dataset

        return to_dataset(self.result, self.config)

    def figure(self) -> Figure:
        """Force against displacement beside the detachment pattern (`brushbem.plot.pull_off_figure`)."""
        from .plot import pull_off_figure

        return pull_off_figure(self.result, self.reference)

    def save(self, out_dir: str | Path) -> Path:
        """Write ``summary.json``, ``result.nc`` and ``pulloff.png`` into ``out_dir`` (as ``brushbem run``)."""
        from .io import write_case
        from .plot import plot_pull_off

        out = Path(out_dir)
        write_case(self.result, out, config=self.config)
        plot_pull_off(self.result, out / "pulloff.png", self.reference)
        return out


def _number(value: Any) -> float:
    return float("nan") if value is None else float(value)


def run(
    config: str | Path | Mapping[str, Any] | RunConfig,
    *,
    progress: Callable[[float, str], None] | None = None,
) -> PullOff:
    """Run the pull-off of a configuration: a TOML file, a mapping of its tables, or a `RunConfig`.

    A file or mapping is validated first (`brushbem.config.ConfigError` lists
    every problem).  Relative file names in a mapping resolve against the
    current directory.  ``progress(fraction, message)`` is called as the run
    advances.
    """
    built: RunConfig | Assembly
    if isinstance(config, RunConfig):
        built = config
    elif isinstance(config, Mapping):
        built = parse(config)
    elif isinstance(config, (str, Path)):
        built = load(config)
    else:
        raise TypeError(f"config = {config!r}: expected a file path, a mapping of tables or a RunConfig")
    from .case import run_case

    result, reference = run_case(built, progress=progress)
    return PullOff(result, reference, built if isinstance(built, RunConfig) else built.config)


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
    method : {"events", "element_events", "fixed"}
        The load path (docs/site/configuration.md, `[protocol]`); ``step`` is the fixed method's step.
    tolerance : float
        Relative residual of every CG solve.
    speed : float, optional
        Pulling speed of viscoelastic pillars (``dataclasses.replace(indenter,
        viscoelastic=brushbem.Viscoelastic(...))``), with ``method="fixed"``.
    xp : array namespace
        NumPy (default) or a GPU namespace such as CuPy.
    """
    from .case import run_problem
    from .protocol import ContactProblem, LoadPath

    contact_modulus = _material("contact_modulus", contact_modulus, indenter)
    work_of_adhesion = _material("work_of_adhesion", work_of_adhesion, indenter)
    problem = ContactProblem(grid, indenter, contact_modulus, work_of_adhesion, xp=xp)
    path = LoadPath(method=method, preload_displacement=preload_displacement, preload_force=preload_force,
                    step=step, tolerance=tolerance, speed=speed)
    result, reference = run_problem(problem, path, progress=progress)
    return PullOff(result, reference, None)
