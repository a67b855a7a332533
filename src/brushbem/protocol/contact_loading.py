"""The loading branch of a brush pressed as non-adhesive contact problems (`_contact_loading`).

A brush whose tips are not all level is pressed by a few Polonsky-Keer
solves at sampled displacements (or along the search for a preload force)
instead of one global solve per element that joins; the samples are checked
to be nested (`_nested_prefix`), and where they are not the path goes on by
element events (`brushbem.protocol.paths`).  Every sample is a step from the
path's state (`brushbem.protocol.steps.solve_from`) and keeps the state it
gave.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from brushbem import settings
from brushbem.numerics.solver import Equilibrium
from brushbem.protocol.path_states import _eq_state, record_state, total_force
from brushbem.protocol.problem import LoadPath
from brushbem.protocol.steps import PathContext, solve_from, without_deflections
from brushbem.protocol.values import PathState

#: Displacements at which `_contact_loading` samples the loading branch besides
#: those of the search for a preload force (evenly spaced from first touch).
LOADING_SAMPLES = 4

#: An element of an earlier sample that a later one has left counts as
#: released when its gap there exceeds this fraction of the indentation depth
#: (the solver's accuracy: one that just touches has a gap of rounding size).
_RELEASE_GAP = 1e-6


@dataclass(frozen=True)
class _Sample:
    """One contact-problem solution on the loading branch (full-grid arrays) and the path's state after it."""

    displacement: float
    force: float
    pressure: object
    contact: object
    eq: Equilibrium
    state: PathState


def _press_as_contact_problems(context: PathContext, state: PathState) -> bool:
    """Whether the loading branch goes by `_contact_loading`: a brush whose tips are not all level.

    A brush of level tips (no roughness, profile or length offsets) touches
    with every footprint element at once, and its element-event loading is
    a single event: the contact problems would only cost more.
    """
    if context.n_pillars < 2:
        return False
    indenter = state.working.problem.indenter
    heights = np.asarray(indenter.height)[np.asarray(indenter.footprint)]
    lowest = float(heights.min())
    return float(heights.max()) - lowest > 1e-12 * max(abs(lowest), 1.0)


def _contact_loading(context: PathContext, state: PathState, path: LoadPath):
    """The loading branch of a brush as non-adhesive contact problems.

    While the base presses, an element joins S where the tip touches, at
    zero pressure, and the event path's state at d is the equilibrium on
    every element that has touched so far.  As long as no element of S
    would have turned tensile (its neighbours' compression lifting it off
    again), every pressure of that state is >= 0 and every gap outside >= 0:
    it solves the non-adhesive contact problem at d, whose solution is
    unique (a convex complementarity problem).  So the whole loading branch
    that the event path follows element event by element (one global solve
    per element: ~40 per pillar of 3.6 elements' radius) is given by
    Polonsky-Keer solutions, a few constrained CG solves in all.

    The premise is checked on the samples: every contact set must hold the
    sets of the smaller displacements sampled before it (an element that a
    larger displacement releases - a gap opening by more than
    ``_RELEASE_GAP`` of the indentation depth - would have been held in
    tension by the event path).  Samples: ``LOADING_SAMPLES`` evenly spaced
    displacements up to a preload displacement, or the iterates of the
    search for a preload force (false position on the piecewise linear,
    increasing F(d); exact by interpolation once both ends of the bracket
    have the same contact set).  Where the check fails, the branch goes on
    from the last sample before it by element events (the states up to it
    are the event path's).

    Yields the loading states in increasing d; returns (the state at the
    end, its d, whether the preload is reached) or None when a solve failed.
    """
    xp = context.xp
    problem = state.working.problem
    lowest = problem.indenter.lowest_height
    samples: list[_Sample] = []
    cost = [0, 0]  # solves, iterations of the samples not yet yielded

    def solve_at(d: float, start: _Sample | None, latest: PathState) -> _Sample:
        """The contact problem at ``d`` from ``start``'s pressure and contact (none: from no contact), on the
        window of ``latest`` (the state of the last sample solved)."""
        if start is None:
            latest = latest.replace(pressure=xp.zeros_like(latest.pressure), contact=xp.zeros_like(latest.contact),
                                    deflection=None)
        else:
            latest = latest.replace(pressure=start.pressure, contact=start.contact, deflection=None)
        after, eq = solve_from(context, latest, d, contact_problem=True)
        cost[0] += eq.n_solves
        cost[1] += eq.cg_iterations
        sample = _Sample(d, total_force(context, after), after.pressure, after.contact, eq, after)
        if not eq.converged:
            return sample
        samples.append(sample)
        return sample

    final = None
    if path.preload_displacement is not None:
        target = path.preload_displacement
        previous = None
        for j in range(1, LOADING_SAMPLES + 1):
            d = target if j == LOADING_SAMPLES else lowest + (target - lowest) * j / LOADING_SAMPLES
            previous = solve_at(d, previous, state if previous is None else previous.state)
            if not previous.eq.converged:
                yield _eq_state(context, previous.state, previous.eq, True)
                return None
        final, state = previous, previous.state
    else:
        outcome = yield from _contact_preload_force(context, state, path, solve_at, lowest)
        if outcome is None:
            return None
        final, state = outcome

    # The path ends at the preload: samples beyond it (the search's upper ends) are not on it.
    samples = [sample for sample in samples if sample.displacement < final.displacement] + [final]
    samples.sort(key=lambda sample: sample.displacement)
    accepted = _nested_prefix(state, samples, lowest)
    for k, sample in enumerate(accepted):
        state = state.replace(pressure=sample.pressure, contact=sample.contact, deflection=None)
        last = k == len(accepted) - 1
        solves, iterations = (cost[0], cost[1]) if last else (sample.eq.n_solves, sample.eq.cg_iterations)
        if not last:
            cost[0] -= solves
            cost[1] -= iterations
        reason = "contact problem" if len(accepted) == len(samples) or not last else (
            "contact problem; element events from here (a larger displacement releases an element)")
        yield record_state(context, state, sample.displacement, True, "equilibrium", total_force(context, state),
                           iterations, solves, True, reason)
    state = without_deflections(context, state)
    end = accepted[-1]
    if end is final or len(accepted) == len(samples):
        return state, end.displacement, True
    return state, end.displacement, False


