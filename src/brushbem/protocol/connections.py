"""Connections with a state along a pull-off (`ConnectionState`): viscoelastic history and pillar-law pieces.

Viscoelastic connections (`brushbem.physics.viscoelastic.Memory`) are stepped in
time: the solves see the pillar springs of the step's stiffness, and before
every step each pillar's tip is raised by its history offset.  A nonlinear
pillar law (`brushbem.physics.pillar_laws.PieceState`) is followed by its pieces: each
piece gives the pillars' springs and tip offsets, and a pillar whose tension
reaches the law's limit breaks (its tip is lifted out of reach).

`ConnectionState` never changes a problem in place: every change comes back
as a `SpringChange` (the problem with the pillars' new springs, or None when
they stay, and the tips' offsets) for the `brushbem.protocol.tracking.Tracker`
to apply to its working window.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from brushbem.physics.structure import SpringLevel
from brushbem.protocol.problem import ContactProblem, LoadPath

__all__ = ["ConnectionState", "SpringChange"]


@dataclasses.dataclass(frozen=True)
class SpringChange:
    """What a change of the connections' state does to the solves.

    ``problem``: the problem with the pillars' new springs (a new operator),
    or None when the springs stay.  ``offsets``: every pillar's tip raise
    (one per pillar).  ``lifted``: the pillars lifted out of reach (the
    broken ones), or None.
    """

    problem: ContactProblem | None
    offsets: np.ndarray
    lifted: np.ndarray | None = None


def with_pillar_stiffness(problem: ContactProblem, stiffness: np.ndarray) -> ContactProblem:
    """``problem`` whose pillars' own springs (level 1) have ``stiffness``."""
    indenter = problem.indenter
    level = indenter.levels[0]
    levels = (SpringLevel(np.array(stiffness, dtype=np.float64), level.cluster), *indenter.levels[1:])
    return dataclasses.replace(problem, indenter=dataclasses.replace(indenter, levels=levels))


class ConnectionState:
    """The viscoelastic memory (``memory``) and the pillar law's pieces (``pieces``), each None when absent.

    Make one with `begin`, which also gives the problem the solves start from.
    """

    def __init__(self, memory=None, pieces=None):
        #: The viscoelastic connections' history along a time-stepped path (`brushbem.physics.viscoelastic`), else None.
        self.memory = memory
        #: The pieces of a nonlinear pillar law and the broken pillars (`brushbem.physics.pillar_laws`), else None.
        self.pieces = pieces

    @classmethod
    def begin(cls, problem: ContactProblem, path: LoadPath) -> tuple[ConnectionState, ContactProblem]:
        """The connections' state at the start of ``path``, and the problem the solves see there.

        Viscoelastic connections: the pillar springs of the step's stiffness
        k_eff.  A pillar law: the springs of the piece that holds F = 0.
        """
        memory = pieces = None
        if problem.indenter.viscoelastic is not None:
            from brushbem.physics.viscoelastic import Memory

            memory = Memory(problem.indenter, path.step, path.speed)
            # The solves see the pillar springs of the step's stiffness k_eff.
            problem = dataclasses.replace(problem, indenter=memory.stepped)
        if problem.indenter.pillar_law is not None:
            from brushbem.physics.pillar_laws import PieceState

            pieces = PieceState(problem.indenter.pillar_law, problem.indenter.levels[0].stiffnesses)
            # The springs of the piece that holds F = 0 (its offset is 0).
            level = problem.indenter.levels[0]
            levels = (SpringLevel(pieces.springs()[0], level.cluster), *problem.indenter.levels[1:])
            problem = dataclasses.replace(problem, indenter=dataclasses.replace(problem.indenter, levels=levels))
        return cls(memory, pieces), problem

    @property
    def has_state(self) -> bool:
        """Whether the connections carry a state (viscoelastic history or law pieces)."""
        return self.memory is not None or self.pieces is not None

    # -- viscoelastic history -------------------------------------------------
    def advance(self) -> SpringChange | None:
        """Before a time step: every pillar's tip raised by its connection's history offset b (None: no memory)."""
        if self.memory is None:
            return None
        return SpringChange(None, self.memory.advance())

    def commit(self, forces: np.ndarray) -> None:
        """After a time step's equilibrium: the connections' compression and arm forces from the pillar ``forces``."""
        self.memory.commit(forces)

    # -- pillar-law pieces --------------------------------------------------------
    @property
    def tension_limit(self) -> float | None:
        """The pillar law's tension limit, or None."""
        return None if self.pieces is None else self.pieces.law.tension_limit

    def saved(self):
        """The pillar law's pieces and breaks (a copy), or None: what `restore` returns to."""
        return None if self.pieces is None else (self.pieces.pieces.copy(), self.pieces.broken.copy())

    def broken(self, saved=None) -> np.ndarray:
        """The broken pillars (bool, one per pillar) now, or in ``saved`` (from `saved`) when given."""
        return self.pieces.broken if saved is None else saved[1]

    def restore(self, saved, problem: ContactProblem) -> SpringChange | None:
        """Back to the pieces and breaks of `saved`; the change to ``problem``'s springs and tips (None: none)."""
        if saved is None:
            return None
        pieces, broken = saved
        if np.array_equal(pieces, self.pieces.pieces) and np.array_equal(broken, self.pieces.broken):
            return None
        moved = not np.array_equal(pieces, self.pieces.pieces)
        self.pieces.pieces, self.pieces.broken = pieces.copy(), broken.copy()
        return self._change(problem, moved)

    def break_pillars(self, pillars: np.ndarray) -> SpringChange:
        """Mark ``pillars`` (bool, one per pillar) broken: their tips lifted, the springs unchanged."""
        self.pieces.broken |= pillars
        _, offsets = self.pieces.springs()
        return SpringChange(None, offsets, self.pieces.broken)

    def update(self, forces: np.ndarray, problem: ContactProblem):
        """The pieces of the pillar ``forces``, and the breaks when no piece moved: ``(moved, broken, change)``.

        ``moved``: the pillars whose piece changed.  ``broken``: the pillars
        that break (marked broken), or None when a piece moved.  ``change``:
        what that does to ``problem``'s springs and tips, or None when
        nothing moved and nothing broke (the pieces have settled).
        """
        moved = self.pieces.update(forces)
        broken = None
        if not moved.any():
            broken = self.pieces.breaking(forces)
            if not broken.any():
                return moved, broken, None
        return moved, broken, self._change(problem, bool(moved.any()))

    def _change(self, problem: ContactProblem, moved: bool) -> SpringChange:
        """The springs and tip offsets of the current pieces: a new problem when a piece ``moved``."""
        stiffness, offsets = self.pieces.springs()
        return SpringChange(with_pillar_stiffness(problem, stiffness) if moved else None, offsets, self.pieces.broken)
