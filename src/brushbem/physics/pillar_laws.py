"""Nonlinear pillar connections: a piecewise-linear force-compression law and a tension cut-off (thesis sec. 8.2, 2).

The pillars' own connections (level 1) follow a force-compression law F(s)
(s: the connection's compression, F: its force, compressive positive) that is
piecewise linear and increasing: between the force breakpoints F_1 < F_2 <
... the slope is k f_i, with k the pillar's stiffness (graded or not) and
f_i > 0 the piece's factor; the piece that holds F = 0 passes through s = 0.
A buckling pillar is stiff up to its buckling load and then soft (a small
factor: the plateau of a post-buckled column, whose stiffness stays
positive); a law stiffer in tension, or one that softens in tension, is the
same with breakpoints below 0.  A law with a falling piece (f_i <= 0) is
refused: with it the equilibrium is no longer unique and snaps.

``tension_limit``: a pillar whose tension exceeds it breaks; from then on it
carries nothing (its tip is lifted out of reach) for the rest of the path.

How the nonlinear equilibrium is found.  On a piece the law is affine, s =
F / (k f_i) + b_i with b_i = s(F_i) - F_i / (k f_i), so for a given piece of
every pillar the equilibrium is the linear (exact) solve with the pillar
stiffness k f_i and the tip raised by b_i.  Each step starts from the pieces
of the previous one, solves, reads every pillar's force and moves each pillar
to the piece that holds it; until no pillar moves (an active-set, or
semi-smooth Newton, iteration on the pieces).  For an increasing law the
map from pieces to forces is monotone in each pillar's own compliance, and
the iteration stops after at most a few rounds in practice; it is bounded by
`MAX_PIECE_ROUNDS`, beyond which the step is reported not converged with the
pillars that kept changing.  Breaks are checked on the converged step: the
broken pillars leave and the step is solved again, until none breaks.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
from dataclasses import dataclass

import numpy as np

from brushbem.errors import ParameterProblem
from brushbem.physics.structure import elastic_connection_problems

__all__ = ["MAX_PIECE_ROUNDS", "PieceState", "PiecewiseLinear", "law_path_problems"]

#: Most piece-selection rounds of one step before it is reported not converged.
MAX_PIECE_ROUNDS = 50


@dataclass(frozen=True)
class PiecewiseLinear:
    """An increasing piecewise-linear force-compression law of the pillars' connections (module docstring).

    Attributes
    ----------
    forces : tuple of float
        Force breakpoints F_1 < F_2 < ..., units of force (compressive
        positive); may be empty.
    factors : tuple of float
        The slopes k f_i of the len(forces) + 1 pieces, as factors f_i > 0 of
        the pillar stiffness k, from the most tensile piece up.
    tension_limit : float or None
        Tension (> 0, units of force) beyond which a pillar breaks; None: never.
    """

    forces: tuple[float, ...] = ()
    factors: tuple[float, ...] = (1.0,)
    tension_limit: float | None = None

    def __post_init__(self):
        forces = tuple(float(f) for f in self.forces)
        factors = tuple(float(f) for f in self.factors)
        object.__setattr__(self, "forces", forces)
        object.__setattr__(self, "factors", factors)
        if not all(math.isfinite(f) for f in forces) or any(b <= a for a, b in itertools.pairwise(forces)):
            raise ValueError(f"pillar_law.forces = {list(forces)} must be finite and strictly increasing")
        if len(factors) != len(forces) + 1:
            raise ValueError(f"pillar_law.factors holds {len(factors)} values; {len(forces)} breakpoints make "
                             f"{len(forces) + 1} pieces, one factor each")
        if not all(math.isfinite(f) and f > 0 for f in factors):
            raise ValueError(
                f"pillar_law.factors = {list(factors)} must all be finite and > 0: the law must be increasing "
                "(monotone); a falling piece makes the equilibrium snap and is not supported (give a post-buckling "
                "plateau a small positive factor)"
            )
        if self.tension_limit is not None and not (math.isfinite(self.tension_limit) and self.tension_limit > 0):
            raise ValueError(f"pillar_law.tension_limit = {self.tension_limit} must be finite and > 0 (a force)")

    @property
    def linear(self) -> bool:
        """One piece of factor 1 and no cut-off: the linear spring."""
        return not self.forces and self.factors == (1.0,) and self.tension_limit is None

    def piece(self, force: np.ndarray) -> np.ndarray:
        """The piece that holds each force (0: the most tensile)."""
        return np.searchsorted(np.asarray(self.forces), force, side="right")

    def compression(self, force: np.ndarray, stiffness: np.ndarray) -> np.ndarray:
        """s(F) of every pillar of stiffness ``stiffness`` (the law integrated from F = 0)."""
        force = np.asarray(force, dtype=np.float64)
        edges = np.concatenate([[-np.inf], self.forces, [np.inf]])
        s = np.zeros(np.broadcast(force, stiffness).shape)
        for i, factor in enumerate(self.factors):
            lo, hi = edges[i], edges[i + 1]
            # The part of [0, F] (or [F, 0]) inside the piece, signed.
            upper = np.clip(np.maximum(force, 0.0), max(lo, 0.0), max(hi, 0.0))
            lower = np.clip(np.minimum(force, 0.0), min(lo, 0.0), min(hi, 0.0))
            s = s + (upper - max(lo, 0.0) + lower - min(hi, 0.0)) / (stiffness * factor)
        return s

    def affine(self, pieces: np.ndarray, stiffness: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(stiffness k f_i, offset b_i) of every pillar on its piece: s = F / (k f_i) + b_i."""
        factors = np.asarray(self.factors)[pieces]
        slope = stiffness * factors
        edges = np.concatenate([[0.0], self.forces])  # a point of each piece (the first piece: any)
        anchor = np.where(pieces > 0, edges[pieces], np.minimum(edges[1] if self.forces else 0.0, 0.0))
        return slope, self.compression(anchor, stiffness) - anchor / slope


