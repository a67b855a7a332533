"""The pillar model's error against its modes and against the pillar radius in elements: ``variants.md``.

Two experiments on square lattices at phi = 0.16 (E* = 1, work of adhesion
1e-4, seed 3, pressed to the rigid flat lattice's force F_c), each variant
of ``brushbem.pillars.pull_off`` against the exact event path on
the same problem:

* modes: 4 x 4 at N = 64 and 8 x 8 at N = 128 (pillars of 3.6 elements'
  radius), each level at k~ = 10, 1e-2 and 1e-4 and rough at k~ = 1e-2,
  sigma~ = 1 and k~ = 10, sigma~ = 0.3 (ten brushes); the variants: the
  uniform mode alone, the tilts without and with peeling, the quadratic
  modes (the default) and the quadratic modes coupled in full.  The table
  gives the range of the errors over the ten brushes.
* radius: a 4 x 4 lattice at N = 40, 64 and 128 (2.3, 3.6 and 7.2
  elements' radius), rough at k~ = 1e-2, sigma~ = 1 and level at k~ = 10.

    nice python docs/pillars/variants.py
"""

from __future__ import annotations

import math
import os
from pathlib import Path

from brushbem.physics.structure import Grid, brush
from brushbem import pillars
from brushbem.protocol import ContactProblem, LoadPath, record_pull_off
from brushbem.protocol.recording import work_of_separation
from brushbem.runs.case import brush_scales

HERE = Path(__file__).resolve().parent
PHI, DGAMMA, SEED = 0.16, 1e-4, 3

VARIANTS = {
    "uniform mode, whole pillars": dict(modes="uniform", peel=False),
    "tilt modes, whole pillars": dict(modes="tilt", peel=False),
    "tilt modes, peeling tips": dict(modes="tilt"),
    "quadratic, peeling, local (default)": dict(),
    "quadratic, peeling, full": dict(coupling="full"),
}


def lattice(elements: int, per_side: int, stiffness: float, sigma: float) -> tuple[ContactProblem, float]:
    grid = Grid(1.0, elements)

    def build(roughness: float) -> ContactProblem:
        tips = brush(grid, layout="square", pillars_per_side=per_side, pillar_radius=math.sqrt(PHI / math.pi) / per_side,
                     contact_modulus=1.0, work_of_adhesion=DGAMMA, stiffness=stiffness, roughness=roughness, seed=SEED)
        return ContactProblem(grid, tips, contact_modulus=1.0, work_of_adhesion=DGAMMA)

    scales = brush_scales(build(0.0))
    return build(sigma * scales["rigid_brush_displacement"]), scales["rigid_brush_force"]


def errors(problem: ContactProblem, preload: float, options: dict, reference: dict) -> tuple[float, float]:
    path = LoadPath(method="pillars", preload_force=preload, max_steps=10**7, pillar_tip_peel=False)
    states = list(pillars.pull_off(problem, path, **options))
    loading = [state for state in states if state.loading]
    unloading = [(loading[-1].displacement, loading[-1].force)]
    unloading += [(state.displacement, state.force) for state in states if not state.loading]
    adhesive = max(0.0, -min(force for _, force in unloading))
    work = work_of_separation([(d, max(force, -adhesive)) for d, force in unloading])
    return adhesive / reference["adhesive_force"] - 1, work / reference["work_of_separation"] - 1


def exact(problem: ContactProblem, preload: float) -> dict:
    return record_pull_off(problem, LoadPath(method="events", preload_force=preload, max_steps=10**7)).summary


def main() -> None:
    brushes = [(elements, n, k, 0.0) for elements, n in ((64, 4), (128, 8)) for k in (10.0, 1e-2, 1e-4)]
    brushes += [(elements, n, k, s) for elements, n in ((64, 4), (128, 8)) for k, s in ((1e-2, 1.0), (10.0, 0.3))]
    found: dict[str, list[tuple[float, float]]] = {name: [] for name in VARIANTS}
    for case in brushes:
        problem, preload = lattice(*case)
        reference = exact(problem, preload)
        for name, options in VARIANTS.items():
            found[name].append(errors(problem, preload, options, reference))
        print(case, {name: found[name][-1] for name in VARIANTS}, flush=True)
    lines = ["# The pillar model's modes and the pillar radius in elements", "",
             "Written by `docs/pillars/variants.py` (the brushes are in its docstring).  Relative errors of the",
             "pillar model against `method = \"events\"` on the same problem.", "",
             "## Modes: range of the errors over ten brushes", "",
             "| variant | F_A error | work error |", "| --- | ---: | ---: |"]
    for name, values in found.items():
        force = [100 * f for f, _ in values]
        work = [100 * w for _, w in values]
        lines.append(f"| {name} | {min(force):+.1f} .. {max(force):+.1f} % | {min(work):+.1f} .. {max(work):+.1f} % |")
    lines += ["", "## Pillar radius in elements: F_A / work errors", "",
              "| radius (elements) | case | uniform | tilt, peeling | quadratic (default) |",
              "| ---: | --- | ---: | ---: | ---: |"]
    chosen = {name: VARIANTS[name] for name in ("uniform mode, whole pillars", "tilt modes, peeling tips",
                                                "quadratic, peeling, local (default)")}
    for elements in (40, 64, 128):
        for stiffness, sigma, label in ((1e-2, 1.0, "k~ = 1e-2, sigma~ = 1"), (10.0, 0.0, "k~ = 10, level")):
            problem, preload = lattice(elements, 4, stiffness, sigma)
            reference = exact(problem, preload)
            radius = math.sqrt(PHI / math.pi) / 4 * elements
            cells = []
            for options in chosen.values():
                force, work = errors(problem, preload, options, reference)
                cells.append(f"{100 * force:+.1f} / {100 * work:+.1f} %")
            lines.append(f"| {radius:.1f} | {label} | " + " | ".join(cells) + " |")
            print(lines[-1], flush=True)
    target = HERE / "variants.md"
    temporary = target.with_suffix(".md.tmp")
    temporary.write_text("\n".join(lines) + "\n")
    os.replace(temporary, target)


if __name__ == "__main__":
    main()
