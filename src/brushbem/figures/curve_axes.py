"""The run figure's axes: the SI prefix that reads, the thesis's normalised axes, the closed-form limits.

`si_prefixed` chooses the prefix that writes a magnitude with 1 to 999 before
its unit (6.208e4 µN is 62.08 mN); `CurveScales` holds the factors and the
labels of the force-displacement axes (physical with that prefix, or
normalised by a brush's N_p F_K and |d_c|, a punch's or a sphere's closed
form); `reference_limits` names the closed-form adhesive forces that
``summary.json`` records, drawn as horizontal lines.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from brushbem.results.units import Units

__all__ = ["CurveScales", "reference_limits", "si_prefixed"]


def reference_limits(theory: Mapping[str, Any], curve_drawn: bool) -> list[tuple[float, str, Any]]:
    """The closed-form adhesive forces drawn as horizontal lines: (force magnitude, label, line style)."""
    def value(key: str) -> float | None:
        number = theory.get(key)
        return float(number) if isinstance(number, (int, float)) and math.isfinite(number) and number > 0 else None

    limits = []
    if value("rigid_brush_force") is not None:
        limits.append((value("rigid_brush_force"), r"$-F_\mathrm{c}$, rigid brush (eq. 4.5)", (0, (5.0, 3.0))))
    if value("ideal_sharing_force") is not None:
        limits.append((value("ideal_sharing_force"), r"$-N_\mathrm{p}F_\mathrm{K}$, equal sharing (eq. 7.4)",
                       (0, (1.0, 2.0))))
    if not limits and not curve_drawn and value("adhesive_force") is not None:
        limits.append((value("adhesive_force"), f"closed form: {str(theory.get('model', '')).split(' (')[0]}",
                       (0, (5.0, 3.0))))
    return limits


#: SI prefixes by their power of ten, for numbers and axes that read (62.08 mN, not 6.208e+04 µN).
_SI = {-15: "f", -12: "p", -9: "n", -6: "µ", -3: "m", 0: "", 3: "k", 6: "M", 9: "G"}
_SI_POWER = {prefix: power for power, prefix in _SI.items()} | {"u": -6}
#: The units a prefix is chosen for (a compound unit such as N/mm keeps its own).
_SI_BASES = ("Pa", "N", "J", "m")


def si_prefixed(label: str, magnitude: float) -> tuple[float, str]:
    """The factor and unit that write ``magnitude`` (in unit ``label``) with 1 to 999 before the unit.

    ``si_prefixed("µN", 6.208e4)`` is ``(1e-3, "mN")``: 6.208e4 µN is 62.08 mN.  A unit that is not a
    prefix and one of `_SI_BASES` (N/mm, MPa·mm) or a magnitude of 0 keeps its unit (factor 1).
    """
    base = next((b for b in _SI_BASES if label.endswith(b) and label[:-len(b)] in _SI_POWER), None)
    if base is None or not (math.isfinite(magnitude) and magnitude > 0):
        return 1.0, label
    power = _SI_POWER[label[:-len(base)]]
    target = power + 3 * math.floor(math.log10(magnitude) / 3 + 1e-9)
    target = min(max(target, min(_SI)), max(_SI))
    if base == "m" and target > 0:  # km of a contact: keep metres
        target = 0
    return 10.0 ** (power - target), _SI[target] + base


class CurveScales:
    """How the curve's numbers are shown: factors (SI prefix or normalisation) and labels of the two axes."""

    def __init__(self, x: float, y: float, x_label: str, y_label: str, units: Units, force_unit: str,
                 force_factor: float, normalized: bool) -> None:
        self.x, self.y, self.x_label, self.y_label = x, y, x_label, y_label
        self._units, self._force_unit, self._force_factor, self._normalized = units, force_unit, force_factor, normalized

    @classmethod
    def of(cls, theory: Mapping[str, Any], units: Units, displacement: np.ndarray, force: np.ndarray,
           normalized: bool) -> CurveScales:
        force_factor, force_unit = (si_prefixed(units.label("force"), float(np.max(np.abs(force), initial=0.0)))
                                    if not units.dimensionless else (1.0, ""))
        if normalized:
            brush = theory.get("ideal_sharing_force"), theory.get("rigid_brush_displacement")
            single = theory.get("adhesive_force"), theory.get("pull_off_displacement")
            if all(isinstance(v, (int, float)) and v for v in brush):
                f_scale, d_scale = float(brush[0]), abs(float(brush[1]))
                labels = (r"$d\,/\,|d_\mathrm{c}|$ (eq. 4.12)", r"$F\,/\,(N_\mathrm{p} F_\mathrm{K})$ (eq. 7.4)")
            elif all(isinstance(v, (int, float)) and v for v in single):
                f_scale, d_scale = float(single[0]), abs(float(single[1]))
                labels = (r"$d\,/\,|d_\mathrm{A}^\mathrm{closed}|$", r"$F\,/\,F_\mathrm{A}^\mathrm{closed}$")
            else:
                raise ValueError("normalized axes: the run's summary records no closed form to normalise by "
                                 "(theory); draw it on physical axes")
            return cls(1.0 / d_scale, 1.0 / f_scale, *labels, units, force_unit, force_factor, True)
        if units.dimensionless:
            return cls(1.0, 1.0, r"base displacement $d$", r"force $F$", units, "", 1.0, False)
        x_factor, x_unit = si_prefixed(units.label("length"), float(np.max(np.abs(displacement), initial=0.0)))
        return cls(x_factor, force_factor, rf"base displacement $d$ ({x_unit})", rf"force $F$ ({force_unit})",
                   units, force_unit, force_factor, False)

    def force_text(self, value: Any, *, physical: bool = False) -> str:
        """A force in the unit of the axis's prefix (on normalised axes: normalised, unless ``physical``)."""
        try:
            number = float(value)
        except (TypeError, ValueError):
            return "nan"
        if self._normalized and not physical:
            return f"{number * self.y:.4g}"
        return f"{number * self._force_factor:.4g}" + (f" {self._force_unit}" if self._force_unit else "")

    def energy_text(self, value: Any) -> str:
        try:
            number = float(value)
        except (TypeError, ValueError):
            return "nan"
        return self._units.readable(number, "energy")
