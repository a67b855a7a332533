"""Conjugate gradients on a contact set: A_S p = rhs, warm-started, with a typed `SolveResult`."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Protocol

from brushbem import backend

__all__ = ["ROUNDING_FLOOR", "WARM_START_WITHIN_TOLERANCE", "CallableOperator", "ProductLedger", "SetOperator",
           "SolveResult", "conjugate_gradient"]


#: Smallest relative residual ||r|| / ||rhs|| that a CG solve is asked to
#: reach: 16 ulps.  A punch on a spring of k / (2 E* a) = 2e-6 needs 2e-14
#: at tolerance 1e-8 and still gives the stiff spring's F_A to 1e-8
#: (`tests/test_reliability_numerics.py`); below that the recursion's
#: residual drifts from the true one.
ROUNDING_FLOOR = 16 * 2.0**-52

@dataclass
class ProductLedger:
    """The error that single-precision products have left in a chain of kept deflections.

    A solve that keeps its solution's deflection from its own products
    (`brushbem.numerics.solver.block_deflection.BlockDeflection`) hands it to
    the next solve of the same chain (the equilibria of a pull-off, or its
    unit responses) as the product of its warm start, without a transform.
    An error E of a product thus stays in the residual of every later solve
    of the chain, which converges to the residual it is told, not the true
    one, until the deflection is transformed afresh.  ``carried`` bounds the
    2-norm on the contact set of the error the chain carries (units of the
    right-hand side); ``scale`` is the converged residual ||r|| of the
    chain's last solve, the unit of the shares below.  ``conjugate_gradient``
    takes a product in single precision only while ``carried`` stays below
    ``CHAIN_SHARE`` x ``scale``; the solve that leaves it above
    ``REFRESH_SHARE`` x ``scale`` does not keep its deflection
    (`brushbem.numerics.solver.set_solve.solve_on_set`), so that its caller
    transforms it afresh, and the chain starts again from zero.  The two
    chains of the event path exchange deflections (the state on an event's
    threshold adds the displacement step times the unit response's, the
    unit guess takes the cascade's change), so each carries at most its own
    share and, scaled so, the other's.
    """

    carried: float = 0.0
    scale: float = 0.0

    def admits(self, scale: float) -> bool:
        """Whether a solve that converges to the residual ``scale`` may start from the chain's kept deflection.

        The chain's converged residuals can fall by orders of magnitude from
        one solve to the next (a soft brush whose springs take over the
        right-hand side): an error that was a small share of the last one
        may exceed the next solve's whole tolerance.
        """
        return self.carried <= CHAIN_SHARE * scale

    def due(self) -> bool:
        """Whether the chain's next kept deflection must be transformed afresh (and the ledger cleared)."""
        return self.carried > REFRESH_SHARE * self.scale


#: Most that one single-precision product may add to a chain's error, as a share of the solve's
#: converged residual: a product is single only once the residual has fallen that far below the
#: right-hand side (the last one or two iterations of a warm-started solve).
PRODUCT_SHARE = 0.002
#: Most error a chain of kept deflections may carry, as a share of the converged residual.
CHAIN_SHARE = 0.03
#: Carried error beyond which the chain's next kept deflection is transformed afresh (below
#: ``CHAIN_SHARE`` by more than a product's share, so that the products stay single until then).
REFRESH_SHARE = 0.02

#: SolveResult.reason when the warm start already met the tolerance (solution = initial on the mask).
WARM_START_WITHIN_TOLERANCE = "initial guess within tolerance"


@dataclass(frozen=True)
class SolveResult:
    """Outcome of one linear solve.

    Attributes
    ----------
    solution : ndarray
        The pressure (zero outside the set), in units of stress.
    converged : bool
    reason : str
        Why the iteration stopped.
    iterations : int
    residual : float
        Final relative residual ||rhs - A x|| / ||rhs|| on the set.
    residual_history : tuple of float
        Relative residual after every iteration (first entry: initial guess).
    """

    solution: object
    converged: bool
    reason: str
    iterations: int
    residual: float
    residual_history: tuple[float, ...]


def _dot(xp, a, b) -> float:
    # Not a matrix product: BLAS threads its dot products of this size, which
    # was 5x slower in total on a busy 2-core machine and not reproducible.
    return float(xp.sum(a * b))


class SetOperator(Protocol):
    """What CG needs of an operator: A_S on the set ``mask``, in the namespace ``xp``.

    ``apply(x)`` is A_S x for x zero outside the mask and is zero outside the
    mask itself (`brushbem.numerics.operator.MaskedOperator` on a window's arrays,
    `brushbem.numerics.operator.ContactSystem` on the |S| values of S).
    """

    mask: Any
    xp: Any

    def apply(self, x: Any) -> Any: ...


@dataclass(frozen=True)
class CallableOperator:
    """A `SetOperator` from a function: ``apply(x) -> A_S x`` on ``mask`` (namespace ``xp``, default: NumPy's)."""

    function: Callable[[Any], Any]
    mask: Any
    xp: Any = None

    def apply(self, x: Any) -> Any:
        return self.function(x)


def conjugate_gradient(
    operator: SetOperator,
    rhs,
    *,
    initial=None,
    initial_product=None,
    preconditioner=None,
    tolerance: float = 1e-8,
    max_iterations: int = 10000,
    reference=None,
    on_step=None,
    inexact: float | None = None,
    ledger: ProductLedger | None = None,
) -> SolveResult:
    """Preconditioned CG for A_S x = rhs on the set S of ``operator``.

    Parameters
    ----------
    operator : SetOperator
        ``operator.apply(x) -> A_S x`` for x zero outside ``operator.mask``
        (the set S), zero outside it; ``operator.xp`` its namespace (None:
        the namespace of ``rhs``).
    rhs : ndarray
        Right-hand side (only the entries on S matter).
    initial : ndarray, optional
        Warm start (restricted to the mask).
    tolerance : float
        Target relative residual.
    max_iterations : int
    preconditioner : callable, optional
        ``preconditioner(r) -> M^-1 r``, symmetric positive definite on S.
    initial_product : ndarray, optional
        The operator applied to ``initial`` (only its masked entries are
        used), when the caller knows it: saves the first ``apply``.
    reference : callable, optional
        ``reference(x) -> float``: the norm the residual must be small
        against, when that is not ||rhs||.  A spring-mounted indenter's rhs
        is mostly the springs' deflection, while the pressure the criterion
        reads is set by the half-space's part, ||rhs - S x|| (S the spring
        sums): a residual of ``tolerance`` x ||rhs|| can leave that part
        unsolved.  Checked (it is cheap: no transform) each time the residual
        passes ``tolerance`` x ||rhs||; the iteration then goes on until
        ||r|| <= ``tolerance`` x ``reference(x)``.  When that is below what
        double precision resolves against ||rhs|| (``ROUNDING_FLOOR`` x
        ||rhs||), the solve stops not converged, saying so.
    on_step : callable, optional
        ``on_step(step)`` after every update x += step * direction, the
        direction being the last vector ``operator.apply`` was given: lets
        the operator keep a product of x in step with x.
    inexact, ledger : float and ProductLedger, optional
        With both, and an operator with ``apply_single`` (A_S with
        single-precision transforms, of relative error at most ``inexact``),
        an iteration takes its product in single precision when the error
        that adds, |step| ``inexact`` ||A d|| (predicted as 2 ``inexact``
        ||r||, the residual's fall), is at most ``PRODUCT_SHARE`` of the
        residual the solve converges to and keeps the error the chain
        carries below ``CHAIN_SHARE`` of it (`ProductLedger`; the residual
        measured by the reference norm at the current iterate): the late
        iterations of a warm-started solve, whose products only refine what
        the early ones found, may be inexact in proportion to how small the
        residual already is (relaxed inexact Krylov methods: Simoncini and
        Szyld, SIAM J. Sci. Comput. 25, 2003, 454-477).  The solution is the
        one of double-precision products to within that share of the
        tolerance.

    Why one function: the iteration and its stopping tests (tolerance, reference norm, rounding floor,
    stagnation, limit) share the state x, r, z, p and the norms of every step; split, each piece would take
    and return them all.
    """
    apply, mask, xp = operator.apply, operator.mask, operator.xp
    if xp is None:
        from brushbem.backend import namespace

        xp = namespace(rhs)
    maskf = xp.astype(mask, rhs.dtype)
    rhs = rhs * maskf
    rhs_norm = math.sqrt(_dot(xp, rhs, rhs))
    if rhs_norm == 0.0:
        return SolveResult(xp.zeros_like(rhs), True, "zero right-hand side", 0, 0.0, (0.0,))
    x = xp.zeros_like(rhs) if initial is None else initial * maskf
    if initial is None:
        residual = rhs
    elif initial_product is not None:
        residual = rhs - initial_product * maskf
    else:
        residual = rhs - apply(x)
    relative = math.sqrt(_dot(xp, residual, residual)) / rhs_norm
    history = [relative]
    # The residual ||r|| / ||rhs|| that counts as converged: lowered when the
    # reference norm asks for more (and then never raised again).
    threshold = tolerance

    def accepted(x) -> SolveResult | bool:
        """True when the reference agrees; a not-converged result when it cannot be met."""
        nonlocal threshold
        if reference is None:
            return True
        wanted = tolerance * float(reference(x)) / rhs_norm
        if wanted >= relative:
            return True
        if wanted < ROUNDING_FLOOR:
            return SolveResult(x, False, (
                f"double precision cannot resolve the half-space's part of the solve: it is "
                f"{wanted / tolerance:.2g} of the right-hand side (the springs' deflection carries the rest), "
                f"so a relative residual of {tolerance:g} on it is below rounding; use stiffer springs, a "
                f"larger LoadPath.tolerance, or a load-controlled model"), 0, relative, tuple(history))
        threshold = wanted
        return False

    if relative <= threshold:
        verdict = accepted(x)
        if verdict is True:
            return SolveResult(x, True, WARM_START_WITHIN_TOLERANCE, 0, relative, tuple(history))
        if isinstance(verdict, SolveResult):
            return verdict
    # x, residual and direction are private arrays from here on (residual may
    # be the masked copy of rhs) and are updated in place: fewer temporaries
    # matter on the small blocks the solves run on.
    direction = residual * maskf if preconditioner is None else preconditioner(residual) * maskf
    # On a device, one host copy per iteration: the residual norm and the curvature, together; every
    # other scalar stays there.  On the host the scalars are Python floats (0-d arrays cost about 15 us
    # an iteration, 8 % of a small window's solve).  A curvature that is not positive ends the solve with
    # x as it was: on the host before the step, on the device through a step of 0.
    host = backend.is_numpy_namespace(xp)
    rz = _dot(xp, residual, direction) if host else xp.sum(residual * direction)
    single_apply = getattr(operator, "apply_single", None) if host and inexact and ledger is not None else None
    if single_apply is not None:
        # The residual the solve converges to (tolerance x the smaller of the two norms it is measured by).
        ledger.scale = tolerance * min(rhs_norm, float(reference(x)) if reference is not None else rhs_norm)
    for iteration in range(1, max_iterations + 1):
        single = False
        if single_apply is not None:
            added = 2.0 * inexact * relative * rhs_norm
            single = _affords(ledger, added)
            if single and reference is not None:
                # The half-space part at this iterate, not at the start: a cold start's is far larger than
                # the solution's where springs carry most of the right-hand side.
                halfspace = float(reference(x))
                ledger.scale = tolerance * min(rhs_norm, halfspace)
                single = _affords(ledger, added)
        a_direction = single_apply(direction) if single else apply(direction)
        if host:
            curvature = _dot(xp, direction, a_direction)
            if not (curvature > 0.0) or not math.isfinite(curvature):
                return _not_positive(x, curvature, iteration, relative, history)
            step = rz / curvature
        else:
            curvature = xp.sum(direction * a_direction)
            positive = curvature > 0.0
            step = xp.where(positive, rz / xp.where(positive, curvature, 1.0), 0.0)
        x += step * direction
        if on_step is not None:
            on_step(step)
        if single:
            ledger.carried += inexact * abs(step) * _norm(xp, a_direction)
        residual -= step * a_direction
        if host:
            squared = _dot(xp, residual, residual)
        else:
            squared, curvature = (float(v) for v in backend.to_numpy(xp.stack([xp.sum(residual * residual),
                                                                                curvature])))
        if not (curvature > 0.0) or not math.isfinite(curvature):  # the device's step was 0: x is unchanged
            return _not_positive(x, curvature, iteration, relative, history)
        relative = math.sqrt(squared) / rhs_norm
        history.append(relative)
        if not math.isfinite(relative):
            return SolveResult(x, False, "non-finite residual", iteration, relative, tuple(history))
        if relative <= threshold:
            verdict = accepted(x)
            if verdict is True:
                return SolveResult(x, True, "relative residual below tolerance", iteration, relative,
                                   tuple(history))
            if isinstance(verdict, SolveResult):
                return dataclasses.replace(verdict, iterations=iteration)
        z = residual * maskf if preconditioner is None else preconditioner(residual) * maskf
        rz_next = _dot(xp, residual, z) if host else xp.sum(residual * z)
        direction *= rz_next / rz
        direction += z
        rz = rz_next
    return SolveResult(
        x, False, f"no convergence in {max_iterations} iterations", max_iterations, relative, tuple(history)
    )


def _affords(ledger: ProductLedger, added: float) -> bool:
    """Whether a single-precision product that adds ``added`` to the chain's error fits its shares."""
    return added <= PRODUCT_SHARE * ledger.scale and ledger.carried + added <= CHAIN_SHARE * ledger.scale


def _not_positive(x, curvature: float, iteration: int, relative: float, history: list[float]) -> SolveResult:
    """The not-converged result of a direction whose curvature is not positive (x before the step)."""
    reason = ("the operator is not positive definite on the contact set" if math.isfinite(curvature)
              else "non-finite values in the iteration")
    return SolveResult(x, False, reason, iteration, relative, tuple(history))


def _norm(xp, values) -> float:
    return math.sqrt(_dot(xp, values, values))
