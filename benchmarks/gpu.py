"""The same pull-offs on NumPy (CPU) and on CuPy (GPU), in one run: time, agreement, and the device's share.

Every case runs once per namespace (after one small warm-up pull-off per
namespace, which loads the FFT plans and kernels), with ``method =
"events"``; it prints one JSON line per case and namespace (wall time,
solves, CG iterations, F_A, work of separation) and one line per case with
the ratio of the NumPy time to the CuPy time and the relative differences of
F_A and of the work (the two take different CG systems on a brush, pillar
blocks on the host for NumPy and the window with the spring preconditioner
on the device, so they agree to the CG tolerance, about 1e-7, not to
rounding; ``tests/test_array_api.py``).  ``--max-seconds`` skips the cases
after the first namespace run that took longer.

    python benchmarks/gpu.py                       # needs cupy and a GPU
    python benchmarks/gpu.py --cases punch brush16 --max-seconds 120
"""

from __future__ import annotations

import argparse
import json
import math
import time

import numpy as np

from brushbem.runs.case import brush_scales
from brushbem.protocol import ContactProblem, LoadPath, record_pull_off
from brushbem.physics.structure import Grid, brush, flat_punch, sphere

DGAMMA = 1e-4


def _rough_brush(elements: int, per_side: int, stiffness_ratio: float, sigma: float):
    grid = Grid(1.0, elements)

    def make(roughness: float):
        return brush(grid, layout="square", pillars_per_side=per_side,
                     pillar_radius=math.sqrt(0.16 / math.pi) / per_side, contact_modulus=1.0,
                     work_of_adhesion=DGAMMA, stiffness=stiffness_ratio * grid.size, roughness=roughness, seed=3)

    scales = brush_scales(ContactProblem(grid, make(0.0), 1.0, DGAMMA))
    d_c = abs(scales["rigid_brush_displacement"])
    return grid, make(sigma * d_c), LoadPath(method="events", preload_force=scales["rigid_brush_force"],
                                             max_steps=10**7)


def _cases():
    return {
        "punch512": lambda: (Grid(1.0, 512), flat_punch(Grid(1.0, 512), 0.25, 0.05),
                             LoadPath(method="events", preload_displacement=1e-3)),
        "jkr512": lambda: (Grid(1.0, 512), sphere(Grid(1.0, 512), 1.0),
                           LoadPath(method="events", preload_displacement=2e-3)),
        "brush16": lambda: _rough_brush(256, 16, 0.01, 1.0),
        "brush32": lambda: _rough_brush(512, 32, 0.01, 1.0),
    }


def _run(grid, indenter, path, xp) -> dict:
    problem = ContactProblem(grid, indenter, 1.0, DGAMMA, xp=xp)
    start = time.perf_counter()
    summary = record_pull_off(problem, path).summary
    if xp is not np:
        xp.cuda.Device().synchronize()
    return {"wall": time.perf_counter() - start, "solves": summary["n_solves"],
            "cg_iterations": summary["n_cg_iterations"], "converged": bool(summary["converged"]),
            "adhesive_force": float(summary["adhesive_force"]),
            "work_of_separation": float(summary["work_of_separation"])}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", nargs="*", default=list(_cases()), choices=list(_cases()))
    parser.add_argument("--max-seconds", type=float, default=240.0)
    args = parser.parse_args()
    import cupy

    namespaces = {"numpy": np, "cupy": cupy}
    warm_grid = Grid(1.0, 64)
    for xp in namespaces.values():
        _run(warm_grid, flat_punch(warm_grid, 0.2, 0.05), LoadPath(method="events", preload_displacement=1e-3), xp)
    for name in args.cases:
        grid, indenter, path = _cases()[name]()
        results = {}
        for label, xp in namespaces.items():
            results[label] = _run(grid, indenter, path, xp)
            print(json.dumps({"case": name, "namespace": label, **results[label]}), flush=True)
        cpu, gpu = results["numpy"], results["cupy"]
        print(json.dumps({
            "case": name, "speedup": round(cpu["wall"] / gpu["wall"], 2),
            "adhesive_force_rel_diff": abs(gpu["adhesive_force"] / cpu["adhesive_force"] - 1),
            "work_rel_diff": abs(gpu["work_of_separation"] / cpu["work_of_separation"] - 1),
        }), flush=True)
        if max(cpu["wall"], gpu["wall"]) > args.max_seconds:
            print(json.dumps({"stopped": f"{name} took over {args.max_seconds} s"}), flush=True)
            break


if __name__ == "__main__":
    main()
