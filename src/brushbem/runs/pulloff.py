"""The typed result of one pull-off, `PullOff`: the record, its closed-form reference, and views of them.

`brushbem.runs.case.run_case` and `run_problem` (and so `brushbem.run`,
`brushbem.pull_off` and `brushbem.runs.refine.refined_run`) return it.  Its views
(`to_xarray`, `figure`, `save`) import the file and figure code on first use.
"""

from __future__ import annotations

import contextlib
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.figure import Figure

    from brushbem.config import RunConfig
    from brushbem.results import CaseResult, Curve, ReferenceCurve, RunSummary, Snapshot

__all__ = ["FIGURE_FILES", "PullOff"]

#: The figure files of a run (`brushbem.figures.plot.plot_pull_off` writes the PNG and a PDF beside it).
FIGURE_FILES = ("pulloff.png", "pulloff.pdf")


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
    def summary(self) -> RunSummary:
        """The ``summary.json`` contract (docs/site/outputs.md): F_A, d_A, work, convergence, theory ratios, warnings;
        after saving (and from `brushbem.load`) with the ``run_id`` and the ``provenance``."""
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
        from brushbem.results.units import Units

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
        design = summary.get("design") or {}
        if design.get("adhesion_strength") is not None:
            rows.insert(1, ("adhesion strength F_A / A0", f"{design['adhesion_strength']:.6g}{unit('stress')}"))
        resolution = summary.get("resolution")
        if resolution:
            rows.append(("F_A discretisation error (est.)", f"{100 * resolution['force_error_estimate']:+.2g} % at "
                                                             f"{resolution['elements']:.3g} elements per "
                                                             f"{resolution['length']}"))
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
        from brushbem.io import to_dataset

        return to_dataset(self.result, self.config)

    def figure(self, *, normalized: bool = False) -> Figure:
        """Force against displacement beside the detachment pattern (`brushbem.figures.plot.pull_off_figure`).

        ``normalized``: on the thesis's axes, F/(N_p F_K) against d/|d_c| for a brush.
        """
        from brushbem.figures.plot import pull_off_figure

        return pull_off_figure(self.result, self.reference, normalized=normalized)

    def save(self, out_dir: str | Path, *, figure: bool = True) -> Path:
        """Write ``summary.json`` and ``result.nc`` into ``out_dir``, then (``figure``) `save_figure` (as ``brushbem run``).

        Raises
        ------
        OSError
            The results could not be written (no file is left half-written);
            nothing else is written then.
        Exception
            From `save_figure`: the results are written, the figure is not.
        """
        from brushbem.io import write_case

        out = Path(out_dir)
        write_case(self.result, out, config=self.config)
        if figure:
            self.save_figure(out)
        return out

    def save_figure(self, out_dir: str | Path) -> Path:
        """Draw the figure into ``out_dir/pulloff.png`` (and ``pulloff.pdf``, `brushbem.figures.plot.plot_pull_off`).

        On any failure no figure file is left there (one of an earlier run
        included, so that it is never taken for this one's) and the exception
        is raised.
        """
        from brushbem.figures import plot

        out = Path(out_dir)
        try:
            plot.plot_pull_off(self.result, out / FIGURE_FILES[0], self.reference)
        except Exception:
            for name in FIGURE_FILES:
                with contextlib.suppress(OSError):
                    (out / name).unlink(missing_ok=True)
            raise
        return out / FIGURE_FILES[0]


def _number(value: Any) -> float:
    return float("nan") if value is None else float(value)
