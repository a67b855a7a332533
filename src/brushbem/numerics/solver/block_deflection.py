"""CG's operator on the pillar blocks that keeps the iterate's tip deflection on the whole window in step.

Its own module so that a CG iteration goes down, never back up: `solve_on_set`
(`brushbem.numerics.solver.set_solve`) builds it and hands it to
`brushbem.numerics.solver.cg.conjugate_gradient`, whose products go through it to the
`brushbem.numerics.operator.ContactSystem`.
"""

from __future__ import annotations

__all__ = ["BlockDeflection"]


class BlockDeflection:
    """A `ContactSystem` as CG's operator, keeping K x on the whole window in step with CG's iterate x.

    The caller of the solve wants the tip deflection of the solution on the
    whole window next (the attachments it predicts, the join check of an
    equilibrium): a transform of the solution.  Here every product of CG
    gives K v on the whole window instead of on S only (`ContactSystem.apply_block`:
    the inverse transforms along the rows of the window, not of S), and the
    product of the last direction is added, times the step, to K x
    (``moved``, CG's ``on_step``): the deflection of x without a transform.
    It starts from K x0: zero for a cold start, or CG's first product (that
    of x0) when no product of the start was given; with a given one (the
    start's tip deflection) it sums K (x - x0) and adds it to that.
    """

    def __init__(self, system, initial_on_set, initial_product):
        self.system = system
        self.mask = system.mask
        self.xp = system.xp
        xp = system.xp
        self._start = None  # (x0 on S, tip deflection of x0 on the window) when given
        self._last = None
        if initial_on_set is None:
            self._product = xp.zeros(system.shape, dtype=xp.float64)
        elif initial_product is None:
            self._product = None  # CG's first product is K x0
        else:
            self._product = xp.zeros(system.shape, dtype=xp.float64)
            self._start = (initial_on_set, initial_product)

    def apply(self, values):
        return self._apply(values, False)

    def apply_single(self, values):
        """`apply` with single-precision transforms (`ContactSystem.apply_block`'s ``single``)."""
        return self._apply(values, True)

    def _apply(self, values, single: bool):
        out, whole = self.system.apply_block(values, single)
        if self._product is None:
            self._product = whole
        else:
            self._last = whole
        return out

    def moved(self, step: float) -> None:
        last = self._last
        last *= step
        self._product += last

    def tip_deflection(self, solution_on_set):
        """K x + springs(x) on the window for CG's solution x (on S), or None where it is not known."""
        system = self.system
        xp = self.xp
        if not bool(xp.any(solution_on_set != 0)):
            # Also the end of a zero right-hand side: CG returns 0 there, whatever x0 was.
            return xp.zeros(system.shape, dtype=xp.float64)
        if self._product is None:
            return None
        springs = system.operator.springs
        if self._start is None:
            deflection = self._product
            moved = solution_on_set
        else:
            x0, deflection = self._start
            deflection = deflection + self._product
            moved = solution_on_set - x0
        if springs:
            deflection = deflection + springs.apply(system.scatter(moved))
        return deflection
