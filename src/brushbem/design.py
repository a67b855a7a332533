"""Design for equal load sharing: pillar lengths (or stiffnesses) with which a brush detaches all at once.

Equal load sharing (ELS, thesis eq. 7.4) is every pillar at its own pull-off
force at the same moment: F_A = sum_n F_K,n, F~ = 1.  For prescribed pillar
forces the rest is linear, so the design is computed directly:

1. **Prescribed forces.**  Every pillar carries the tension F_n = -F_K,n
   (Kendall's force at the radius of its rasterised footprint).  The
   flat tips are rigid, so the surface under pillar n moves by one amount
   w_n: the pressure p minimises the elastic energy 1/2 p^T K p under the
   constraints "the pressure of pillar n sums to F_n", whose Lagrange
   multipliers are the w_n.  It is solved by conjugate gradients projected on
   those constraints (`prescribed_force_state`): every iteration is one
   half-space transform, nothing is approximated.
2. **Lengths.**  The gap of an element of pillar n is g_n + s_n + u - d
   (g: the tip's offset, s: the springs' compression, u = K p); in contact
   with u = w_n it vanishes, so g_n = d - s_n - w_n, shifted so that min g =
   0.  (Stiffnesses instead: keep the offsets, and give pillar n the spring
   k_n = F_n / (d - g_n - w_n - s_n,above) with d chosen so that the mean
   stiffness is the configured one.)
3. **Corrective pull-offs.**  The prescribed-force state equalises the
   pillars' forces, not exactly their edge stresses, which decide the mesh
   criterion, where the verification's loading history differs.  A full
   pull-off (the event path) gives the displacement d_n at which every
   pillar's tension peaked; a pillar that peaks early (d_n above the median)
   is lengthened by the difference (its whole curve shifts with its offset),
   and the pull-off is repeated, up to `iterations` times, while some pillar
   peaks apart from the rest; the best verified F~ is kept.

The design is deterministic: the same configuration gives the same offsets to
rounding.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from brushbem.physics import theory
from brushbem.physics.halfspace import HalfSpace
from brushbem.protocol import ContactProblem, LoadPath, record_pull_off
from brushbem.results.mapping import MappingRecord
from brushbem.physics.structure import BrushGeometry, Indenter, SpringLevel

__all__ = ["Design", "DesignError", "DesignInterrupted", "critical_forces", "design", "prescribed_force_state",
           "sharing_bound"]


class DesignError(ValueError):
    """A brush the design cannot handle: says which and why."""


class DesignInterrupted(RuntimeError):
    """Stopped (``stop``) before any design was verified."""


@dataclass(frozen=True, kw_only=True)
class Design(MappingRecord):
    """A designed brush and its verification (``design.json`` holds the scalar fields).

    Attributes
    ----------
    target : {"lengths", "stiffness"}
    values : ndarray, shape (M,)
        The designed offsets g_n (units of length, min 0) or stiffnesses k_n.
    predicted_force_ratio : float
        F~ of the prescribed-force state: 1 by construction (every pillar at
        its Kendall force).
    verified_force_ratio : float
        F~ = F_A / (N F_K) of the ordinary pull-off of the best design.
    history : list of float
        Verified F~ after the direct solve and each corrective pull-off.
    detachment : ndarray, shape (M,)
        Every pillar's detachment displacement in the verified pull-off: the
        base displacement at which its tension peaked (its own pull-off).
    spread : float
        (max - min) of ``detachment`` over |d_c| (eq. 4.12): 0 when every
        pillar peaks at the same moment.
    iterations : int
    converged : bool
        Every verification pull-off converged, and so did the solve.
    bound_force_ratio : float or None
        With ``bound=True``: `sharing_bound` over N F_K, the most any design
        reaches while every pillar is in full contact (None when not computed).
    start_force_ratio : float or None
        F~ of the brush as given (before the design), verified by the same pull-off.
    preload_displacement : float or None
        The preload the verification used, raised where the design's offsets
        would have left pillars out of contact (None: a force-controlled preload).
    warnings : tuple of str
        What a user must know: a raised preload, a design that does not beat the brush as given.
    """

    target: str
    values: np.ndarray
    predicted_force_ratio: float
    verified_force_ratio: float
    history: list = field(default_factory=list)
    detachment: np.ndarray
    spread: float
    iterations: int
    converged: bool
    adhesive_force: float
    ideal_sharing_force: float
    rigid_brush_displacement: float
    bound_force_ratio: float | None = None
    start_force_ratio: float | None = None
    preload_displacement: float | None = None
    warnings: tuple = ()
    interrupted: bool = False

    def scalars(self) -> dict:
        """The JSON-able fields (arrays summarised)."""
        return {
            "target": self.target, "predicted_force_ratio": self.predicted_force_ratio,
            "verified_force_ratio": self.verified_force_ratio, "history": list(self.history),
            "spread_by_rigid_brush_displacement": self.spread, "iterations": self.iterations,
            "converged": self.converged, "adhesive_force": self.adhesive_force,
            "ideal_sharing_force": self.ideal_sharing_force,
            "rigid_brush_displacement": self.rigid_brush_displacement,
            "pillars": int(self.values.size), "bound_force_ratio": self.bound_force_ratio,
            "start_force_ratio": self.start_force_ratio, "preload_displacement": self.preload_displacement,
            "warnings": list(self.warnings), "interrupted": self.interrupted,
        }


def prescribed_force_state(halfspace: HalfSpace, pillar: np.ndarray, forces: np.ndarray, *,
                           tolerance: float = 1e-10, max_iterations: int = 2000,
                           initial: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Pressure and pillar displacements of rigid flat pillars carrying the forces ``forces`` (module step 1).

    Parameters
    ----------
    halfspace : HalfSpace
        Of the whole grid.
    pillar : ndarray of int, shape (N, N)
        Pillar of every element, -1 outside the footprints.
    forces : ndarray, shape (M,)
        Force of every pillar (compressive positive), units of force.
    initial : ndarray, shape (N, N), optional
        A starting pressure whose pillar sums are ``forces`` (a warm start).

    Returns
    -------
    pressure : ndarray, shape (N, N)
    displacement : ndarray, shape (M,)
        w_n, the surface displacement under pillar n (into the body positive).

    Raises
    ------
    DesignError
        If the projected CG does not reach ``tolerance``.
    """
    labels = pillar.ravel()
    on = np.flatnonzero(labels >= 0)
    owner = labels[on]
    m = int(forces.size)
    counts = np.bincount(owner, minlength=m).astype(float)
    h2 = halfspace.element_size**2
    shape = pillar.shape

    def apply(values: np.ndarray) -> np.ndarray:
        full = np.zeros(shape)
        full.ravel()[on] = values
        return halfspace.apply(full).ravel()[on]

    def project(values: np.ndarray) -> np.ndarray:  # remove every pillar's mean: zero pillar sums
        return values - (np.bincount(owner, weights=values, minlength=m) / counts)[owner]

    if initial is None:
        p = (forces / (h2 * counts))[owner]  # uniform on each pillar: the pillar sums hold
    else:
        p = np.asarray(initial, float).ravel()[on]
    residual = -project(apply(p))
    reference = float(np.linalg.norm(apply(p))) or 1.0
    direction = residual.copy()
    rr = float(residual @ residual)
    for _ in range(max_iterations):
        if math.sqrt(rr) <= tolerance * reference:
            break
        q = apply(direction)
        alpha = rr / float(direction @ q)
        p = p + alpha * direction
        residual = residual - alpha * project(q)
        rr_new = float(residual @ residual)
        direction = residual + (rr_new / rr) * direction
        rr = rr_new
    else:
        raise DesignError(f"the prescribed-force solve did not reach the tolerance {tolerance:g} in "
                          f"{max_iterations} iterations")
    deflection = apply(p)
    displacement = np.bincount(owner, weights=deflection, minlength=m) / counts
    pressure = np.zeros(shape)
    pressure.ravel()[on] = p
    return pressure, displacement