def _contact_preload_force(context: PathContext, state: PathState, path: LoadPath, solve_at, lowest: float):
    """The contact problem at which the loading force reaches ``path.preload_force`` (a `_Sample`), and the state of
    the last sample solved (the interpolated one's, where the search ends between two), or None.

    F(d) of the non-adhesive problem is continuous, increasing and piecewise
    linear (affine while the contact set stays).  Below the target the next
    displacement is the independent pillars' (`_IndependentPillars`) for the
    target force plus the displacement their elastic interaction adds,
    extrapolated from the samples (proportional to the force from one
    sample, affine in it from two); then the Illinois variant of false
    position, until F is within 1e-9 of the target (the event path's test)
    or both ends of the bracket have the same contact set - then the state
    at the target is their exact interpolation.  (A secant of F itself from
    the first touch overshot the chapter-5 brush's preload seven-fold: F is
    convex where pillars join.)
    """
    xp = context.xp
    problem = state.working.problem
    target = path.preload_force
    model = _IndependentPillars(problem.indenter, problem.contact_modulus, context.h2)
    lo = hi = None  # samples below and above the target
    interaction: list[tuple[float, float]] = []  # (F, d - the independent pillars' d at F) below the target
    lo_points = [(lowest, 0.0)]  # (d, F) below the target, for the secant without the preload model
    f_lo = f_hi = 0.0  # residuals F - target at the ends, halved by the Illinois rule
    side = 0
    d = model.displacement(target) if settings.switches().preload_model else lowest + target * model.punch_compliance
    start = None
    for _ in range(200):
        sample = solve_at(d, start, state)
        state = sample.state
        if not sample.eq.converged:
            yield _eq_state(context, state, sample.eq, True)
            return None
        start = sample
        residual = sample.force - target
        if abs(residual) <= 1e-9 * target:
            return sample, state
        if residual > 0:
            hi, f_hi = sample, residual
            if side > 0:
                f_lo *= 0.5
            side = 1
        else:
            lo, f_lo = sample, residual
            lo_points.append((sample.displacement, sample.force))
            if sample.force > 0:
                interaction.append((sample.force, sample.displacement - model.displacement(sample.force)))
            if side < 0:
                f_hi *= 0.5
            side = -1
        if hi is None:
            if not settings.switches().preload_model:  # the secant of the last two points
                (d0, g0), (d1, g1) = lo_points[-2], lo_points[-1]
                step = (target - g1) * (d1 - d0) / (g1 - g0) if g1 > g0 else 2.0 * (d1 - lowest)
                d = d1 + max(step, 1e-3 * (d1 - lowest))
                continue
            # Below the target: the independent pillars' displacement plus the interaction's, extrapolated.
            if not interaction:
                d = lowest + 2.0 * (sample.displacement - lowest)
                continue
            f1, e1 = interaction[-1]
            if len(interaction) > 1 and interaction[-2][0] < f1:
                f0, e0 = interaction[-2]
                extra = e1 + (target - f1) * (e1 - e0) / (f1 - f0)
            else:
                extra = e1 * target / f1
            d = max(model.displacement(target) + extra, sample.displacement + 1e-3 * (sample.displacement - lowest))
            continue
        if lo is None:
            d = lowest + 0.5 * (hi.displacement - lowest)
            continue
        if bool(xp.all(lo.contact == hi.contact)):
            # One contact set at both ends: F and p are affine in between.
            theta = (target - lo.force) / (hi.force - lo.force)
            d = lo.displacement + theta * (hi.displacement - lo.displacement)
            pressure = lo.pressure + theta * (hi.pressure - lo.pressure)
            state = state.replace(pressure=pressure, contact=hi.contact, deflection=None)
            eq = dataclasses.replace(hi.eq, n_solves=0, cg_iterations=0)
            return _Sample(d, total_force(context, state), pressure, hi.contact, eq, state), state
        width = hi.displacement - lo.displacement
        if width <= 4 * np.finfo(float).eps * abs(hi.displacement):
            return hi, state
        d = lo.displacement - f_lo * width / (f_hi - f_lo)
    yield record_state(context, state, d, True, "equilibrium", total_force(context, state), 0, 0, False,
                       "the search for the preload force did not converge in 200 contact problems")
    return None


