"""Frozen records that also read as mappings: typed for code, plain for JSON, NetCDF and tables."""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from dataclasses import fields
from typing import Any

__all__ = ["MappingRecord"]


class MappingRecord(Mapping):
    """A frozen record that also reads as the mapping of its fields (the keys of ``summary.json``).

    Code reads the attributes (``summary.adhesive_force``); JSON, NetCDF
    attributes and sweep tables read it as a mapping, in field order.  A field
    named in ``_ABSENT_WHEN_NONE`` that is None is not a key (a punch has no
    brush normalisations).
    """

    _ABSENT_WHEN_NONE: frozenset[str] = frozenset()

    def _keys(self) -> list[str]:
        return [f.name for f in fields(self)
                if not (f.name in self._ABSENT_WHEN_NONE and getattr(self, f.name) is None)]

    def __getitem__(self, key: str) -> Any:
        if key in self._keys():
            return getattr(self, key)
        raise KeyError(key)

    def __iter__(self) -> Iterator[str]:
        return iter(self._keys())

    def __len__(self) -> int:
        return len(self._keys())

    def to_dict(self) -> dict[str, Any]:
        """The plain mapping (nested mappings as they are)."""
        return {key: getattr(self, key) for key in self._keys()}