#: Most rounds of the fixed point that brings every pillar's edge to the criterion at once.
MAX_CRITICAL_ROUNDS = 200


def critical_forces(halfspace: HalfSpace, pillar: np.ndarray, forces: np.ndarray, critical: float, *,
                    tolerance: float = 1e-8, stop=None) -> tuple[np.ndarray, np.ndarray, float]:
    """Pillar tensions at which every pillar's most stressed element reaches the criterion at once.

    Starting from ``forces`` (Kendall's tensions), each round solves the
    prescribed-force state and scales every pillar's force by Sigma_c over
    its largest tensile stress, until every pillar's largest stress is
    Sigma_c to ``tolerance``: the state in which the whole brush is on the
    verge of detachment, the mesh's equal load sharing.  Returns the forces,
    the pillar displacements w_n of that state and its total tension.

    Raises DesignError if the rounds do not settle, `DesignInterrupted` when ``stop()`` turns True.
    """
    labels = pillar.ravel()
    on = labels >= 0
    owner = labels[on]
    pressure = None
    for _ in range(MAX_CRITICAL_ROUNDS):
        _check_stop(stop, "before the direct solve settled")
        pressure, w = prescribed_force_state(halfspace, pillar, forces, initial=pressure)
        tension = np.zeros(forces.size)
        np.maximum.at(tension, owner, -pressure.ravel()[on])
        if not np.all(tension > 0):
            raise DesignError("a pillar carries no tension in the prescribed-force state")
        ratio = critical / tension
        if float(np.max(np.abs(ratio - 1.0))) <= tolerance:
            return forces, w, float(-forces.sum())
        forces = forces * ratio
        pressure = pressure * np.where(pillar >= 0, ratio[np.maximum(pillar, 0)], 0.0)
    raise DesignError(f"the pillars' edges did not reach the criterion together in {MAX_CRITICAL_ROUNDS} rounds")


