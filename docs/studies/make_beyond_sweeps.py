"""Write the sweep files of the studies beyond the thesis (tip_shape, grading, tilt, viscoelastic).

Every preload is 2 N F_K of the rasterised brush (N F_K the ideal-sharing force
of eq. 7.4, as in the thesis's ch. 7), computed here from the structure so
that the files state plain numbers.  Run from the repository root:

    python docs/studies/make_beyond_sweeps.py
"""

from __future__ import annotations

import math
from pathlib import Path

from brushbem.runs.case import brush_scales
from brushbem.protocol import ContactProblem
from brushbem.physics.structure import Grid, brush

SWEEPS = Path(__file__).resolve().parents[2] / "src" / "brushbem" / "studies" / "sweeps"
DGAMMA = 1e-4

# (elements, pillars per side): the full grids and their quick twins.
SQUARE = {"full": (256, 16), "quick": (64, 4)}  # phi = 0.12, r = 3.1 elements (thesis ch. 4)
CIRCLE = {"full": (512, 16), "quick": (64, 4)}  # phi = 0.06 in a circle (thesis ch. 7)


def _square_radius(per_side: int) -> float:
    return round(math.sqrt(0.12 / math.pi) / per_side, 7)


def _circle_radius(per_side: int) -> float:
    return round(math.sqrt(0.06 / math.pi) / per_side, 8)


def _scales(elements: int, per_side: int, radius: float, region: str) -> dict:
    grid = Grid(1.0, elements)
    indenter = brush(grid, layout="square", region=region, pillars_per_side=per_side, pillar_radius=radius,
                     contact_modulus=1.0, work_of_adhesion=DGAMMA, stiffness=1.0)
    return brush_scales(ContactProblem(grid, indenter, contact_modulus=1.0, work_of_adhesion=DGAMMA))


def _toml(value) -> str:
    if isinstance(value, str):
        return f'"{value}"'
    if isinstance(value, dict):
        return "{ " + ", ".join(f"{k} = {_toml(v)}" for k, v in value.items()) + " }"
    if isinstance(value, list):
        return "[" + ", ".join(_toml(v) for v in value) + "]"
    return repr(float(value)) if isinstance(value, float) else str(value)


def _write(name: str, header: str, base: dict, sweep: dict, mode: str = "product") -> None:
    lines = [f"# {line}".rstrip() for line in header.strip().splitlines()]
    lines += [f"base = {_toml(base)}", f'mode = "{mode}"', "realizations = 1", "seed = 0", "", "[sweep]"]
    lines += [f'"{key}" = {_toml(values)}' for key, values in sweep.items()]
    (SWEEPS / name).write_text("\n".join(lines) + "\n")


