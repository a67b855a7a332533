"""Values turned into JSON and NetCDF attributes, and back.

`_json` (strict JSON of `brushbem.results.plain.to_json_safe`'s values),
`netcdf_attributes` (what NetCDF can store as an attribute) and `_attribute`
(an attribute as written); `from_json_safe`, the inverse of `to_json_safe`,
is `brushbem.results.plain`'s.
"""

from __future__ import annotations

import json
from typing import Any

import numpy as np

from brushbem.results.plain import to_json_safe


def _json(value: Any, indent: int | None = None) -> str:
    # allow_nan=False: a non-finite number that slipped through is a bug to see.
    return json.dumps(to_json_safe(value), indent=indent, allow_nan=False)


def _netcdf_attribute(value: Any) -> str | int | float | np.ndarray:
    """A value NetCDF can store as an attribute; structured values become JSON."""
    if isinstance(value, (bool, np.bool_)):
        # NetCDF has no boolean attribute type.
        return int(value)
    if isinstance(value, (str, int, float, np.integer, np.floating)):
        return value
    return _json(value)


def netcdf_attributes(attributes: dict[str, Any]) -> dict[str, Any]:
    """Attributes NetCDF can store: strings and numbers kept, the rest as JSON.

    Parameters
    ----------
    attributes : dict
        Any provenance values (nested dicts and lists become JSON strings,
        booleans integers, since NetCDF has neither).

    Returns
    -------
    dict
    """
    return {str(key): _netcdf_attribute(value) for key, value in attributes.items()}


def _attribute(value: Any) -> Any:
    """A NetCDF attribute as `to_dataset` wrote it: JSON strings decoded, the rest as is."""
    if isinstance(value, str) and (value.startswith(("{", "[")) or value == "null"):
        try:
            return json.loads(value)
        except ValueError:
            return value
    return value.item() if isinstance(value, np.generic) else value
