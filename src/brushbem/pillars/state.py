"""The state of a pull-off in the pillar model: `PillarState`.

It holds the amplitudes of every pillar's modes on the current attached set
and rasters (affine in d: ``d alpha - beta``), the pillar-level solver, and
the steps that change them: a solve (with the higher modes' near field fed
back while tips touch in part, `brushbem.pillars.solver.radiate`), pillars
that join, leave or peel, and the cascade of peeling and touching at one d.
The model is described in `brushbem.pillars`.
"""

from __future__ import annotations

import numpy as np

from brushbem.pillars.basis import Basis, PillarModel
from brushbem.pillars.solver import Solver, full_solve, radiate
from brushbem.protocol.problem import LoadPath, State

__all__ = ["PillarState"]


#: At most this many attached pillars that change their raster at once are updated in the kept inverse one by
#: one in place (`Solver.reshape`, one pass over it each); more leave and join in two block updates.
_RESHAPED = 2


class Interrupted(Exception):
    """``stop()`` turned True inside a long step of the pillar model (a cascade, a peel, a press)."""


class PillarState:
    """The state of a pull-off in the pillar model (amplitudes, attached pillars, their rasters) and its steps:
    the solves, the peeling and the cascades.

    ``stop`` (a callable, or None) is asked in every round of those steps; when it returns True they raise
    `Interrupted`, so that a stop request is honoured within a round, not after the whole cascade.
    """

    def __init__(self, model: PillarModel, path: LoadPath, stop=None):
        self.model = model
        self.path = path
        self.stop = stop
        self.solver = Solver(model, path.pillar_solve)
        self.attached = self.solver.attached  # shared
        self.alpha = np.zeros((model.M, model.m))
        self.beta = np.zeros((model.M, model.m))
        self.solves = 0
        self._reported = 0  # solves already reported with a state
        #: Whether the higher modes' near field is fed back (`_radiate`): while a brush whose tips are not
        #: level is pressed, where tips touch in part.
        self.radiate = False
        #: Whether `press` feeds the higher modes' near field back once its active set has settled without.
        self.press_radiates = False
        self.radiation_rounds = 0
        #: The d of the last contact problem settled with the near field fed back (`loading.press`), None
        #: once the state has changed otherwise.
        self.pressed: float | None = None
        #: The footprint slots whose joins that press had spent (`loading.press`): a press at nearly its d
        #: starts with them spent, None with ``pressed``.
        self.spent: np.ndarray | None = None
        #: Bumped by every change of the state (a solve, a pillar that joins, leaves or peels): the key of
        #: `_memo`, which keeps the element pressures and penetrations of the current state (the event search
        #: asks for those the cascade has just computed at the same d).
        self._stamp = 0
        self._memo: dict[tuple, object] = {}
        self.last = (0.0, True)  # (d, loading) of the last state yielded

    # -- state ---------------------------------------------------------------
    def check_stop(self) -> None:
        """Raise `Interrupted` when ``stop()`` asks to stop (one flag read: asked in every round)."""
        if self.stop is not None and self.stop():
            raise Interrupted("stopped inside a step of the pillar model")

    def solve(self) -> None:
        model = self.model
        self.solves += 1
        _changed(self)
        if model.coupling == "full":
            self.alpha, self.beta = full_solve(model, self.attached)
            amplitudes = np.stack([self.alpha, self.beta], axis=-1)  # (M, m, 2)
            # The others' field on every mode: all blocks but the pillar's own (diag(gram)).
            self.fields = (np.einsum("ijkl,jlc->kic", model.Gf, amplitudes)
                           - (model.gram[:, :, None] * amplitudes).transpose(1, 0, 2))
            self.surface = self.fields[0]
            return
        sol, fields = self.solver.solve()
        # The others' field on every mode: G0's diagonal is the pillar's own uniform mode.
        fields[0] -= model.gram[:, :1] * sol
        if model.m > 1 and self.radiate:
            sol, fields, rounds = radiate(model, self.solver, self.attached, sol, fields)
            self.radiation_rounds += rounds
        self.fields = fields
        self.surface = fields[0]
        self.alpha = model.amplitudes(sol[:, 0], self.fields[..., 0], self.attached)
        self.beta = model.amplitudes(sol[:, 1], self.fields[..., 1], self.attached)

    def amplitudes(self, d: float) -> np.ndarray:
        return d * self.alpha - self.beta

    def force(self, d: float) -> float:
        model = self.model
        return float(model.h2 * np.sum(np.where(self.attached, model.force * (d * self.alpha[:, 0] - self.beta[:, 0]),
                                                0.0)))

    def on(self) -> np.ndarray:
        """The attached pillars (indices, kept until the state changes)."""
        return _remember(self, ("on",), lambda: np.flatnonzero(self.attached))

    def pressures_at(self, d: float) -> np.ndarray:
        """`pressures` of the amplitudes at d (kept until the state changes)."""
        return _remember(self, ("pressures", float(d)), lambda: self.pressures(self.amplitudes(d)))

    def pressures(self, x: np.ndarray) -> np.ndarray:
        """Element pressures on the footprint slots of the attached pillars (`on`): (n, width), 0 off
        their rasters."""
        model = self.model
        on = self.on()
        # One product per group of pillars that share their footprint and raster (and so their modes'
        # pressures, `PillarModel.surface_group`): every pillar of a level lattice in full contact is one.
        out = np.zeros((on.size, model.phi.shape[1]))
        if on.size == 0:
            return out
        for members in _remember(self, ("groups",), lambda: _surface_groups(self)):
            pillars = on[members]
            out[members] = np.take(x, pillars, axis=0) @ model.phi[pillars[0]].T
        # np.take: the rows gathered as fancy indexing gathers them, many times faster.
        return np.where(np.take(model.raster, on, axis=0), out, 0.0)

    def element_penetration(self, d: float, rows: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray,
                                                                                       np.ndarray]:
        """The footprint slots' penetration at d (tip below the surface > 0) and its slope, of the pillars
        ``rows`` (a mask; default all): (their indices, penetration (R, width), slope (R, width)).

        The surface under a tip is the others' field fitted by the tip's
        polynomials from its projections on the modes, plus the tip's own
        modes' displacement; the tip is level, at d - g less its springs'
        stretch.  Slots off the footprint read -inf.
        """
        key = ("penetration", float(d), None if rows is None else rows.tobytes())
        return _remember(self, key, lambda: _element_penetration(self, d, rows))

    def touch_candidates(self, d: float, end: float, tolerance: float) -> np.ndarray:
        """The free pillars that may touch at a displacement between d and ``end`` (a mask): those whose
        `touch_bound` is above -``tolerance``."""
        return ~self.attached & (self.touch_bound(d, end) > -tolerance)

    def touch_bound(self, d: float, end: float) -> np.ndarray:
        """Every free pillar's largest slot penetration between d and ``end``, bounded from above: (M,).

        A free pillar's own amplitudes are zero, so the surface under it is
        the fit of the others' field, u_s = fitted_s . f(d') with f(d') =
        d' f_a - f_b affine.  Over the slots, u_s lies within c . f(d') +- r .
        |f(d')| (c, r: `PillarModel.fit_centre`, `fit_spread`), so no slot
        penetrates more than  d' (wa - c . f_a) - (wb - c . f_b) + r . |f(d')|,
        a convex function of d' whose largest value on [d, end] is at an end.
        (Entries of attached pillars mean nothing.)
        """
        spread = self.model.fit_spread
        fa, fb, level_a, level_b = _remember(self, ("touch",), lambda: _touch_terms(self))
        return np.maximum(d * level_a - level_b + np.sum(spread * np.abs(d * fa - fb), axis=0),
                          end * level_a - level_b + np.sum(spread * np.abs(end * fa - fb), axis=0))

    def install(self, masks: np.ndarray, pillars: np.ndarray) -> None:
        """The ``pillars`` hold the footprint slots ``masks[p]`` (none: off)."""
        _apply(self, [(int(p), masks[p]) for p in pillars])

    def state(self, d: float, loading: bool, kind: str, reason: str, converged: bool = True) -> State:
        model = self.model
        self.last = (float(d), loading)
        rows = self.on()
        on = np.take(model.raster, rows, axis=0)
        force = 0.0
        slots, values = np.zeros(0, dtype=np.int64), np.zeros(0)
        if kind != "separated" and rows.size:
            slots = np.take(model.reports, rows, axis=0)[on]
            values = self.pressures_at(d)[on]
            force = float(model.h2 * values.sum())
        # On the global grid (the tips' raster may be finer: `brushbem.pillars.tips`).
        pressure, contact = model.tips.to_grid(slots, values)
        solves, self._reported = self.solves - self._reported, self.solves
        return State(displacement=float(d), force=force, contact_area=model.h2 * int(np.count_nonzero(on)),
                     attached_pillars=int(np.count_nonzero(self.attached)), loading=loading, kind=kind,
                     trial_force=force, cg_iterations=0, n_solves=solves, converged=converged, reason=reason,
                     pressure=pressure, contact=contact)

    # -- changes -------------------------------------------------------------
    def attach_many(self, pillars: np.ndarray) -> None:
        """Several pillars join at once (one factorisation instead of one update each)."""
        _changed(self)
        for p in pillars:
            self.model.set_raster(int(p), self.model.full[p])
        self.attached[pillars] = True
        if self.model.coupling == "local":
            self.solver.refactor()

    def cascade(self, d: float, loading: bool) -> None:
        """Rounds at d: solve, peel every pillar beyond the criterion, let touching pillars in; until stable."""
        model = self.model
        tolerance = 1e-10 * max(abs(d), float(np.max(np.abs(model.g))), 1e-300)
        for _ in range(10 * model.M + 100):
            self.check_stop()
            self.solve()
            x = self.amplitudes(d)
            p = self.pressures_at(d)
            rows = self.on()
            tense = np.take(model.raster, rows, axis=0) & (p < -model.critical[rows, None] * (1 + 1e-10))
            hit = np.flatnonzero(tense.any(axis=1))
            if hit.size:
                peel_all(self, [(int(rows[i]), tense[i]) for i in hit], x, d)
                continue
            candidates = self.touch_candidates(d, d, tolerance)
            if candidates.any():
                rows, penetration, _ = self.element_penetration(d, candidates)
                touching = penetration > tolerance
                joining = touching.any(axis=1)
                if joining.any():
                    masks = np.zeros(model.full.shape, dtype=bool)
                    masks[rows] = touching
                    self.install(masks, rows[joining])
                    continue
            return
        raise RuntimeError(f"the cascade at d = {d:.6g} did not settle")