class _IndependentPillars:
    """F(d) of a brush's pillars pressed each on its own: the preload search's model of the loading branch.

    Pillar i touches at the height h_i of its lowest element and then pushes
    with k_i (d - h_i), k_i the flat punch of its footprint's area
    (2 E* a_i) in series with its own spring; the springs of the levels above
    it (shared by clusters) are one spring of their summed stiffness in
    series with the whole brush.  The half-space's coupling of the pillars
    is left out: it is what the search learns from its samples.
    """

    def __init__(self, indenter, contact_modulus: float, h2: float):
        n = indenter.n_pillars
        labels = indenter.pillar[indenter.footprint]
        heights = np.full(n, np.inf)
        np.minimum.at(heights, labels, indenter.height[indenter.footprint])
        counts = np.bincount(labels, minlength=n)
        compliance = 1.0 / (2.0 * contact_modulus * np.sqrt(counts * h2 / math.pi))
        self.series = 0.0
        every_level = 0.0  # each level's springs in parallel, the levels in series
        for level in indenter.elastic_levels:
            every_level += 1.0 / float(np.sum(level.stiffnesses))
            if level.n_clusters == n:
                compliance = compliance + 1.0 / level.stiffnesses[level.cluster]
            else:
                self.series += 1.0 / float(np.sum(level.stiffnesses))
        # The whole footprint as one punch on the springs in series (the first guess without the preload model).
        area = float(np.sum(counts)) * h2
        self.punch_compliance = 1.0 / (2.0 * contact_modulus * math.sqrt(area / math.pi)) + every_level
        order = np.argsort(heights)
        self.heights = heights[order]
        stiffness = 1.0 / compliance[order]
        self.slopes = np.cumsum(stiffness)  # dF/dd with the first j + 1 pillars touching
        self.offsets = np.cumsum(stiffness * self.heights)
        # F where pillar j + 1 touches: every pillar up to j pushing at d = h_(j+1).
        self.forces = self.slopes[:-1] * self.heights[1:] - self.offsets[:-1]

    def displacement(self, force: float) -> float:
        """The base displacement at which the independent pillars carry ``force`` (> 0)."""
        j = int(np.searchsorted(self.forces, force))
        return float((force + self.offsets[j]) / self.slopes[j]) + self.series * force


def _nested_prefix(state: PathState, samples: list, lowest: float) -> list:
    """The samples (increasing d) up to the first whose contact set does not hold an earlier one's."""
    xp = state.working.problem.xp
    accepted = samples[:1]
    union = samples[0].contact
    for sample in samples[1:]:
        released = union & ~sample.contact
        if bool(xp.any(released)):
            gap = -state.working.full_penetration(sample.displacement, sample.pressure)
            depth = max(sample.displacement - lowest, 1e-300)
            if bool(xp.any(released & (gap > _RELEASE_GAP * depth))):
                break
        accepted.append(sample)
        union = union | sample.contact
    return accepted
