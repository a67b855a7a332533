"""Chapter 4's work of separation of a stiff brush (Fig. 4-7, 'roughly equal to' the rigid punch): W~ against the mesh.

W~ = W / (2 dgamma A) is 1 exactly for the compact rigid punch of the same real area A and for the
homogenised rigid brush of eq. 4.5 and 4.12 (both release W = F d / 2 = 2 dgamma A at once).  The
discrete brush is not homogenised: this probe computes W~, F_A / F_c and d_A / d_c of the 8 x 8
brush of `flat_brush.regular` (phi ~ 0.12, L = 1, E* = 1, dgamma = 1e-4) at k~ = 10 and with rigid
pillars, on N = 256, 512 and 1024, to tell a mesh error from the brush's own energy.

Run from the repository root: ``python docs/reproduction/probe_rigid_work.py`` (a few CPU-minutes).
"""

from __future__ import annotations

import math
import time

from brushbem import pull_off
from brushbem.physics import theory
from brushbem.physics.structure import Grid, brush

E, DGAMMA, RADIUS, PER_SIDE = 1.0, 1e-4, 0.02443, 8

print("| N | k~ | pillar radius (elements) | F_A / F_c | d_A / d_c | W~ | solves | CPU s |")
print("| --- | --- | --- | --- | --- | --- | --- | --- |")
for n in (256, 512, 1024):
    grid = Grid(1.0, n)
    for k in (10.0, math.inf):
        start = time.process_time()
        indenter = brush(grid, layout="square", pillars_per_side=PER_SIDE, pillar_radius=RADIUS, contact_modulus=E,
                         work_of_adhesion=DGAMMA, stiffness=k)
        phi = indenter.description["real_area"]  # L = 1: the rasterised filling factor
        result = pull_off(grid, indenter, contact_modulus=E, work_of_adhesion=DGAMMA, preload_displacement=0.002)
        fc = theory.rigid_brush_force(phi, 1.0, contact_modulus=E, work_of_adhesion=DGAMMA)
        dc = abs(theory.rigid_brush_displacement(phi, 1.0, contact_modulus=E, work_of_adhesion=DGAMMA))
        w = result.work_of_separation / (2 * DGAMMA * phi)
        print(f"| {n} | {k:g} | {RADIUS * n:.1f} | {result.adhesive_force / fc:.4f} | "
              f"{abs(result.pull_off_displacement) / dc:.4f} | {w:.4f} | {result.summary['n_solves']} | "
              f"{time.process_time() - start:.0f} |", flush=True)