# -- the steps' parts and the peeling (module functions of a `PillarState`) ---------------------------------

def _changed(run: PillarState) -> None:
    run._stamp += 1
    run._memo.clear()


def _remember(run: PillarState, key: tuple, compute):
    key = (run._stamp, *key)
    value = run._memo.get(key)
    if value is None:
        value = run._memo[key] = compute()
    return value


def _surface_groups(run: PillarState) -> list[np.ndarray]:
    """The attached pillars (`on`) by `PillarModel.surface_group`: positions in `on` per group."""
    _, inverse, counts = np.unique(run.model.surface_group[run.on()], return_inverse=True, return_counts=True)
    return np.split(np.argsort(inverse, kind="stable"), np.cumsum(counts)[:-1])


def _element_penetration(run: PillarState, d: float, rows: np.ndarray | None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    model = run.model
    rows = np.arange(model.M) if rows is None else np.flatnonzero(rows)
    width = model.full.shape[1]
    if rows.size == 0:
        return rows, np.zeros((0, width)), np.zeros((0, width))
    coefficients = np.concatenate([run.fields[:, rows].transpose(1, 0, 2),
                                   np.stack([run.alpha[rows], run.beta[rows]], axis=-1)], axis=1)
    # u = d ua - ub on the slots, (rows, width, 2): one product per group of pillars that share their
    # footprint and raster (those of a lattice in full contact, or off), one per pillar for the rest.
    u = np.zeros((rows.size, width, 2))
    groups, inverse, counts = np.unique(model.surface_group[rows], return_inverse=True, return_counts=True)
    shared = counts[inverse] > 1
    for g in np.flatnonzero(counts > 1):
        members = np.flatnonzero(inverse == g)
        surface_map = model.surface_group_map(int(groups[g]))
        product = surface_map @ coefficients[members].transpose(1, 0, 2).reshape(surface_map.shape[1], -1)
        u[members, :surface_map.shape[0]] = product.reshape(surface_map.shape[0], members.size, 2).transpose(1, 0, 2)
    alone = np.flatnonzero(~shared)
    if alone.size:
        u[alone] = np.matmul(model.surface_map[rows[alone]], coefficients[alone])
    wa, wb = _tip_levels(run, rows)
    full = model.full[rows]
    slope = np.where(full, wa[:, None] - u[..., 0], 0.0)
    penetration = np.where(full, d * slope - (wb[:, None] - u[..., 1]), -np.inf)
    return rows, penetration, slope


def _tip_levels(run: PillarState, rows: np.ndarray | slice) -> tuple[np.ndarray, np.ndarray]:
    """(wa, wb) of the pillars ``rows``: a tip stands at d wa - wb (its springs' stretch taken off)."""
    model = run.model
    wb = model.g[rows]
    if model.levels:
        wa = 1.0 - model.tip_deflection(run.alpha[:, 0], run.attached)[rows]
        wb = wb - model.tip_deflection(run.beta[:, 0], run.attached)[rows]
    else:
        wa = np.ones(wb.size)
    return wa, wb


def _touch_terms(run: PillarState) -> tuple[np.ndarray, ...]:
    """`touch_bound`'s terms of the state: the fields fa, fb (m, M) and wa - c . fa, wb - c . fb (M,)."""
    fa, fb = np.ascontiguousarray(run.fields[..., 0]), np.ascontiguousarray(run.fields[..., 1])
    centre = run.model.fit_centre
    wa, wb = _tip_levels(run, slice(None))
    return fa, fb, wa - np.sum(centre * fa, axis=0), wb - np.sum(centre * fb, axis=0)


def _apply(run: PillarState, changes: list[tuple[int, np.ndarray]]) -> None:
    """Each pillar p of ``changes`` holds the footprint slots of its mask (none: off).

    In the kept inverse the pillars that leave or change their raster go out in one block update and
    those on a raster come (back) in in another (`Solver.remove_many`, `Solver.add_many`); one or two
    attached pillars that only change their raster (a peel) are updated in place (`Solver.reshape`).
    """
    model = run.model
    _changed(run)
    if model.coupling != "local":
        for p, mask in changes:
            run.attached[p] = bool(mask.any())
            model.set_raster(p, mask if mask.any() else model.full[p])
        return
    leaving = [p for p, mask in changes if run.attached[p] and not (
        mask.any() and np.array_equal(mask, model.raster[p]))]
    reshaping = [(p, mask) for p, mask in changes if run.attached[p] and mask.any()
                 and not np.array_equal(mask, model.raster[p])]
    if len(reshaping) <= _RESHAPED and not run.solver.iterative:
        others = {p for p, _ in reshaping}
        run.solver.remove_many(np.array([p for p in leaving if p not in others], dtype=np.int64))
        for p, mask in reshaping:
            model.set_raster(p, mask)
            run.solver.reshape(p)
    else:
        run.solver.remove_many(np.array(leaving, dtype=np.int64))
    joining = []
    for p, mask in changes:
        if not mask.any():
            model.set_raster(p, model.full[p])
        elif not run.attached[p]:
            model.set_raster(p, mask)
            joining.append(p)
    run.solver.add_many(np.array(joining, dtype=np.int64))


def local_amplitudes(run: PillarState, p: int, mask: np.ndarray, frozen: np.ndarray, x: np.ndarray,
                     d: float) -> tuple[np.ndarray, Basis]:
    """Pillar p's amplitudes on the raster ``mask``, the pillars ``frozen`` held at the amplitudes ``x``.

    With ``coupling = "local"`` the frozen pillars are those of the last solve at d (``x`` its
    amplitudes), and their field across p's footprint is its fit from p's modes
    (`PillarModel.fitted`), projected on the modes of ``mask``; ``"full"`` couples the new raster
    with every frozen pillar's modes exactly.
    """
    model = run.model
    compliance = 0.0
    siblings = 0.0
    for (cluster, stiffness), alone in zip(model.levels, model.alone):
        c = cluster[p]
        compliance += model.h2 / stiffness[c]
        if alone:  # no siblings (the pillars' own springs): skip the O(M) pass, which would add 0.0
            continue
        same = (cluster == c) & frozen
        same[p] = False
        siblings += model.h2 / stiffness[c] * float(np.sum(model.force[same] * x[same, 0]))
    if model.coupling == "full":
        others, blocks, basis = model.blocks(p, mask)
        keep = frozen[others]
        others, blocks = others[keep], blocks[keep]
        s = basis.force
        A = np.diag(basis.gram).copy()
        A[0, 0] += compliance * s * s
        rhs = -np.einsum("jab,jb->a", blocks, x[others])
        rhs[0] += s * (d - model.g[p]) - s * siblings
        return np.linalg.solve(A, rhs), basis
    basis, _ = model.mask_basis(p, mask)
    s = basis.force
    field = model.fitted[p][mask] @ (d * run.fields[:, p, 0] - run.fields[:, p, 1])
    projections = basis.phi.T @ field
    a = np.zeros(model.m)
    a[0] = (s * (d - model.g[p]) - s * siblings - projections[0]) / (basis.gram[0] + compliance * s * s)
    if model.m > 1:
        a[1:] = -projections[1:] / basis.gram[1:]
    return a, basis


def peeled(run: PillarState, p: int, leave: np.ndarray, frozen: np.ndarray, x: np.ndarray, d: float) -> np.ndarray:
    """The raster that pillar p keeps after losing the slots ``leave`` and peeling on its own.

    The pillars ``frozen`` stay at the amplitudes ``x`` (the element path's local cascade); the model
    is not changed (the caller installs the result).  An empty mask: the pillar comes off.
    """
    model = run.model
    mask = model.raster[p] & ~leave
    if not model.peel:
        return np.zeros_like(mask)
    while mask.any():
        run.check_stop()
        a, basis = local_amplitudes(run, p, mask, frozen, x, d)
        pressure = basis.phi @ a
        tense = pressure < -model.critical[p] * (1 + 1e-10)
        if not tense.any():
            break
        slots = np.flatnonzero(mask)
        mask = mask.copy()
        mask[slots[tense]] = False
    return mask


def peel_all(run: PillarState, hits: list[tuple[int, np.ndarray]], x: np.ndarray, d: float) -> None:
    """Every hit pillar peels on its own against the state before any of them moved; then all are installed."""
    frozen = run.attached.copy()
    _apply(run, [(p, peeled(run, p, leave, frozen, x, d)) for p, leave in hits])