def sharing_bound(halfspace: HalfSpace, pillar: np.ndarray, critical: float, *,
                  stop=None) -> tuple[float, np.ndarray]:
    """The largest total tension rigid flat pillars in full contact can carry with no element past Sigma_c.

    Lengths and stiffnesses decide only which pillar forces F_n a brush
    reaches together: with free offsets every force vector is the state of
    some design.  In full contact the pressure is linear in the forces,
    p = P F (one prescribed-force solve per pillar gives the columns of P),
    so the best any design can do before its first element detaches is the
    linear programme

        maximise sum_n t_n  subject to  (P t)_e <= Sigma_c for every element e

    (t = -F, the tensions; `scipy.optimize.linprog`, HiGHS).  A lone flat
    punch detaches as a whole once its edge reaches the criterion (Kendall's
    instability), so this bounds F_A of every length or stiffness design
    whose pillars stay in full contact up to the adhesive force.  In a dense
    array a pillar can keep part of its contact after its first elements
    let go, and the ordinary pull-off may then pass the bound: at the
    chapter-7 grid (N = 512, 16 x 16 in a circle; ours) the verified design meets
    it at phi = 0.06 (0.942 both) and exceeds it by 2-3 % at phi = 0.15
    (0.853 and 0.866 against 0.839).  Returns the bound and the optimal
    tensions.  Costs one solve per pillar and a dense elements-in-footprints
    x pillars matrix: 0.1 GB for 192 pillars at N = 512, about 2 GB for 2304
    pillars at N = 1024.

    Raises DesignError if the programme has no solution, `DesignInterrupted` when ``stop()`` turns True
    (asked before every solve).
    """
    from scipy.optimize import linprog

    labels = np.asarray(pillar).ravel()
    on = np.flatnonzero(labels >= 0)
    m = int(labels.max()) + 1
    columns = np.empty((on.size, m))
    for n in range(m):
        _check_stop(stop, f"during the load-sharing bound ({n} of {m} solves)")
        unit = np.zeros(m)
        unit[n] = 1.0  # a unit tension on pillar n: p is the tensile stress per unit tension
        pressure, _ = prescribed_force_state(halfspace, np.asarray(pillar), -unit)
        columns[:, n] = -pressure.ravel()[on]
    solution = linprog(-np.ones(m), A_ub=columns, b_ub=np.full(on.size, float(critical)),
                       bounds=[(None, None)] * m, method="highs")
    if solution.status != 0:
        raise DesignError(f"the load-sharing bound's linear programme failed: {solution.message}")
    return float(-solution.fun), np.asarray(solution.x)


