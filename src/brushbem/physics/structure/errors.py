"""The error of a structure that cannot be built as asked (`StructureError`)."""

from __future__ import annotations

from brushbem.errors import ParameterError

__all__ = ["StructureError"]


class StructureError(ParameterError):
    """A structure that cannot be built as asked: names the parameter (``key``), the value and what is allowed.

    A `ParameterError` of ``brush`` (``owner``) whose ``parameter`` is ``key``.
    """

    def __init__(self, key: str, value: object, allowed: str):
        self.key = key
        self.value = value
        self.allowed = allowed
        super().__init__("brush", key, f"brush({key}={value!r}): {allowed}")
