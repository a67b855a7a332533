"""The pillar-level model of a brush of flat rigid tips: ``LoadPath.method = "pillars"``.

The element-level paths solve for the pressure on every element of every
tip.  A flat rigid tip in full contact carries a pressure that is almost
fixed by its own raster: the half-space inverse of a uniform displacement,
with small corrections where its neighbours' field is not uniform across it.
This model keeps a few numbers per pillar instead of every element.

Basis
    For every raster shape (the elements a tip holds), the full BEM on that
    tip alone gives the pressures phi_k = K_R^-1 P_k of the displacement
    polynomials P_k of the tip's coordinates: 1 (the uniform mode, whose
    amplitude is the tip's mean displacement), x and y (``modes="tilt"``),
    and x^2, x y, y^2 (``modes="quadratic"``, the default), made
    K-orthogonal to phi_0, so that only phi_0 carries a net force.  A tip's
    pressure is p = sum_k a_k phi_k.  Bases are cached by raster shape:
    pillars of a lattice share one; a random layout has a few shapes.

Coupling
    G_ij = Phi_i^T K_ij Phi_j, the Galerkin projection of the half-space
    between the modes of pillars i and j: exact (element-pair sums of the
    Love kernel over the two footprints, cached by the pair's shapes and
    offset) for centres closer than ``near`` (default 8 pillar radii), and by
    the multipole expansion of 1/r to second order in the modes' moments
    (the monopole F / (pi E* r) with its dipole and quadrupole corrections,
    and the element square's own second moment) beyond.  On a lattice
    (`brushbem.protocol.pillar_lattice`) the far sums are convolutions over
    the lattice, done by FFT, with every tip's moments taken about its
    lattice point; other layouts keep dense couplings.  Springs of every
    level (`brushbem.physics.structure.SpringLevel`, pillars' own and hierarchy
    clusters) enter the uniform mode as in the element operator: the
    Galerkin projection of A = K + sum_l (h^2 / k_l) P_l^T P_l.

Equilibrium
    On the attached set S the uniform amplitudes solve the pillar-level
    system (G00 + H)_SS a_0 = s_S (d - g_S) (s the force of phi_0, g the
    pillar's length offset): a dense SPD system of the attached pillars
    whose inverse is kept and updated by rank-one steps as pillars join,
    leave or change shape (checked by its residual, refactorised when it
    drifts); on a lattice with more than
    `brushbem.protocol.pillar_solver.KEPT_PILLARS` attached, by CG on the
    lattice's FFT product with a circulant preconditioner
    (`brushbem.protocol.pillar_cg`), to a relative residual of 1e-11.  The
    higher modes follow locally from the field that the
    others' uniform modes cause across the tip (``coupling="local"``);
    ``coupling="full"`` solves all modes together (a dense factorisation per
    solve, small brushes).  Everything is affine in d on a fixed state, so,
    as on the element event path, the next event is found in closed form.

Loading of tips of unequal lengths (roughness, a length profile, a lengths file)
    The exact path presses such a brush as the non-adhesive contact problem
    at every d (`brushbem.protocol.contact_loading`): a tip that has just
    touched is in partial contact.  The model solves that problem at the
    pillar level (`brushbem.protocol.pillar_loading`): a tip holds the footprint slots where it
    meets the surface (the others' field across its footprint fitted by its
    polynomials from their projections on its modes, plus its own modes'
    exact displacement), an element in tension leaves, until neither
    happens; the preload force's displacement by Newton steps on the affine
    F(d) of a fixed set.  While pressing, the higher modes' near field is
    fed back (a fixed point): the edge of a partial contact depends on it
    (a concave 16 x 16 brush at k~ = 1e-2 without it: F_A +9.7 %).

Detachment (Pohrt-Popov) and touch
    The criterion is the element grid's: an element of a tip detaches when
    its pressure, reconstructed from the basis, falls below -Sigma_c,
    Sigma_c = sqrt(E* dgamma / (0.473201 h)).  An element that reaches it
    leaves and the pillar peels on its own with the rest of the brush frozen,
    exactly as the element path's local cascade does (a raster of the
    remaining elements gets its own basis, the others' field across it is
    the fit above), until it is stable or gone; then the brush is solved
    again at the same d, and so on (the cascade).  A pillar that touches
    while pulled (a footprint slot meets the surface) enters with the slots
    that penetrate.

Accuracy against ``method = "events"`` (`docs/pillars/variants.md`, written
by ``docs/pillars/variants.py``, on ten 4 x 4 and 8 x 8 lattices, level and
rough, k~ from 10 to 1e-4): the uniform mode alone is +6.5 .. +22 % off on
F_A (the neighbours' field tilts and bends the pressure on every tip, a tip
on the brush's edge most, and the uniform mode misplaces the edge stress);
tilts with peeling tips -1.6 .. -0.2 %; the quadratic modes with peeling
(the default) -0.3 .. +0.4 % on F_A and -0.4 .. +0.2 % on the work, and
coupled in full -0.1 .. +0.1 %.  A tip peels (its corner elements leave
first): one that detaches whole at its first edge element comes off early.
At 2.3, 3.6 and 7.2 elements' radius the uniform and tilt models get worse
as the tip is resolved better, the quadratic model stays within 0.6 %.

The families of `docs/pillars/validation.md` (written by
``docs/pillars/validation.py``: flat, rough, random, hierarchical and
concave brushes of 64, 256 and 1024 pillars at k~ = 10, 1e-2 and 1e-5,
each against the exact path) hold every case within 1 % on F_A, 3 % on
the work and 2 % on the pillars attached at pull-off.

Cost: per event O(n^2) for the n attached pillars (the kept inverse), or
O(M log M) per CG iteration beyond ``KEPT_PILLARS`` on a lattice (7-9
iterations a solve), and O(M log M) for the M pillars of a lattice (the
FFT, and a bound at pillar level on how far each free tip is from the
surface, so that only the attached pillars and the free ones that may touch
are looked at slot by slot); O(M^2) off a lattice.  On a lattice the memory
is O(M) besides the kept inverse and G00, kept up to
`brushbem.protocol.pillar_basis.DENSE_PILLARS` pillars and filled entry by
entry as the solve reads it.  Measured on the chapter-5 family
(``benchmarks/large_brush.py``, CPU seconds of one core): 1024 pillars
3.2-3.5 s (the exact path 79-87 s, ``benchmarks/pillars.py``), 4096 pillars
16 s, 10^4 pillars 45-51 s in 0.66 GB (806 pillars attached at the preload),
10^5 pillars (316 x 316, N = 5056) 35-39 min in 3.5 GB (2353 attached, 10523
states).  A level brush attaches every pillar (``--sigma 0 --kept-baseline``):
4096 pillars 12.6 s by CG against 39.4 s with the kept inverse, 10^4 pillars
42 s in at most 1 GB against 356 s in 4.1 GB (the same F_A to 5e-11 and work
to 4e-10).

Where it does not apply it refuses, naming the key: tips that are not flat
(``brush(tip=...)``), a tilted base (``brush(tilt=...)``), viscoelastic
connections (``Indenter.viscoelastic``), nonlinear pillar laws
(``Indenter.pillar_law``), and indenters that are not brushes.

Here: the state of the path (`_Path`: the solves, the peeling and the
cascades).  The events, from the first touch to separation, are in
`brushbem.protocol.pillar_events`, the loading of unequal tips in
`brushbem.protocol.pillar_loading`, the
bases, couplings and springs in
`brushbem.protocol.pillar_basis` (`PillarModel`), the lattice's FFT in
`brushbem.protocol.pillar_lattice`, the pillar-level solve (the kept
inverse) in `brushbem.protocol.pillar_solver`, the refusals in
`brushbem.protocol.pillar_checks`.
"""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np
from threadpoolctl import ThreadpoolController