def _check_stop(stop, when: str) -> None:
    if stop is not None and stop():
        raise DesignInterrupted(f"interrupted {when}: nothing to keep")


def _spring_compression(indenter: Indenter, forces: np.ndarray, skip_first: bool = False) -> np.ndarray:
    """Compression of every pillar's springs (all elastic levels, or those above the pillars) under ``forces``."""
    s = np.zeros(forces.size)
    for index, level in enumerate(indenter.levels):
        if level.rigid or (skip_first and index == 0):
            continue
        cluster_force = np.bincount(level.cluster, weights=forces, minlength=level.n_clusters)
        s += (cluster_force / level.stiffnesses)[level.cluster]
    return s


def _with_offsets(indenter: Indenter, offsets: np.ndarray) -> Indenter:
    """``indenter`` with pillar n's offset set to ``offsets[n]``: every element of its tip moves with it.

    The rest of each element's height (a tilt's slope across the tip) is kept, so the verification pulls
    off the brush as configured, tilt included.
    """
    footprint = indenter.pillar >= 0
    owner = np.maximum(indenter.pillar, 0)
    shift = np.asarray(offsets, float) - np.asarray(indenter.description.offsets, float)
    height = np.where(footprint, np.asarray(indenter.height, float) + shift[owner], np.inf)
    description = dataclasses.replace(indenter.description, offsets=np.array(offsets))
    return dataclasses.replace(indenter, height=height, description=description)


def _with_stiffness(indenter: Indenter, stiffness: np.ndarray) -> Indenter:
    levels = (SpringLevel(np.array(stiffness), indenter.levels[0].cluster), *indenter.levels[1:])
    description = dataclasses.replace(indenter.description, graded=True)
    return dataclasses.replace(indenter, levels=levels, description=description)


