"""Which problems the pillar-level model (``LoadPath.method = "pillars"``, `brushbem.pillars`) represents.

The rule, stated once as a predicate of plain values (`pillar_model_problems`):
brushes of flat, level tips on elastic linear connections, with adhesion, on
the NumPy backend, without a pulling speed.  Tips of unequal lengths
(roughness, a length profile or file) are modelled (`brushbem.pillars.loading`).
The pillar model raises the first problem at its start
(`brushbem.pillars.check_applicable`); the configuration's rules on the
rasterised structure report it before a run without importing the model or
SciPy (``brushbem validate`` stays light).
"""

from __future__ import annotations

import numpy as np

from brushbem.errors import ParameterProblem
from brushbem.physics.structure import BrushGeometry, Indenter

__all__ = ["default_tip_peel", "pillar_model_problems"]

_WHERE = "LoadPath.method = 'pillars'"


def default_tip_peel(method: str, calibration: bool = False) -> bool:
    """The tips' criterion of a path that does not name one (``LoadPath.pillar_tip_peel`` None): whole tips at
    their continuum capacity for the pillar model (the flat, hierarchical and concave 8 x 8 families within 1 % of
    their limit at 3.6 elements per radius, the raster's own criterion +2.8 .. +8.1 %: ``docs/pillars/peel.py``,
    ``docs/pillars/accuracy.md``), unless its tips are calibrated (``pillar_tip_calibration``, a criterion of its
    own); no other method has tips of its own (False)."""
    return method == "pillars" and not calibration


def pillar_model_problems(indenter: Indenter, *, work_of_adhesion: float, speed: float | None = None,
                          on_numpy: bool = True) -> list[ParameterProblem]:
    """Why the pillar model does not apply to ``indenter`` (every reason, as problems of ``LoadPath.method``).

    ``work_of_adhesion``: the contact's; ``speed``: the path's pulling speed (None: none); ``on_numpy``:
    whether the arrays are NumPy's.
    """
    info = indenter.description
    reasons = []
    if not isinstance(info, BrushGeometry):
        return [_refused(f"models brushes of flat pillars (built by brush()); this indenter is "
                         f"{getattr(info, 'shape', 'custom')!r}: use method = 'events'")]
    if indenter.viscoelastic is not None:
        reasons.append("does not model Indenter.viscoelastic: use method = 'fixed'")
    if indenter.pillar_law is not None:
        reasons.append("does not model Indenter.pillar_law: use method = 'fixed'")
    if info.tip != "flat":
        reasons.append(f"needs flat tips in full contact; brush(tip=...) gives {info.tip!r}: use method = 'events'")
    if info.tilt_angle != 0.0:
        reasons.append(f"needs level tips; brush(tilt=...) (angle {info.tilt_angle:g} deg) peels a tip partly: use "
                       "method = 'events'")
    if speed is not None:
        reasons.append("LoadPath.speed applies to viscoelastic pillars only; remove it")
    if not work_of_adhesion > 0:
        # Without adhesion a slot leaves at the least tension (the criterion is p < 0), and at the edge of a
        # partial contact the fitted field lets it touch again at once: the model's cascade does not settle.
        reasons.append(f"models adhesive pull-off; ContactProblem.work_of_adhesion = {work_of_adhesion:g} must be "
                       "> 0 (without adhesion F_A = 0): use method = 'events'")
    if not on_numpy:
        reasons.append("runs on NumPy (the pillar-level arrays are small); use the default backend")
    if not reasons and _uneven_tips(indenter):
        reasons.append("needs flat tips: a pillar's elements are at different heights (brush(tip=...) or tilt=...): "
                       "use method = 'events'")
    return [_refused(reason) for reason in reasons]


def _uneven_tips(indenter: Indenter) -> bool:
    """Whether some pillar's elements lie at different heights (to rounding)."""
    height = np.asarray(indenter.height)
    labels = np.asarray(indenter.pillar)
    inside = labels >= 0
    top = np.full(indenter.n_pillars, -np.inf)
    low = np.full(indenter.n_pillars, np.inf)
    np.maximum.at(top, labels[inside], height[inside])
    np.minimum.at(low, labels[inside], height[inside])
    return bool(np.any(top - low > 1e-12 * np.maximum(np.abs(top), 1.0) + 1e-300))


def _refused(reason: str) -> ParameterProblem:
    """The pillar model's refusal: a problem of ``LoadPath.method``."""
    return ParameterProblem("LoadPath", "method", "pillars", reason)
