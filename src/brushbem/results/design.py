"""What a run reports beyond its pull-off: ``summary.json``'s ``resolution`` and ``design``.

`brushbem.config.advice.resolution` estimates the resolution (`ResolutionRecord`, the one record of it
from the estimate to the file and back);
`brushbem.runs.case.design_numbers` gives what a designer reports (`DesignNumbers`,
with its `Spring`).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import ClassVar

from brushbem.results.mapping import MappingRecord

__all__ = ["DesignNumbers", "ResolutionRecord", "Spring"]


@dataclass(frozen=True, kw_only=True)
class ResolutionRecord(MappingRecord):
    """The elements across the length that decides F_A and the discretisation error estimated there.

    Attributes
    ----------
    length : str
        What the length is ("pillar radius", "punch radius", "JKR contact radius at pull-off").
    key : str
        The configuration key it comes from.
    value, elements : float
        The length (units of length) and the length over the element size h.
    minimum_elements : float
        The fewest elements without a warning (`brushbem.config.advice.MIN_ELEMENTS_PER_RADIUS`).
    force_error_estimate, work_error_estimate : float, float or None
        The estimated relative error of F_A and of the work of separation (signed: > 0, too high).
    force_error_range, work_error_range : list of float, or None
        The smallest and largest error measured at this resolution.
    basis : str
        Where the estimate comes from.
    """

    length: str
    key: str
    value: float
    elements: float
    minimum_elements: float
    force_error_estimate: float
    force_error_range: list
    work_error_estimate: float | None
    work_error_range: list | None
    basis: str

    @property
    def resolved(self) -> bool:
        """Whether the length spans `minimum_elements` or more (no warning)."""
        return self.elements >= self.minimum_elements


@dataclass(frozen=True, kw_only=True)
class Spring(MappingRecord):
    """The (pillars') spring: its stiffness k, where it came from (key ``from``), its k~ as the run
    normalises it and, with ``indenter.fibril.buckling``, Euler's buckling force."""

    _ABSENT_WHEN_NONE = frozenset({"buckling_force"})
    _KEY_OF: ClassVar[Mapping[str, str]] = MappingProxyType({"origin": "from"})

    stiffness: float
    origin: str
    stiffness_ratio: float | None
    buckling_force: float | None = None


@dataclass(frozen=True, kw_only=True)
class DesignNumbers(MappingRecord):
    """What a designer reports, with the unit of each number (`brushbem.runs.case.design_numbers`).

    ``apparent_area`` and ``adhesion_strength`` (F_A / A0) are absent for a sphere and a height map;
    ``pillars`` and ``adhesive_force_per_pillar`` are a brush's; ``spring`` is absent for a rigid
    indenter; ``units`` maps each dimensional number to its unit ("1" without ``[units]``).
    """

    _ABSENT_WHEN_NONE = frozenset({"apparent_area", "adhesion_strength", "pillars", "adhesive_force_per_pillar",
                                   "spring"})

    apparent_area: float | None = None
    adhesion_strength: float | None = None
    pillars: int | None = None
    adhesive_force_per_pillar: float | None = None
    spring: Spring | None = None
    units: dict = field(default_factory=dict)

    @classmethod
    def _nested(cls):
        return {"spring": Spring.from_mapping}