def design(problem: ContactProblem, path: LoadPath, *, target: str = "lengths", iterations: int = 3,
           progress=None, bound: bool = False, stop=None) -> Design:
    """Offsets (or stiffnesses) of ``problem``'s brush for equal load sharing, verified by pull-offs.

    Parameters
    ----------
    problem : ContactProblem
        A brush of two or more pillars with adhesion (its offsets and springs
        are the starting point; a lengths design replaces the offsets).
    path : LoadPath
        The verification pull-off (the configured protocol).
    target : {"lengths", "stiffness"}
    iterations : int
        Corrective pull-offs after the direct solve (>= 0).
    progress : callable, optional
        ``progress(fraction, message)``.
    bound : bool
        Also compute `sharing_bound` (one solve per pillar), the best any
        design can reach, to show how far the design is from it.
    stop : callable or None
        Asked after every verification pull-off: when it returns True (Ctrl-C
        in `brushbem design`), the best design verified so far is returned,
        ``interrupted`` and with a warning; before the first verification
        there is none, and `DesignInterrupted` is raised.

    Notes
    -----
    Why these parameters: the problem and the path are the configuration's; target and iterations are the
    design's only choices.
    """
    indenter = problem.indenter
    info = indenter.description
    if not isinstance(info, BrushGeometry):
        raise DesignError(f"indenter.shape = {info.shape!r}: the design needs a brush (shape = 'brush')")
    if indenter.n_pillars < 2:
        raise DesignError("the brush has one pillar: equal load sharing needs two or more")
    if not problem.work_of_adhesion > 0:
        raise DesignError("halfspace.work_of_adhesion = 0: without adhesion there is no pull-off to share")
    if target not in ("lengths", "stiffness"):
        raise DesignError(f"target = {target!r} must be 'lengths' or 'stiffness'")
    if target == "stiffness" and (not indenter.levels or indenter.levels[0].rigid):
        raise DesignError("target = 'stiffness' needs elastic pillars (a finite indenter.stiffness or "
                          "stiffness_ratio): rigid pillars have no stiffness to design")
    if indenter.viscoelastic is not None or indenter.pillar_law is not None:
        raise DesignError("the design assumes linear elastic pillars: remove indenter.viscoelastic and "
                          "indenter.pillar_law")
    if getattr(info, "tip", "flat") != "flat":
        raise DesignError(f"indenter.tip: the design assumes flat tips in full contact (Kendall's force per "
                          f"pillar); this brush's tips are {info.tip!r}")
    if any(not level.uniform for level in indenter.levels[1:]):
        raise DesignError("indenter.levels.grading: the design solves the pillars' forces for uniform springs "
                          "above the pillars; remove the grading of the levels")
    if not (isinstance(iterations, int) and 0 <= iterations <= 50):
        raise DesignError(f"iterations = {iterations!r} must be an integer in [0, 50]")
    grid = problem.grid
    h2 = grid.element_size**2
    radii = np.sqrt(np.asarray(info.pillar_elements, float) * h2 / math.pi)
    kendall = np.asarray(theory.kendall_force(radii, contact_modulus=problem.contact_modulus,
                                              work_of_adhesion=problem.work_of_adhesion))
    ideal = float(kendall.sum())
    halfspace = HalfSpace(grid.elements, grid.element_size, problem.contact_modulus)
    forces, w, predicted = critical_forces(halfspace, np.asarray(indenter.pillar), -kendall, problem.critical_stress,
                                           stop=stop)
    if target == "lengths":
        g = -_spring_compression(indenter, forces) - w
        values = g - g.min()
        build = _with_offsets
    else:
        g = np.asarray(info.offsets, float)
        above = _spring_compression(indenter, forces, skip_first=True)
        base = indenter.levels[0].stiffnesses
        mean = float(np.mean(base))
        rest = g + w + above  # d - rest = the pillar spring's compression s_n = F_n / k_n (< 0: stretched)

        def mean_stiffness(d: float) -> float:
            return float(np.mean(forces / (d - rest)))

        # k_n > 0 needs d < min(rest); the mean falls from +inf to 0 as d goes down from there.
        top = float(rest.min())
        low = top - 1.0
        while mean_stiffness(low) > mean:
            low = top - 2.0 * (top - low)
        from scipy.optimize import brentq

        d = brentq(lambda x: mean_stiffness(x) - mean, low, top - 1e-15 * max(1.0, abs(top)), xtol=1e-300,
                   rtol=1e-14, maxiter=500)
        values = forces / (d - rest)
        build = _with_stiffness
    scales_dc = abs(float(theory.rigid_brush_displacement(
        min(info.filling_factor, 1.0), info.apparent_area, contact_modulus=problem.contact_modulus,
        work_of_adhesion=problem.work_of_adhesion)))
    notes: list[str] = []
    tilted = float(getattr(info, "tilt_angle", 0.0) or 0.0) != 0.0
    if tilted:
        notes.append(f"indenter.tilt.angle = {info.tilt_angle:g} degrees: the direct solve assumes untilted "
                     "tips; the verification pull-offs are of the tilted brush, and the offsets are the "
                     "pillars' heights at their centres on the tilted base")
    configured = path
    first = build(indenter, values)
    # Every designed tip pressed, or said, before any pull-off is computed.
    _touching_path(dataclasses.replace(problem, indenter=first), configured,
                   values if target == "lengths" else None, notes, stop)
    if progress is not None:
        progress(0.0, "the brush as given: one pull-off to compare the design with")
    start = record_pull_off(problem, path, stop=stop).summary
    if start["interrupted"] or (stop is not None and stop()):
        raise DesignInterrupted("interrupted before the first design was verified: nothing to keep")
    interrupted = False
    start_ratio = float(start["adhesive_force"]) / ideal
    history, best, converged = [], None, bool(start["converged"])
    for round_ in range(iterations + 1):
        if progress is not None:
            progress(round_ / (iterations + 1), f"verifying design {round_ + 1} of {iterations + 1}")
        trial = dataclasses.replace(problem, indenter=first if round_ == 0 else build(indenter, values))
        try:
            path = _touching_path(trial, configured, values if target == "lengths" else None, notes, stop)
            record = record_pull_off(trial, path, stop=stop)
        except DesignInterrupted:
            record = None
        summary = {"interrupted": True} if record is None else record.summary
        if summary["interrupted"]:
            if best is None:
                raise DesignInterrupted("interrupted before the first design was verified: nothing to keep")
            interrupted = True
            notes.append(f"interrupted during verification {round_ + 1} of {iterations + 1}: the best design "
                         "verified before it")
            break
        converged &= bool(summary["converged"])
        ratio = float(summary["adhesive_force"]) / ideal
        detachment = np.asarray(record.pillars["max_tension_displacement"], float)
        untouched = int(np.count_nonzero(~np.isfinite(detachment)))
        if untouched:
            raise DesignError(
                f"{untouched} of {detachment.size} pillars never touch in the verification pull-off at "
                f"{_preload_words(path)}, although pressing the designed brush to it touched every one; "
                "raise the preload")
        history.append(ratio)
        if best is None or ratio > best[0]:
            best = (ratio, values.copy(), detachment, float(summary["adhesive_force"]), path.preload_displacement)
        if stop is not None and stop() and round_ < iterations:
            interrupted = True
            notes.append(f"interrupted after {round_ + 1} of {iterations + 1} verifications: the best design "
                         "verified so far")
            break
        spread_now = float(np.ptp(detachment)) if np.all(np.isfinite(detachment)) else math.inf
        if round_ == iterations or not math.isfinite(spread_now) or spread_now <= 1e-9 * max(scales_dc, 1e-300):
            break
        early = detachment - np.median(detachment)
        if target == "lengths":
            values = values - early
            values = values - values.min()
        else:
            # The pillar spring's stretch s_n = F_n / k_n moves the same way as the offset would.
            stretch = forces / values - early
            if np.any(stretch >= 0):
                break
            values = forces / stretch
    ratio, values, detachment, force, preload = best
    bound_ratio = None
    if bound and not interrupted:
        if progress is not None:
            progress(1.0, f"the load-sharing bound: {indenter.n_pillars} prescribed-force solves")
        try:
            bound_ratio = sharing_bound(halfspace, np.asarray(indenter.pillar), problem.critical_stress,
                                        stop=stop)[0] / ideal
        except DesignInterrupted:
            notes.append("interrupted during the load-sharing bound (--bound): the design is kept, the bound "
                         "is not computed")
    interrupted = interrupted or bool(stop is not None and stop())
    spread = float(np.ptp(detachment) / scales_dc)  # every pillar touched (checked above)
    if ratio <= start_ratio:
        notes.append(f"the design does not beat the brush as given: verified F~ = {ratio:.4g} against "
                     f"{start_ratio:.4g} undesigned (keep the brush as it is, or raise the iterations)")
    return Design(target=target, values=values, predicted_force_ratio=predicted / ideal, verified_force_ratio=ratio,
                  history=history, detachment=detachment, spread=spread, iterations=len(history) - 1,
                  converged=converged, adhesive_force=force, ideal_sharing_force=ideal,
                  rigid_brush_displacement=scales_dc, bound_force_ratio=bound_ratio, start_force_ratio=start_ratio,
                  preload_displacement=preload, warnings=tuple(dict.fromkeys(notes)), interrupted=interrupted)


