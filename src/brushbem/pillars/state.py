"""The state of a pull-off in the pillar model as a frozen value (`PillarState`), its cache, and its steps.

`PillarState` holds what the path is at: the attached pillars, every
pillar's raster (the footprint slots it holds), the amplitudes of every
pillar's modes on them (affine in d: ``d alpha - beta``) and the others'
field on them from the last solve, and the loading's flags.  It is never
written into: each step takes a state and returns the next (`solved`,
`installed`, `attached_together`, `peel_all`, `cascade`, and the presses of
`brushbem.pillars.loading`), and a saved state is that value, which the path
can hand to a step again.  A state after a change of its set or rasters and
before its solve carries no amplitudes (None).

`RasterCache` is what the steps reuse, owned by the path: the model's
arrays derived from the rasters (`PillarModel.set_raster`: the bases,
moments, couplings and surface maps of each pillar's raster; rows of 20
arrays, 14.4 MB on the chapter-5 brush, so not copied per step) and the
kept inverse of the pillar-level system on the attached set
(`brushbem.pillars.solver.Solver`).  They are keyed by (pillar, raster):
`PillarModel.raster` and ``Solver.attached`` say which rasters and set the
arrays are of, and a step given a state of other rasters (a saved one)
brings them to its rasters first, pillar by pillar (`_follow`).  The cache
also keeps the path's ledger: the solves, and those already reported.

The model is described in `brushbem.pillars`.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from brushbem.pillars import peel
from brushbem.pillars.basis import Basis, PillarModel
from brushbem.pillars.modes import MODES
from brushbem.pillars.solver import Solver, full_solve, radiate
from brushbem.protocol.problem import LoadPath, State

__all__ = ["PillarState", "RasterCache", "attached_together", "begin", "cascade", "installed", "peel_all",
           "record", "solved", "tip_strengths", "tip_tilts"]


#: At most this many attached pillars that change their raster at once are updated in the kept inverse one by
#: one in place (`Solver.reshape`, one pass over it each); more leave and join in two block updates.
_RESHAPED = 2


class Interrupted(Exception):
    """``stop()`` turned True inside a long step of the pillar model (a cascade, a peel, a press)."""


@dataclass(frozen=True)
class PillarState:
    """The state of a pull-off in the pillar model (module docstring), as one frozen value.

    Attributes
    ----------
    attached : ndarray of bool, shape (M,)
        The attached pillars.
    raster : ndarray of bool, shape (M, width)
        The footprint slots every pillar holds (its whole footprint while it is off).
    alpha, beta : ndarray, shape (M, m), or None
        The amplitudes of every pillar's modes at d, ``d alpha - beta`` (0 off the attached set), of the
        last solve; None after a change of the set or rasters before its solve.
    fields : ndarray, shape (m, M, 2), or None
        The others' field on every pillar's modes, ``d fields[..., 0] - fields[..., 1]``, of that solve.
    radiate : bool
        Whether the solves feed the higher modes' near field back (`brushbem.pillars.solver.radiate`):
        while a brush whose tips are not level is pressed, where tips touch in part.
    press_radiates : bool
        Whether a press (`brushbem.pillars.loading.press`) feeds it back once its set has settled without.
    pressed : float or None
        The d of the last contact problem settled with the near field fed back; None once the state has
        changed otherwise.
    spent : ndarray of bool, shape (M, width), or None
        The footprint slots whose joins that press spent (a press at nearly its d starts with them spent).

    The arrays are read-only; a new state shares those that did not change.  ``memo`` keeps what is
    derived of the state (element pressures at a d, penetrations), computed once per state.
    """

    attached: Any
    raster: Any
    alpha: Any = None
    beta: Any = None
    fields: Any = None
    radiate: bool = False
    press_radiates: bool = False
    pressed: float | None = None
    spent: Any = None
    memo: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    def __post_init__(self):
        for array in (self.attached, self.raster, self.alpha, self.beta, self.fields, self.spent):
            if array is not None:
                array.flags.writeable = False

    def replace(self, **changes) -> PillarState:
        """The state with ``changes`` (the other fields, and their arrays, shared; what is derived afresh)."""
        return dataclasses.replace(self, **changes)


class RasterCache:
    """What the steps of one pull-off reuse (module docstring); the path owns it.

    ``stop`` (a callable, or None) is asked in every round of the long steps; when it returns True they raise
    `Interrupted`, so that a stop request is honoured within a round, not after the whole cascade.
    """

    def __init__(self, model: PillarModel, path: LoadPath, stop=None):
        self.model = model
        self.solver = Solver(model, path.pillar_solve)
        self.stop = stop
        #: The ``raster`` and ``attached`` arrays of the state whose rasters and set the arrays are of.
        self.key: tuple = (None, None)
        self.solves = 0
        self.reported = 0  # solves already reported with a state
        self.radiation_rounds = 0
        #: The largest relative n = 1 amplitude of K along its edge of a tip that left whole at its continuum
        #: capacity (`tip_tilts` as it left; the first-order peel's domain, `brushbem.pillars.domain.peel_warning`).
        self.largest_tilt = 0.0

    def check_stop(self) -> None:
        """Raise `Interrupted` when ``stop()`` asks to stop (one flag read: asked in every round)."""
        if self.stop is not None and self.stop():
            raise Interrupted("stopped inside a step of the pillar model")


def begin(model: PillarModel, path: LoadPath, stop=None) -> tuple[RasterCache, PillarState]:
    """The cache of a pull-off and its first state: no pillar attached, every raster whole."""
    cache = RasterCache(model, path, stop)
    state = PillarState(attached=cache.solver.attached.copy(), raster=model.raster.copy(),
                        alpha=np.zeros((model.M, model.m)), beta=np.zeros((model.M, model.m)))
    cache.key = (state.raster, state.attached)
    return cache, state


# -- reading a state -------------------------------------------------------------------------------------------

def amplitudes(state: PillarState, d: float) -> np.ndarray:
    return d * state.alpha - state.beta


def force(cache: RasterCache, state: PillarState, d: float) -> float:
    model = cache.model
    return float(model.h2 * np.sum(np.where(state.attached, model.force * (d * state.alpha[:, 0] - state.beta[:, 0]),
                                            0.0)))


def force_rate(cache: RasterCache, state: PillarState) -> float:
    """dF/dd on the state's set (F is affine in d there)."""
    model = cache.model
    return model.h2 * float(np.sum(np.where(state.attached, model.force * state.alpha[:, 0], 0.0)))


