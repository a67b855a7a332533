"""Chapter 4's work of separation of a stiff brush (Fig. 4-7, 'roughly equal to' the rigid punch): W~ against the mesh.

W~ = W / (2 dgamma A) is 1 exactly for the compact rigid punch of the same real area A and for the
homogenised rigid brush of eq. 4.5 and 4.12 (both release W = F d / 2 = 2 dgamma A at once).  The
discrete brush is not homogenised: this probe computes W~, F_A / F_c and d_A / d_c of the 8 x 8
brush of `flat_brush.regular` (phi ~ 0.12, L = 1, E* = 1, dgamma = 1e-4) at k~ = 10 and with rigid
pillars, on N = 256, 512 and 1024 (``--elements``: a subset), to tell a mesh error from the brush's own
energy.

Every finished case is written at once, atomically, to ``probe_rigid_work.csv`` beside this file; a
rerun skips the (N, k~) already there, so a stopped run resumes.  Run from the repository root:
``python docs/reproduction/probe_rigid_work.py [--elements 256 512]`` (a few CPU-minutes for all three N).
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

import pandas as pd

from brushbem import pull_off
from brushbem.io import atomic_path
from brushbem.physics import theory
from brushbem.physics.structure import Grid, brush

E, DGAMMA, RADIUS, PER_SIDE = 1.0, 1e-4, 0.02443, 8
OUTPUT = Path(__file__).with_suffix(".csv")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--elements", type=int, nargs="+", default=[256, 512, 1024])
    args = parser.parse_args()
    rows = pd.read_csv(OUTPUT).to_dict("records") if OUTPUT.exists() else []
    done = {(r["elements"], r["stiffness_ratio"]) for r in rows}
    print("| N | k~ | pillar radius (elements) | F_A / F_c | d_A / d_c | W~ | solves | CPU s |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- |")
    for n in args.elements:
        grid = Grid(1.0, n)
        for k in (10.0, math.inf):
            if (n, k) in done:
                continue
            start = time.process_time()
            indenter = brush(grid, layout="square", pillars_per_side=PER_SIDE, pillar_radius=RADIUS, contact_modulus=E,
                             work_of_adhesion=DGAMMA, stiffness=k)
            phi = indenter.description["real_area"]  # L = 1: the rasterised filling factor
            result = pull_off(grid, indenter, contact_modulus=E, work_of_adhesion=DGAMMA, preload_displacement=0.002)
            fc = theory.rigid_brush_force(phi, 1.0, contact_modulus=E, work_of_adhesion=DGAMMA)
            dc = abs(theory.rigid_brush_displacement(phi, 1.0, contact_modulus=E, work_of_adhesion=DGAMMA))
            rows.append({"elements": n, "stiffness_ratio": k, "radius_elements": RADIUS * n,
                         "force_over_fc": result.adhesive_force / fc,
                         "displacement_over_dc": abs(result.pull_off_displacement) / dc,
                         "work_tilde": result.work_of_separation / (2 * DGAMMA * phi),
                         "n_solves": result.summary["n_solves"], "cpu_s": time.process_time() - start})
            row = rows[-1]
            print(f"| {n} | {k:g} | {row['radius_elements']:.1f} | {row['force_over_fc']:.4f} | "
                  f"{row['displacement_over_dc']:.4f} | {row['work_tilde']:.4f} | {row['n_solves']} | "
                  f"{row['cpu_s']:.0f} |", flush=True)
            with atomic_path(OUTPUT) as path:
                pd.DataFrame(rows).to_csv(path, index=False)


if __name__ == "__main__":
    main()