#: Most raises of a displacement preload before the design says which preload it needs (each presses the
#: designed brush once, without adhesion).
MAX_PRELOAD_RAISES = 40


def _preload_words(path: LoadPath) -> str:
    if path.preload_displacement is not None:
        return f"protocol.preload_displacement = {path.preload_displacement:.6g}"
    return f"protocol.preload_force = {path.preload_force:.6g}"


def _touching_path(problem: ContactProblem, path: LoadPath, offsets: np.ndarray | None, notes: list[str],
                   stop=None) -> LoadPath:
    """``path``, with its preload displacement raised until every pillar of ``problem`` is pressed.

    Designed offsets recess some tips; such a pillar never touches, never pulls, and the verification
    would rate a brush the design did not mean.  The brush is pressed to the preload without adhesion
    (as the event path presses a brush) and, while some pillar is not in full contact (the design's
    premise), the displacement is raised (the surface sinks around pressed neighbours, so the offsets
    alone are not enough) and pressed again.  A displacement preload is raised so, with a warning;
    a force preload that leaves a pillar off is refused, naming the preload that presses all of them.
    Each press is one contact solve, no pull-off: this is decided before any pull-off is computed.
    """
    from brushbem.protocol import indent

    pillar = np.asarray(problem.indenter.pillar)
    footprint = pillar >= 0
    m = problem.indenter.n_pillars
    dry = dataclasses.replace(problem, work_of_adhesion=0.0)
    halfspace = HalfSpace(problem.grid.elements, problem.grid.element_size, problem.contact_modulus)
    height = np.asarray(problem.indenter.height, float)
    lowest_of_each = np.full(m, np.inf)
    np.minimum.at(lowest_of_each, pillar[footprint], height[footprint])
    if path.preload_displacement is None:
        # Just past the last tip reached, were the surface not to sink (a press needs some penetration).
        start = float(lowest_of_each.max()) + 1e-3 * problem.grid.element_size
    else:
        start = float(path.preload_displacement)
        if offsets is not None:
            start = max(start, float(np.max(offsets)) + start)  # every tip pressed at least the preload
    def press(d: float):
        _check_stop(stop, "while pressing the designed brush to its preload")
        state = indent(dry, d, tolerance=min(path.tolerance, 1e-8), max_iterations=path.max_iterations)
        # Pressed means in full contact: the design's prediction is of flat tips in full contact.
        off = footprint & ~np.asarray(state.contact, bool)
        touched = np.bincount(pillar[off], minlength=m) == 0
        return state, touched

    # The surface under a free tip sinks with its pressed neighbours, so the gap closes slower than d grows
    # (in a dense array much slower): the raise doubles until every tip touches, then bisection brings it
    # back to within 2 % of the first displacement that presses them all (contact grows with d).
    d, low = start, None
    state, touched = press(d)
    step = 0.0
    for _ in range(MAX_PRELOAD_RAISES):
        if touched.all():
            break
        deflection = np.asarray(halfspace.apply(np.asarray(state.pressure, float)))
        gap = float(np.max(np.where(footprint & ~np.asarray(state.contact, bool), height + deflection - d,
                                    -np.inf)))
        low = d
        step = max(2.0 * step, 1.1 * max(gap, 0.0), 1e-9 * max(abs(d), problem.grid.element_size))
        d += step
        state, touched = press(d)
    else:
        raise DesignError(f"pressing the designed brush by up to d = {d:.6g} left pillars out of contact "
                          f"(after {MAX_PRELOAD_RAISES} raises of the preload): the design cannot be verified")
    while low is not None and d - low > 0.02 * (d - start) and d - low > 1e-12 * abs(d):
        middle = 0.5 * (low + d)
        trial, trial_touched = press(middle)
        if trial_touched.all():
            d, state = middle, trial
        else:
            low = middle
    if path.preload_force is not None:
        if path.preload_force >= state.force:
            return path
        raise DesignError(
            f"{_preload_words(path)} leaves some of the {m} designed pillars out of full contact (their tips "
            f"are recessed by up to {float(np.ptp(lowest_of_each)):.6g}); pressing every one fully takes "
            f"protocol.preload_force >= {state.force:.6g} (or protocol.preload_displacement = {d:.6g})")
    if d <= path.preload_displacement * (1 + 1e-12):
        return path
    notes[:] = [note for note in notes if not note.startswith("protocol.preload_displacement raised")]
    notes.append(f"protocol.preload_displacement raised from {path.preload_displacement:g} to {d:g}: "
                 "the designed offsets recess tips beyond the configured preload, and this presses every "
                 "designed pillar into full contact")
    return dataclasses.replace(path, preload_displacement=d)
