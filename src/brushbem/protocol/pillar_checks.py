"""Where the pillar model (``protocol.method = "pillars"``) does not apply: `check_applicable`.

It refuses, naming the key, indenters that are not brushes, viscoelastic
connections, nonlinear pillar laws, tips that are not flat or not level, tips
of different lengths, a pulling speed and backends other than NumPy.
"""

from __future__ import annotations

import numpy as np

from ..structure import BrushGeometry
from .problem import ContactProblem, LoadPath

__all__ = ["check_applicable"]


def check_applicable(problem: ContactProblem, path: LoadPath | None = None) -> None:
    """Raise ValueError, naming the key, where the pillar model does not apply."""
    indenter = problem.indenter
    info = indenter.description
    where = "protocol.method = 'pillars'"
    if not isinstance(info, BrushGeometry):
        raise ValueError(f"{where} models brushes of flat pillars (indenter.shape = 'brush'); this indenter is "
                         f"{getattr(info, 'shape', 'custom')!r}: use method = 'events'")
    if indenter.viscoelastic is not None:
        raise ValueError(f"{where} does not model indenter.viscoelastic: use method = 'fixed'")
    if indenter.pillar_law is not None:
        raise ValueError(f"{where} does not model indenter.pillar_law: use method = 'fixed'")
    if info.tip != "flat":
        raise ValueError(f"{where} needs flat tips in full contact; indenter.tip = {info.tip!r}: use "
                         "method = 'events'")
    if info.tilt_angle != 0.0:
        raise ValueError(f"{where} needs level tips; indenter.tilt (angle {info.tilt_angle:g} deg) peels a tip "
                         "partly: use method = 'events'")
    offsets = np.asarray(getattr(info, "offsets", np.zeros(1)), dtype=float)
    if offsets.size and np.ptp(offsets) > 0:
        raise ValueError(
            f"{where} presses every tip in whole; tips of different lengths (indenter.roughness, "
            f"indenter.lengths_file or indenter.profile: lengths spread {np.ptp(offsets):.3g}) touch partly while "
            "pressed, which it does not model (a rough 16 x 16 brush: work +4.4 %, 146 pillars attached at F_A "
            "against 131): use method = 'events'")
    if path is not None and path.speed is not None:
        raise ValueError(f"{where}: protocol.speed applies to viscoelastic pillars only; remove it")
    if problem.xp is not np:
        raise ValueError(f"{where} runs on NumPy (the pillar-level arrays are small); use the default backend")
    height = np.asarray(indenter.height)
    labels = np.asarray(indenter.pillar)
    inside = labels >= 0
    top = np.full(indenter.n_pillars, -np.inf)
    low = np.full(indenter.n_pillars, np.inf)
    np.maximum.at(top, labels[inside], height[inside])
    np.minimum.at(low, labels[inside], height[inside])
    if np.any(top - low > 1e-12 * np.maximum(np.abs(top), 1.0) + 1e-300):
        raise ValueError(f"{where} needs flat tips: a pillar's elements are at different heights "
                         "(indenter.tip or indenter.tilt): use method = 'events'")
