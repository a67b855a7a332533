"""Recomputing one row of the comparison: the cases its number reads (`plan_row`) and their run (`reproduce_row`).

`plan_row` finds, from the committed tables, the parameter points a thesis
number reads, adds the rivals closest to changing it (`_rivals`), and names
the shipped sweep file and case hashes they come from; `reproduce_row` runs
those cases and computes the number from them.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from brushbem.sweep.spec import case_hash
from brushbem.reproduction.comparison import _compute, _plain, _same
from brushbem.reproduction.tables import PROVENANCE_FILE, load_tables

__all__ = ["RIVALS", "RIVAL_STEPS", "ReproduceError", "RowPlan", "plan_row", "reproduce_row"]


class ReproduceError(ValueError):
    """A row that cannot be recomputed: unknown study or quantity, or no finished case it reads."""


@dataclass(frozen=True)
class RowPlan:
    """What recomputing one row runs: per part, the parameter points the row reads.

    Attributes
    ----------
    study, quantity : str
    committed : float
        The row's value from the committed tables' first ``realizations`` seeds: what the run must give.
    points : dict
        Part -> list of swept-value mappings (one per parameter point the row reads).
    sweep_files : dict
        Part -> the shipped sweep file those points come from.
    realizations : int
        How many realisations (the first ones, with the sweep's own seeds) are run.
    cases : int
        The cases that makes.
    recorded_seconds : float
        Their wall time as recorded in the tables (an estimate of the run's).
    case_hashes : dict
        Part -> the committed cases' hashes (their ids after the index) that the run must give again.
    every_seed : float
        The row's value from every seed of the tables (the one the comparison prints).
    rivals : dict
        Part -> those of ``points`` that the number does not read but would
        if their results changed by a little (the runners-up of a maximum).
    """

    study: str
    quantity: str
    committed: float
    points: dict[str, list[dict[str, Any]]]
    sweep_files: dict[str, Path]
    realizations: int
    cases: int
    recorded_seconds: float
    case_hashes: dict[str, list[str]] = dataclasses.field(default_factory=dict)
    every_seed: float = math.nan
    rivals: dict[str, list[dict[str, Any]]] = dataclasses.field(default_factory=dict)


RIVALS = 2
"""Points a row's plan adds beyond those its number reads: the ones closest to changing it."""

RIVAL_STEPS = (0.0025, 0.005, 0.01, 0.02)
"""Relative changes of a point's results tried, smallest first, to rank the points that could change a number.

The largest, 2 %, is above the spread of neighbouring points around the
thesis's maxima (chapter 7's refined ĥ points differ by under 1 %), and
below the 5 % at which a deviation needs explaining.
"""

_NOT_RESULTS = {"index", "realization", "seed", "wall_time_s"}


def _rivals(number, tables: Mapping[str, pd.DataFrame], point_of: Mapping[str, Mapping[str, tuple]],
            candidates: set, committed: float, limit: int) -> set:
    """The (at most ``limit``) points left out of a plan whose results, changed least, change the number.

    Each candidate's float results (every float column but its swept values
    and bookkeeping) are scaled by ``1 ± step`` for the steps of
    :data:`RIVAL_STEPS`, smallest first, in the full tables; the step at which
    the number first moves ranks it.  A point that no step moves is no rival.
    For a number that reads every point (a mean, a fit) there are none left to
    add; for the position of a maximum they are the points whose value is
    within a step of the maximum's.
    """
    if limit <= 0 or not candidates:
        return set()

    ranked = []
    for candidate in sorted(candidates, key=repr):
        part, point = candidate
        frame = tables[part]
        rows = frame["case_id"].map(lambda i, part=part, point=point: point_of[part].get(i) == point).to_numpy()
        keys = {key for key, _ in point}
        columns = [c for c in frame.columns if c not in keys and c not in _NOT_RESULTS
                   and pd.api.types.is_float_dtype(frame[c])]

        def moves(step: float, frame=frame, rows=rows, columns=columns, part=part) -> bool:
            for factor in (1 + step, 1 - step):
                # Column by column as plain arrays: `.loc` with a frame on the right aligns it first, and
                # with rows and columns at once it goes column by column through pandas' indexer (8 ms).
                changed = frame.assign(**{c: np.where(rows, frame[c].to_numpy() * factor, frame[c].to_numpy())
                                          for c in columns})
                if not _same(_compute(number, {**tables, part: changed})[0], committed):
                    return True
            return False

        if moves(RIVAL_STEPS[-1]):  # then the smallest step that moves it ranks it
            ranked.append((next(s for s in RIVAL_STEPS if s == RIVAL_STEPS[-1] or moves(s)), repr(candidate),
                           candidate))
    return {candidate for _, _, candidate in sorted(ranked)[:limit]}


def _find_number(study, quantity: str):
    exact = [n for n in study.numbers if n.quantity == quantity]
    found = exact or [n for n in study.numbers if quantity.lower() in n.quantity.lower()]
    if len(found) != 1:
        known = "; ".join(repr(n.quantity) for n in study.numbers)
        what = "no" if not found else f"{len(found)}"
        raise ReproduceError(f"study {study.name!r}: {what} quantities match {quantity!r}; its quantities: {known}")
    return found[0]


def _file_with(points: list[dict[str, Any]], files: list[Path]) -> Path:
    """The first of a part's sweep files that lists every one of ``points`` (else the first file).

    A part merged from several sampled sets (same base and seed) can run a
    row's points from any of them; the one that holds them names it truthfully.
    """
    import itertools
    import tomllib

    for path in files:
        spec = tomllib.loads(path.read_text(encoding="utf-8"))
        keys, values = list(spec.get("sweep", {})), list(spec.get("sweep", {}).values())
        combine = itertools.product if spec.get("mode", "zip") == "product" else zip
        listed = {tuple(_plain(v) for v in row) for row in combine(*values)}
        if all(tuple(_plain(point.get(key)) for key in keys) in listed for point in points):
            return path
    return files[0]


def _as_swept(spec: dict[str, Any], key: str, value: Any) -> Any:
    """A table cell of the swept column ``key`` as the sweep file ``spec`` writes it.  A key swept after
    some cases were recorded leaves those cells empty (NaN): they ran the base's value.  A column with
    such gaps reads as floats; where the file sweeps integers, a whole number is an integer again."""
    if isinstance(value, float) and math.isnan(value):
        value = spec.get("base", {})
        for name in key.split("."):
            value = value.get(name, math.nan) if isinstance(value, dict) else math.nan
    values = spec.get("sweep", {}).get(key, [])
    if values and all(type(v) is int for v in values) and isinstance(value, float) and value.is_integer():
        return int(value)
    return _plain(value)


def plan_row(tables_root: str | Path, study_name: str, quantity: str, realizations: int | None = None,
             rivals: int = RIVALS) -> RowPlan:
    """The cases that recompute one row of the comparison: the parameter points its number reads.

    Starting from every finished point of the committed tables, each point
    whose cases can be left out without changing the number is left out; the
    points that remain give the committed number by themselves.  The number
    is a function of the tables, so this finds what it reads without the
    study declaring it.  To these come up to ``rivals`` points the number
    would read if their results were a little different (see
    :func:`_rivals`): for a maximum or its position, the runners-up, so the
    recomputed number is a check of the ranking and not only of one case.
    The cases
    are the shipped sweep file's (same configurations, seeds and case hashes),
    for the first ``realizations`` seeds (default: as many as the tables have
    finished); with fewer, the plan and its committed number are those of the
    tables' first seeds, so a run of a few seeds is checked too.

    Raises
    ------
    ReproduceError
        Unknown study or quantity, or a number that no finished case determines.
    """
    import tomllib

    from brushbem.studies import StudyError, get_study
    from brushbem.studies.base import SWEEPS_DIR

    try:
        study = get_study(study_name)
    except StudyError as exc:  # the message lists the known studies
        raise ReproduceError(str(exc)) from None
    folder = Path(tables_root) / study.name
    if not (folder / PROVENANCE_FILE).is_file():
        raise ReproduceError(f"no tables of study {study.name!r} in {tables_root} (no {PROVENANCE_FILE})")
    number = _find_number(study, quantity)
    provenance, tables = load_tables(folder)
    every_seed, _ = _compute(number, tables)
    if realizations is not None:  # the row as the first seeds give it: planned, run and checked on those
        tables = {part: frame[frame["realization"] < realizations] if "realization" in frame.columns else frame
                  for part, frame in tables.items()}
    committed, _ = _compute(number, tables)
    if not math.isfinite(committed):
        seeds = "" if realizations is None else f" of the first {realizations} seed(s)"
        raise ReproduceError(f"{number.quantity!r} is n/a in the committed tables{seeds}: no finished case "
                             "determines it")
    # Every finished case's parameter point, by the shipped sweep's case hashes.
    point_of: dict[str, dict[str, tuple]] = {}
    paths: dict[str, Path] = {}
    for part, frame in tables.items():
        if not {"status", "case_id"} <= set(frame.columns):
            continue
        done = frame[frame["status"] == "finished"]
        if not len(done):
            continue
        paths[part] = SWEEPS_DIR / provenance["parts"][part]["sweep_file"]
        spec = tomllib.loads(paths[part].read_text(encoding="utf-8"))
        keys = sorted(spec.get("sweep", {}))
        missing = [key for key in keys if key not in done.columns]
        if missing:
            raise ReproduceError(f"the table of part {part!r} lacks the swept column(s) {', '.join(missing)}")
        point_of[part] = {case_id: tuple((key, _as_swept(spec, key, value)) for key, value in zip(keys, values))
                          for case_id, *values in done[["case_id", *keys]].itertuples(index=False)}

    def restricted(keep: set[tuple[str, tuple]]) -> dict[str, pd.DataFrame]:
        return {part: frame[frame["case_id"].map(lambda i, part=part: (part, point_of.get(part, {}).get(i)) in keep)]
                if part in point_of else frame for part, frame in tables.items()}

    # Leave out, one by one, every point whose cases the number does not need: what is left
    # gives the committed value by itself (of equal plateau preloads, one is kept).
    everything = {(part, point) for part, ids in point_of.items() for point in set(ids.values())}
    keep = set(everything)
    for candidate in sorted(keep, key=repr):
        value, _ = _compute(number, restricted(keep - {candidate}))
        if _same(value, committed):
            keep.discard(candidate)
    runners_up = _rivals(number, tables, point_of, everything - keep, committed, rivals)
    keep |= runners_up
    points: dict[str, list[dict[str, Any]]] = {}
    for part, point in sorted(keep, key=repr):
        points.setdefault(part, []).append(dict(point))
    sweep_files = {part: _file_with(part_points, [SWEEPS_DIR / name for name in provenance["parts"][part].get(
        "sweep_files", [])] or [paths[part]]) for part, part_points in points.items()}
    selected = restricted(keep)
    selected_rows = {part: frame[frame["status"] == "finished"] for part, frame in selected.items() if part in points}
    if not points and not study.parts:  # its one run computes the table every row reads
        raise ReproduceError(f"study {study.name!r} has no sweep: its one run recomputes every row "
                             f"(`brushbem study {study.name} --out DIR`, then `brushbem export-tables DIR --to {tables_root}`)")
    if not points:
        raise ReproduceError(f"{number.quantity!r} depends on no single case of the tables (a closed form): "
                             "there is nothing to recompute")
    # (the seeds finished by the parts the row reads: another part's extra seeds do not change its plan)
    realizations = realizations or max((int(frame["realization"].nunique()) for frame in selected_rows.values()
                                        if "realization" in frame.columns), default=1)
    chosen_by_part = {}
    for part, frame in selected_rows.items():
        if "realization" in frame.columns:
            frame = frame[frame["realization"] < realizations]
        chosen_by_part[part] = frame
    chosen = pd.concat(list(chosen_by_part.values()))
    case_hashes = {part: sorted(case_hash(i) for i in frame["case_id"])
                   for part, frame in chosen_by_part.items()}
    seconds = float(pd.to_numeric(chosen.get("wall_time_s", pd.Series(dtype=float)), errors="coerce").sum())
    cases = 0
    for part, part_points in points.items():
        spec_realizations = int(tomllib.loads(sweep_files[part].read_text(encoding="utf-8")).get("realizations", 1))
        cases += len(part_points) * min(realizations, spec_realizations)
    rival_points = {part: [dict(point) for p, point in sorted(runners_up, key=repr) if p == part]
                    for part in points}
    return RowPlan(study.name, number.quantity, committed, points, sweep_files, realizations, cases, seconds,
                   case_hashes, every_seed, rival_points)


def reproduce_row(plan: RowPlan, out_dir: str | Path, executor: Any = None, *, workers: int | None = None,
                  progress: bool = False) -> float:
    """Run the cases of ``plan`` into ``out_dir/<part>`` (resuming) and return the number from them.

    Each part runs as a sweep of the plan's points with the shipped file's
    base, seed and mode of seeding, so its cases are the committed ones
    (``SeedSequence.spawn`` gives the first seeds alike for any count).
    """
    import tomllib

    from brushbem.studies import get_study
    from brushbem.sweep import load_summary, run_sweep

    study = get_study(plan.study)
    number = _find_number(study, plan.quantity)
    tables: dict[str, pd.DataFrame] = {}
    for part, path in plan.sweep_files.items():
        spec = tomllib.loads(path.read_text(encoding="utf-8"))
        keys = list(plan.points[part][0])
        subset = {
            "base": spec["base"],
            "mode": "zip",
            "realizations": min(plan.realizations, int(spec.get("realizations", 1))),
            "seed": spec.get("seed", 0),
            "sweep": {key: [point[key] for point in plan.points[part]] for key in keys},
        }
        if "refine" in spec:
            subset["refine"] = spec["refine"]
        run_sweep(subset, Path(out_dir) / part, executor, workers=workers, progress=progress,
                  base_dir=path.parent)
        tables[part] = load_summary(Path(out_dir) / part)
        if plan.case_hashes.get(part) and not set(plan.case_hashes[part]) <= {
                case_hash(case_id) for case_id in tables[part]["case_id"]}:
            raise ReproduceError(f"part {part!r}: the recomputed cases are not the committed ones (their "
                                 "configurations or seeds differ: the sweep file changed since the tables)")
    for part in study.parts:
        tables.setdefault(part, pd.DataFrame(columns=["case_id", "status"]))
    value, note = _compute(number, tables)
    if not math.isfinite(value):
        raise ReproduceError(f"{plan.quantity!r}: the recomputed cases give n/a ({note})")
    return value
