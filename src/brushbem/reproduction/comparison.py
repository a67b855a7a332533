"""The thesis's numbers computed from the tables: each one with its standard error over realisations.

`compare` computes every `brushbem.studies.ThesisNumber` of every study with
tables under a root, from those tables alone, as `ComparisonRow` rows.  Where
a part has several realisations the number is that of the realisations that
have finished every point it reads (`_counted_realizations`), with the
standard error over them (`_standard_error`).
"""

from __future__ import annotations

import dataclasses
import math
import statistics
from collections.abc import Collection, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pandas as pd

from brushbem.studies.verdicts import REPRODUCED, Judgement, derived, held_out, judgement
from brushbem.reproduction.tables import PROVENANCE_FILE, load_tables

__all__ = ["ComparisonRow", "compare"]


@dataclass(frozen=True)
class ComparisonRow:
    """One thesis number beside ours."""

    study: str
    quantity: str
    where: str
    thesis: float
    ours: float
    standard_error: float
    realizations: int
    note: str
    verdict: str | None = None  # None: judged on the numbers alone (`judge` with nothing declared)
    evidence: str = ""
    claim: str | None = None  # ">" or "<": a trend the thesis asserts against ``thesis``
    reason: str = ""  # why the rule, not the study, decided the verdict ("imprecise, ...")
    qualitative: bool = False  # a trend or a thesis 0: judged by its side of a threshold
    outside: str = ""  # non-empty: outside the counts, and why (`ThesisNumber.outside`)

    @property
    def deviation(self) -> float:
        if not (self.thesis and math.isfinite(self.ours)):
            return math.nan
        return (self.ours - self.thesis) / self.thesis


def _compute(number, tables: Mapping[str, pd.DataFrame]) -> tuple[float, str]:
    try:
        value = float(number.compute(tables))
    except Exception as exc:  # noqa: BLE001 - reported in the row, not raised
        return math.nan, f"{type(exc).__name__}: {exc}"
    return value, "" if math.isfinite(value) else "not computable from these cases"


def _swept_keys(provenance: Mapping[str, Any]) -> dict[str, list[str]]:
    """Part -> the swept keys of its shipped sweep file(s): what tells one parameter point from another."""
    import tomllib

    from brushbem.studies.base import SWEEPS_DIR

    keys: dict[str, list[str]] = {}
    for part, info in provenance.get("parts", {}).items():
        found: set[str] = set()
        for name in info.get("sweep_files", [info.get("sweep_file", "")]):
            path = SWEEPS_DIR / str(name)
            if name and path.is_file():
                found |= set(tomllib.loads(path.read_text(encoding="utf-8")).get("sweep", {}))
        keys[part] = sorted(found)
    return keys


def _realizations(tables: Mapping[str, pd.DataFrame]) -> list[int]:
    """Every realisation the tables hold (a part without the column has none)."""
    return sorted({int(r) for frame in tables.values() if "realization" in frame.columns
                           for r in frame["realization"].tolist()})


def _of_realizations(tables: Mapping[str, pd.DataFrame], keep: Collection[int]) -> dict[str, pd.DataFrame]:
    """The tables' rows of the realisations ``keep`` (a part without the column whole)."""
    return {part: frame[frame["realization"].isin(list(keep))] if "realization" in frame.columns else frame
            for part, frame in tables.items()}


@dataclass(frozen=True)
class _Points:
    """Each table row's parameter point, and the points each realisation has finished."""

    point: dict[str, pd.Series]
    have: dict[int, dict[str, set]]


def _points(tables: Mapping[str, pd.DataFrame], keys: Mapping[str, list[str]]) -> _Points:
    realizations = _realizations(tables)
    point, have = {}, {r: {} for r in realizations}
    for part, frame in tables.items():
        columns = [key for key in keys.get(part, []) if key in frame.columns]
        values = zip(*(frame[c].map(_plain) for c in columns)) if columns else ((None,) for _ in range(len(frame)))
        point[part] = pd.Series(list(values), index=frame.index, dtype=object)
        finished_rows = frame["status"] == "finished" if "status" in frame.columns else pd.Series(True, frame.index)
        for r in realizations:
            rows = finished_rows & (frame["realization"] == r) if "realization" in frame.columns else finished_rows
            have[r][part] = set(point[part][rows])
    return _Points(point, have)


def _counted_realizations(number, tables: Mapping[str, pd.DataFrame], points: _Points | None = None) -> list[int]:
    """The realisations that have finished every point the number reads.

    A run in progress goes seed by seed, so its last seed has some points
    only; read alone, a number would there come from other points (c read at
    a plateau preload, say) and its spread would not be a standard error.
    The reference is the realisation with the most finished points: a
    realisation lacking some of them counts when the reference, without those
    points, gives the same number (the number does not read them).  Without
    ``points`` (the tables' swept keys unknown) every realisation counts.
    """
    realizations = _realizations(tables)
    if len(realizations) < 2 or points is None:
        return realizations
    have = points.have
    reference = max(realizations, key=lambda r: (sum(len(v) for v in have[r].values()), -r))
    subset = _of_realizations(tables, [reference])
    full, _ = _compute(number, subset)
    counted = []
    for r in realizations:
        lacking = {part: have[reference][part] - have[r][part] for part in tables}
        if any(lacking.values()):
            # (not Series.isin: it reads a set of tuples as a 2-D array)
            without = {part: frame[~points.point[part].loc[frame.index].map(lacking[part].__contains__).astype(bool)]
                       if lacking[part] else frame for part, frame in subset.items()}
            value, _ = _compute(number, without)
            if not _same(value, full):
                continue
        counted.append(r)
    return counted


