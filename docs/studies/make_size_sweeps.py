"""Write the sweep files of the ``size`` study: F~_A and the work against the number of pillars.

Square lattices of n x n flat pillars at the thesis's ch. 4 filling factor
phi = 0.12 in the unit square, pillars of 3.1 elements' radius (N = 16 n),
E* = 1, work of adhesion 1e-4, pressed to the rigid flat brush's force F_c
(computed here for every n, so that the files state plain numbers) and
pulled off by the pillar-level model (``protocol.method = "pillars"``).  One
part per brush, its sizes zipped with the grid, the radius and the preload:

* ``stiff`` (k~ = 10, near the rigid limit of eq. 4.9), ``soft``
  (k~ = 1e-2) and ``softer`` (k~ = 1e-4, the plateau of eq. 4.10): level tips;
* ``rough_small`` and ``rough_large``: k~ = 1e-2 with Gaussian lengths of
  sigma~ = 0.1 and 1 (sigma = sigma~ d_c, d_c of the same n).

Full: n = 8, 16, 32, 48, 64, 80, 100 (64 to 10^4 pillars), and for the level
parts and both rough ones also n = 316 (10^5 pillars; a level brush attaches
all of them, solved by CG on the lattice's FFT product instead of a kept
inverse, `brushbem.pillars.cg`); quick: n = 4, 6, 8.  Run from the repository root:

    python docs/studies/make_size_sweeps.py
"""

from __future__ import annotations

import math
from pathlib import Path

from brushbem.physics.structure import Grid, brush
from brushbem.protocol import ContactProblem
from brushbem.runs.case import brush_scales

SWEEPS = Path(__file__).resolve().parents[2] / "src" / "brushbem" / "studies" / "sweeps"
DGAMMA, PHI = 1e-4, 0.12
SIZES = {"full": [8, 16, 32, 48, 64, 80, 100], "quick": [4, 6, 8]}
#: Sizes of the full grid beyond 10^4 pillars, by part.
BEYOND = {"stiff": [316], "soft": [316], "softer": [316], "rough_small": [316], "rough_large": [316]}
PARTS = {
    "stiff": (10.0, 0.0),
    "soft": (1e-2, 0.0),
    "softer": (1e-4, 0.0),
    "rough_small": (1e-2, 0.1),
    "rough_large": (1e-2, 1.0),
}


def _radius(per_side: int) -> float:
    return round(math.sqrt(PHI / math.pi) / per_side, 9)


def _scales(per_side: int) -> dict:
    grid = Grid(1.0, 16 * per_side)
    indenter = brush(grid, layout="square", pillars_per_side=per_side, pillar_radius=_radius(per_side),
                     contact_modulus=1.0, work_of_adhesion=DGAMMA, stiffness=1.0)
    return brush_scales(ContactProblem(grid, indenter, contact_modulus=1.0, work_of_adhesion=DGAMMA))


def _toml(value) -> str:
    if isinstance(value, str):
        return f'"{value}"'
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, dict):
        return "{ " + ", ".join(f"{k} = {_toml(v)}" for k, v in value.items()) + " }"
    if isinstance(value, list):
        return "[" + ", ".join(_toml(v) for v in value) + "]"
    return repr(float(value)) if isinstance(value, float) else str(value)


def main() -> None:
    for kind, suffix in (("full", ""), ("quick", ".quick")):
        scales = {n: _scales(n) for n in SIZES[kind]}
        for part, (ratio, sigma) in PARTS.items():
            sizes = SIZES[kind] + (BEYOND.get(part, []) if kind == "full" else [])
            scales.update({n: _scales(n) for n in sizes if n not in scales})
            indenter = {"shape": "brush", "layout": "square", "pillars_per_side": sizes[0],
                        "pillar_radius": _radius(sizes[0]), "stiffness_ratio": ratio, "seed": 0}
            sweep = {"grid.elements": [16 * n for n in sizes], "indenter.pillars_per_side": sizes,
                     "indenter.pillar_radius": [_radius(n) for n in sizes],
                     "protocol.preload_force": [round(scales[n]["rigid_brush_force"], 9) for n in sizes]}
            if sigma:
                indenter["roughness"] = {"sigma": round(sigma * scales[sizes[0]]["rigid_brush_displacement"], 10)}
                sweep["indenter.roughness.sigma"] = [round(sigma * scales[n]["rigid_brush_displacement"], 10)
                                                     for n in sizes]
            base = {"halfspace": {"contact_modulus": 1.0, "work_of_adhesion": DGAMMA},
                    "grid": {"size": 1.0, "elements": 16 * sizes[0]}, "indenter": indenter,
                    "protocol": {"method": "pillars", "preload_force": sweep["protocol.preload_force"][0],
                                 "pillar_tip_peel": False}}
            brush_text = f"k~ = {ratio:g}" + (f", Gaussian lengths sigma~ = {sigma:g} (sigma = sigma~ d_c)"
                                              if sigma else ", level tips")
            header = [f"Size study, part {part}: n x n pillars for n = {sizes} ({sizes[0]**2} to {sizes[-1]**2}), "
                      f"{brush_text}.",
                      f"phi = {PHI} (thesis ch. 4), r = 3.1 elements (N = 16 n); pressed to the rigid flat brush's "
                      "F_c of each n; method = \"pillars\" (docs/pillars/validation.md).",
                      "Written by docs/studies/make_size_sweeps.py."]
            if kind == "quick":
                header.append("Quick grid: tests the machinery, not a converged number.")
            lines = [f"# {line}" for line in header]
            lines += [f"base = {_toml(base)}", 'mode = "zip"', "realizations = 1", "seed = 0", "", "[sweep]"]
            lines += [f'"{key}" = {_toml(values)}' for key, values in sweep.items()]
            (SWEEPS / f"size.{part}{suffix}.toml").write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