def on(state: PillarState) -> np.ndarray:
    """The attached pillars (indices)."""
    return _remember(state, ("on",), lambda: np.flatnonzero(state.attached))


def tip_strengths(cache: RasterCache, state: PillarState, d: float) -> np.ndarray:
    """Where the tips leave at their continuum capacity (``PillarModel.continuum_peel``): every whole tip's
    strength at d, the tensile force at which it leaves, F_K (1 + G) / max g (`brushbem.pillars.peel`); NaN for
    the pillars that are off, hold part of their footprint, carry no defined K(theta) or one that varies along
    their edge beyond the gain's table (`peel.strength`): their elements' criterion serves.  (M,).

    The amplitudes a of a tip's modes are the pressure of the displacement polynomial c = fit (gram a) across
    it (`Basis.fit`: the modes are K-orthogonal, so their projections of the tip's own displacement are
    gram a); K(theta) of a rigid circle under it is `peel.tip_intensity`'s closed form, g = K / K_P with
    K_P = P / (2 a sqrt(pi a)) of the circle's own load P under it.
    """
    return _remember(state, ("peel", float(d)), lambda: _tip_peel(cache, state, d))[0]


def tip_tilts(cache: RasterCache, state: PillarState, d: float) -> np.ndarray:
    """The relative n = 1 amplitude of every whole tip's K along its edge at d (`peel.shape_parameters`; the
    first-order peel's domain, `brushbem.pillars.domain.PEEL_TILT`); NaN where `tip_strengths` has no K.  (M,)."""
    return _remember(state, ("peel", float(d)), lambda: _tip_peel(cache, state, d))[1]


