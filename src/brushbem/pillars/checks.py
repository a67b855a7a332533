"""Where the pillar model (``LoadPath.method = "pillars"``) does not apply: `check_applicable`.

It refuses, naming the key, indenters that are not brushes, viscoelastic
connections, nonlinear pillar laws, tips that are not flat, tilted bases, no
adhesion (work of adhesion 0), a pulling speed and backends other than NumPy.  Tips of unequal lengths
(roughness, a length profile or file) are modelled (`brushbem.pillars.loading`).
"""

from __future__ import annotations

import numpy as np

from brushbem.errors import ParameterError
from brushbem.physics.structure import BrushGeometry
from brushbem.protocol.problem import ContactProblem, LoadPath

__all__ = ["check_applicable"]


def check_applicable(problem: ContactProblem, path: LoadPath | None = None) -> None:
    """Raise `ParameterError` (of ``LoadPath.method``), naming the parameter, where the pillar model does not apply."""
    indenter = problem.indenter
    info = indenter.description
    where = "LoadPath.method = 'pillars'"
    if not isinstance(info, BrushGeometry):
        raise _refused(f"{where} models brushes of flat pillars (built by brush()); this indenter is "
                         f"{getattr(info, 'shape', 'custom')!r}: use method = 'events'")
    if indenter.viscoelastic is not None:
        raise _refused(f"{where} does not model Indenter.viscoelastic: use method = 'fixed'")
    if indenter.pillar_law is not None:
        raise _refused(f"{where} does not model Indenter.pillar_law: use method = 'fixed'")
    if info.tip != "flat":
        raise _refused(f"{where} needs flat tips in full contact; brush(tip=...) gives {info.tip!r}: use "
                         "method = 'events'")
    if info.tilt_angle != 0.0:
        raise _refused(f"{where} needs level tips; brush(tilt=...) (angle {info.tilt_angle:g} deg) peels a tip "
                         "partly: use method = 'events'")
    if path is not None and path.speed is not None:
        raise _refused(f"{where}: LoadPath.speed applies to viscoelastic pillars only; remove it")
    if not problem.work_of_adhesion > 0:
        # Without adhesion a slot leaves at the least tension (the criterion is p < 0), and at the edge of a
        # partial contact the fitted field lets it touch again at once: the model's cascade does not settle.
        raise _refused(f"{where} models adhesive pull-off; ContactProblem.work_of_adhesion = "
                       f"{problem.work_of_adhesion:g} must be > 0 (without adhesion F_A = 0): use method = 'events'")
    if problem.xp is not np:
        raise _refused(f"{where} runs on NumPy (the pillar-level arrays are small); use the default backend")
    height = np.asarray(indenter.height)
    labels = np.asarray(indenter.pillar)
    inside = labels >= 0
    top = np.full(indenter.n_pillars, -np.inf)
    low = np.full(indenter.n_pillars, np.inf)
    np.maximum.at(top, labels[inside], height[inside])
    np.minimum.at(low, labels[inside], height[inside])
    if np.any(top - low > 1e-12 * np.maximum(np.abs(top), 1.0) + 1e-300):
        raise _refused(f"{where} needs flat tips: a pillar's elements are at different heights "
                         "(brush(tip=...) or tilt=...): use method = 'events'")


def _refused(message: str) -> ParameterError:
    """The pillar model's refusal: a `ParameterError` of ``LoadPath.method``."""
    return ParameterError("LoadPath", "method", message)
