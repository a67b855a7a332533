"""The nested-loop method of thesis chapter 2, kept as an independent check.

A single rigid pillar hangs on a spring of stiffness k.  At base displacement d
the pillar tip sits at u0 = d - dl, dl the spring's deflection.  The outer loop
corrects dl until the spring force k dl equals the contact force h^2 sum p of
the rigid indentation at u0 (thesis sec. 2.2.1, Fig. 2-2, secant corrections);
then elements beyond the critical tension detach, penetrating ones attach, and
the balance is found again, until the contact set is stable (Fig. 2-3).

It solves the same equations as the coupled operator A = K + (h^2/k) P^T P
(``brushbem.numerics.operator``), by a different route; tests compare the two.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from brushbem.numerics.operator import ContactOperator, MaskedOperator
from brushbem.numerics.solver import conjugate_gradient

__all__ = ["NestedBrushResult", "NestedLoopResult", "nested_loop_brush_equilibrium", "nested_loop_equilibrium"]


@dataclass(frozen=True)
class NestedLoopResult:
    """Equilibrium found by the nested loop.

    Attributes
    ----------
    pressure, contact : ndarray
        On the operator's window.
    spring_deflection : float
        dl, in units of length.
    converged : bool
    reason : str
    balance_iterations : int
        Outer (position-correction) iterations, all rounds together.
    cg_iterations : int
    """

    pressure: object
    contact: object
    spring_deflection: float
    converged: bool
    reason: str
    balance_iterations: int
    cg_iterations: int


def nested_loop_equilibrium(
    rigid_operator: ContactOperator,
    height,
    displacement: float,
    stiffness: float,
    contact,
    pressure,
    critical: float,
    tolerance: float = 1e-10,
    max_balance: int = 200,
    max_rounds: int = 10000,
) -> NestedLoopResult:
    """Equilibrium of one pillar on a spring by position correction.

    Parameters
    ----------
    rigid_operator : ContactOperator
        The half-space operator without springs (a rigid indenter's).
    height : ndarray
        Tip heights on the operator's window (inf outside the footprint).
    displacement : float
        Base displacement d.
    stiffness : float
        Spring stiffness k (finite, > 0).
    contact, pressure : ndarray
        Starting contact set and pressure (history).
    critical : float
        Sigma_c (0: no adhesion).
    tolerance : float
        Relative tolerance of the force balance and of every CG solve.

    This is `nested_loop_brush_equilibrium` with one pillar: the same secant
    corrections of the pillar position, started by a Newton step with the
    punch stiffness of the contact.

    Why these parameters: the thesis's nested loop (sec. 3.2) is kept as an independent reference for the
    coupled operator, with the arguments the thesis's algorithm takes; it is not on any production path.
    """
    xp = rigid_operator.xp
    one_pillar = xp.where(xp.isfinite(height), 0, -1)
    result = nested_loop_brush_equilibrium(
        rigid_operator, one_pillar, height, displacement, stiffness, contact, pressure, critical,
        tolerance=tolerance, max_balance=max_balance, max_rounds=max_rounds,
    )
    return NestedLoopResult(
        result.pressure, result.contact, float(result.spring_deflection[0]), result.converged, result.reason,
        result.balance_iterations, result.cg_iterations,
    )


@dataclass(frozen=True)
class NestedBrushResult:
    """Equilibrium of many pillars found by per-pillar position correction.

    Attributes
    ----------
    pressure, contact : ndarray
        On the operator's window.
    spring_deflection : ndarray, shape (M,)
        dl_n of every pillar, in units of length.
    converged : bool
    reason : str
    balance_iterations, cg_iterations : int
    """

    pressure: object
    contact: object
    spring_deflection: object
    converged: bool
    reason: str
    balance_iterations: int
    cg_iterations: int


def nested_loop_brush_equilibrium(
    rigid_operator: ContactOperator,
    pillar,
    height,
    displacement: float,
    stiffness: float,
    contact,
    pressure,
    critical: float,
    tolerance: float = 1e-10,
    max_balance: int = 500,
    max_rounds: int = 10000,
) -> NestedBrushResult:
    """The nested loop extended to a brush: one position correction per pillar.

    Every pillar n sits at u_n = d - dl_n.  The outer loop corrects all dl_n
    together until every spring force k dl_n equals that pillar's contact force
    h^2 sum_n p of the rigid indentation with the pillars at their current
    positions (the chapter-2 idea applied pillar by pillar, thesis sec. 3.3
    Fig. 3-5).  Each pillar's correction is a secant step on its own force
    mismatch; the pillars interact through the half-space, which the
    per-pillar steps ignore, so the iteration converges linearly rather than
    superlinearly.  Detachment and attachment then follow as in
    `nested_loop_equilibrium`.

    Parameters
    ----------
    rigid_operator : ContactOperator
        Half-space operator without springs.
    pillar : ndarray of int
        Pillar index of every window element (-1 outside the footprints).
    height : ndarray
        Tip heights on the window (inf outside the footprints).
    displacement, stiffness, contact, pressure, critical, tolerance
        As for `nested_loop_equilibrium`; ``stiffness`` is every pillar's k.

    Why these parameters: as `nested_loop_equilibrium`, the thesis's algorithm with its own arguments, kept
    independent of the solver it checks.
    """
    if rigid_operator.has_springs:
        raise ValueError("the nested loop needs the rigid (spring-free) operator")
    if not (math.isfinite(stiffness) and stiffness > 0):
        raise ValueError(f"stiffness = {stiffness} must be finite and > 0")
    xp = rigid_operator.xp
    h = rigid_operator.halfspace.element_size
    h2 = h * h
    labels = np.asarray(pillar)
    n_pillars = int(labels.max()) + 1
    flat = np.where(labels >= 0, labels, n_pillars).ravel()
    footprint = xp.isfinite(height)
    contact = contact & footprint
    pressure = xp.where(contact, pressure, 0.0)

    def forces(p):
        return h2 * np.bincount(flat, weights=np.asarray(p).ravel(), minlength=n_pillars + 1)[:n_pillars]

    deflection = forces(pressure) / stiffness
    balance = cg_total = 0
    for _ in range(max_rounds):
        if bool(xp.any(contact)):
            previous = None
            for _inner in range(max_balance):
                tip = displacement - deflection[np.maximum(labels, 0)]
                rhs = xp.where(contact, tip - height, 0.0)
                result = conjugate_gradient(MaskedOperator(rigid_operator, contact), rhs,
                                            initial=pressure, tolerance=tolerance, max_iterations=20000)
                cg_total += result.iterations
                balance += 1
                if not result.converged:
                    return NestedBrushResult(result.solution, contact, deflection, False, result.reason,
                                             balance, cg_total)
                pressure = result.solution
                force = forces(pressure)
                mismatch = force - stiffness * deflection
                length = max(abs(displacement), h)
                scale = max(float(np.max(np.abs(force))), stiffness * float(np.max(np.abs(deflection))),
                            stiffness * length)
                if float(np.max(np.abs(mismatch))) <= 100 * tolerance * scale:
                    break
                if previous is None:
                    # First step: Newton with the punch stiffness 2 E* a of each pillar's contact.
                    counts = np.bincount(flat, weights=np.asarray(contact, dtype=float).ravel(),
                                         minlength=n_pillars + 1)[:n_pillars]
                    contact_stiffness = 2 * rigid_operator.halfspace.contact_modulus * np.sqrt(counts * h2 / math.pi)
                    step = mismatch / (stiffness + contact_stiffness)
                else:
                    change = deflection - previous[0]
                    moved = np.abs(change) > 0
                    slope = np.where(moved, (mismatch - previous[1]) / np.where(moved, change, 1.0), -stiffness)
                    step = -mismatch / np.where(slope < 0, slope, -stiffness)
                previous = (deflection, mismatch)
                deflection = deflection + step
            else:
                return NestedBrushResult(pressure, contact, deflection, False,
                                         f"force balance not reached in {max_balance} corrections", balance, cg_total)
        else:
            pressure = xp.zeros_like(height)
            deflection = np.zeros(n_pillars)
        leaving = contact & ((pressure < -critical) if critical > 0 else (pressure < 0))
        if bool(xp.any(leaving)):
            contact = contact & ~leaving
            pressure = xp.where(contact, pressure, 0.0)
            continue
        tip = displacement - deflection[np.maximum(labels, 0)]
        reach = tip - height - rigid_operator.halfspace_deflection(pressure)
        slack = 10 * tolerance * max(abs(displacement), 1e-300)
        joining = footprint & ~contact & (reach > slack)
        if bool(xp.any(joining)):
            contact = contact | joining
            continue
        return NestedBrushResult(pressure, contact, deflection, True, "contact set stable", balance, cg_total)
    return NestedBrushResult(pressure, contact, deflection, False, "contact set did not stabilise", balance, cg_total)