def _tip_peel(cache: RasterCache, state: PillarState, d: float) -> tuple[np.ndarray, np.ndarray]:
    _follow(cache, state)
    model = cache.model
    out = np.full(model.M, np.nan)
    tilts = np.full(model.M, np.nan)
    rows = np.flatnonzero(state.attached & np.all(state.raster == model.full, axis=1))
    if rows.size == 0:
        return out, tilts
    x = d * np.take(state.alpha, rows, axis=0) - np.take(state.beta, rows, axis=0)
    serials = np.array([model.basis[p].serial for p in rows])
    coefficients = np.zeros((rows.size, len(MODES["quadratic"])))
    columns = [MODES["quadratic"].index(power) for power in model.powers]
    sizes = np.zeros(rows.size)
    for serial in np.unique(serials):
        members = np.flatnonzero(serials == serial)
        basis = model.basis[rows[members[0]]]
        coefficients[np.ix_(members, columns)] = (x[members] * basis.gram) @ basis.fit.T
        sizes[members] = basis.size
    radius = model.tip_radius[rows]
    intensity = peel.tip_intensity(coefficients, sizes, radius)
    parameters = peel.shape_parameters(intensity)
    tilts[rows] = parameters[:, 0]
    out[rows] = peel.strength(intensity, peel.circle_load(coefficients, sizes, radius), model.peel_control[rows],
                              model.kendall, parameters=parameters)
    return out, tilts


def pressures_at(cache: RasterCache, state: PillarState, d: float) -> np.ndarray:
    """`pressures` of the amplitudes at d."""
    return _remember(state, ("pressures", float(d)), lambda: pressures(cache, state, amplitudes(state, d)))


def pressures(cache: RasterCache, state: PillarState, x: np.ndarray) -> np.ndarray:
    """Element pressures on the footprint slots of the attached pillars (`on`): (n, width), 0 off
    their rasters."""
    _follow(cache, state)
    model = cache.model
    rows = on(state)
    # One product per group of pillars that share their footprint and raster (and so their modes'
    # pressures, `PillarModel.surface_group`): every pillar of a level lattice in full contact is one.
    out = np.zeros((rows.size, model.phi.shape[1]))
    if rows.size == 0:
        return out
    for members in _remember(state, ("groups",), lambda: _surface_groups(cache, state)):
        pillars = rows[members]
        out[members] = np.take(x, pillars, axis=0) @ model.phi[pillars[0]].T
    # np.take: the rows gathered as fancy indexing gathers them, many times faster.
    return np.where(np.take(state.raster, rows, axis=0), out, 0.0)


