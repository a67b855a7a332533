"""Closed-form limits of adhesive contact: the thesis's analytical reference solutions.

Every function here is a pure function of plain floats (most broadcast over NumPy
arrays): no state, no side effects, no logging.  They are the rungs the numerical
model is checked against (DESIGN.md, section 5) and the scales the thesis uses to
make its results dimensionless.  Every public name is re-exported here, so
``brushbem.physics.theory.kendall_force`` and ``from brushbem.physics.theory import ...`` work
whichever submodule holds the function.

Contents (by thesis chapter; equation numbers are the thesis's)
---------------------------------------------------------------
``material``
    :func:`contact_modulus_from`, ``E* = E / (1 - nu**2)`` (eq. 2.1); a fibril's spring
    :func:`fibril_stiffness` (``k = pi r^2 E_f / l``, sec. 6.3) and :func:`euler_buckling_force`.
``punch`` (ch. 2)
    Kendall flat punch (eq. 2.1-2.7): ``punch_stiffness``, ``kendall_*``; the
    punch on a spring (eq. 2.8, 2.16-2.19): ``normalized_punch_stiffness``,
    ``punch_spring_*``.
``sphere`` (ch. 1-2)
    Hertz (``hertz_*``), JKR (eq. 1.1, 2.20-2.27: ``jkr_*``), DMT, Tabor and
    Maugis (eq. 1.2-1.5: ``dmt_pull_off_force``, ``tabor_parameter``,
    ``maugis_parameter``).
``sphere_spring`` (ch. 2)
    JKR sphere on a spring, works of separation (eq. 2.28-2.39): the
    ``SPHERE_*`` constants and ``sphere_*``.
``brush`` (ch. 4, scales of ch. 5-7)
    Flat rigid and soft brushes (eq. 4.5-4.18, 5.3-5.4): ``rigid_brush_*``,
    ``compact_punch_force``, ``soft_brush_*``, and ``ideal_sharing_force`` (eq. 7.4).
``rough`` (ch. 5)
    Rough brushes (eq. 5.8): ``adhesion_coefficient``, ``critical_roughness``; the
    brush of independent pillars (eq. 5.7's model with each punch's compliance):
    ``independent_pillars_pull_off``, ``independent_rough_brush``,
    ``independent_gaussian_plateau``.
``hierarchy`` (ch. 6)
    Hierarchical brushes (eq. 6.20-6.28): ``hierarchy_stiffnesses``,
    ``total_filling_factor``, ``equivalent_single_level_stiffness``.
``concave`` (ch. 7)
    Concave profile for a uniform stress (eq. 7.1-7.3): ``concave_*``.
``_common``
    The private input-validation helpers, and the conventions in full.

Conventions (in full in :mod:`brushbem.physics.theory._common`)
-------------------------------------------------------
Displacements are positive into the half-space and forces positive when
compressive; characteristic adhesive forces (``..._force``) are returned as
positive magnitudes and critical displacements (``..._displacement``) signed
(negative: pulled away).  The half-space enters through the contact modulus E*
and the work of adhesion dgamma, in any consistent units, always passed by
keyword after the positional geometry and load
(``kendall_force(radius, contact_modulus=E, work_of_adhesion=dgamma)``).  Every function
validates its arguments and raises :class:`ValueError` naming the parameter,
the offending value and the allowed range.
"""

from __future__ import annotations