@dataclass(frozen=True)
class PieceState:
    """The pieces and the broken pillars along a path, as a value (a path's state holds one).

    Make the first with `PieceState.start`; `update`, `breaking` and `with_broken` give the next ones
    (a value is never changed: a saved path state holds it as it was).

    Attributes
    ----------
    law : PiecewiseLinear
    base : ndarray
        k of every pillar (level 1).
    pieces : ndarray of int
        The piece of every pillar.
    broken : ndarray of bool
        The broken pillars.
    """

    law: PiecewiseLinear
    base: np.ndarray
    pieces: np.ndarray
    broken: np.ndarray

    @classmethod
    def start(cls, law: PiecewiseLinear, stiffness: np.ndarray) -> PieceState:
        """Every pillar of stiffness ``stiffness`` on the piece that holds F = 0, none broken."""
        base = np.array(stiffness, dtype=np.float64)
        return cls(law, base, law.piece(np.zeros_like(base)), np.zeros(base.shape, dtype=bool))

    def springs(self) -> tuple[np.ndarray, np.ndarray]:
        """(stiffness, offset) of every pillar on its current piece."""
        return self.law.affine(self.pieces, self.base)

    def update(self, forces: np.ndarray) -> tuple[PieceState, np.ndarray]:
        """Every intact pillar on the piece of its force: the new state and the pillars that moved (bool)."""
        pieces = np.where(self.broken, self.pieces, self.law.piece(forces))
        return dataclasses.replace(self, pieces=pieces), pieces != self.pieces

    def breaking(self, forces: np.ndarray) -> tuple[PieceState, np.ndarray]:
        """The intact pillars whose tension exceeds the limit marked broken: the new state and those pillars (bool)."""
        limit = self.law.tension_limit
        if limit is None:
            return self, np.zeros(self.base.shape, dtype=bool)
        new = ~self.broken & (forces < -limit)
        return self.with_broken(new), new

    def with_broken(self, pillars: np.ndarray) -> PieceState:
        """The state with ``pillars`` (bool, one per pillar) broken too."""
        return dataclasses.replace(self, broken=self.broken | pillars)


def law_path_problems(law: object, *, method: str, preload_displacement: float | None, viscoelastic: bool,
                      preload_force: float | None = None, stiffness: float | None = None) -> list[ParameterProblem]:
    """The rule of a nonlinear pillar law, stated once: it is followed by fixed steps to a preload displacement,
    on elastic connections of finite stiffness (its slopes are factors of it).

    ``law``: the `PiecewiseLinear` law (None: no rule applies); ``stiffness``: the pillars' stiffness where it
    is known before the indenter is built (None: not checked; an `Indenter` refuses a rigid one: the rigid-pillar
    rule is `brushbem.physics.structure.elastic_connection_problems`).  Returns
    every problem; the load path raises the first, the configuration names them all by key.
    """
    if law is None:
        return []
    problems = []
    if method != "fixed":
        problems.append(ParameterProblem("LoadPath", "method", method,
                                         "needs method = 'fixed' with Indenter.pillar_law (the law is followed step "
                                         "by step)"))
    if preload_displacement is None:
        problems.append(ParameterProblem("LoadPath", "preload_force", preload_force,
                                         "a nonlinear pillar law (Indenter.pillar_law) is pressed to "
                                         "LoadPath.preload_displacement instead (a force target would search across "
                                         "the law's pieces)"))
    if viscoelastic:
        problems.append(ParameterProblem("Indenter", "pillar_law", law,
                                         "cannot be combined with Indenter.viscoelastic: remove one of them"))
    if stiffness is not None:
        problems.extend(elastic_connection_problems(stiffness, viscoelastic=False, pillar_law=law))
    return problems
