"""How much a fixed displacement step moves chapter 5's numbers (the thesis states none: 'incremental displacement', L648).

Two cases of the committed chapter-5 tables (N = 512, 32 x 32 pillars, phi = 0.16, seed 0 of the
preload sweep), pulled off by the exact event path and by fixed steps of d_c/2 to d_c/40:

- a stiff brush in the linear region, k~ = 10, sigma~ = 0.5, F~_P = 0.3 (it carries c and Table 1);
- a soft one, k~ = 0.001, sigma~ = 1.0, F~_P = 0.1.

Prints F~_A = F_A / F_c and W / (F_c d_c) per step, and their ratio to the exact path.
Run from the repository root: ``python docs/reproduction/probe_step_range.py`` (CPU-minutes).
"""

from __future__ import annotations

import time

from brushbem import pull_off
from brushbem.physics.structure import Grid, brush

E, DGAMMA, PER_SIDE, RADIUS, N = 1.0, 1e-4, 32, 0.00705237, 512
F_C, D_C = 0.00849802, 0.00753117  # eq. 5.3-5.4 at phi = 0.16 (nominal), L = 1
SEED = 803261128  # the preload sweep's seed of realisation 0
CASES = [(10.0, 0.5, 0.3), (0.001, 1.0, 0.1)]
STEPS = [None, 2, 5, 10, 20, 40]  # None: the exact event path; else d_c / STEP

grid = Grid(1.0, N)
print("| k~ | sigma~ | F~_P | step | F~_A | W / (F_c d_c) | F_A / exact | W / exact | solves | CPU s |")
print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
for k, sigma, preload in CASES:
    indenter = brush(grid, layout="square", pillars_per_side=PER_SIDE, pillar_radius=RADIUS, contact_modulus=E,
                     work_of_adhesion=DGAMMA, stiffness=k * E * 1.0, roughness=sigma * D_C, seed=SEED)
    exact = None
    for divisor in STEPS:
        start = time.process_time()
        kwargs = {"method": "events"} if divisor is None else {"method": "fixed", "step": D_C / divisor}
        result = pull_off(grid, indenter, contact_modulus=E, work_of_adhesion=DGAMMA, preload_force=preload * F_C,
                          **kwargs)
        fa, w = result.adhesive_force / F_C, result.work_of_separation / (F_C * D_C)
        exact = exact or (fa, w)
        label = "exact" if divisor is None else f"d_c/{divisor}"
        print(f"| {k:g} | {sigma:g} | {preload:g} | {label} | {fa:.4f} | {w:.4f} | {fa / exact[0]:.3f} | "
              f"{w / exact[1]:.3f} | {result.summary['n_solves']} | {time.process_time() - start:.0f} |", flush=True)