from brushbem.physics.theory.brush import (
    compact_punch_force,
    ideal_sharing_force,
    rigid_brush_displacement,
    rigid_brush_enhancement,
    rigid_brush_force,
    soft_brush_enhancement,
    soft_brush_force,
    soft_brush_work_normalized,
    soft_brush_work_of_separation,
)
from brushbem.physics.theory.concave import (
    concave_offsets,
    concave_pillar_profile,
    concave_profile,
    concave_reference_stress,
)
from brushbem.physics.theory.hierarchy import (
    equivalent_single_level_stiffness,
    hierarchy_stiffnesses,
    total_filling_factor,
)
from brushbem.physics.theory.material import (
    BUCKLING_LENGTH_FACTORS,
    contact_modulus_from,
    euler_buckling_force,
    fibril_stiffness,
)
from brushbem.physics.theory.punch import (
    kendall_displacement,
    kendall_force,
    kendall_work_of_separation,
    normalized_punch_stiffness,
    punch_spring_separation_displacement,
    punch_spring_work_of_separation,
    punch_stiffness,
)
from brushbem.physics.theory.rough import (
    ROUGHNESS_SCALES,
    IndependentPullOff,
    IndependentRoughBrush,
    adhesion_coefficient,
    critical_roughness,
    independent_gaussian_plateau,
    independent_pillars_pull_off,
    independent_rough_brush,
)
from brushbem.physics.theory.sphere import (
    dmt_pull_off_force,
    hertz_contact_radius,
    hertz_force,
    hertz_max_pressure,
    jkr_displacement_from_radius,
    jkr_force_from_displacement,
    jkr_force_from_radius,
    jkr_normalized_displacement,
    jkr_normalized_force,
    jkr_pull_off_displacement,
    jkr_pull_off_force,
    jkr_pull_off_radius,
    jkr_radius_from_displacement,
    jkr_separation_displacement,
    jkr_separation_force,
    jkr_separation_radius,
    jkr_total_energy,
    jkr_work_of_separation,
    jkr_zero_force_radius,
    maugis_parameter,
    tabor_parameter,
)
from brushbem.physics.theory.sphere_spring import (
    SPHERE_ABAR_PULL_OFF,
    SPHERE_ABAR_SEPARATION,
    SPHERE_ABAR_ZERO_FORCE,
    SPHERE_WORK_SWITCH,
    sphere_normalization_energy,
    sphere_normalization_radius,
    sphere_normalized_stiffness,
    sphere_preload_contact_radius,
    sphere_spring_energy_normalized,
    sphere_spring_separation_radius,
    sphere_spring_work,
    sphere_spring_work_from_preload,
    sphere_spring_work_high,
    sphere_spring_work_low,
    sphere_spring_work_of_separation,
)

__all__ = [  # noqa: RUF022 - grouped by thesis chapter
    # material
    "contact_modulus_from",
    "fibril_stiffness",
    "euler_buckling_force",
    "BUCKLING_LENGTH_FACTORS",
    # Kendall flat punch
    "punch_stiffness",
    "kendall_force",
    "kendall_displacement",
    "kendall_work_of_separation",
    # punch on a spring
    "normalized_punch_stiffness",
    "punch_spring_work_of_separation",
    "punch_spring_separation_displacement",
    # Hertz
    "hertz_force",
    "hertz_contact_radius",
    "hertz_max_pressure",
    # JKR
    "jkr_force_from_radius",
    "jkr_displacement_from_radius",
    "jkr_total_energy",
    "jkr_normalized_force",
    "jkr_normalized_displacement",
    "jkr_pull_off_force",
    "jkr_pull_off_radius",
    "jkr_pull_off_displacement",
    "jkr_zero_force_radius",
    "jkr_separation_radius",
    "jkr_separation_force",
    "jkr_separation_displacement",
    "jkr_radius_from_displacement",
    "jkr_force_from_displacement",
    "jkr_work_of_separation",
    # DMT, Tabor, Maugis
    "dmt_pull_off_force",
    "tabor_parameter",
    "maugis_parameter",
    # sphere on a spring
    "SPHERE_ABAR_ZERO_FORCE",
    "SPHERE_ABAR_SEPARATION",
    "SPHERE_ABAR_PULL_OFF",
    "SPHERE_WORK_SWITCH",
    "sphere_normalization_radius",
    "sphere_normalization_energy",
    "sphere_normalized_stiffness",
    "sphere_spring_energy_normalized",
    "sphere_spring_separation_radius",
    "sphere_spring_work_high",
    "sphere_spring_work_low",
    "sphere_spring_work",
    "sphere_spring_work_of_separation",
    "sphere_spring_work_from_preload",
    "sphere_preload_contact_radius",
    # brushes
    "rigid_brush_force",
    "rigid_brush_displacement",
    "compact_punch_force",
    "rigid_brush_enhancement",
    "soft_brush_enhancement",
    "soft_brush_force",
    "ideal_sharing_force",
    "soft_brush_work_of_separation",
    "soft_brush_work_normalized",
    "adhesion_coefficient",
    "critical_roughness",
    "ROUGHNESS_SCALES",
    "IndependentPullOff",
    "IndependentRoughBrush",
    "independent_pillars_pull_off",
    "independent_rough_brush",
    "independent_gaussian_plateau",
    # hierarchy
    "hierarchy_stiffnesses",
    "total_filling_factor",
    "equivalent_single_level_stiffness",
    # concave profile
    "concave_reference_stress",
    "concave_profile",
    "concave_pillar_profile",
    "concave_offsets",
]
