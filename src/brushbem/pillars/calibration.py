"""A tip's strength on its raster, and the criterion calibrated to Kendall's (``LoadPath.pillar_tip_calibration``).

The Pohrt-Popov criterion of an element, Sigma_c = sqrt(E* dgamma / (0.473201
h)), gives a lone flat tip Kendall's force F_K = sqrt(8 pi E* dgamma a^3)
only as its raster is refined: on a raster of a few elements per radius the
lone tip's pull-off force F_R is several per cent off, by an amount that
depends on where the circle falls on the grid (``data/resolution_error.csv``).
A lone rigid tip's pressure is d K_R^-1 1 on every raster of its peel, so
F_R is proportional to Sigma_c: the critical stress Sigma_c F_K / F_R makes
the lone tip on its raster come off at exactly F_K.  `calibrated_criteria`
gives that stress per pillar (one lone-tip pull-off per footprint shape).

This removes the lone tip's error, not a brush's: in a brush the neighbours'
field tilts and bends the pressure across every tip, and a factor fixed on a
lone tip's uniform pull does not carry over to those modes.  Measured on
the validation families (``docs/pillars/calibration.csv``, written by
``docs/pillars/calibration.py``), see `brushbem.pillars` ("Calibrated tips").
"""

from __future__ import annotations

import math

import numpy as np

from brushbem.physics.theory.punch import kendall_force
from brushbem.pillars.modes import Bases

__all__ = ["calibrated_criteria", "lone_pull_off", "tip_criteria"]


def lone_pull_off(bases: Bases, footprint: np.ndarray, critical: float, h2: float) -> tuple[float, int]:
    """(F_R, events): the pull-off force of a lone rigid flat tip on the raster ``footprint`` (element offsets)
    under displacement control, and the number of its detachment events.

    The exact event path of one tip: on a raster R the pressure is d phi_0
    (phi_0 = K_R^-1 1, `Bases`), so the next element to reach -``critical``
    is the one of largest phi_0, at d = -critical / max phi_0; there the
    elements beyond the criterion leave, round by round at that d, until
    the raster is stable or gone.  F_R is the largest tensile force h^2 d s
    at an event (s = sum phi_0).
    """
    mask = np.ones(footprint.shape[0], dtype=bool)
    d, force, events = 0.0, 0.0, 0
    while mask.any():
        basis = bases.get(footprint, mask)
        d = min(d, -critical / float(basis.phi[:, 0].max()))
        force = max(force, -h2 * basis.force * d)
        events += 1
        while mask.any():
            basis = bases.get(footprint, mask)
            # The elements at the criterion (to rounding) leave together, as the event path's ties do.
            tense = d * basis.phi[:, 0] <= -critical * (1 - 1e-10)
            if not tense.any():
                break
            mask[np.flatnonzero(mask)[tense]] = False
    return force, events


def calibrated_criteria(bases: Bases, footprints: list[np.ndarray], critical: float, h2: float,
                        kendall: float) -> np.ndarray:
    """Every pillar's critical stress: ``critical`` x ``kendall`` / F_R of its footprint (`lone_pull_off`).

    ``footprints``: every pillar's element offsets; pillars of one shape share one lone-tip pull-off.
    """
    factors: dict[bytes, float] = {}
    out = np.empty(len(footprints))
    for p, footprint in enumerate(footprints):
        offsets = footprint - footprint.min(axis=0)
        key = offsets.tobytes()
        if key not in factors:
            force = lone_pull_off(bases, offsets, critical, h2)[0]
            if not (math.isfinite(force) and force > 0):
                raise ValueError(f"a lone tip of {offsets.shape[0]} elements has no pull-off force ({force})")
            factors[key] = kendall / force
        out[p] = critical * factors[key]
    return out


def tip_criteria(model, problem, critical: float, calibrate: bool) -> np.ndarray:
    """Every pillar's critical stress (M,) in the `brushbem.pillars.basis.PillarModel` ``model`` (its bases,
    footprints and h^2): ``critical`` (the tips' raster's Sigma_c), or calibrated (`calibrated_criteria`)."""
    if not calibrate:
        return np.full(model.M, critical)
    sizes = np.count_nonzero(model.full, axis=1)
    footprints = [np.stack([model.rows[p][:sizes[p]], model.cols[p][:sizes[p]]], axis=1) for p in range(model.M)]
    kendall = float(kendall_force(float(problem.indenter.description.pillar_radius),
                                  contact_modulus=problem.contact_modulus, work_of_adhesion=problem.work_of_adhesion))
    return calibrated_criteria(model.bases, footprints, critical, model.h2, kendall)
