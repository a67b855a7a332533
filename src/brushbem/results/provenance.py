"""Where the numbers of a run come from: ``summary.json``'s ``provenance``.

`brushbem.io.write_case` records it when it writes a run's files, and
`brushbem.io.load_result` reads it back with the summary.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from brushbem.results.mapping import MappingRecord

__all__ = ["Provenance"]


@dataclass(frozen=True, kw_only=True)
class Provenance(MappingRecord):
    """Version, commit, time, backend, units and configuration of a saved run.

    Attributes
    ----------
    brushbem_version : str
    commit : str or None
        The git commit of a checkout, None for an installed package.
    created : str
        UTC, ISO 8601 (``result.nc`` carries it as ``date_created``).
    backend : str or None
        The array backend the run computed on.
    units : str or dict
        The unit of length, stress, force and energy, or the statement that the
        numbers are in the units of the inputs.
    config : dict or None
        The resolved configuration (defaults filled in, file paths absolute).
    """

    brushbem_version: str | None
    commit: str | None
    created: str | None
    backend: str | None
    units: Any
    config: Any = None
