"""Where the pillar model (``LoadPath.method = "pillars"``) does not apply: `check_applicable`.

The rule is `brushbem.physics.pillar_model_domain` (light, so that validation reads it without loading the
model).  It refuses, naming the key, indenters that are not brushes, viscoelastic
connections, nonlinear pillar laws, tips that are not flat, tilted bases, no
adhesion (work of adhesion 0), a pulling speed and backends other than NumPy.  Tips of unequal lengths
(roughness, a length profile or file) are modelled (`brushbem.pillars.loading`).
"""

from __future__ import annotations

import numpy as np

from brushbem.errors import raise_first
from brushbem.physics.pillar_model_domain import pillar_model_problems
from brushbem.protocol.problem import ContactProblem, LoadPath

__all__ = ["check_applicable"]


def check_applicable(problem: ContactProblem, path: LoadPath | None = None) -> None:
    """Raise `ParameterError` (of ``LoadPath.method``), naming the parameter, where the pillar model does not apply
    (the rule: `brushbem.physics.pillar_model_domain.pillar_model_problems`)."""
    raise_first(pillar_model_problems(problem.indenter, work_of_adhesion=problem.work_of_adhesion,
                                      speed=None if path is None else path.speed, on_numpy=problem.xp is np))
