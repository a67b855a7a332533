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

``per_element``: every element its own critical stress, -d_K phi_0 at the
lone tip's Kendall displacement d_K = F_K / (h^2 sum phi_0) (the pressure
each element carries when the whole edge is at Kendall's stress intensity),
so that under a uniform pull every element reaches its criterion at once at
F_K, and under a tilted or bent field the element where the stress
intensity is largest goes first.  A measured variant, not a path's setting
(``docs/pillars/criteria.py``): it starts each tip's peel where the
continuum does, but the peel that follows is what decides a brush's F_A.
"""

from __future__ import annotations

import math

import numpy as np

from brushbem.physics.theory.punch import kendall_force
from brushbem.pillars.modes import Bases
from brushbem.pillars.peel import load_control

__all__ = ["CRITERIA", "calibrated_criteria", "install_criterion", "lone_pull_off", "tip_criteria"]

#: The tips' criteria: the raster's Sigma_c, calibrated to Kendall's force (``LoadPath.pillar_tip_calibration``),
#: and whole tips leaving at their continuum capacity (``LoadPath.pillar_tip_peel``).
CRITERIA = ("raster", "calibrated", "peel")


def lone_pull_off(bases: Bases, footprint: np.ndarray, critical: float | np.ndarray,
                  h2: float) -> tuple[float, int]:
    """(F_R, events): the pull-off force of a lone rigid flat tip on the raster ``footprint`` (element offsets)
    under displacement control, and the number of its detachment events; ``critical`` one stress or one per
    element of ``footprint``.

    The exact event path of one tip: on a raster R the pressure is d phi_0
    (phi_0 = K_R^-1 1, `Bases`), so the next element to reach -``critical``
    is the one of largest phi_0 / Sigma_c, at d = -max (Sigma_c / phi_0); there the
    elements beyond the criterion leave, round by round at that d, until
    the raster is stable or gone.  F_R is the largest tensile force h^2 d s
    at an event (s = sum phi_0).
    """
    mask = np.ones(footprint.shape[0], dtype=bool)
    critical = np.broadcast_to(np.asarray(critical, dtype=np.float64), mask.shape)
    d, force, events = 0.0, 0.0, 0
    while mask.any():
        basis = bases.get(footprint, mask)
        phi = basis.phi[:, 0]
        pulled = phi > 0
        d = min(d, float(np.max(-critical[mask][pulled] / phi[pulled])))
        force = max(force, -h2 * basis.force * d)
        events += 1
        while mask.any():
            basis = bases.get(footprint, mask)
            # The elements at the criterion (to rounding) leave together, as the event path's ties do.
            tense = d * basis.phi[:, 0] <= -critical[mask] * (1 - 1e-10)
            if not tense.any():
                break
            mask[np.flatnonzero(mask)[tense]] = False
    return force, events


def calibrated_criteria(bases: Bases, footprints: list[np.ndarray], critical: float, h2: float,
                        kendall: float, per_element: bool = False) -> list[np.ndarray]:
    """Every pillar's critical stress per element of its footprint: ``critical`` x ``kendall`` / F_R of its
    footprint (`lone_pull_off`), or, ``per_element``, each element's in proportion to its pressure under the
    lone tip's uniform pull (phi_0), scaled so that the lone tip comes off at ``kendall``.

    ``footprints``: every pillar's element offsets; pillars of one shape share one lone-tip pull-off.
    """
    factors: dict[bytes, np.ndarray] = {}
    out = []
    for footprint in footprints:
        offsets = footprint - footprint.min(axis=0)
        key = offsets.tobytes()
        if key not in factors:
            shape = np.full(offsets.shape[0], critical)
            if per_element:
                phi = bases.get(offsets).phi[:, 0]
                shape = critical * phi / phi.max()
            force = lone_pull_off(bases, offsets, shape, h2)[0]
            if not (math.isfinite(force) and force > 0):
                raise ValueError(f"a lone tip of {offsets.shape[0]} elements has no pull-off force ({force})")
            factors[key] = shape * (kendall / force)
        out.append(factors[key])
    return out


def tip_criteria(model, problem, critical: float, calibrate: bool, per_element: bool = False) -> np.ndarray:
    """Every footprint slot's critical stress in the `brushbem.pillars.basis.PillarModel` ``model`` (its bases,
    footprints and h^2): ``critical`` (the tips' raster's Sigma_c), or calibrated (`calibrated_criteria`),
    (M, 1) (one per pillar, broadcast over its slots); ``per_element``: (M, width), the padding slots holding
    their pillar's largest."""
    if not calibrate:
        return np.full((model.M, 1), critical)
    out = np.full(model.full.shape, critical)
    sizes = np.count_nonzero(model.full, axis=1)
    footprints = [np.stack([model.rows[p][:sizes[p]], model.cols[p][:sizes[p]]], axis=1) for p in range(model.M)]
    kendall = float(kendall_force(float(problem.indenter.description.pillar_radius),
                                  contact_modulus=problem.contact_modulus, work_of_adhesion=problem.work_of_adhesion))
    for p, values in enumerate(calibrated_criteria(model.bases, footprints, critical, model.h2, kendall,
                                                   per_element)):
        out[p, :sizes[p]] = values
        out[p, sizes[p]:] = values.max()
    return out if per_element else out[:, :1].copy()


def install_criterion(model, problem, criterion: str, critical: float,
                       sizes: np.ndarray, h: float) -> None:
    """The tips' criterion (``criterion``, `CRITERIA`): every pillar's critical stress, ``model.critical``, (M, 1)
    over its slots: the tips' raster's Sigma_c or calibrated to Kendall's force per footprint shape; and, where
    whole tips leave at their continuum capacity (``continuum_peel``, `brushbem.pillars.peel`), what that needs: every tip's circle radius (elements of
    the tips' raster), Kendall's force of the circles and f(0) of each edge's response
    (`brushbem.pillars.peel.load_control`: the contact's share of the tip's compliance)."""
    model.continuum_peel = criterion == "peel"
    # Whole tips leaving at their continuum capacity do not read their elements' criterion; a tip in part
    # contact (a rough brush's) peels by the raster's Sigma_c, as the exact path's elements do.
    model.critical = tip_criteria(model, problem, critical, criterion == "calibrated")
    described = getattr(problem.indenter.description, "pillar_radius", None)
    model.tip_radius = np.full(model.M, float(described) / h) if described else np.sqrt(sizes / math.pi)
    model.kendall = float(kendall_force(model.tip_radius[0] * h, contact_modulus=problem.contact_modulus,
                                        work_of_adhesion=problem.work_of_adhesion))
    compliance = np.zeros(model.M)
    for level in problem.indenter.elastic_levels:
        compliance += 1.0 / np.asarray(level.stiffnesses, dtype=np.float64)[np.asarray(level.cluster)]
    contact = 1.0 / (2.0 * problem.contact_modulus * model.tip_radius * h)
    model.peel_control = load_control(contact / (contact + compliance))
