"""Connections with a state along a pull-off (`ConnectionState`): viscoelastic history and pillar-law pieces.

Viscoelastic connections (`brushbem.physics.viscoelastic.Memory`) are stepped in
time: the solves see the pillar springs of the step's stiffness, and before
every step each pillar's tip is raised by its history offset.  A nonlinear
pillar law (`brushbem.physics.pillar_laws.PieceState`) is followed by its pieces: each
piece gives the pillars' springs and tip offsets, and a pillar whose tension
reaches the law's limit breaks (its tip is lifted out of reach).

`ConnectionState` is a value (the path's state holds it,
`brushbem.protocol.values.PathState`): every change gives a new one, and
never changes a problem in place: what it does to the solves comes back as a
`SpringChange` (the problem with the pillars' new springs, or None when they
stay, and the tips' offsets) for `brushbem.protocol.steps.with_change` to
apply to the state's working window.
"""

from __future__ import annotations

import dataclasses
from typing import Any

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


@dataclasses.dataclass(frozen=True)
class ConnectionState:
    """The connections' state as a value: the viscoelastic memory and the pillar law's pieces, each None when absent.

    Make the first with `begin`, which also gives the problem the solves start from.  Every change gives a
    new value (and what it does to the solves, a `SpringChange`); a value is never changed, so a saved path
    state holds the connections as they were.

    Attributes
    ----------
    memory : brushbem.physics.viscoelastic.Memory or None
        The viscoelastic connections' history along a time-stepped path.
    pieces : brushbem.physics.pillar_laws.PieceState or None
        The pieces of a nonlinear pillar law and the broken pillars.
    """

    memory: Any = None
    pieces: Any = None

    @classmethod
    def begin(cls, problem: ContactProblem, path: LoadPath) -> tuple[ConnectionState, ContactProblem]:
        """The connections' state at the start of ``path``, and the problem the solves see there.

        Viscoelastic connections: the pillar springs of the step's stiffness
        k_eff.  A pillar law: the springs of the piece that holds F = 0.
        """
        memory = pieces = None
        if problem.indenter.viscoelastic is not None:
            from brushbem.physics.viscoelastic import Memory

            memory = Memory.start(problem.indenter, path.step, path.speed)
            # The solves see the pillar springs of the step's stiffness k_eff.
            problem = dataclasses.replace(problem, indenter=memory.stepped)
        if problem.indenter.pillar_law is not None:
            from brushbem.physics.pillar_laws import PieceState

            pieces = PieceState.start(problem.indenter.pillar_law, problem.indenter.levels[0].stiffnesses)
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
    def advance(self) -> tuple[ConnectionState, SpringChange | None]:
        """Before a time step: every pillar's tip raised by its connection's history offset b (no change: no memory)."""
        if self.memory is None:
            return self, None
        memory = self.memory.advance()
        return dataclasses.replace(self, memory=memory), SpringChange(None, memory.offset)

    def commit(self, forces: np.ndarray) -> ConnectionState:
        """After a time step's equilibrium: the connections' compression and arm forces from the pillar ``forces``."""
        return dataclasses.replace(self, memory=self.memory.commit(forces))

    # -- pillar-law pieces --------------------------------------------------------
    @property
    def tension_limit(self) -> float | None:
        """The pillar law's tension limit, or None."""
        return None if self.pieces is None else self.pieces.law.tension_limit

    def broken(self) -> np.ndarray:
        """The broken pillars (bool, one per pillar)."""
        return self.pieces.broken

    def restore(self, saved: ConnectionState, problem: ContactProblem) -> tuple[ConnectionState, SpringChange | None]:
        """Back to the pieces and breaks of ``saved`` (the memory stays); the change to ``problem``'s springs and
        tips (None: none)."""
        if saved.pieces is None or saved.pieces is self.pieces:
            return self, None
        old, new = self.pieces, saved.pieces
        if np.array_equal(new.pieces, old.pieces) and np.array_equal(new.broken, old.broken):
            return self, None
        moved = not np.array_equal(new.pieces, old.pieces)
        state = dataclasses.replace(self, pieces=new)
        return state, state._change(problem, moved)

    def break_pillars(self, pillars: np.ndarray) -> tuple[ConnectionState, SpringChange]:
        """Mark ``pillars`` (bool, one per pillar) broken: their tips lifted, the springs unchanged."""
        pieces = self.pieces.with_broken(pillars)
        _, offsets = pieces.springs()
        return dataclasses.replace(self, pieces=pieces), SpringChange(None, offsets, pieces.broken)

    def update(self, forces: np.ndarray, problem: ContactProblem):
        """The pieces of the pillar ``forces``, and the breaks when no piece moved: ``(state, moved, broken, change)``.

        ``state``: the new connections' state.  ``moved``: the pillars whose
        piece changed.  ``broken``: the pillars that break (marked broken),
        or None when a piece moved.  ``change``: what that does to
        ``problem``'s springs and tips, or None when nothing moved and
        nothing broke (the pieces have settled).
        """
        pieces, moved = self.pieces.update(forces)
        broken = None
        if not moved.any():
            pieces, broken = pieces.breaking(forces)
            if not broken.any():
                return dataclasses.replace(self, pieces=pieces), moved, broken, None
        state = dataclasses.replace(self, pieces=pieces)
        return state, moved, broken, state._change(problem, bool(moved.any()))

    def _change(self, problem: ContactProblem, moved: bool) -> SpringChange:
        """The springs and tip offsets of the current pieces: a new problem when a piece ``moved``."""
        stiffness, offsets = self.pieces.springs()
        return SpringChange(with_pillar_stiffness(problem, stiffness) if moved else None, offsets, self.pieces.broken)
