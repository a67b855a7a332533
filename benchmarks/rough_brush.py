"""Full pull-off of the thesis's chapter-5 rough brush: the exact path against its references.

A square n x n lattice of flat pillars filling the 1 x 1 domain at filling
factor phi = 0.16 (32 x 32 pillars of 3.6 elements' radius at N = 512: ours, the
thesis states no grid for chapter 5), Gaussian pillar lengths of standard deviation
sigma = sigma~ d_c, pressed to the force F_P = F~_P F_c and pulled off to
complete separation.  d_c and F_c are the rigid brush's pull-off
displacement and force of this rasterised brush (``case.brush_scales``),
E* = 1, work of adhesion 1e-4, L = 1.

For every k~ x sigma~ it prints one JSON line: the median wall time of
``--repeat`` runs of ``method = "events"`` (the default: the brush pressed
as contact problems, retracted event by event), its solves, F_A, the work of
separation, and, for each reference path named in ``--references`` (run
once, in the same process), its time, the ratio of its time to the events
path's and the relative differences of the events path's F_A and work
against it (``events / reference - 1``):

* ``element_events`` - every element event on both branches (the exact
  reference; affordable at N = 256 with 16 x 16 pillars: ~1.5 min a case),
* ``fixed`` - fixed steps of ``--fixed-step`` d_c (the shipped chapter-5
  sweeps used d_c / 5).

``--transforms`` also counts, in one more run of the events path, the padded
convolutions (the FFT pairs that every CG product and every deflection
costs), their median time, those of them in single precision (the late CG
iterations' products, `brushbem.numerics.solver.cg.ProductLedger`), the events of the pull-off and the solves per
event, and prints the floor they imply for any path that solves the
contact set exactly after each event: two solves per event (the state and
its unit response), each at least one product, at the measured cost of a
product (``floor_seconds``); the transforms of the run itself give
``transform_seconds``.

    python benchmarks/rough_brush.py --elements 512 --pillars-per-side 32
    python benchmarks/rough_brush.py --elements 512 --stiffness-ratios 0.01 --sigmas 1 --transforms
    python benchmarks/rough_brush.py --elements 256 --pillars-per-side 16 \\
        --references element_events fixed
"""

from __future__ import annotations

import argparse
import json
import math
import statistics
import time
from contextlib import contextmanager

from brushbem import backend
from brushbem.runs.case import brush_scales
from brushbem.protocol import ContactProblem, LoadPath, record_pull_off
from brushbem.physics.structure import Grid, brush


def _problem(grid: Grid, per_side: int, phi: float, ratio: float, roughness: float, seed: int) -> ContactProblem:
    indenter = brush(grid, layout="square", pillars_per_side=per_side,
                     pillar_radius=math.sqrt(phi / math.pi) / per_side,
                     contact_modulus=1.0, work_of_adhesion=1e-4, stiffness=ratio * grid.size,
                     roughness=roughness, seed=seed)
    return ContactProblem(grid, indenter, contact_modulus=1.0, work_of_adhesion=1e-4)


def _run(problem: ContactProblem, path: LoadPath) -> tuple[float, dict]:
    start = time.perf_counter()
    record = record_pull_off(problem, path)
    return time.perf_counter() - start, record.summary


@contextmanager
def _counted_transforms():
    """Count and time `backend.padded_convolution` and `padded_convolution_rows` while the block runs."""
    times: dict[str, list[float]] = {"padded_convolution": [], "padded_convolution_rows": []}
    originals = {name: getattr(backend, name) for name in times}
    times["single"] = []  # the products of padded_convolution_rows in single precision, among its others

    def timed(name):
        original = originals[name]

        def wrapper(*args, **kwargs):
            start = time.perf_counter()
            try:
                return original(*args, **kwargs)
            finally:
                times[name].append(time.perf_counter() - start)
                if name == "padded_convolution_rows" and args[1].dtype == "float32":
                    times["single"].append(times[name][-1])
        return wrapper

    for name in originals:
        setattr(backend, name, timed(name))
    try:
        yield times
    finally:
        for name, original in originals.items():
            setattr(backend, name, original)