from brushbem.errors import ParameterError

from brushbem.protocol.pillar_basis import MODES, NEAR_RADII, Basis, PillarModel
from brushbem.protocol.pillar_cg import NotConverged
from brushbem.protocol.pillar_checks import check_applicable
from brushbem.protocol.pillar_events import events
from brushbem.protocol.pillar_loading import press, radiate
from brushbem.protocol.pillar_solver import Solver, full_solve
from brushbem.protocol.problem import ContactProblem, LoadPath, State

__all__ = ["MODES", "NEAR_RADII", "Basis", "PillarModel", "check_applicable", "pull_off"]

class _Path:
    """The state of a pull-off in the pillar model and its steps."""

    def __init__(self, model: PillarModel, path: LoadPath):
        self.model = model
        self.path = path
        self.solver = Solver(model)
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
        #: Bumped by every change of the state (a solve, a pillar that joins, leaves or peels): the key of
        #: `_memo`, which keeps the element pressures and penetrations of the current state (the event search
        #: asks for those the cascade has just computed at the same d).
        self._stamp = 0
        self._memo: dict[tuple, object] = {}
        self.last = (0.0, True)  # (d, loading) of the last state yielded

    # -- state ---------------------------------------------------------------
    def _changed(self) -> None:
        self._stamp += 1
        self._memo.clear()

    def _remember(self, key: tuple, compute):
        key = (self._stamp, *key)
        value = self._memo.get(key)
        if value is None:
            value = self._memo[key] = compute()
        return value

    def solve(self) -> None:
        model = self.model
        self.solves += 1
        self._changed()
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
            sol, fields = radiate(self, sol, fields)
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
        return self._remember(("on",), lambda: np.flatnonzero(self.attached))

    def pressures_at(self, d: float) -> np.ndarray:
        """`pressures` of the amplitudes at d (kept until the state changes)."""
        return self._remember(("pressures", float(d)), lambda: self.pressures(self.amplitudes(d)))

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
        _, inverse, counts = np.unique(model.surface_group[on], return_inverse=True, return_counts=True)
        order = np.argsort(inverse, kind="stable")
        for members in np.split(order, np.cumsum(counts)[:-1]):
            pillars = on[members]
            out[members] = x[pillars] @ model.phi[pillars[0]].T
        return np.where(model.raster[on], out, 0.0)

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
        return self._remember(key, lambda: self._element_penetration(d, rows))

    def _element_penetration(self, d: float, rows: np.ndarray | None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        model = self.model
        rows = np.arange(model.M) if rows is None else np.flatnonzero(rows)
        width = model.full.shape[1]
        if rows.size == 0:
            return rows, np.zeros((0, width)), np.zeros((0, width))
        coefficients = np.concatenate([self.fields[:, rows].transpose(1, 0, 2),
                                       np.stack([self.alpha[rows], self.beta[rows]], axis=-1)], axis=1)
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
        wa, wb = self._tip_levels(rows)
        full = model.full[rows]
        slope = np.where(full, wa[:, None] - u[..., 0], 0.0)
        penetration = np.where(full, d * slope - (wb[:, None] - u[..., 1]), -np.inf)
        return rows, penetration, slope

    def _tip_levels(self, rows: np.ndarray | slice) -> tuple[np.ndarray, np.ndarray]:
        """(wa, wb) of the pillars ``rows``: a tip stands at d wa - wb (its springs' stretch taken off)."""
        model = self.model
        wb = model.g[rows]
        if model.levels:
            wa = 1.0 - model.tip_deflection(self.alpha[:, 0], self.attached)[rows]
            wb = wb - model.tip_deflection(self.beta[:, 0], self.attached)[rows]
        else:
            wa = np.ones(wb.size)
        return wa, wb

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
        model = self.model
        fa, fb = self.fields[..., 0], self.fields[..., 1]  # (m, M)
        centre, spread = model.fit_centre, model.fit_spread
        wa, wb = self._tip_levels(slice(None))
        ca, cb = np.sum(centre * fa, axis=0), np.sum(centre * fb, axis=0)
        return np.maximum(d * (wa - ca) - (wb - cb) + np.sum(spread * np.abs(d * fa - fb), axis=0),
                          end * (wa - ca) - (wb - cb) + np.sum(spread * np.abs(end * fa - fb), axis=0))

    def install(self, masks: np.ndarray, pillars: np.ndarray) -> None:
        """The ``pillars`` hold the footprint slots ``masks[p]`` (none: off)."""
        self._apply([(int(p), masks[p]) for p in pillars])

    def _apply(self, changes: list[tuple[int, np.ndarray]]) -> None:
        """Each pillar p of ``changes`` holds the footprint slots of its mask (none: off).

        In the kept inverse the pillars that leave or change their raster go out in one block update and
        those on a raster come (back) in in another (`Solver.remove_many`, `Solver.add_many`).
        """
        model = self.model
        self._changed()
        if model.coupling != "local":
            for p, mask in changes:
                self.attached[p] = bool(mask.any())
                model.set_raster(p, mask if mask.any() else model.full[p])
            return
        leaving = [p for p, mask in changes if self.attached[p] and not (
            mask.any() and np.array_equal(mask, model.raster[p]))]
        self.solver.remove_many(np.array(leaving, dtype=np.int64))
        joining = []
        for p, mask in changes:
            if not mask.any():
                model.set_raster(p, model.full[p])
            elif not self.attached[p]:
                model.set_raster(p, mask)
                joining.append(p)
        self.solver.add_many(np.array(joining, dtype=np.int64))

    def press(self, d: float) -> int:
        """The non-adhesive contact problem at d (`brushbem.protocol.pillar_loading.press`): the rounds it took."""
        return press(self, d)

    def state(self, d: float, loading: bool, kind: str, reason: str, converged: bool = True) -> State:
        model = self.model
        self.last = (float(d), loading)
        n = model.n
        pressure = np.zeros(n * n)
        contact = np.zeros(n * n, dtype=bool)
        rows = self.on()
        on = model.raster[rows]
        force = 0.0
        if kind != "separated" and rows.size:
            slots = model.slots[rows][on]
            values = self.pressures_at(d)[on]
            pressure[slots] = values
            contact[slots] = True
            force = float(model.h2 * values.sum())
        solves, self._reported = self.solves - self._reported, self.solves
        return State(displacement=float(d), force=force, contact_area=model.h2 * int(np.count_nonzero(on)),
                     attached_pillars=int(np.count_nonzero(self.attached)), loading=loading, kind=kind,
                     trial_force=force, cg_iterations=0, n_solves=solves, converged=converged, reason=reason,
                     pressure=pressure.reshape(n, n), contact=contact.reshape(n, n))

    # -- changes -------------------------------------------------------------
    def attach_many(self, pillars: np.ndarray) -> None:
        """Several pillars join at once (one factorisation instead of one update each)."""
        self._changed()
        for p in pillars:
            self.model.set_raster(int(p), self.model.full[p])
        self.attached[pillars] = True
        if self.model.coupling == "local":
            self.solver.refactor()

    def local_amplitudes(self, p: int, mask: np.ndarray, frozen: np.ndarray, x: np.ndarray,
                         d: float) -> tuple[np.ndarray, Basis]:
        """Pillar p's amplitudes on the raster ``mask``, the pillars ``frozen`` held at the amplitudes ``x``.

        With ``coupling = "local"`` the frozen pillars are those of the last solve at d (``x`` its
        amplitudes), and their field across p's footprint is its fit from p's modes
        (`PillarModel.fitted`), projected on the modes of ``mask``; ``"full"`` couples the new raster
        with every frozen pillar's modes exactly.
        """
        model = self.model
        compliance = 0.0
        siblings = 0.0
        for cluster, stiffness in model.levels:
            c = cluster[p]
            compliance += model.h2 / stiffness[c]
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
        rc = np.stack([model.rows[p][mask], model.cols[p][mask]], axis=1)
        basis = model.raster_basis(rc - rc.min(axis=0))
        s = basis.force
        field = model.fitted[p][mask] @ (d * self.fields[:, p, 0] - self.fields[:, p, 1])
        projections = basis.phi.T @ field
        a = np.zeros(model.m)
        a[0] = (s * (d - model.g[p]) - s * siblings - projections[0]) / (basis.gram[0] + compliance * s * s)
        if model.m > 1:
            a[1:] = -projections[1:] / basis.gram[1:]
        return a, basis

    def peeled(self, p: int, leave: np.ndarray, frozen: np.ndarray, x: np.ndarray, d: float) -> np.ndarray:
        """The raster that pillar p keeps after losing the slots ``leave`` and peeling on its own.

        The pillars ``frozen`` stay at the amplitudes ``x`` (the element path's local cascade); the model
        is not changed (the caller installs the result).  An empty mask: the pillar comes off.
        """
        model = self.model
        mask = model.raster[p] & ~leave
        if not model.peel:
            return np.zeros_like(mask)
        while mask.any():
            a, basis = self.local_amplitudes(p, mask, frozen, x, d)
            pressure = basis.phi @ a
            tense = pressure < -model.critical * (1 + 1e-10) if model.critical > 0 else pressure < 0
            if not tense.any():
                break
            slots = np.flatnonzero(mask)
            mask = mask.copy()
            mask[slots[tense]] = False
        return mask

    def peel_all(self, hits: list[tuple[int, np.ndarray]], x: np.ndarray, d: float) -> None:
        """Every hit pillar peels on its own against the state before any of them moved; then all are installed."""
        frozen = self.attached.copy()
        self._apply([(p, self.peeled(p, leave, frozen, x, d)) for p, leave in hits])

    def cascade(self, d: float, loading: bool) -> None:
        """Rounds at d: solve, peel every pillar beyond the criterion, let touching pillars in; until stable."""
        model = self.model
        tolerance = 1e-10 * max(abs(d), float(np.max(np.abs(model.g))), 1e-300)
        for _ in range(10 * model.M + 100):
            self.solve()
            x = self.amplitudes(d)
            p = self.pressures_at(d)
            rows = self.on()
            tense = model.raster[rows] & (p < -model.critical * (1 + 1e-10) if model.critical > 0 else p < 0)
            hit = np.flatnonzero(tense.any(axis=1))
            if hit.size:
                self.peel_all([(int(rows[i]), tense[i]) for i in hit], x, d)
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


def pull_off(problem: ContactProblem, path: LoadPath, *, modes: str = "quadratic", coupling: str = "local",
             peel: bool = True, near: float | None = None) -> Iterator[State]:
    """The states of a press-and-pull-off in the pillar model (module docstring), as `paths.pull_off` yields them.

    ``modes``, ``coupling``, ``peel`` and ``near`` select the model's
    variants (the defaults meet the accuracy of the module docstring).
    """
    check_applicable(problem, path)
    lowest = problem.indenter.lowest_height
    if path.preload_displacement is not None and path.preload_displacement <= lowest:
        raise ParameterError(
            "LoadPath", "preload_displacement",
            f"LoadPath.preload_displacement = {path.preload_displacement:g} must be > {lowest:.6g}, "
            "the height of the indenter's lowest element (where it first touches)"
        )
    # The pillar-level matrices are small (M^2 for M pillars): BLAS threads gain little there, and on a
    # machine whose cores are busy they lose a great deal (a 256 x 256 Cholesky factorisation took 0.26 s
    # on two threads of two loaded cores against 0.75 ms on one).  The limit holds while the states are
    # consumed too, and is lifted when the generator ends or is closed.
    with ThreadpoolController().limit(limits=1, user_api="blas"):
        model = PillarModel(problem, modes=modes, coupling=coupling, peel=peel, near=near)
        run = _Path(model, path)
        try:
            yield from events(run, path)
        except NotConverged as error:
            # The last state stands; the path stops there, saying why (as the element paths do).
            d, loading = run.last
            yield run.state(d, loading, "equilibrium", str(error), converged=False)
