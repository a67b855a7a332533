"""The adhesive equilibrium at a base displacement (Pohrt-Popov criterion) and the non-adhesive contact problem.

The criterion itself, Sigma_c of the mesh, is `brushbem.physics.adhesion.critical_stress`.

The CG solve on a fixed contact set (`solve_on_set`, with its pillar-block
path and the switches `brushbem.settings.Switches.reuse_set_solver` and ``keep_solution_deflection``)
is in `brushbem.numerics.solver.set_solve`; it is re-exported here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from brushbem import backend
from brushbem.numerics.operator import ContactOperator
from brushbem.numerics.solver.cache import SolverCache
from brushbem.numerics.solver.cascade_deflection import moved_deflection
from brushbem.numerics.solver.cg import WARM_START_WITHIN_TOLERANCE, ProductLedger
from brushbem.numerics.solver.preconditioners import BLOCK_LIMIT, laplacian_preconditioner
from brushbem.numerics.solver.set_solve import solve_on_set

__all__ = [
    "Equilibrium",
    "Settings",
    "Start",
    "equilibrium",
    "local_cascade",
    "penetration",
    "polonsky_keer",
    "solve_on_set",
    "tip_deflection",
]


def local_cascade(operator: ContactOperator, contact, pressure, leaving, critical: float,
                  max_block: int = BLOCK_LIMIT):
    """Detachment rounds on the pillars that lose elements, each pillar solved on its own.

    The state (``pressure`` on ``contact``, window arrays) is an equilibrium
    and ``leaving`` the elements that must leave.  Every pillar P that loses
    one keeps the deflection that the rest of the structure causes on it
    fixed: its new pressure q solves

        A_PP|S' q = (A_PP p_P)|S',   A_PP = K_PP + (sum_l h^2 / k_l) 1 1^T,

    on its remaining contact S' (the springs of every level above P load all
    of P's elements alike), exactly, with the pillar's half-space block
    (``HalfSpace.block_inverse``, shared by pillars of the same contact shape)
    and the Sherman-Morrison formula for the springs.  Elements of P whose
    tension then exceeds ``critical`` leave too, until P is stable.  The rest
    of the structure is not touched; the caller's next global solve adds the
    change of the far field.  A soft pillar that starts to peel thus peels in
    a few dense solves of its own size, instead of one global solve per ring
    of elements.

    Returns (contact, pressure, number of elements that left) or None where
    it does not apply: an element of ``leaving`` off the pillars, or a
    pillar contact of more than ``max_block`` elements.
    """
    xp = operator.xp
    labels = np.asarray(backend.to_numpy(operator.pillar_labels))
    in_contact = np.asarray(backend.to_numpy(contact), dtype=bool)
    leave = np.asarray(backend.to_numpy(leaving), dtype=bool) & in_contact
    hit = np.unique(labels[leave])
    if hit.size == 0 or hit[0] < 0:
        return None
    rows, cols = np.nonzero(in_contact & np.isin(labels, hit))  # row-major
    by_pillar = np.argsort(labels[rows, cols], kind="stable")
    rows, cols = rows[by_pillar], cols[by_pillar]
    counts = np.bincount(np.searchsorted(hit, labels[rows, cols]), minlength=hit.size)
    if int(counts.max()) > max_block:
        return None
    halfspace = operator.halfspace
    # Every hit pillar's springs in series: the sum over the levels of its cluster's compliance.
    compliances = sum(np.asarray(c)[np.asarray(cluster)[hit]] for c, cluster in operator.spring_levels)
    compliances = np.broadcast_to(np.asarray(compliances, dtype=np.float64), hit.shape)
    values = np.array(backend.to_numpy(pressure), dtype=np.float64)
    new_contact = in_contact.copy()
    origin = np.array([operator.window.r0, operator.window.c0])
    detached = 0
    for start, count, compliance in zip(np.r_[0, np.cumsum(counts)[:-1]].tolist(), counts.tolist(),
                                        compliances.tolist()):
        r, c = rows[start : start + count], cols[start : start + count]
        offsets = np.stack([r, c], axis=1) + origin
        p = values[r, c]
        b = halfspace.block_matrix(offsets) @ p + compliance * p.sum()
        keep = ~leave[r, c]
        parent = (offsets, halfspace.block_inverse(offsets))
        q = np.zeros(count)
        while bool(np.any(keep)):
            sub = offsets[keep]
            inverse = halfspace.block_inverse(sub, parent=parent)
            y = inverse @ b[keep]
            z = inverse.sum(axis=1)
            q = np.zeros(count)
            q[keep] = y - z * (compliance * y.sum() / (1.0 + compliance * z.sum()))
            tense = keep & ((q < -critical) if critical > 0 else (q < 0))
            if not bool(np.any(tense)):
                break
            parent = (sub, inverse)
            keep &= ~tense
        values[r, c] = np.where(keep, q, 0.0)
        new_contact[r, c] = keep
        detached += int(count - np.count_nonzero(keep))
    return xp.asarray(new_contact), xp.asarray(values), detached


@dataclass(frozen=True, kw_only=True)
class Equilibrium:
    """The state at one base displacement (on the operator's window).

    Attributes
    ----------
    displacement : float
        Base displacement d.
    pressure : ndarray
        Pressure on the window, compressive positive.
    contact : ndarray of bool
        Contact set on the window.
    converged : bool
    reason : str
    cg_iterations : int
        CG iterations spent, all solves together.
    n_solves : int
    trial_force_sum : float
        Sum of the pressure of the first global solve (the fixed-set force
        the path passes through before a cascade; after the local rounds of
        `local_cascade` where the cascade starts on the pillars).
    detached, attached : int
        Elements that left and joined S.
    deflection : ndarray or None
        ``tip_deflection`` (K p + springs) on the window for the returned pressure, when the
        solver computed it anyway (the final join check of ``equilibrium``),
        so that callers need not transform the pressure again.
    trial_pressure : ndarray or None
        The pressure of the first global solve (on the starting contact set,
        before any element left or joined; the sum of it is
        ``trial_force_sum``); None where no solve ran.
    """

    displacement: float
    pressure: object
    contact: object
    converged: bool
    reason: str
    cg_iterations: int
    n_solves: int
    trial_force_sum: float
    detached: int
    attached: int
    deflection: object = None
    trial_pressure: object = None


def tip_deflection(operator: ContactOperator, pressure, cache: SolverCache | None = None):
    """Half-space deflection plus spring deflection of ``pressure`` on the window (unmasked): the one a solve
    kept in ``cache`` where it has it, else transformed."""
    return operator.tip_deflection(pressure) if cache is None else cache.tip_deflection(operator, pressure)


def penetration(operator: ContactOperator, height, displacement: float, pressure, cache: SolverCache | None = None):
    """How far the tip reaches into the deformed half-space (> 0: penetrates), on the window."""
    return displacement - height - tip_deflection(operator, pressure, cache)


@dataclass(frozen=True, kw_only=True)
class Settings:
    """How an equilibrium is solved: tolerances, limits, the cascade and the solves' scope.

    Attributes
    ----------
    tolerance : float
        Relative residual of every CG solve; an element joins S when it
        penetrates by more than ``10 * tolerance`` times the problem's length
        scale (`equilibrium`).
    max_iterations : int
        CG iterations per solve.
    max_rounds : int
        Leave/join rounds before the contact set is declared not stable.
    cascade : {"local", "global"}
        How the detachment rounds of a brush run.  "global": every round is a
        solve on the whole contact set (the thesis's loop).  "local" (on
        structures of two or more pillars; the others always run "global"):
        the pillars that lose elements peel in rounds of their own
        (`local_cascade`), with the rest of the structure held, and a global
        solve then adds the far field and checks every element again.  Both
        end in a state where no element exceeds the criterion and none
        penetrates; they may differ in which elements a cascade takes along
        when one is within the far field's change of the threshold.
    window_preconditioner : callable, optional
        M^-1 on the window's arrays.  With one, every solve runs on the whole
        window with it and the cascade is global; without one (the default),
        a solve runs on the block around S with the preconditioner that
        `solve_on_set` chooses, and the cascade follows ``cascade``.
    """

    tolerance: float = 1e-8
    max_iterations: int = 10000
    max_rounds: int = 100000
    cascade: str = "local"
    window_preconditioner: object = None

    def __post_init__(self) -> None:
        if self.cascade not in ("local", "global"):
            raise ValueError(f"cascade = {self.cascade!r} must be 'local' or 'global'")


@dataclass(frozen=True, kw_only=True)
class Start:
    """The state an equilibrium starts from (on the operator's window), and the event applied to it.

    Attributes
    ----------
    contact : ndarray of bool
        Contact set to start from (the history).
    pressure : ndarray
        Warm start.
    deflection : ndarray, optional
        ``operator.tip_deflection(pressure)``, when the caller knows it (the
        event-driven path does: the state is affine between events).  It is
        kept in step while nothing is solved: the first solve starts without
        applying the operator, and when that solve finds the warm start
        within tolerance (an attachment exactly at the touching point does
        not change the pressure) the join check needs no transform either.
    detach, attach : ndarray of bool, optional
        Elements that leave / join S before the first solve (the event that
        the event-driven path has reached exactly).
    """

    contact: object
    pressure: object
    deflection: object = None
    detach: object = None
    attach: object = None


def equilibrium(
    operator: ContactOperator,
    height,
    displacement: float,
    start: Start,
    *,
    critical: float,
    settings: Settings = Settings(),
    length_scale: float = 0.0,
    ledger: ProductLedger | None = None,
    cache: SolverCache | None = None,
) -> Equilibrium:
    """Adhesive equilibrium at base displacement ``displacement`` (module docstring).

    Parameters
    ----------
    operator : ContactOperator
    height : ndarray
        Tip heights on the operator's window (inf outside the footprints).
    displacement : float
        d, in units of length.
    start : Start
        The contact set, pressure (and deflection if known) to start from,
        with the elements forced to leave or join first.
    critical : float
        Sigma_c; 0 means no adhesion (elements leave when p < 0).
    settings : Settings
        Tolerances, limits, cascade and solve scope.
    length_scale : float
        The load path's displacement scale (the largest |d| so far), in
        units of length.  An element joins S when it penetrates by more than
        the solve's accuracy in length, ``10 * tolerance`` times the largest
        of this, |d| and the largest |d - height|; near d = 0 (a flat tip
        pulled back to its zero without adhesion) |d| alone would let
        rounding errors of the pressure keep the contact forever.
    ledger : ProductLedger, optional
        The chain of kept deflections that ``start.deflection`` belongs to:
        the solves may then take their late products in single precision
        (`solve_on_set`).
    cache : SolverCache, optional
        What the solves on this indenter reuse, the caller's (None: a fresh
        one; the numbers are the same, nothing is reused).

    The loop (solve on S, drop the elements beyond the criterion, add the
    penetrating ones, until neither happens) is written out in one function:
    its state (contact, pressure, the known deflection, the counts) threads
    through every branch, and split into pieces it would pass 8 values in and
    out of each.
    """
    xp = operator.xp
    cache = SolverCache() if cache is None else cache
    footprint = xp.isfinite(height)
    local = (settings.cascade == "local" and settings.window_preconditioner is None
             and operator.indenter.n_pillars >= 2)
    contact, pressure, deflection, detached, attached = _apply_event(operator, footprint, start, critical, local)
    target = xp.where(footprint, displacement - height, 0.0)
    iterations = solves = 0
    trial = trial_pressure = None
    # Penetration tolerance: the solve's accuracy in units of length.
    scale = float(xp.max(xp.abs(target))) if bool(xp.any(footprint)) else 0.0
    slack = 10.0 * settings.tolerance * max(scale, abs(displacement), length_scale, 1e-300)

    def state(converged: bool, reason: str, **extra) -> Equilibrium:
        return Equilibrium(
            displacement=displacement, pressure=pressure, contact=contact, converged=converged, reason=reason,
            cg_iterations=iterations, n_solves=solves,
            trial_force_sum=trial if trial is not None else (float(xp.sum(pressure)) if solves else 0.0),
            detached=detached, attached=attached, **extra,
        )

    for _ in range(settings.max_rounds):
        if bool(xp.any(contact)):
            result, block = _solve(operator, contact, target, pressure, deflection, settings, ledger, cache)
            iterations += result.iterations
            solves += 1
            if result.iterations or result.reason != WARM_START_WITHIN_TOLERANCE:
                deflection = None  # the pressure moved
            pressure = xp.zeros_like(target)
            pressure[block] = result.solution
            if not result.converged:
                return state(False, result.reason)
        else:
            pressure = xp.zeros_like(target)
        if trial is None:
            trial = float(xp.sum(pressure))
            trial_pressure = pressure
        leaving = contact & (pressure < -critical) if critical > 0 else contact & (pressure < 0)
        n_leaving = int(xp.count_nonzero(leaving))
        if n_leaving and local:
            known = cache.known_tip_deflection(operator, pressure)
            cascaded = local_cascade(operator, contact, pressure, leaving, critical)
            if cascaded is not None:
                deflection = moved_deflection(operator, known, pressure, cascaded[1])
                contact, pressure, n_left = cascaded
                detached += n_left
                continue
        if n_leaving:
            contact = contact & ~leaving
            if deflection is not None:
                deflection = deflection - operator.element_deflection(pressure, leaving)
            pressure = xp.where(contact, pressure, 0.0)
            detached += n_leaving
            continue
        if deflection is None:
            deflection = tip_deflection(operator, pressure, cache)
        joining = footprint & ~contact & (displacement - height - deflection > slack)
        n_joining = int(xp.count_nonzero(joining))
        if n_joining:
            contact = contact | joining
            attached += n_joining
            continue
        return state(True, "contact set stable", deflection=deflection, trial_pressure=trial_pressure)
    return state(False, f"contact set did not stabilise in {settings.max_rounds} rounds")


def _apply_event(operator: ContactOperator, footprint, start: Start, critical: float, local: bool):
    """The start's contact, pressure and deflection after its forced leaves and joins, and their counts."""
    xp = operator.xp
    contact = start.contact & footprint
    pressure, deflection, detach = start.pressure, start.deflection, start.detach
    detached = attached = 0
    outside = True  # whether the pressure may hold values outside the contact set
    if detach is not None and local and bool(xp.any(contact & detach)):
        # The caller's state is an equilibrium: the cascade starts on the pillars.
        cascaded = local_cascade(operator, contact, xp.where(contact, pressure, 0.0), detach, critical)
        if cascaded is not None:
            deflection = moved_deflection(operator, deflection, pressure, cascaded[1])
            contact, pressure, detached = cascaded
            detach = None
            outside = False
    if detach is not None:
        detached += int(xp.count_nonzero(contact & detach))
        contact = contact & ~detach
    if start.attach is not None:
        joining = start.attach & footprint & ~contact
        attached += int(xp.count_nonzero(joining))
        contact = contact | joining
    if deflection is not None and outside:
        # The pressure outside the new set (elements forced to leave) is dropped.
        deflection = deflection - operator.element_deflection(pressure, ~contact)
    return contact, xp.where(contact, pressure, 0.0) if outside else pressure, deflection, detached, attached


def _solve(operator: ContactOperator, contact, target, pressure, deflection, settings: Settings,
           ledger: ProductLedger | None, cache: SolverCache):
    """One solve on S: on the block around S, or on the whole window with the settings' preconditioner.

    Returns the solve's result and the slices of the window it covers.
    """
    if settings.window_preconditioner is None:
        # The solve only needs the deflection on S: run it on the block around S.
        block, block_operator = cache.sub_operator(operator, contact)
    else:
        block, block_operator = operator.window.slices_local, operator
    result = solve_on_set(
        block_operator, contact[block], target[block], pressure[block],
        None if deflection is None else deflection[block], settings.tolerance, settings.max_iterations,
        settings.window_preconditioner, ledger, cache,
    )
    return result, block


def polonsky_keer(
    operator: ContactOperator,
    height,
    displacement: float,
    pressure,
    tolerance: float = 1e-8,
    max_iterations: int = 10000,
) -> Equilibrium:
    """Non-adhesive contact at base displacement d by constrained CG (Polonsky & Keer 1999).

    Minimises 1/2 p.A p - p.(d - height) subject to p >= 0 on the footprint.
    The contact set is the set where p > 0; elements with p = 0 and a negative
    gap join it inside the iteration (the conjugacy is then reset).  The
    stopping test is the relative residual of the gap on the contact set plus
    the absence of penetration outside it.

    Why one function: the algorithm of Polonsky and Keer (1999) as published, one loop whose state (pressure,
    conjugate direction, G, delta) each step updates; written like the paper so that it can be checked against
    it.
    """
    xp = operator.xp
    footprint = xp.isfinite(height)
    target = xp.where(footprint, displacement - height, 0.0)
    if not bool(xp.any(target > 0)):
        zeros = xp.zeros_like(target)
        return Equilibrium(
            displacement=displacement, pressure=zeros, contact=zeros > 0, converged=True,
            reason="no penetration", cg_iterations=0, n_solves=1, trial_force_sum=0.0, detached=0,
            attached=0,
        )
    # The rigid-punch-like guess: a small uniform pressure where the tip penetrates.
    guess = xp.astype(target > 0, xp.float64) * (float(xp.max(target)) / operator.halfspace.diagonal()) * 0.1
    pressure = xp.where(footprint & (pressure > 0), pressure, 0.0)
    if not bool(xp.any(pressure > 0)):
        pressure = guess
    target_norm = math.sqrt(float(xp.sum(target[target > 0] ** 2)))
    direction = xp.zeros_like(pressure)
    # The deflection is tracked, not recomputed: one FFT pair per iteration for
    # the search direction, and one more only in iterations where the
    # projection (p < 0 -> 0) or the joining of overlapping elements changed p.
    deflection = operator.deflection(pressure)
    g_old = 1.0
    reset = True
    relative = math.inf
    for iteration in range(1, max_iterations + 1):
        contact = pressure > 0
        if not bool(xp.any(contact)):
            # A step projected every pressure to zero (a warm start far too
            # high): start again from the guess, which loads the penetration.
            pressure = guess
            deflection = operator.deflection(pressure)
            reset = True
            contact = pressure > 0
        gap = deflection - target  # > 0: separated, < 0: penetrating
        gap_c = xp.where(contact, gap, 0.0)
        g_norm2 = float(xp.sum(gap_c * gap_c))
        relative = math.sqrt(g_norm2) / target_norm
        outside_penetration = bool(xp.any(footprint & ~contact & (gap < -tolerance * target_norm)))
        if relative <= tolerance and not outside_penetration and iteration > 1:
            return Equilibrium(
                displacement=displacement, pressure=pressure, contact=contact, converged=True,
                reason="relative gap residual below tolerance", cg_iterations=iteration - 1, n_solves=1,
                trial_force_sum=float(xp.sum(pressure)), detached=0, attached=0,
            )
        if relative <= tolerance and outside_penetration:
            # S is solved but elements outside it penetrate: the gradient on
            # S vanishes, so no search direction would reach them.  They join
            # with the pressure that closes their own gap (the diagonal), and
            # the iteration restarts on the larger set.
            joining = footprint & ~contact & (gap < -tolerance * target_norm)
            change = xp.where(joining, -gap / operator.halfspace.diagonal(), 0.0)
            pressure = pressure + change
            deflection = deflection + operator.deflection(change)
            reset = True
            continue
        # Preconditioned direction (Vollebregt 2014): z = M^-1 gap on S.
        z = laplacian_preconditioner(contact)(gap_c)
        rz = float(xp.sum(gap_c * z))
        direction = z + (0.0 if reset else rz / g_old) * direction
        direction = xp.where(contact, direction, 0.0)
        g_old = rz
        response_full = operator.deflection(direction)
        denominator = float(xp.sum(direction * response_full))
        if not (denominator > 0):
            return Equilibrium(
                displacement=displacement, pressure=pressure, contact=contact, converged=False,
                reason="search direction lost positivity", cg_iterations=iteration, n_solves=1,
                trial_force_sum=float(xp.sum(pressure)), detached=0, attached=0,
            )
        step = float(xp.sum(gap_c * direction)) / denominator
        moved = pressure - step * direction
        deflection = deflection - step * response_full
        projected = xp.where(moved > 0, moved, 0.0)
        overlap = footprint & (projected <= 0) & (gap < 0)
        reset = bool(xp.any(overlap))
        if reset:
            projected = projected - xp.where(overlap, step * gap, 0.0)
        change = projected - moved
        if bool(xp.any(change != 0)):
            deflection = deflection + operator.deflection(change)
        pressure = projected
    return Equilibrium(
        displacement=displacement, pressure=pressure, contact=pressure > 0, converged=False,
        reason=f"no convergence in {max_iterations} iterations", cg_iterations=max_iterations, n_solves=1,
        trial_force_sum=float(xp.sum(pressure)), detached=0, attached=0,
    )
