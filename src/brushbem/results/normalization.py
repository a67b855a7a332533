"""A brush's numbers in the thesis's normalisations: ``summary.json``'s ``normalized``.

The scales are the thesis's (eq. 4.5-4.13, 7.4): F_c of one compact punch of
the brush's real area (eq. 4.11), F_c of the rigid brush (eq. 4.5), N F_K of
ideal load sharing (eq. 7.4), and the rigid brush's critical displacement
|d_c| (eq. 4.12); stiffnesses as k~ = k / (E* L) (eq. 4.13).
`brushbem.physics.comparison.brush_normalizations` computes it.
"""

from __future__ import annotations

from dataclasses import dataclass

from brushbem.results.mapping import MappingRecord

__all__ = ["BrushNormalization"]


@dataclass(frozen=True, kw_only=True)
class BrushNormalization(MappingRecord):
    """The thesis's normalisations of an adhesive brush's summary numbers.

    Attributes
    ----------
    force_by_compact_punch, force_by_rigid_brush, force_by_ideal_sharing : float or None
        F_A over F_c of one compact punch of the real area (eq. 4.11), over F_c of
        the rigid brush (eq. 4.5) and over N F_K (eq. 7.4).
    displacement_by_rigid_brush, separation_displacement_by_rigid_brush, max_displacement_by_rigid_brush : float or None
        d_A, the separation displacement and the largest d over |d_c| (eq. 4.12).
    preload_by_rigid_brush, preload_by_compact_punch : float or None
        The preload force over the rigid brush's and the compact punch's F_c.
    roughness_by_rigid_brush : float or None
        The roughness sigma over |d_c| (sigma~, ch. 6).
    stiffness_ratio : float
        k~ = k / (E* L) of the first spring level (eq. 4.13); a graded level by its mean k.
    level_stiffness_ratios : list of float
        k~ of every level, the pillars' first.
    filling_factor : float
        phi, the pillars' share of the placement region.
    pillars, attached_pillars_at_pull_off : int
        N_p, and the pillars in contact at the adhesive force.
    profile_amplification : float or None
        h~ of a concave brush (eq. 7.2-7.3).
    equivalent_single_level_stiffness_ratio : float or None
        A hierarchy's k~ of the single level of the same stiffness (eq. 6.28); not a key without levels.
    """

    _ABSENT_WHEN_NONE = frozenset({"equivalent_single_level_stiffness_ratio"})

    force_by_compact_punch: float | None
    force_by_rigid_brush: float | None
    force_by_ideal_sharing: float | None
    displacement_by_rigid_brush: float | None
    separation_displacement_by_rigid_brush: float | None
    max_displacement_by_rigid_brush: float | None
    preload_by_rigid_brush: float | None
    preload_by_compact_punch: float | None
    roughness_by_rigid_brush: float | None
    stiffness_ratio: float
    level_stiffness_ratios: list
    filling_factor: float
    pillars: int
    attached_pillars_at_pull_off: int | None
    profile_amplification: float | None
    equivalent_single_level_stiffness_ratio: float | None = None
