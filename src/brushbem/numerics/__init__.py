"""The numerics: transforms on any array namespace, the contact operator, and the solvers.

Modules
    `backend`
        The one host/device boundary (`backend.to_numpy`), the padded FFT
        convolutions, segment sums and the small dense SPD solves, for NumPy
        or a device namespace (CuPy).
    `operator`
        A = K + springs on a window of the grid (`ContactOperator`), restricted
        to a contact set (`MaskedOperator`, `ContactSystem`).
    `solver`
        Preconditioned CG on a contact set, its preconditioners (shifted
        Laplacian, springs by Woodbury, the two-level pillar blocks), the
        equilibrium with the Pohrt-Popov detachment criterion and its local
        cascade, and Polonsky-Keer for the contact problems.
    `nested`
        The thesis's nested loop (ch. 3), kept to compare with the convolution.

No module here knows a configuration key: errors name the parameters of the
Python objects (`brushbem.errors.ParameterError`), and
`brushbem.runs.assembly` maps them back to keys.
"""
