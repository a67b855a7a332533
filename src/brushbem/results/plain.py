"""The plain JSON form of result values, and back: ``summary.json``, NetCDF attributes, sweep tables.

JSON has no infinity or NaN, and ``null`` would read as "missing", so
`to_json_safe` writes ``inf``, ``-inf`` and ``nan`` as the strings
``"inf"``, ``"-inf"`` and ``"nan"``, and `from_json_safe` reads them back.
Records (`MappingRecord`) are written as the mappings of their fields.  The
configuration (`brushbem.config.config_to_dict`), the result files
(`brushbem.io`) and the sweep tables all write through here.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

__all__ = ["from_json_safe", "to_json_safe"]

#: How `to_json_safe` writes the non-finite numbers JSON has no literal for.
_NON_FINITE = {"nan": float("nan"), "inf": float("inf"), "-inf": float("-inf")}


def to_json_safe(value: Any) -> Any:
    """Convert to plain JSON data; non-finite floats become strings.

    Parameters
    ----------
    value : any
        Nested mappings (records included), lists, tuples, numbers, strings,
        booleans, None, NumPy scalars or arrays.

    Returns
    -------
    any
        The same structure with JSON-representable leaves only.
    """
    if isinstance(value, Mapping):
        return {str(key): to_json_safe(item) for key, item in value.items()}
    if isinstance(value, (list, tuple)):
        return [to_json_safe(item) for item in value]
    if isinstance(value, np.ndarray):
        return to_json_safe(value.tolist())
    if isinstance(value, np.generic):
        return to_json_safe(value.item())
    if isinstance(value, float) and not math.isfinite(value):
        return "nan" if math.isnan(value) else ("inf" if value > 0 else "-inf")
    return value


def from_json_safe(node: Any) -> Any:
    """A decoded summary with its non-finite numbers ("nan", "inf") numbers again (`to_json_safe`'s inverse)."""
    if isinstance(node, dict):
        return {key: from_json_safe(value) for key, value in node.items()}
    if isinstance(node, list):
        return [from_json_safe(value) for value in node]
    return _NON_FINITE.get(node, node) if isinstance(node, str) else node
