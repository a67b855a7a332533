"""The typed records of a run, below the load path and the files.

`brushbem.protocol` records a pull-off into them, `brushbem.runs` adds the
closed forms, `brushbem.io` writes them and reads them back as the same
types, and sweeps and studies read their fields.  Nothing here imports any
other part of brushbem.

Modules
    `mapping`
        `MappingRecord`: a frozen record that also reads as the mapping of
        its fields (the keys of ``summary.json``).
    `case`
        The curve, the snapshots, the summary, the closed-form records and
        `CaseResult`, everything one run produces.
    `normalization`, `refinement`, `provenance`, `design`
        The summary's ``normalized`` (a brush in the thesis's scales),
        ``refinement`` (``--refine``), ``provenance`` (recorded on saving),
        ``resolution`` and ``design``.
    `units`
        The unit system a configuration declares (``[units]``).
"""

from __future__ import annotations

from brushbem.results.case import (
    BrushTheory,
    CaseResult,
    Curve,
    PullOffSummary,
    PunchTheory,
    ReferenceCurve,
    RunSummary,
    Snapshot,
    SphereTheory,
    Theory,
    theory_from_mapping,
)
from brushbem.results.design import DesignNumbers, ResolutionRecord, Spring
from brushbem.results.mapping import MappingRecord
from brushbem.results.normalization import BrushNormalization
from brushbem.results.provenance import Provenance
from brushbem.results.refinement import Extrapolation, Refinement

__all__ = ["BrushNormalization", "BrushTheory", "CaseResult", "Curve", "DesignNumbers", "Extrapolation",
           "MappingRecord", "Provenance", "PullOffSummary", "PunchTheory", "ReferenceCurve", "Refinement",
           "ResolutionRecord", "RunSummary", "Snapshot", "SphereTheory", "Spring", "Theory", "theory_from_mapping"]
