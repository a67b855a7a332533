"""The columns of a sweep's table, declared from the fields of the result records.

A sweep's table (`brushbem.sweep.build_summary`) has one column per field of
a run's `RunSummary`, a nested record's fields as dotted columns
(``normalized.stiffness_ratio``, ``theory.equivalent_radius``,
``refinement.adhesive_force.extrapolated``).  `SUMMARY_COLUMNS` lists them,
derived from the records here, never typed again; a study names the columns
it reads through `summary_column`, at import, so that a renamed field fails
when the study is imported and not at a missing column of a finished sweep.

Fields whose value is a plain mapping with open keys (``theory.ratios``,
``theory.not_applicable``, ``stages_not_reached``, ``design.units``) are declared as prefixes (`OPEN_PREFIXES`): any column under
them is a column of the table.
"""

from __future__ import annotations

import difflib
from dataclasses import fields

from brushbem.results.case import BrushTheory, PunchTheory, RunSummary, SphereTheory
from brushbem.results.design import DesignNumbers, ResolutionRecord, Spring
from brushbem.results.normalization import BrushNormalization
from brushbem.results.refinement import Extrapolation, Refinement

__all__ = ["OPEN_PREFIXES", "SUMMARY_COLUMNS", "summary_column"]

#: The record types of the summary's nested fields, by field (a field's several kinds all count).
_NESTED: dict[type, dict[str, tuple[type, ...]]] = {
    RunSummary: {"normalized": (BrushNormalization,), "theory": (PunchTheory, SphereTheory, BrushTheory),
                 "refinement": (Refinement,), "resolution": (ResolutionRecord,), "design": (DesignNumbers,)},
    DesignNumbers: {"spring": (Spring,)},
    Refinement: {"adhesive_force": (Extrapolation,), "work_of_separation": (Extrapolation,)},
}

#: Fields that a sweep's table does not hold: the files' id and provenance (a sweep records its own).
_NOT_IN_THE_TABLE = frozenset({"run_id", "provenance"})

#: Fields whose value is a mapping of open keys: every column under ``prefix.`` belongs to the table.
OPEN_PREFIXES: frozenset[str] = frozenset({"stages_not_reached", "design.units", "theory.ratios",
                                           "theory.not_applicable"})


def _columns(record: type, prefix: str = "") -> set[str]:
    names: set[str] = set()
    nested = _NESTED.get(record, {})
    for field in fields(record):
        if record is RunSummary and field.name in _NOT_IN_THE_TABLE:
            continue
        name = prefix + getattr(record, "_KEY_OF", {}).get(field.name, field.name)
        if name in OPEN_PREFIXES:
            continue
        if field.name in nested:
            for kind in nested[field.name]:
                names |= _columns(kind, name + ".")
        else:
            names.add(name)
    return names


#: Every column of a sweep's table that a run's summary gives (the open prefixes' columns aside).
SUMMARY_COLUMNS: frozenset[str] = frozenset(_columns(RunSummary))


def summary_column(name: str) -> str:
    """``name`` if it is a column of a sweep's table (`SUMMARY_COLUMNS`, or under an `OPEN_PREFIXES` entry).

    Raises
    ------
    KeyError
        ``name`` is no such column; the message names the closest ones.
    """
    if name in SUMMARY_COLUMNS or any(name.startswith(prefix + ".") for prefix in OPEN_PREFIXES):
        return name
    close = difflib.get_close_matches(name, sorted(SUMMARY_COLUMNS), n=3)
    raise KeyError(f"{name!r} is no column of a sweep's table (the fields of brushbem.results.RunSummary); "
                   f"closest: {', '.join(close) or 'none'}")