def _standard_error(number, tables: Mapping[str, pd.DataFrame],
                    counted: list[int] | None = None) -> tuple[float, int]:
    """Standard error of the number over the ``counted`` realisations of its tables (nan below two)."""
    realizations = counted if counted is not None else _realizations(tables)
    if len(realizations) < 2:
        return math.nan, len(realizations)
    values = []
    for r in realizations:
        value, _ = _compute(number, _of_realizations(tables, [r]))
        if math.isfinite(value):
            values.append(value)
    if len(values) < 2:
        return math.nan, len(realizations)
    return statistics.stdev(values) / math.sqrt(len(values)), len(realizations)


def compare(tables_root: str | Path) -> tuple[list[ComparisonRow], dict[str, dict[str, Any]]]:
    """Every thesis number of every study with tables under ``tables_root`` (studies in name order)."""
    from brushbem.studies import get_study

    rows: list[ComparisonRow] = []
    provenances: dict[str, dict[str, Any]] = {}
    for folder in sorted(p for p in Path(tables_root).iterdir() if (p / PROVENANCE_FILE).is_file()):
        provenance, tables = load_tables(folder)
        study = get_study(provenance["study"])
        provenances[study.name] = provenance
        keys = _swept_keys(provenance)
        points = _points(tables, keys) if any(keys.values()) else None
        judged_by: dict[str, Judgement] = {}
        start = len(rows)
        for number in study.numbers:
            ours, note = _compute(number, tables)
            error, realizations = math.nan, 0
            if math.isfinite(ours):
                counted = _counted_realizations(number, tables, points)
                if set(_realizations(tables)) - set(counted):  # the number of the seeds with all its points
                    ours, note = _compute(number, _of_realizations(tables, counted))
                error, realizations = _standard_error(number, tables, counted)
                if number.error is not None:  # the number's own estimator (a bootstrap of a fit)
                    error, _ = _compute(_Own(number.error), _of_realizations(tables, counted))
            judged = judgement(float(number.thesis), ours, error, number.verdict, number.claim, realizations,
                               number.tie, number.mesh, number.untested)
            if number.tied is not None and math.isfinite(ours):  # the row at the identification's tied candidates
                identified, tied = number.tied(_with_probes(tables, study, folder.parent))
                judged = held_out(judged, float(number.thesis), ours, tied, number.verdict, number.claim, number.tie,
                                  identified, number.mesh)
            judged_by[number.quantity] = judged
            verdict = judged.verdict
            rows.append(ComparisonRow(study.name, number.quantity, number.where, float(number.thesis), ours,
                                      error, realizations, note, verdict,
                                      number.evidence if number.verdict is None or verdict != REPRODUCED else "", number.claim,
                                      judged.reason, judged.qualitative, number.outside))
        for i, number in enumerate(study.numbers):  # rows computed from other rows: their inputs' status
            if number.inputs:
                rows[start + i] = _derived(rows[start + i], judged_by, number)
    return rows, provenances


def _derived(row: ComparisonRow, judged_by: Mapping[str, Judgement], number) -> ComparisonRow:
    """``row`` with its inputs' held-out status (`brushbem.studies.verdicts.derived`)."""
    missing = [q for q in number.inputs if q not in judged_by]
    if missing:
        raise ValueError(f"{number.quantity!r}: inputs {missing} are not rows of its study")
    judged = derived(Judgement(row.verdict, row.reason, row.qualitative), {q: judged_by[q] for q in number.inputs})
    if judged.verdict == row.verdict and judged.reason == row.reason:
        return row
    evidence = number.evidence if number.verdict is None or judged.verdict != REPRODUCED else ""
    return dataclasses.replace(row, verdict=judged.verdict, reason=judged.reason, evidence=evidence)


def _with_probes(tables: Mapping[str, pd.DataFrame], study, root: Path) -> dict[str, pd.DataFrame]:
    """``tables`` and the study's committed probe outputs under ``root`` (by file stem), as its identification reads them."""
    return {**tables, **{Path(probe).stem: pd.read_csv(root / probe) for probe in study.probes
                         if (root / probe).is_file()}}


@dataclass(frozen=True)
class _Own:
    """A number's own standard-error estimator, computed as `_compute` computes a number."""

    compute: Any


def _same(a: float, b: float) -> bool:
    if math.isnan(a) or math.isnan(b):
        return math.isnan(a) and math.isnan(b)
    return math.isclose(a, b, rel_tol=1e-12, abs_tol=1e-300)


def _plain(value: Any) -> Any:
    """A table cell as the sweep file writes it (numpy scalars as Python numbers)."""
    return value.item() if hasattr(value, "item") else value
