"""The pillar model's path: `pull_off` (``LoadPath.method = "pillars"``), as `brushbem.protocol.pull_off` yields it.

The model is described in `brushbem.pillars`.
"""

from __future__ import annotations

import dataclasses
import warnings
from collections.abc import Iterator

from threadpoolctl import ThreadpoolController

from brushbem.errors import ParameterError
from brushbem.pillars.basis import PillarModel
from brushbem.pillars.cg import NotConverged
from brushbem.pillars.checks import check_applicable
from brushbem.pillars.domain import PillarDomainWarning, domain_warning, peel_warning
from brushbem.pillars.events import events
from brushbem.pillars.state import Interrupted, begin, record
from brushbem.pillars.tips import tip_factor
from brushbem.protocol.problem import ContactProblem, LoadPath, State, check_preload

__all__ = ["pull_off"]

def pull_off(problem: ContactProblem, path: LoadPath, *, modes: str | None = None, coupling: str = "local",
             peel: bool = True, near: float | None = None, stop=None) -> Iterator[State]:
    """The states of a press-and-pull-off in the pillar model (module docstring), as `paths.pull_off` yields them.

    ``modes``, ``coupling``, ``peel`` and ``near`` select the model's
    variants (the defaults meet the accuracy of the module docstring);
    ``modes`` and ``near`` default to ``path.pillar_modes`` and
    ``path.pillar_near``, and ``path.pillar_solve`` chooses the solve
    (`brushbem.pillars.solver.Solver`).
    ``stop`` (callable or None) is asked in every round of the model's long
    steps (cascades, peels, presses): when it returns True the path ends
    there, without a state for the unfinished step.
    """
    check_applicable(problem, path)
    check_preload(problem.indenter, path)
    warning = domain_warning(problem)
    if warning is not None:
        warnings.warn(warning, PillarDomainWarning, stacklevel=2)
    # The pillar-level matrices are small (M^2 for M pillars): BLAS threads gain little there, and on a
    # machine whose cores are busy they lose a great deal (a 256 x 256 Cholesky factorisation took 0.26 s
    # on two threads of two loaded cores against 0.75 ms on one).  The limit holds while the states are
    # consumed too, and is lifted when the generator ends or is closed.
    with ThreadpoolController().limit(limits=1, user_api="blas"):
        model = PillarModel(problem, modes=path.pillar_modes if modes is None else modes, coupling=coupling,
                            peel=peel, near=path.pillar_near if near is None else near,
                            tips=tip_factor(problem, path.pillar_tip_resolution),
                            criterion="peel" if path.tip_peel else
                            "calibrated" if path.pillar_tip_calibration else "raster")
        if path.pillar_solve == "cg" and model.lattice is None:
            raise ParameterError("LoadPath", "pillar_solve", "LoadPath.pillar_solve = 'cg' solves on a lattice's "
                                 "FFT; this brush's pillars are not on a lattice: use 'auto' or 'kept'")
        cache, start = begin(model, path, stop)
        last = None
        try:
            warned = not model.continuum_peel
            for _, last in events(cache, start, path):
                if not warned and peel_warning(cache.largest_tilt) is not None:
                    # Once, when a tip first varies beyond the first-order peel's measured domain.
                    warned = True
                    warnings.warn(peel_warning(cache.largest_tilt), PillarDomainWarning, stacklevel=2)
                yield last
        except Interrupted:
            return  # the caller asked to stop: the last state yielded stands
        except NotConverged as error:
            # The last state stands (before the first, the start: nothing attached); the path stops there, saying
            # why (as the element paths do).
            if last is None:
                yield record(cache, start, 0.0, True, "equilibrium", str(error), converged=False)
            else:
                yield dataclasses.replace(last, kind="equilibrium", reason=str(error), converged=False,
                                          n_solves=cache.solves - cache.reported)
