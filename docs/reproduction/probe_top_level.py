"""Chapter 6, Fig. 6-8 b: what the top level's stiffness k~3 can do, by the number of top-level units.

The shipped sweeps cluster the 40 x 40 lattice 5 x 5 (level 2) then 4 x 4 (level 3): N1 N2 = 400,
which eq. 6.28 with the thesis's k~ and k~1' = 0.4e-4 asks for, leaves 1600 / 400 = 4 top-level
units (N3, left open by the thesis: it follows from the pillar count, not stated).  Four springs
of 20 x 20 pillars can share load only between four blocks, so k~3 moves F~_A little.  This runs
the seed-0 cases of the ``stiffness`` set (k~3 = 2e-3 and 2e-2, sigma~ = 0.04 and 0.2, F~_P =
14.3) with the shipped clusters and with smaller top-level clusters (5 x 5 then 2 x 2: 16 units of
10 x 10 pillars; 2 x 2 then 2 x 2: 100 units of 4 x 4), and prints F~_A (rasterised F_c) and the
ratio sigma~ = 0.2 over 0.04 that the comparison's row reads:

    python docs/reproduction/probe_top_level.py
"""

import math

from brushbem.studies import SWEEPS_DIR
from brushbem.sweep import load_sweep
from probe_clusters import run_clustered  # this folder's probe of the level-2 and -3 cluster sizes

D_C = 0.00293498  # nominal (the sweeps' header)
K3 = "indenter.levels.1.stiffness_ratio"
CLUSTERINGS = ((5, 4), (5, 2), (2, 2))  # (pillars per side of a level-2 cluster, level-2 clusters per side of a level-3)
cases = [c for c in load_sweep(SWEEPS_DIR / "hierarchy.stiffness_k3.stiffness.sampled.toml").cases
         if c.realization == 0 and c.values["indenter.roughness.sigma"] / D_C < 0.3]
for first, second in CLUSTERINGS:
    forces = {}
    for case in cases:
        result, seconds = run_clustered(case, first, second)
        sigma_tilde = round(case.values["indenter.roughness.sigma"] / D_C, 3)
        forces[(case.values[K3], sigma_tilde)] = force = result.summary["normalized"]["force_by_rigid_brush"]
        units = (40 // (first * second)) ** 2
        print(f"clusters {first} x {first} then {second} x {second} ({units} top units): k~3 = {case.values[K3]:g}, "
              f"sigma~ = {sigma_tilde}: F~_A = {force:.4f}, converged {result.converged}, "
              f"{seconds:.0f} s", flush=True)
    for k3 in sorted({k for k, _ in forces}):
        low, high = (forces.get((k3, s), math.nan) for s in (0.04, 0.2))
        print(f"  k~3 = {k3:g}: F~_A(sigma~ = 0.2) / F~_A(0.04) = {high / low:.4f}", flush=True)
