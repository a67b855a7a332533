"""Chapter 5's 32 x 32 sensitivity rows against the mesh: seed 0 of the preload sweep at N = 512 and 1024.

The 32 x 32 brush of the part ``preload`` (N = 512, pillar radius 3.6 elements, phi = 0.16) refined to
N = 1024 (7.2 elements), the exact event path, realisation 0's seed: the plateaus (F~_P = 20) at
k~ = 10, sigma~ = 0.07; k~ = 0.001, sigma~ = 0.01 and 2.1, and the stiff brush's loss of adhesion
(k~ = 10, sigma~ = 0.39 at F~_P = 0.3 and 0.68 at F~_P = 1).  F~_A = F_A / F_c by the nominal F_c of
eq. 5.3 (the notes extrapolate to first order, 2 F(1024) - F(512)).  Only realisation 0 is run; the
plateaus' N = 512 cases (the first three) are also committed rows of ``rough_brush/preload.csv`` (seed
803261128, the same F~_A to the last digit where both ran), so ``--elements 1024`` alone refines them.
Every finished case is written at once, atomically, to ``probe_plateau_mesh.csv`` beside this file
(``--out``: elsewhere); a rerun skips the (case, N) already there, so a stopped run resumes.  ``--cases``
picks cases by their index in ``CASES`` (default: all).  Run from the repository root (CPU-hours
for all: the N = 512 cases take minutes each, as the committed seed-0 rows' wall times show, and N = 1024
four to five times longer; a 32 x 32 brush needs N >= 288 for its 2 elements a radius).  The committed table
holds the subset

    python docs/reproduction/probe_plateau_mesh.py --cases 1 --elements 512 1024     # 30 + 90 CPU-s
    python docs/reproduction/probe_plateau_mesh.py --cases 0 2 --elements 1024       # 229 and 801 CPU-s

The stiff brush's loss of adhesion (cases 3 and 4) is not in it.  ``--step D`` pulls off by fixed steps of
d_c / D (ours: the thesis states none) instead of the exact path, and writes only to a table named by ``--out``
(the committed table holds the exact path alone).
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import pandas as pd

from brushbem import pull_off
from brushbem.io import atomic_path
from brushbem.physics.structure import Grid, brush

E, DGAMMA, PER_SIDE, RADIUS = 1.0, 1e-4, 32, 0.00705237
F_C, D_C = 0.00849802, 0.00753117  # eq. 5.3-5.4 at phi = 0.16 (nominal), L = 1
SEED = 803261128  # the preload sweep's seed of realisation 0
#: (k~, sigma~, F~_P) of the rows the notes quote.
CASES = [(10.0, 0.07, 20.0), (0.001, 0.01, 20.0), (0.001, 2.1, 20.0), (10.0, 0.39, 0.3), (10.0, 0.68, 1.0)]
OUTPUT = Path(__file__).with_suffix(".csv")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--elements", type=int, nargs="+", default=[512, 1024])
    parser.add_argument("--out", type=Path, default=OUTPUT, help="the table written (default: beside this file)")
    parser.add_argument("--cases", type=int, nargs="+", default=list(range(len(CASES))),
                        help="indices into CASES (k~, sigma~, F~_P)")
    parser.add_argument("--step", type=float, default=None,
                        help="fixed steps of d_c / STEP instead of the exact event path (needs --out)")
    args = parser.parse_args()
    if args.step is not None and args.out == OUTPUT:
        parser.error(f"--step {args.step:g} needs --out: {OUTPUT.name} holds the exact event path only")
    protocol = {"method": "events"} if args.step is None else {"method": "fixed", "step": D_C / args.step}
    rows = pd.read_csv(args.out).to_dict("records") if args.out.exists() else []
    done = {(r["stiffness_ratio"], r["sigma_tilde"], r["preload_tilde"], r["elements"]) for r in rows}
    print("| k~ | sigma~ | F~_P | N | F~_A | solves | CPU s |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for k, sigma, preload in (CASES[i] for i in args.cases):
        for elements in args.elements:
            if (k, sigma, preload, elements) in done:
                continue
            grid = Grid(1.0, elements)
            indenter = brush(grid, layout="square", pillars_per_side=PER_SIDE, pillar_radius=RADIUS,
                             contact_modulus=E, work_of_adhesion=DGAMMA, stiffness=k * E * 1.0,
                             roughness=sigma * D_C, seed=SEED)
            start = time.process_time()
            result = pull_off(grid, indenter, contact_modulus=E, work_of_adhesion=DGAMMA,
                              preload_force=preload * F_C, **protocol)
            cpu = time.process_time() - start
            rows.append({"stiffness_ratio": k, "sigma_tilde": sigma, "preload_tilde": preload, "elements": elements,
                         "adhesive_force_tilde": result.adhesive_force / F_C, "n_solves": result.summary["n_solves"],
                         "cpu_s": cpu})
            print(f"| {k:g} | {sigma:g} | {preload:g} | {elements} | {rows[-1]['adhesive_force_tilde']:.4f} | "
                  f"{rows[-1]['n_solves']} | {cpu:.0f} |", flush=True)
            with atomic_path(args.out) as path:
                pd.DataFrame(rows).to_csv(path, index=False)

if __name__ == "__main__":
    main()
