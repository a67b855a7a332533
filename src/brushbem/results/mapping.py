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
    brush normalisations).  ``_KEY_OF`` names the key of a field whose key is no
    Python name (``origin`` read as ``"from"``).
    """

    _ABSENT_WHEN_NONE: frozenset[str] = frozenset()
    _KEY_OF: Mapping[str, str] = {}

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
        field_of = {cls._KEY_OF.get(name, name): name for name in names}
        unknown = sorted(set(mapping) - set(field_of))
        if unknown:
            raise ValueError(f"{cls.__name__}: unknown keys {unknown}; its keys are {list(field_of)}")
        nested = cls._nested()
        values = {field_of[key]: nested[field_of[key]](value) if field_of[key] in nested and value is not None
                  else value for key, value in mapping.items()}
        try:
            return cls(**values)
        except TypeError as exc:  # a required field missing
            raise ValueError(f"{cls.__name__}: {exc}; its fields are {names}") from None

    def _fields_by_key(self) -> dict[str, str]:
        """Key -> field, in field order, the absent ones left out."""
        return {self._KEY_OF.get(f.name, f.name): f.name for f in fields(self)
                if not (f.name in self._ABSENT_WHEN_NONE and getattr(self, f.name) is None)}

    def _keys(self) -> list[str]:
        return list(self._fields_by_key())

    def __getitem__(self, key: str) -> Any:
        field_name = self._fields_by_key().get(key)
        if field_name is not None:
            return getattr(self, field_name)
        raise KeyError(key)

    def __iter__(self) -> Iterator[str]:
        return iter(self._keys())

    def __len__(self) -> int:
        return len(self._keys())

    def to_dict(self) -> dict[str, Any]:
        """The plain mapping (nested mappings as they are)."""
        return {key: getattr(self, name) for key, name in self._fields_by_key().items()}