def _transform_line(problem: ContactProblem, path: LoadPath) -> dict:
    """One more events run with its transforms counted: counts, medians, events and the exact-path floor."""
    with _counted_transforms() as times:
        record = record_pull_off(problem, path)
    curve = record.curve
    # Every event of the pull-off records two states: on its threshold, and after its cascade.
    events = max(1, int((~curve.loading).sum()) // 2)
    rows, full = times["padded_convolution_rows"], times["padded_convolution"]
    product = statistics.median(rows) if rows else statistics.median(full)
    return {
        "products": len(rows),
        "product_ms": round(1e3 * product, 3),
        "single_products": len(times["single"]),
        "single_product_ms": round(1e3 * statistics.median(times["single"]), 3) if times["single"] else None,
        "full_transforms": len(full),
        "full_transform_ms": round(1e3 * statistics.median(full), 3) if full else None,
        "transform_seconds": round(sum(rows) + sum(full), 2),
        "unloading_events": events,
        "solves_per_event": round(record.summary["n_solves"] / events, 2),
        "transforms_per_event": round((len(rows) + len(full)) / events, 2),
        "floor_seconds": round(2 * events * product, 2),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--elements", type=int, default=512)
    parser.add_argument("--pillars-per-side", type=int, default=32)
    parser.add_argument("--filling-factor", type=float, default=0.16)
    parser.add_argument("--stiffness-ratios", type=float, nargs="+", default=[10, 0.1, 0.01, 0.001])
    parser.add_argument("--sigmas", type=float, nargs="+", default=[0.1, 1.0, 2.0], help="sigma~ = sigma / d_c")
    parser.add_argument("--preload", type=float, default=1.0, help="F~_P = F_P / F_c")
    parser.add_argument("--seed", type=int, default=3)
    parser.add_argument("--references", nargs="*", default=[], choices=["element_events", "fixed"])
    parser.add_argument("--fixed-step", type=float, default=0.2, help="step of the fixed reference, in d_c")
    parser.add_argument("--repeat", type=int, default=1)
    parser.add_argument("--transforms", action="store_true",
                        help="count the padded convolutions of one more run and print the exact-path floor")
    args = parser.parse_args()
    grid = Grid(1.0, args.elements)
    n = args.pillars_per_side
    for ratio in args.stiffness_ratios:
        smooth = _problem(grid, n, args.filling_factor, ratio, 0.0, args.seed)
        scales = brush_scales(smooth)
        d_c = abs(scales["rigid_brush_displacement"])
        f_c = scales["rigid_brush_force"]
        for sigma in args.sigmas:
            problem = _problem(grid, n, args.filling_factor, ratio, sigma * d_c, args.seed)
            path = LoadPath(method="events", preload_force=args.preload * f_c, max_steps=10**7)
            runs = [_run(problem, path) for _ in range(args.repeat)]
            seconds = statistics.median(t for t, _ in runs)
            summary = runs[-1][1]
            line = {
                "elements": args.elements,
                "pillars": problem.indenter.n_pillars,
                "stiffness_ratio": ratio,
                "sigma_by_dc": sigma,
                "preload_by_fc": args.preload,
                "seconds": round(seconds, 2),
                "solves": summary["n_solves"],
                "converged": summary["converged"],
                "adhesive_force": summary["adhesive_force"],
                "force_by_fc": summary["adhesive_force"] / f_c,
                "work_of_separation": summary["work_of_separation"],
            }
            if args.transforms:
                line["transforms"] = _transform_line(problem, path)
            for name in args.references:
                method = "fixed" if name == "fixed" else "element_events"
                reference_path = LoadPath(method=method, preload_force=args.preload * f_c, max_steps=10**7,
                                          step=args.fixed_step * d_c)
                t_ref, ref = _run(problem, reference_path)
                line[name] = {
                    "seconds": round(t_ref, 2),
                    "solves": ref["n_solves"],
                    "speedup": round(t_ref / seconds, 2),
                    "adhesive_force_rel_diff": summary["adhesive_force"] / ref["adhesive_force"] - 1,
                    "work_rel_diff": summary["work_of_separation"] / ref["work_of_separation"] - 1,
                }
            print(json.dumps(line), flush=True)


if __name__ == "__main__":
    main()
