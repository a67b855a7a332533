"""Frozen records that also read as mappings: typed for code, plain for JSON, NetCDF and tables."""

from __future__ import annotations

from collections.abc import Callable, Iterator, Mapping
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

    @classmethod
    def _nested(cls) -> Mapping[str, Callable[[Any], Any]]:
        """Field -> what rebuilds its value from a mapping (a nested record); none by default."""
        return {}

    @classmethod
    def from_mapping(cls, mapping: Mapping[str, Any]) -> Any:
        """The record of ``mapping``, as `to_dict` or ``summary.json`` gives it, nested records rebuilt.

        The inverse of reading the record as a mapping: ``type(r).from_mapping(r) == r`` for every record.

        Raises
        ------
        ValueError
            A key that is no field of the record, or a field without a default that is missing
            (a file of another layout), named.
        """
        if isinstance(mapping, cls):
            return mapping
        if not isinstance(mapping, Mapping):
            raise ValueError(f"{cls.__name__}: expected a mapping of its fields, got {type(mapping).__name__}")
        names = [f.name for f in fields(cls)]
        unknown = sorted(set(mapping) - set(names))
        if unknown:
            raise ValueError(f"{cls.__name__}: unknown keys {unknown}; its fields are {names}")
        nested = cls._nested()
        values = {key: nested[key](value) if key in nested and value is not None else value
                  for key, value in mapping.items()}
        try:
            return cls(**values)
        except TypeError as exc:  # a required field missing
            raise ValueError(f"{cls.__name__}: {exc}; its fields are {names}") from None

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