def main() -> None:
    for kind, suffix in (("full", ""), ("quick", ".quick")):
        n, m = SQUARE[kind]
        radius = _square_radius(m)
        s = _scales(n, m, radius, "square")
        preload = round(2 * s["ideal_sharing_force"], 7)
        d_c = s["rigid_brush_displacement"]
        grid_note = f"Grid N = {n}, {m} x {m} pillars, phi = 0.12 (r = {radius / (1 / n):.2g} elements)"
        quick_note = " Quick grid: tests the machinery, not a converged number." if kind == "quick" else ""
        square = {
            "halfspace": {"contact_modulus": 1.0, "work_of_adhesion": DGAMMA},
            "grid": {"size": 1.0, "elements": n},
            "indenter": {"shape": "brush", "layout": "square", "pillars_per_side": m, "pillar_radius": radius,
                         "stiffness_ratio": 1.0, "seed": 0},
            "protocol": {"method": "events", "preload_force": preload},
        }
        # Tip shapes: spherical caps r / R and concave dishes depth / |d_c|.
        caps = dict(square, indenter={**square["indenter"], "tip": {"shape": "spherical_cap", "radius": 1.0}})
        cap_ratios = [0.02, 0.1, 0.2, 0.5, 1.0] if kind == "full" else [0.02, 0.5, 1.0]
        _write(f"tip_shape.caps{suffix}.toml",
               f"Tip shapes (thesis sec. 8.2, 1): spherical caps of radius R on every pillar, r / R = "
               f"{cap_ratios}.\n{grid_note}; k~ = 10 and 0.01; pressed to 2 N F_K = {preload:g} (eq. 7.4), "
               f"pulled off by the exact event path.{quick_note}",
               caps, {"indenter.stiffness_ratio": [10.0, 0.01],
                      "indenter.tip.radius": [round(radius / c, 7) for c in cap_ratios]})
        dishes = dict(square, indenter={**square["indenter"], "tip": {"shape": "concave", "depth": 1e-4}})
        depths = [0.05, 0.2, 0.5, 1.0] if kind == "full" else [0.05, 1.0]
        _write(f"tip_shape.dishes{suffix}.toml",
               f"Tip shapes: concave dishes of depth delta = {depths} |d_c| (|d_c| = {d_c:.4g}, eq. 4.12).\n"
               f"{grid_note}; k~ = 10 and 0.01; pressed to 2 N F_K = {preload:g}.{quick_note}",
               dishes, {"indenter.stiffness_ratio": [10.0, 0.01],
                        "indenter.tip.depth": [round(x * d_c, 8) for x in depths]})
        # Tilt: angles whose height range across the brush is up to ~5 |d_c|.
        angles = [0.0, 0.05, 0.1, 0.2, 0.5, 1.0, 2.0] if kind == "full" else [0.0, 0.2, 1.0]
        tilted = dict(square, indenter={**square["indenter"], "tilt": {"angle": 0.0, "azimuth": 0.0}})
        _write(f"tilt.angle{suffix}.toml",
               f"Misalignment: the base tilted by {angles} degrees about the y axis (azimuth 0).\n"
               f"tan(angle) L against |d_c| = {d_c:.4g}: 1 degree lifts the far edge by "
               f"{math.tan(math.radians(1)) / d_c:.2g} |d_c|.\n{grid_note}; stiff (k~ = 10) and soft (k~ = 0.01) "
               f"brushes; pressed to 2 N F_K = {preload:g}.{quick_note}",
               tilted, {"indenter.stiffness_ratio": [10.0, 0.01], "indenter.tilt.angle": angles})
        # Viscoelastic brush: a standard linear solid, k_0 = 10 k_inf, tau = 1, speeds v tau / |d_c|.
        speeds = [1e-3, 1e-2, 0.1, 1.0, 10.0, 100.0] if kind == "full" else [1e-3, 1.0, 100.0]
        step = round(d_c / 40, 9)
        visco = dict(square, indenter={**square["indenter"], "stiffness_ratio": 0.01,
                                       "viscoelastic": {"model": "standard_linear_solid", "relaxation_time": 1.0,
                                                        "instantaneous_factor": 10.0}},
                     protocol={"method": "fixed", "preload_displacement": round(0.5 * d_c, 9), "step": step,
                               "speed": 1.0})
        _write(f"viscoelastic.brush{suffix}.toml",
               f"Viscoelastic pillars (sec. 8.2, 3): standard linear solid, k_inf~ = 0.01, k_0 = 10 k_inf, "
               f"tau = 1;\nspeeds v = {speeds} |d_c| / tau (|d_c| = {d_c:.4g}); time-stepped by fixed steps "
               f"|d_c| / 40 to d = 0.5 |d_c|.\n{grid_note}.{quick_note}",
               visco, {"protocol.speed": [round(v * d_c, 10) for v in speeds]})
        # Viscoelastic punch: one flat pillar, k_inf = 2 E* a (k~ = 1), k_0 = 10 k_inf, tau = 1.
        grid_n = 256 if kind == "full" else 64
        a = 0.1
        d_k = math.sqrt(2 * math.pi * a * DGAMMA)  # eq. 2.4a, E* = 1
        _write(f"viscoelastic.punch{suffix}.toml",
               f"Viscoelastic single pillar: a flat punch of radius a = {a} on a standard linear solid, "
               f"k_inf = 2 E* a, k_0 = 10 k_inf, tau = 1;\nspeeds v = {speeds} d_K / tau (d_K = sqrt(2 pi a "
               f"dgamma / E*) = {d_k:.4g}, eq. 2.4a); fixed steps d_K / 40 to d = 0.5 d_K.\nGrid N = {grid_n} "
               f"(a = {a * grid_n:g} elements).{quick_note}",
               {"halfspace": {"contact_modulus": 1.0, "work_of_adhesion": DGAMMA},
                "grid": {"size": 1.0, "elements": grid_n},
                "indenter": {"shape": "flat_punch", "radius": a, "stiffness": 2 * a,
                             "viscoelastic": {"model": "standard_linear_solid", "relaxation_time": 1.0,
                                              "instantaneous_factor": 10.0}},
                "protocol": {"method": "fixed", "preload_displacement": round(0.5 * d_k, 9),
                             "step": round(d_k / 40, 9), "speed": 1.0}},
               {"protocol.speed": [round(v * d_k, 10) for v in speeds]})
        # Grading: circle region, phi = 0.06, radial amplitude (k at the rim / k at the centre - 1).
        n, m = CIRCLE[kind]
        radius = _circle_radius(m)
        s = _scales(n, m, radius, "circle")
        preload = round(2 * s["ideal_sharing_force"], 7)
        amplitudes = [-0.9, -0.75, -0.5, -0.25, 0.0, 0.5] if kind == "full" else [-0.75, 0.0]
        _write(f"grading.amplitude{suffix}.toml",
               f"Stiffness gradient (sec. 8.2, 2): k_n = k (1 + a (r_n / R)^2), a = {amplitudes} (a < 0: softer "
               f"rim), k~ = 6e-4 and 0.1,\ncircle region, phi = 0.06 (thesis ch. 7, Fig. 7-5's setting: its best "
               f"concave brush reaches F~ = 0.95).\nGrid N = {n}, {m} x {m} lattice (r = {radius * n:.2g} "
               f"elements); pressed to 2 N F_K = {preload:g}.{quick_note}",
               {"halfspace": {"contact_modulus": 1.0, "work_of_adhesion": DGAMMA},
                "grid": {"size": 1.0, "elements": n},
                "indenter": {"shape": "brush", "layout": "square", "region": "circle", "pillars_per_side": m,
                             "pillar_radius": radius, "stiffness_ratio": 6e-4, "seed": 0,
                             "grading": {"rule": "radial", "amplitude": 0.0, "exponent": 2.0}},
                "protocol": {"method": "events", "preload_force": preload}},
               {"indenter.stiffness_ratio": [6e-4, 0.1], "indenter.grading.amplitude": amplitudes})


if __name__ == "__main__":
    main()
