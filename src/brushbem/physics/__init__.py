"""The model: the elastic body, the pillars' connections, the geometry, and the closed forms.

Modules
    `halfspace`
        The elastic half-space: the Love influence coefficients of uniform
        square elements, their spectrum for the FFT products, exact blocks.
    `springs`
        The linear pillar springs of every level (a pillar's own, hierarchy
        clusters) as segment sums over the elements.
    `pillar_laws`
        Nonlinear pillar force laws (piecewise linear: buckling, a tension
        cut-off) and the state of their pieces.
    `viscoelastic`
        Rate-dependent connections (Kelvin-Voigt, standard linear solid)
        and their history along a time-stepped path.
    `structure`
        The geometry: the grid, punches, spheres, height maps and brushes
        (layouts, lengths, tips, tilt, grading, hierarchy levels) rasterised
        on it, as `Indenter` records.
    `theory`
        The closed forms the computations are checked against: Kendall's
        punch, JKR, a punch or sphere on a spring, brushes (eq. 4.10),
        hierarchies, concave brushes, rough brushes.
    `comparison`
        A run's comparison with them (the ``theory`` record, a brush's
        scales and normalisations), beside the closed forms it calls.
    `pillar_model_domain`
        The rule of which problems the pillar-level model represents.
    `scales`, `adhesion`
        E*, k <-> k~ and the JKR radius once; the adhesion criterion.

Where are the pillar springs? Their stiffness is a record of the geometry
(`structure.SpringLevel`), their action on the elements is `springs` (linear)
or `pillar_laws` / `viscoelastic` (the nonlinear and rate-dependent
connections); `brushbem.numerics.operator` adds them to the half-space, and
`brushbem.protocol.connections` keeps their state along a pull-off.
"""
