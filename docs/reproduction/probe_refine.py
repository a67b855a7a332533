"""Where a mesh refinement of Kendall's punch is in its asymptotic range (`brushbem.runs.refine`).

A rigid flat punch (r = 0.25, E* = 1, dgamma = 1e-3, L = 1, preload displacement 0.01) on N = 8
to 256 (r / h = 2 to 64).  Prints F_A and the work of separation against Kendall's closed forms
(eq. 2.16, 2.18-2.19): F_A is +2.0, +5.8, +6.3, +2.2, +0.5, +0.7 % off, rising up to r / h = 8
and oscillating from 32 on with the rasterised circle's staircase.  This is why a refinement's
coarsest grid must resolve the deciding length by 8 elements (`MIN_REFINE_ELEMENTS`) and why
the three-grid bound includes the change of the extrapolation between grid pairs.
Run from the repository root: ``python docs/reproduction/probe_refine.py`` (about 2 CPU-s).
"""

from __future__ import annotations

from brushbem.physics import theory
from brushbem.runs.assembly import parse_config
from brushbem.runs.case import run_case

RADIUS = 0.25
force = float(theory.kendall_force(RADIUS, contact_modulus=1.0, work_of_adhesion=1e-3))
work = float(theory.punch_spring_work_of_separation(RADIUS, float("inf"), contact_modulus=1.0, work_of_adhesion=1e-3))
print("| N | r / h | F_A / Kendall - 1 | W / closed form - 1 |")
print("| --- | --- | --- | --- |")
for elements in (8, 16, 32, 64, 128, 256):
    config = parse_config({
        "halfspace": {"contact_modulus": 1.0, "work_of_adhesion": 1e-3},
        "grid": {"size": 1.0, "elements": elements},
        "indenter": {"shape": "flat_punch", "radius": RADIUS},
        "protocol": {"preload_displacement": 0.01},
    })
    summary = run_case(config).result.summary
    print(f"| {elements} | {RADIUS * elements:g} | {summary['adhesive_force'] / force - 1:+.4f} | "
          f"{summary['work_of_separation'] / work - 1:+.4f} |", flush=True)
