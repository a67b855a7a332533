"""The unit system a configuration declares (``[units]``), for labels and NetCDF ``units``.

brushbem computes in whatever consistent units the inputs use: E* sets the
stress and ``grid.size`` the length, and every other quantity follows (a
force is a stress times an area).  The numbers never change with the unit
system; ``[units]`` only names it, so that figures, tables and ``result.nc``
say "mm" and "N" instead of "units of the inputs"::

    [units]
    length = "mm"
    stress = "MPa"     # then forces are in N, works in mJ, work of adhesion in N/mm

Without ``[units]`` (the default) the quantities are dimensionless: the
NetCDF ``units`` attribute is CF's ``"1"`` and the physical dimension is kept
in the attribute ``dimension``.  Every unit written is a UDUNITS-2 string, as
CF-1.10 asks (``um`` is the micrometre; figures show it as µm).
"""

from __future__ import annotations

import json
import math
import re
from dataclasses import dataclass

__all__ = ["DIMENSIONS", "LENGTH_UNITS", "STRESS_UNITS", "Units"]

#: Length units by their power of ten in metres.
LENGTH_UNITS = {"m": 0, "cm": -2, "mm": -3, "um": -6, "nm": -9}
#: Stress units by their power of ten in pascal.
STRESS_UNITS = {"Pa": 0, "kPa": 3, "MPa": 6, "GPa": 9}
#: The physical dimensions brushbem writes, in its own notation.
DIMENSIONS = ("length", "stress", "force", "length^2", "force / length", "energy")

_PREFIXES = {-12: "p", -9: "n", -6: "u", -3: "m", 0: "", 3: "k", 6: "M", 9: "G"}


def _prefixed(exponent: int, unit: str) -> str | None:
    prefix = _PREFIXES.get(exponent)
    return None if prefix is None else prefix + unit


@dataclass(frozen=True)
class Units:
    """A length and a stress unit, or neither (dimensionless).

    Parameters
    ----------
    length : str or None
        One of `LENGTH_UNITS`.
    stress : str or None
        One of `STRESS_UNITS`; given with ``length`` or not at all.
    """

    length: str | None = None
    stress: str | None = None

    def __post_init__(self) -> None:
        if (self.length is None) != (self.stress is None):
            raise ValueError(f"units: give both length and stress, or neither (got length = {self.length!r}, "
                             f"stress = {self.stress!r})")
        if self.length is not None and self.length not in LENGTH_UNITS:
            raise ValueError(f"units.length = {self.length!r}: must be one of {', '.join(LENGTH_UNITS)}")
        if self.stress is not None and self.stress not in STRESS_UNITS:
            raise ValueError(f"units.stress = {self.stress!r}: must be one of {', '.join(STRESS_UNITS)}")

    @property
    def dimensionless(self) -> bool:
        return self.length is None

    def of(self, dimension: str) -> str:
        """The UDUNITS-2 unit of ``dimension`` (one of `DIMENSIONS`); ``"1"`` when dimensionless."""
        if dimension not in DIMENSIONS:
            raise ValueError(f"dimension {dimension!r}: must be one of {', '.join(DIMENSIONS)}")
        if self.dimensionless:
            return "1"
        length, stress = str(self.length), str(self.stress)
        metres, pascals = LENGTH_UNITS[length], STRESS_UNITS[stress]
        force = _prefixed(pascals + 2 * metres, "N") or f"{stress} {length}2"
        if dimension == "length":
            return length
        if dimension == "stress":
            return stress
        if dimension == "force":
            return force
        if dimension == "length^2":
            return f"{length}2"
        if dimension == "force / length":
            return f"{force} {length}-1" if force.endswith("N") else f"{stress} {length}"
        return _prefixed(pascals + 3 * metres, "J") or f"{force} {length}"  # energy

    def label(self, dimension: str) -> str:
        """``of(dimension)`` for a figure: µm for um, N/mm for "N mm-1", ``"-"`` when dimensionless."""
        if self.dimensionless:
            return "-"
        text = re.sub(r"\bu(?=[mNJ])", "µ", self.of(dimension))
        if text.endswith("-1"):
            numerator, _, denominator = text[:-2].rpartition(" ")
            text = f"{numerator}/{denominator}"
        return text.replace("2", "²")

    def readable(self, value: float, dimension: str) -> str:
        """``value`` (in this system's unit of ``dimension``) with the SI prefix that puts 1 <= |mantissa| < 1000.

        ``7868.83`` µN reads "7.87 mN", ``0.0112`` MPa "11.2 kPa"; an area keeps the inputs' unit
        (µm², mm²), and a dimensionless system (or a zero, an infinity) gives the number alone.
        """
        if self.dimensionless or not math.isfinite(value):
            return f"{value:.4g}"
        if dimension == "length^2":
            return f"{value:.4g} {self.label(dimension)}"
        metres, pascals = LENGTH_UNITS[str(self.length)], STRESS_UNITS[str(self.stress)]
        exponent, base = {"length": (metres, "m"), "stress": (pascals, "Pa"), "force": (pascals + 2 * metres, "N"),
                          "energy": (pascals + 3 * metres, "J"),
                          "force / length": (pascals + metres, "N/m")}[dimension]
        si = value * 10.0**exponent
        if si == 0:
            return f"0 {base}"
        power = max(-12, min(9, 3 * math.floor(math.log10(abs(si)) / 3)))
        return f"{si / 10.0**power:.4g} {_PREFIXES[power].replace('u', 'µ')}{base}"

    def axis(self, name: str, dimension: str) -> str:
        """An axis label: ``name (unit)``, or ``name (units of the inputs)`` when dimensionless."""
        if self.dimensionless:
            return f"{name} (units of the inputs)"
        return f"{name} ({self.label(dimension)})"

    @classmethod
    def of_record(cls, attributes: dict) -> Units:
        """The units of a run's provenance attributes: ``attributes["config"]`` as a mapping or as the
        JSON text a ``result.nc`` stores; dimensionless when absent or unreadable."""
        config = attributes.get("config")
        if isinstance(config, str):
            try:
                config = json.loads(config)
            except ValueError:
                config = None
        return cls.from_config(config) if isinstance(config, dict) else cls()

    @classmethod
    def from_config(cls, config: object) -> Units:
        """The units of a `RunConfig` or of its JSON form (a mapping); dimensionless when absent."""
        table = config.get("units") if isinstance(config, dict) else getattr(config, "units", None)
        if table is None:
            return cls()
        if isinstance(table, dict):
            return cls(table.get("length"), table.get("stress"))
        return cls(getattr(table, "length", None), getattr(table, "stress", None))
