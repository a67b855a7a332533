"""The error of a structure that cannot be built as asked (`StructureError`)."""

from __future__ import annotations

__all__ = ["StructureError"]


class StructureError(ValueError):
    """A structure that cannot be built as asked: names the key, the value and what is allowed."""

    def __init__(self, key: str, value: object, allowed: str):
        self.key = key
        self.value = value
        self.allowed = allowed
        super().__init__(f"indenter.{key} = {value!r}: {allowed}")
