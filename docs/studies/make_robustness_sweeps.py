"""Write the sweeps of the `robustness` study: designed, flat and concave brushes under roughness and tilt.

For each grid (the full one of the thesis's Fig. 7-5 setting and its quick
twin) and each stiffness (k~ = 6e-4 and 10), the equal-load-sharing design
of `brushbem design` is computed here and shipped as a lengths file
(``robustness.<grid>.k<k~>.npy``, lengths = -offsets), beside a file of zeros
(the flat brush); the concave brush is the flat one with the thesis's
profile h~ (eq. 7.3) near its optimum for that stiffness (0.2 for k~ = 6e-4,
measured on the full grid; 0.04 for k~ = 10, the thesis's Fig. 7-6 a).
Every brush is then pulled off with added Gaussian roughness sigma~ (pillar
lengths, eq. 5.1, in units of |d_c|; several seeds) and under a tilt of the
base.  Run from the repository root:

    python docs/studies/make_robustness_sweeps.py
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from make_beyond_sweeps import _toml

from brushbem.runs.case import brush_scales
from brushbem.design import design
from brushbem.protocol import ContactProblem, LoadPath
from brushbem.physics.structure import Grid, brush

SWEEPS = Path(__file__).resolve().parents[2] / "src" / "brushbem" / "studies" / "sweeps"
DGAMMA, PHI = 1e-4, 0.06
GRIDS = {"full": (512, 16), "quick": (64, 4)}
STIFFNESS = {6e-4: 0.2, 10.0: 0.04}  # k~ -> the concave brush's h~


def main() -> None:
    for kind, (n, m) in GRIDS.items():
        suffix = "" if kind == "full" else ".quick"
        grid = Grid(1.0, n)
        radius = round(math.sqrt(PHI / math.pi) / m, 8)
        zeros = None
        rows = {"lengths": [], "profile": [], "stiffness": [], "label": []}
        for k, h in STIFFNESS.items():
            indenter = brush(grid, layout="square", region="circle", pillars_per_side=m, pillar_radius=radius,
                             contact_modulus=1.0, work_of_adhesion=DGAMMA, stiffness=k)
            problem = ContactProblem(grid, indenter, contact_modulus=1.0, work_of_adhesion=DGAMMA)
            scales = brush_scales(problem)
            preload = round(2 * scales["ideal_sharing_force"], 7)
            d_c = scales["rigid_brush_displacement"]
            result = design(problem, LoadPath(method="events", preload_force=preload, max_steps=10**6),
                            iterations=0)
            name = f"robustness{suffix}.k{k:g}.npy"
            np.save(SWEEPS / name, -result.values)
            if zeros is None:
                zeros = f"robustness{suffix}.flat.npy"
                np.save(SWEEPS / zeros, np.zeros(indenter.n_pillars))
            print(kind, k, "designed F~", result.verified_force_ratio)
            for label, lengths, profile in (("flat", zeros, 0.0), ("concave", zeros, h), ("designed", name, 0.0)):
                rows["lengths"].append(lengths)
                rows["profile"].append(profile)
                rows["stiffness"].append(k)
                rows["label"].append(label)
        base = {
            "halfspace": {"contact_modulus": 1.0, "work_of_adhesion": DGAMMA},
            "grid": {"size": 1.0, "elements": n},
            "indenter": {"shape": "brush", "layout": "square", "region": "circle", "pillars_per_side": m,
                         "pillar_radius": radius, "stiffness_ratio": 10.0, "seed": 0,
                         "lengths_file": zeros, "profile": {"amplification": 0.0},
                         "roughness": {"sigma": 0.0}, "tilt": {"angle": 0.0}},
            "protocol": {"method": "events", "preload_force": preload},
        }
        header = (f"Robustness of the equal-load-sharing design (brushbem design) against the flat and the concave\n"
                  f"brush (h~ = {STIFFNESS[6e-4]} for k~ = 6e-4, {STIFFNESS[10.0]} for k~ = 10): the brushes "
                  f"{rows['label'][:3]} per stiffness, zipped.\nCircle region, phi = {PHI}, grid N = {n}, "
                  f"{m} x {m} lattice; pressed to 2 N F_K = {preload:g} (eq. 7.4).")
        if kind == "quick":
            header += "\nQuick grid: tests the machinery, not a converged number."
        sigmas = [0.0, 0.1, 0.3, 1.0] if kind == "full" else [0.0, 0.5]
        realizations = 5 if kind == "full" else 2
        angles = [0.0, 0.05, 0.1, 0.2, 0.5] if kind == "full" else [0.0, 0.2]
        for part, swept, note in (
            ("roughness", ("indenter.roughness.sigma", [round(s * d_c, 9) for s in sigmas]),
             f"Added Gaussian roughness sigma = {sigmas} |d_c| (|d_c| = {d_c:.4g}), {realizations} seeds each."),
            ("tilt", ("indenter.tilt.angle", angles), f"Tilt of the base: {angles} degrees (azimuth 0)."),
        ):
            key, values = swept
            lines = [f"# {line}" for line in (header + "\n" + note).splitlines()]
            cases = [(lf, pr, st, v) for lf, pr, st in zip(rows["lengths"], rows["profile"], rows["stiffness"])
                     for v in values]
            lines += [f"base = {_toml(base)}", 'mode = "zip"',
                      f"realizations = {realizations if part == 'roughness' else 1}", "seed = 11", "", "[sweep]",
                      f'"indenter.lengths_file" = {_toml([c[0] for c in cases])}',
                      f'"indenter.profile.amplification" = {_toml([c[1] for c in cases])}',
                      f'"indenter.stiffness_ratio" = {_toml([c[2] for c in cases])}',
                      f'"{key}" = {_toml([c[3] for c in cases])}']
            (SWEEPS / f"robustness.{part}{suffix}.toml").write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
