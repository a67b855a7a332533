"""What the solves on one indenter reuse, owned by their caller and passed in: `SolverCache`.

The operator (`brushbem.numerics.operator.ContactOperator`) computes and keeps
nothing between calls; a caller that solves again and again on the same
indenter (the load paths' context) holds one `SolverCache` and passes it to
every solve (`brushbem.numerics.solver.equilibrium`, `solve_on_set`,
`tip_deflection`).  It holds:

* ``pillars``: the pillar-block preconditioner's `PillarCache` (the pillars'
  centres and coupling, the coarse factor, each pillar's last block), valid
  while the springs stay: across working windows;
* per operator window, the last pillar-block set solver (its contact set,
  `ContactSystem`, preconditioner and the coarse entry it was built with),
  the last kept solution (a pressure and its tip deflection, which the solve
  had without a transform), and the operators on the blocks around contact
  sets (`ContactOperator.block_window`): valid for one working window, dropped
  by `on_new_window`.

A solve without a cache (``cache=None``) works on a fresh one: the same
numbers, nothing reused.  ``Switches.reuse_set_solver`` and
``Switches.keep_solution_deflection`` switch the reuse off.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from brushbem import backend
from brushbem.numerics.operator import ContactOperator

__all__ = ["PillarCache", "SolverCache"]

#: Block operators kept per working window (a block per contact extent seen recently).
_SUB_OPERATOR_CACHE = 64


@dataclass
class PillarCache:
    """What the solves of one indenter reuse across windows and contact sets.

    Part of the caller's `SolverCache` (kept across windows while the springs
    stay) and filled by the pillar-block preconditioner
    (`brushbem.numerics.solver.preconditioners`).

    Attributes
    ----------
    centres : ndarray or None
        (n_pillars, 2) footprint centroids, in elements of the whole grid.
    coupling : tuple or None
        (springs + point-load coupling, springs only): the pillars' dense
        compliance matrices over all pillars.
    coarse : tuple or None
        (its solve, the pillars it was made for, their stiffnesses) of the
        last coarse matrix, reused while it stays valid.
    coarse_base : object or None
        The last Cholesky factor of a coarse matrix, through which the
        matrices near it are solved (`brushbem.numerics.solver.preconditioners`).
    blocks : dict
        Pillar -> (grid offsets of its last contact, inverse of its half-space
        block): the parent a shrinking contact is downdated from.
    signature : ndarray or None
        Shape signature of every pillar's last contact.
    """

    centres: np.ndarray | None = None
    coupling: tuple | None = None
    coarse: tuple | None = None
    coarse_base: object | None = None
    blocks: dict = field(default_factory=dict)
    signature: np.ndarray | None = None


@dataclass
class SolverCache:
    """What the solves on one indenter reuse (module docstring); the caller owns it."""

    pillars: PillarCache = field(default_factory=PillarCache)
    #: Operator window -> (set, `ContactSystem`, preconditioner, the coarse entry) of its last pillar-block solve.
    set_solvers: dict = field(default_factory=dict)
    #: Operator window -> (pressure, its tip deflection) of the last solve there that kept it.
    solutions: dict = field(default_factory=dict)
    #: Block window -> its operator (`ContactOperator.block_window`).
    blocks: dict = field(default_factory=dict)

    def on_new_window(self) -> SolverCache:
        """The cache for a new working window: the pillars' entries kept, the window's dropped."""
        return SolverCache(pillars=self.pillars)

    def sub_operator(self, operator: ContactOperator, mask) -> tuple[tuple[slice, slice], ContactOperator]:
        """The operator on the smallest FFT-friendly block of ``operator``'s window around ``mask``, and the
        block's slices relative to that window (`ContactOperator.block_window`; kept by block)."""
        block = operator.block_window(mask)
        if block is None:
            return operator.window.slices_local, operator
        window = operator.window
        slices = (slice(block.r0 - window.r0, block.r1 - window.r0), slice(block.c0 - window.c0, block.c1 - window.c0))
        found = self.blocks.get(block)
        if found is None:
            if len(self.blocks) >= _SUB_OPERATOR_CACHE:
                self.blocks.clear()
            found = self.blocks[block] = operator.for_window(block)
        return slices, found

    def known_tip_deflection(self, operator: ContactOperator, pressure):
        """The kept tip deflection of ``pressure`` on ``operator``'s window (not to be modified), or None."""
        known = self.solutions.get(operator.window)
        if known is not None and known[0].shape == pressure.shape and bool(operator.xp.all(known[0] == pressure)):
            return known[1]
        return None

    def remember_solution(self, operator: ContactOperator, pressure, deflection) -> None:
        """Keep ``deflection``, the tip deflection of ``pressure`` on ``operator``'s window."""
        self.solutions[operator.window] = (pressure, deflection)

    def tip_deflection(self, operator: ContactOperator, pressure):
        """``operator.tip_deflection(pressure)``: the kept one (a copy) where a solve had it, else transformed."""
        known = self.known_tip_deflection(operator, pressure)
        if known is not None:
            return operator.xp.asarray(known, copy=True)
        return operator.tip_deflection(pressure)

    def pillar_centres(self, operator: ContactOperator) -> np.ndarray:
        """Centroid of every pillar's footprint, (n_pillars, 2) in element units of the whole grid."""
        centres = self.pillars.centres
        if centres is None:
            centres = self.pillars.centres = _pillar_centres(operator.indenter)
        return centres


def _pillar_centres(indenter) -> np.ndarray:
    labels = np.asarray(backend.to_numpy(indenter.pillar))
    on = labels >= 0
    rows, cols = np.nonzero(on)
    n = indenter.n_pillars
    counts = np.maximum(np.bincount(labels[on], minlength=n), 1)
    return np.stack([np.bincount(labels[on], weights=rows, minlength=n) / counts,
                     np.bincount(labels[on], weights=cols, minlength=n) / counts], axis=1)
