"""A run on refined grids and its Richardson extrapolation: ``summary.json``'s ``refinement``.

`brushbem.runs.refine` computes it (``brushbem run --refine``); the error of
the Pohrt-Popov criterion is first order in h (`FORMAL_ORDER`).
"""

from __future__ import annotations

from dataclasses import dataclass

from brushbem.results.mapping import MappingRecord

__all__ = ["FORMAL_ORDER", "Extrapolation", "Refinement"]

#: The order in h of the Pohrt-Popov criterion's error.
FORMAL_ORDER = 1.0


@dataclass(frozen=True, kw_only=True)
class Extrapolation(MappingRecord):
    """One quantity on the refined grids (`brushbem.runs.refine`): its values, coarse to fine, and the
    extrapolated value with its error estimate and the order used."""

    values: list
    extrapolated: float
    error_estimate: float | None  # None: no bound (two grids)
    observed_order: float | None
    order: float = FORMAL_ORDER
    basis: str = "formal order"
    formal_order: float = FORMAL_ORDER


@dataclass(frozen=True, kw_only=True)
class Refinement(MappingRecord):
    """``summary.json``'s ``refinement``: the grids and the extrapolated quantities."""

    elements: list
    adhesive_force: Extrapolation
    work_of_separation: Extrapolation
    converged: bool
    _ABSENT_WHEN_NONE = frozenset({"tip_elements_per_radius"})

    #: The pillar model refines its tips alone (``elements`` are then the grids that resolve them as much).
    tip_elements_per_radius: list | None = None

    @classmethod
    def _nested(cls):
        return {"adhesive_force": Extrapolation.from_mapping, "work_of_separation": Extrapolation.from_mapping}