def element_penetration(cache: RasterCache, state: PillarState, d: float,
                        rows: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The footprint slots' penetration at d (tip below the surface > 0) and its slope, of the pillars
    ``rows`` (a mask; default all): (their indices, penetration (R, width), slope (R, width)).

    The surface under a tip is the others' field fitted by the tip's
    polynomials from its projections on the modes, plus the tip's own
    modes' displacement; the tip is level, at d - g less its springs'
    stretch.  Slots off the footprint read -inf.
    """
    key = ("penetration", float(d), None if rows is None else rows.tobytes())
    return _remember(state, key, lambda: _element_penetration(cache, state, d, rows))


def touch_candidates(cache: RasterCache, state: PillarState, d: float, end: float, tolerance: float) -> np.ndarray:
    """The free pillars that may touch at a displacement between d and ``end`` (a mask): those whose
    `touch_bound` is above -``tolerance``."""
    return ~state.attached & (touch_bound(cache, state, d, end) > -tolerance)


def touch_bound(cache: RasterCache, state: PillarState, d: float, end: float) -> np.ndarray:
    """Every free pillar's largest slot penetration between d and ``end``, bounded from above: (M,).

    A free pillar's own amplitudes are zero, so the surface under it is
    the fit of the others' field, u_s = fitted_s . f(d') with f(d') =
    d' f_a - f_b affine.  Over the slots, u_s lies within c . f(d') +- r .
    |f(d')| (c, r: `PillarModel.fit_centre`, `fit_spread`), so no slot
    penetrates more than  d' (wa - c . f_a) - (wb - c . f_b) + r . |f(d')|,
    a convex function of d' whose largest value on [d, end] is at an end.
    (Entries of attached pillars mean nothing.)
    """
    _follow(cache, state)
    spread = cache.model.fit_spread
    fa, fb, level_a, level_b = _remember(state, ("touch",), lambda: _touch_terms(cache, state))
    return np.maximum(d * level_a - level_b + np.sum(spread * np.abs(d * fa - fb), axis=0),
                      end * level_a - level_b + np.sum(spread * np.abs(end * fa - fb), axis=0))


def record(cache: RasterCache, state: PillarState, d: float, loading: bool, kind: str, reason: str,
           converged: bool = True) -> State:
    """The recorded equilibrium of ``state`` at d (the solves since the last record counted in it)."""
    model = cache.model
    rows = on(state)
    held = np.take(state.raster, rows, axis=0)
    total = 0.0
    slots, values = np.zeros(0, dtype=np.int64), np.zeros(0)
    if kind != "separated" and rows.size:
        slots = np.take(model.reports, rows, axis=0)[held]
        values = pressures_at(cache, state, d)[held]
        total = float(model.h2 * values.sum())
    # On the global grid (the tips' raster may be finer: `brushbem.pillars.tips`), its grids built when read.
    pressed = model.tips.pressed(slots, values)
    solves, cache.reported = cache.solves - cache.reported, cache.solves
    return State(displacement=float(d), force=total, contact_area=model.h2 * int(np.count_nonzero(held)),
                 attached_pillars=int(np.count_nonzero(state.attached)), loading=loading, kind=kind,
                 trial_force=total, cg_iterations=0, n_solves=solves, converged=converged, reason=reason,
                 pressed=pressed)


# -- steps: a state in, the next out ---------------------------------------------------------------------------

def solved(cache: RasterCache, state: PillarState) -> PillarState:
    """The state with the amplitudes of its set and rasters (the pillar-level solve)."""
    _follow(cache, state)
    model = cache.model
    cache.solves += 1
    if model.coupling == "full":
        alpha, beta = full_solve(model, state.attached)
        both = np.stack([alpha, beta], axis=-1)  # (M, m, 2)
        # The others' field on every mode: all blocks but the pillar's own (diag(gram)).
        fields = (np.einsum("ijkl,jlc->kic", model.Gf, both) - (model.gram[:, :, None] * both).transpose(1, 0, 2))
        return state.replace(alpha=alpha, beta=beta, fields=fields)
    sol, fields = cache.solver.solve()
    # The others' field on every mode: G0's diagonal is the pillar's own uniform mode.
    fields[0] -= model.gram[:, :1] * sol
    if model.m > 1 and state.radiate:
        sol, fields, rounds = radiate(model, cache.solver, state.attached, sol, fields)
        cache.radiation_rounds += rounds
    return state.replace(alpha=model.amplitudes(sol[:, 0], fields[..., 0], state.attached),
                         beta=model.amplitudes(sol[:, 1], fields[..., 1], state.attached), fields=fields)


def installed(cache: RasterCache, state: PillarState, masks: np.ndarray, pillars: np.ndarray) -> PillarState:
    """The state in which the ``pillars`` hold the footprint slots ``masks[p]`` (none: off), not solved."""
    _follow(cache, state)
    return _apply(cache, state, [(int(p), masks[p]) for p in pillars])


def attached_together(cache: RasterCache, state: PillarState, pillars: np.ndarray) -> PillarState:
    """Several pillars join whole at once (one factorisation instead of one update each), not solved."""
    _follow(cache, state)
    model = cache.model
    for p in pillars:
        model.set_raster(int(p), model.full[p])
    cache.solver.attached[pillars] = True
    if model.coupling == "local":
        cache.solver.refactor()
    return _changed(cache, state)


def cascade(cache: RasterCache, state: PillarState, d: float, loading: bool) -> PillarState:
    """Rounds at d: solve, peel every pillar beyond the criterion, let touching pillars in; until stable."""
    model = cache.model
    tolerance = 1e-10 * max(abs(d), float(np.max(np.abs(model.g))), 1e-300)
    for _ in range(10 * model.M + 100):
        cache.check_stop()
        state = solved(cache, state)
        x = amplitudes(state, d)
        p = pressures_at(cache, state, d)
        rows = on(state)
        tense = np.take(state.raster, rows, axis=0) & (p < -model.critical[rows] * (1 + 1e-10))
        if model.continuum_peel:
            # A whole tip leaves whole at its strength; its elements' criterion does not serve.
            strength = tip_strengths(cache, state, d)[rows]
            tip = np.isfinite(strength)
            tense[tip] = False
            tense[tip, 0] = model.h2 * model.force[rows[tip]] * x[rows[tip], 0] < -strength[tip] * (1 + 1e-10)
        hit = np.flatnonzero(tense.any(axis=1))
        if hit.size:
            state = peel_all(cache, state, [(int(rows[i]), tense[i]) for i in hit], x, d)
            continue
        candidates = touch_candidates(cache, state, d, d, tolerance)
        if candidates.any():
            rows, penetration, _ = element_penetration(cache, state, d, candidates)
            touching = penetration > tolerance
            joining = touching.any(axis=1)
            if joining.any():
                masks = np.zeros(model.full.shape, dtype=bool)
                masks[rows] = touching
                state = installed(cache, state, masks, rows[joining])
                continue
        return state
    raise RuntimeError(f"the cascade at d = {d:.6g} did not settle")


def peel_all(cache: RasterCache, state: PillarState, hits: list[tuple[int, np.ndarray]], x: np.ndarray,
             d: float) -> PillarState:
    """Every hit pillar peels on its own against ``state`` (none of them moved); then all are installed."""
    _follow(cache, state)
    frozen = state.attached
    return _apply(cache, state, [(p, peeled(cache, state, p, leave, frozen, x, d)) for p, leave in hits])


# -- the steps' parts and the peeling ---------------------------------------------------------------------------

def _follow(cache: RasterCache, state: PillarState) -> None:
    """Bring the cache to the state's rasters and set (those of another state: a saved one), pillar by pillar."""
    raster, attached = cache.key
    if raster is state.raster and attached is state.attached:
        return
    model, solver = cache.model, cache.solver
    wanted = np.where(state.attached[:, None], state.raster, False)
    held = solver.attached[:, None] & model.raster
    changed = np.flatnonzero((wanted != held).any(axis=1) | (state.attached != solver.attached))
    _apply(cache, state, [(int(p), wanted[p]) for p in changed])
    cache.key = (state.raster, state.attached)


