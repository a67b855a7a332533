"""Where the pillar model is accurate: `domain_warning`, `smallest_gap`.

A tip's pressure is six polynomials' (`brushbem.pillars`); the field of its
neighbours across it is not, and the more of the surface the footprints
cover the larger the part it plays.  Against the exact path
(``docs/pillars/validation.md``, the domain rows) the error follows the
filling factor phi rather than the smallest gap: random layouts with
footprints one element apart are within 0.2 % at phi = 0.05 and within
0.8 % / 2.9 % at 0.3, while a level lattice 6.2 elements apart at phi = 0.3
is -1.3 % (F_A), and at 0.6 (1.9 elements apart) the errors reach -4.4 %
(F_A) and +12 % (work).  The
path warns (`PillarDomainWarning`) beyond `VALIDATED_FILLING`, naming phi,
the smallest gap and the errors measured there.
"""

from __future__ import annotations

import numpy as np
import scipy.spatial

from brushbem.protocol.problem import ContactProblem

__all__ = ["MEASURED", "PEEL_TILT", "VALIDATED_FILLING", "PillarDomainWarning", "domain_warning", "peel_warning",
           "smallest_gap"]


def smallest_gap(problem: ContactProblem) -> float:
    """The smallest gap between two pillars' footprints, in elements (inf with fewer than two pillars).

    Each footprint is taken as the circle of its area (its element count
    over pi) about its centroid; the gap of two is their centres' distance
    less both radii.
    """
    labels = np.asarray(problem.indenter.pillar)
    rows, cols = np.nonzero(labels >= 0)
    owner = labels[rows, cols]
    count = int(owner.max()) + 1 if owner.size else 0
    if count < 2:
        return float("inf")
    sizes = np.bincount(owner, minlength=count).astype(float)
    centres = np.stack([np.bincount(owner, rows, count), np.bincount(owner, cols, count)], axis=1) / sizes[:, None]
    radii = np.sqrt(sizes / np.pi)
    k = min(count, 9)
    distance, index = scipy.spatial.cKDTree(centres).query(centres, k=k)
    gaps = distance[:, 1:] - radii[:, None] - radii[index[:, 1:]]
    return float(gaps.min())


#: The filling factor up to which the model is within 1 % (F_A) and 3 % (work) of the exact path: the
#: validation families at phi = 0.16 and the domain rows at 0.05 are; at 0.3 a level lattice at k~ = 10 is
#: not (F_A -1.3 %).  The limit between is ours (no row between 0.16 and 0.3).
VALIDATED_FILLING = 0.2

#: The largest errors measured against the exact path above `VALIDATED_FILLING` (the domain rows of
#: ``docs/pillars/validation.md``: flat, rough and random 8 x 8 brushes at k~ = 10 and 1e-5, N = 128):
#: (phi, largest |F_A error| %, largest |work error| %) at each filling factor measured.
MEASURED = ((0.3, 1.3, 2.9), (0.44, 2.0, 2.8), (0.6, 4.4, 11.9), (0.78, 3.8, 8.2))


class PillarDomainWarning(UserWarning):
    """The pillar model runs outside the domain where it was measured within 1 % / 3 % of the exact path."""


def domain_warning(problem: ContactProblem) -> str | None:
    """The warning for a brush outside the model's validated domain (its filling factor, the smallest gap
    between footprints and the errors measured nearest above it), or None inside it.

    A lone pillar has no neighbour whose field the model could miss: it is exact there (a lone tip
    equals the exact path's punch, ``tests/test_adhesive_inputs.py``), whatever its filling factor.
    """
    phi = float(problem.indenter.description.filling_factor)
    if not phi > VALIDATED_FILLING:
        return None
    gap = smallest_gap(problem)
    if gap == float("inf"):
        return None
    rows = [row for row in MEASURED if row[0] >= phi - 0.05] or [MEASURED[-1]]
    measured = "; ".join(f"phi = {p:g}: F_A up to {a:g} %, work up to {w:g} %" for p, a, w in rows[:2])
    return (f"LoadPath.method = 'pillars' on a brush of filling factor phi = {phi:.3g} (smallest gap between "
            f"footprints {gap:.2g} elements): beyond phi = {VALIDATED_FILLING:g} the model "
            f"is not within 1 % (F_A) / 3 % (work) of the exact path; measured ({measured}; "
            "docs/pillars/validation.md); check with method = 'events'")


#: The largest relative n = 1 amplitude of K along its edge, as it leaves, of a tip that leaves whole at its
#: continuum capacity (``LoadPath.pillar_tip_peel``; `brushbem.pillars.peel.shape_parameters`) at which the
#: option was measured within 1 % of the limit: the lattice families' tips reach 0.31; a random layout whose
#: closest tips reach 0.52-0.55 lies within 1 % of both ends of its limit (+0.33 / -0.87 %), but its first-order
#: gains there are half its raster tips' at 80 elements per radius (``docs/pillars/front_random_tips.csv``), so
#: beyond 0.35 a tip's gain is a lower end.  Tips beyond
#: the gain's table (0.6, `brushbem.pillars.peel.TABLE_LIMITS`) do not leave whole: they peel by their elements'
#: criterion.  The rough 8 x 8 family's tips leave whole at 0.02-0.09 (median) and 0.13 at most
#: (``docs/pillars/rough.csv``).  The limit between 0.31 and 0.52 is ours.
PEEL_TILT = 0.35


def peel_warning(largest_tilt: float) -> str | None:
    """The warning for tips that left at their continuum capacity (``LoadPath.pillar_tip_peel``) with K varying
    along their edges by more than `PEEL_TILT` (the first-order peel's gain is a lower end there), or None."""
    if not largest_tilt > PEEL_TILT:
        return None
    return (f"LoadPath.pillar_tip_peel: a tip left at its continuum capacity with its stress intensity varying "
            f"along its edge by {largest_tilt:.2f} of its mean (relative n = 1 amplitude), beyond {PEEL_TILT:g}: "
            "the first-order peel's gain is a lower end there (its neglected terms grow as that amplitude times the "
            "gain); measured on a random layout whose tips reach 0.52-0.55: F_A +0.33 % above its continuum "
            "first-order brush and -0.87 % below its raster tips' capacity at 80 elements per radius "
            "(docs/pillars/front_random.csv, front_random_tips.csv); check with finer tips (pillar_tip_resolution)")
