"""What a study is: the `Study` and `ThesisNumber` records, and where its sweep files live.

The study modules import these (not the package, whose registry imports
them), so the imports run one way: `brushbem.studies` -> study modules ->
this module.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import pandas as pd

__all__ = ["SWEEPS_DIR", "Study", "ThesisNumber", "finished", "sampled_sets", "sweep_file"]

#: Where the shipped sweep files live.
SWEEPS_DIR = Path(__file__).resolve().parent / "sweeps"


@dataclass(frozen=True)
class ThesisNumber:
    """A number the thesis states, and how to compute ours from a study's results.

    Attributes
    ----------
    quantity : str
        What it is, e.g. "F~_A of 16 x 16 pillars at k~ = 0.455".
    where : str
        Where the thesis states it, e.g. "Fig. 4-3 a, text p. 43".
    thesis : float
        The thesis's value.
    compute : callable
        ``compute(results) -> float`` with ``results`` the part name ->
        summary DataFrame mapping (as `brushbem.sweep.load_summary` returns).
    verdict : str, optional
        The verdict where ours does not meet the thesis's value within the
        tolerance or the standard errors (`brushbem.studies.verdicts`): "reproduced
        with a stated choice", "contradicted", or "open"; None: open.
    evidence : str
        What decides the verdict: the closed form, limit or run that shows it
        (or, for open, what was tried), in one or two sentences.
    claim : str, optional
        ``">"`` or ``"<"``: the row is a trend the text asserts, ours above or
        below ``thesis`` (`brushbem.studies.verdicts.judge`); None: a value.
    error : callable, optional
        ``error(results) -> float``: the number's standard error by its own
        estimator (for a fitted quantity, a bootstrap over seeds of the same
        fit that gives the value).  None: the standard error of the
        per-seed values (`brushbem.reproduction.comparison`).
    outside : str
        Non-empty: the row stays outside the verdict counts, and this says why
        (a sensitivity to a choice the chapter's identification did not
        make, or a duplicate of a counted row).
    tie : float
        For a trend (``claim``): the distance from ``thesis`` within which
        ours cannot tell the two sides apart, the model's measured error on
        the compared numbers (named in ``evidence``); such a row is open, a
        tie, however many seeds (`brushbem.studies.verdicts.judgement`).  0:
        none stated.
    tied : callable, optional
        ``tied(tables) -> (identified, {candidate: value})``: for a held-out row of a chapter whose
        identification has tied candidates, the identified candidate's name and the row's value at
        each other tied candidate (NaN where not computed), from the tables and the study's probes;
        the row is judged at each (`brushbem.studies.verdicts.held_out`).  None: the row is judged
        at the identified candidate only.
    mesh : float
        For a trend: a further error of the compared numbers (the chapter's
        `brushbem.studies.verdicts.RESOLUTIONS` mesh error) a decided row must clear.
    untested : str
        Non-empty: why the row's evidence does not test its qualitative claim (the row is open).
    inputs : tuple of str
        The quantities of the study's rows whose values this row is computed from: it inherits
        their held-out status (`brushbem.studies.verdicts.derived`).
    """

    quantity: str
    where: str
    thesis: float
    compute: Callable[[Mapping[str, pd.DataFrame]], float]
    verdict: str | None = None
    evidence: str = ""
    claim: str | None = None
    error: Callable[[Mapping[str, pd.DataFrame]], float] | None = None
    outside: str = ""
    tie: float = 0.0
    tied: Callable[[Mapping[str, pd.DataFrame]], tuple[str, Mapping[str, float]]] | None = None
    mesh: float = 0.0
    untested: str = ""
    inputs: tuple[str, ...] = ()


@dataclass(frozen=True)
class Study:
    """One study of the thesis.

    Attributes
    ----------
    name : str
        Command-line name, e.g. ``"punch_spring"``.
    title : str
        One line, naming the thesis figures / table it reproduces.
    figures : tuple of str
        Thesis figure numbers, e.g. ``("2-4", "2-5", "2-6")``.
    parts : tuple of str
        Names of its sweeps; part ``p`` is ``sweeps/<name>.<p>.toml`` (and
        ``.quick.toml``), run into ``DIR/<p>/``.
    draw : callable
        ``draw(results, figures_dir) -> list[Path]``: writes the figures (PNG,
        atomically) from ``results`` (part -> summary DataFrame; the case files
        are in ``DIR/<part>/cases/`` for curves and snapshots, reachable as
        ``results.attrs``-free paths via the ``case_file`` column).
    numbers : tuple of ThesisNumber
        The numbers the thesis states that this study reproduces.
    draw_tables : callable, optional
        ``draw_tables(tables, figures_dir) -> list[Path]``: the figures that
        the exported per-case tables alone determine (no case files: no
        snapshots or load curves), drawn from ``docs/reproduction/<name>``
        by `brushbem.reproduction.draw_table_figures`.  None: the study's
        figures all need case files.
    identification : callable, optional
        ``identification(tables) -> str``: the Markdown of the chapter's one
        identification from the committed tables (the candidates tried for the
        parameters the thesis leaves open, and their score on the rows used to
        identify them), printed after the study's rows.
    probes : tuple of str
        Committed probe outputs (CSV file names beside the study folders, e.g.
        ``"probe_concave_count.csv"``) that ``identification`` also reads: they
        reach it in ``tables`` under the file's stem, where the file exists.
    tables : callable, optional
        ``tables(run_folder) -> {part: DataFrame}``: the tables a study computes without a sweep
        (read from its run folder), which `brushbem.reproduction.export_tables` commits as parts
        beside the sweep parts' tables.  None: every table is a sweep's.
    """

    name: str
    title: str
    figures: tuple[str, ...]
    parts: tuple[str, ...]
    draw: Callable[[Mapping[str, pd.DataFrame], Path], list[Path]]
    numbers: tuple[ThesisNumber, ...] = ()
    notes: str = ""
    draw_tables: Callable[[Mapping[str, pd.DataFrame], Path], list[Path]] | None = None
    identification: Callable[[Mapping[str, pd.DataFrame]], str] | None = None
    probes: tuple[str, ...] = ()
    tables: Callable[[Path], Mapping[str, pd.DataFrame]] | None = None
    extra: dict[str, Any] = field(default_factory=dict)


def sampled_sets(study: str) -> dict[str, tuple[str, ...]]:
    """The named sampled sets a study ships: set name -> the parts that have it.

    A named set is a further subset of a part's full sweep,
    ``<study>.<part>.<set>.sampled.toml`` (e.g. chapter 6's small-preload
    points, too slow to share the plateau file), run into its own folder.
    """
    sets: dict[str, list[str]] = {}
    for path in sorted(SWEEPS_DIR.glob(f"{study}.*.*.sampled.toml")):
        _, part, name, *_ = path.name.split(".")
        sets.setdefault(name, []).append(part)
    return {name: tuple(parts) for name, parts in sets.items()}


def sweep_file(study: str, part: str, quick: bool, sampled: bool = False, subset: str | None = None) -> Path:
    """The shipped sweep file of one part of a study.

    ``sampled`` asks for the part's ``.sampled.toml``: the parameter points of
    the full sweep (same grid, seeds and case ids) that carry the thesis's
    stated numbers, where the full product is unaffordable.  A part without
    one runs its full sweep.  ``subset`` asks for the part's named sampled set
    ``<set>.sampled.toml`` (`sampled_sets`); a part without it is an error.

    Raises
    ------
    FileNotFoundError
        ``subset`` is given and the part does not ship that set.
    """
    if subset is not None:
        path = SWEEPS_DIR / f"{study}.{part}.{subset}.sampled.toml"
        if not path.is_file():
            raise FileNotFoundError(path)
        return path
    if sampled and not quick:
        subset = SWEEPS_DIR / f"{study}.{part}.sampled.toml"
        if subset.is_file():
            return subset
    return SWEEPS_DIR / f"{study}.{part}{'.quick' if quick else ''}.toml"


def finished(frame: pd.DataFrame) -> pd.DataFrame:
    """The rows of a summary whose case finished (converged); the others are dropped.

    A study's ``draw`` must tolerate failed, unconverged and missing cases (a
    study whose run was interrupted or partly failed is still drawn from what
    finished): filter with this before plotting.
    """
    if "status" not in frame.columns:
        return frame.iloc[0:0]
    return frame[frame["status"] == "finished"]