def _changed(cache: RasterCache, state: PillarState) -> PillarState:
    """The state of the cache's set and rasters (a change of them: no amplitudes until solved)."""
    new = state.replace(attached=cache.solver.attached.copy(), raster=cache.model.raster.copy(), alpha=None,
                        beta=None, fields=None)
    cache.key = (new.raster, new.attached)
    return new


def _remember(state: PillarState, key: tuple, compute):
    value = state.memo.get(key)
    if value is None:
        value = state.memo[key] = compute()
    return value


def _surface_groups(cache: RasterCache, state: PillarState) -> list[np.ndarray]:
    """The attached pillars (`on`) by `PillarModel.surface_group`: positions in `on` per group."""
    _, inverse, counts = np.unique(cache.model.surface_group[on(state)], return_inverse=True, return_counts=True)
    return np.split(np.argsort(inverse, kind="stable"), np.cumsum(counts)[:-1])


def _element_penetration(cache: RasterCache, state: PillarState, d: float,
                         rows: np.ndarray | None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    _follow(cache, state)
    model = cache.model
    rows = np.arange(model.M) if rows is None else np.flatnonzero(rows)
    width = model.full.shape[1]
    if rows.size == 0:
        return rows, np.zeros((0, width)), np.zeros((0, width))
    coefficients = np.concatenate([state.fields[:, rows].transpose(1, 0, 2),
                                   np.stack([state.alpha[rows], state.beta[rows]], axis=-1)], axis=1)
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
    wa, wb = _tip_levels(cache, state, rows)
    full = model.full[rows]
    slope = np.where(full, wa[:, None] - u[..., 0], 0.0)
    penetration = np.where(full, d * slope - (wb[:, None] - u[..., 1]), -np.inf)
    return rows, penetration, slope


def _tip_levels(cache: RasterCache, state: PillarState, rows: np.ndarray | slice) -> tuple[np.ndarray, np.ndarray]:
    """(wa, wb) of the pillars ``rows``: a tip stands at d wa - wb (its springs' stretch taken off)."""
    model = cache.model
    wb = model.g[rows]
    if model.levels:
        wa = 1.0 - model.tip_deflection(state.alpha[:, 0], state.attached)[rows]
        wb = wb - model.tip_deflection(state.beta[:, 0], state.attached)[rows]
    else:
        wa = np.ones(wb.size)
    return wa, wb


def _touch_terms(cache: RasterCache, state: PillarState) -> tuple[np.ndarray, ...]:
    """`touch_bound`'s terms of the state: the fields fa, fb (m, M) and wa - c . fa, wb - c . fb (M,)."""
    fa, fb = np.ascontiguousarray(state.fields[..., 0]), np.ascontiguousarray(state.fields[..., 1])
    centre = cache.model.fit_centre
    wa, wb = _tip_levels(cache, state, slice(None))
    return fa, fb, wa - np.sum(centre * fa, axis=0), wb - np.sum(centre * fb, axis=0)


def _apply(cache: RasterCache, state: PillarState, changes: list[tuple[int, np.ndarray]]) -> PillarState:
    """The state in which each pillar p of ``changes`` holds the footprint slots of its mask (none: off).

    In the kept inverse the pillars that leave or change their raster go out in one block update and
    those on a raster come (back) in in another (`Solver.remove_many`, `Solver.add_many`); one or two
    attached pillars that only change their raster (a peel) are updated in place (`Solver.reshape`).
    No changes: the same state (the solver still asked, as its choice of a kept inverse or CG may move).
    """
    model, solver = cache.model, cache.solver
    attached = solver.attached
    if model.coupling != "local":
        for p, mask in changes:
            attached[p] = bool(mask.any())
            model.set_raster(p, mask if mask.any() else model.full[p])
        return _changed(cache, state) if changes else state
    leaving = [p for p, mask in changes if attached[p] and not (
        mask.any() and np.array_equal(mask, model.raster[p]))]
    reshaping = [(p, mask) for p, mask in changes if attached[p] and mask.any()
                 and not np.array_equal(mask, model.raster[p])]
    if len(reshaping) <= _RESHAPED and not solver.iterative:
        others = {p for p, _ in reshaping}
        solver.remove_many(np.array([p for p in leaving if p not in others], dtype=np.int64))
        for p, mask in reshaping:
            model.set_raster(p, mask)
            solver.reshape(p)
    else:
        solver.remove_many(np.array(leaving, dtype=np.int64))
    joining = []
    for p, mask in changes:
        if not mask.any():
            model.set_raster(p, model.full[p])
        elif not attached[p]:
            model.set_raster(p, mask)
            joining.append(p)
    solver.add_many(np.array(joining, dtype=np.int64))
    return _changed(cache, state) if changes else state


def local_amplitudes(cache: RasterCache, state: PillarState, p: int, mask: np.ndarray, frozen: np.ndarray,
                     x: np.ndarray, d: float) -> tuple[np.ndarray, Basis]:
    """Pillar p's amplitudes on the raster ``mask``, the pillars ``frozen`` held at the amplitudes ``x``.

    With ``coupling = "local"`` the frozen pillars are those of the last solve at d (``x`` its
    amplitudes), and their field across p's footprint is its fit from p's modes
    (`PillarModel.fitted`), projected on the modes of ``mask``; ``"full"`` couples the new raster
    with every frozen pillar's modes exactly.
    """
    model = cache.model
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
    field = model.fitted[p][mask] @ (d * state.fields[:, p, 0] - state.fields[:, p, 1])
    projections = basis.phi.T @ field
    a = np.zeros(model.m)
    a[0] = (s * (d - model.g[p]) - s * siblings - projections[0]) / (basis.gram[0] + compliance * s * s)
    if model.m > 1:
        a[1:] = -projections[1:] / basis.gram[1:]
    return a, basis


def peeled(cache: RasterCache, state: PillarState, p: int, leave: np.ndarray, frozen: np.ndarray, x: np.ndarray,
           d: float) -> np.ndarray:
    """The raster that pillar p keeps after losing the slots ``leave`` and peeling on its own.

    The pillars ``frozen`` stay at the amplitudes ``x`` (the element path's local cascade); the state is
    not changed (the caller installs the result).  An empty mask: the pillar comes off.
    """
    model = cache.model
    mask = state.raster[p] & ~leave
    if not model.peel:
        return np.zeros_like(mask)
    if model.continuum_peel and np.array_equal(state.raster[p], model.full[p]) \
            and np.isfinite(tip_strengths(cache, state, d)[p]):
        # A whole tip at its continuum capacity has no equilibrium left: it leaves whole.
        cache.largest_tilt = max(cache.largest_tilt, float(tip_tilts(cache, state, d)[p]))
        return np.zeros_like(mask)
    while mask.any():
        cache.check_stop()
        a, basis = local_amplitudes(cache, state, p, mask, frozen, x, d)
        pressure = basis.phi @ a
        tense = pressure < -np.broadcast_to(model.critical[p], mask.shape)[mask] * (1 + 1e-10)
        if not tense.any():
            break
        slots = np.flatnonzero(mask)
        mask = mask.copy()
        mask[slots[tense]] = False
    return mask
