"""The pillar-level model (``method = "pillars"``) against the exact event path, and its cost with the brush's size.

The chapter-5 rough brush: a square n x n lattice of flat pillars filling the
1 x 1 domain at phi = 0.16 (pillars of 3.6 elements' radius: N = 16 n),
Gaussian pillar lengths of sigma = sigma~ d_c, k~ = 0.01, E* = 1, work of
adhesion 1e-4, pressed to F_c and pulled off to separation (d_c and F_c: the
rigid brush's scales, ``case.brush_scales``).

First line (``--compare``, default 32 x 32 at N = 512, sigma~ = 1): the exact
path's (``method = "events"``) CPU time, F_A and work, the pillar model's
(the median CPU time of ``--repeat`` runs), their relative differences and
the time ratio, measured in the same run.
Then one line per size of ``--sizes`` (pillars per side): the pillar model
alone (its time, states, solves, and the memory of its dense pillar-level
arrays); a size whose arrays exceed ``--memory-gb`` is reported with its
estimate instead of run.

With ``--tips Q ...`` instead: the tips' resolution (``protocol.pillar_tip_resolution``).  The same brush
(``--tip-brush`` pillars per side, ``--sigma``, ``--stiffness-ratio``) on the chapter-5 grid (3.6 elements
per radius: 16 per pitch, ``--tip-grid`` times that) with every tip on its own raster of at least Q elements
per radius (the grid subdivided f times; Q <= 3.6 x ``--tip-grid``: the grid's own): per Q the pillar model's
CPU time, F_A and work, and the exact path's beside it on the grid f N, the same brush (the same absolute
tip heights), where f N <= ``--exact-elements``, with their differences.  The pillar model runs here with its
tips on their rasters (``pillar_tip_peel = false``: the model the exact path checks element for element); the
first line is that with the grid's own tips.  ``--calibrate``: every resolution also with the tips' criterion
calibrated to Kendall's force (``protocol.pillar_tip_calibration``), its time and F_A beside; ``--peel``: also
with whole tips leaving at their continuum capacity (``protocol.pillar_tip_peel``, the model's default), its
time and its ratio to the rasters' in the same run.

Measured (CPU seconds of one core on a shared machine, sigma~ = 1, k~ = 0.01 unless named; 4.0 elements per
radius on the grid, ``--tip-grid 1.109``):

    pillars  tips/radius   CPU s    F_A          beside the exact path on the grid f N
    1024     4.0 (grid)     6.5     1.4958e-3
    1024     8.0           15.4     1.4813e-3
    1024     16.0          61.3     1.3038e-3
    10^4     4.0 (grid)    69.1     1.0363e-5
    10^4     8.0          144.3     9.680e-6
    10^4     16.0         510.4     9.502e-6     (3.9 GB resident)
    64       16.0           4.7     8.930e-4     k~ = 10: -0.02 % F_A, +0.12 % work (exact path 461 s)
    64       16.0          12.7     8.417e-3     k~ = 10, level: -0.39 %, -0.80 % (exact path 113 s)

Measured again with ``--calibrate`` (the tips' criterion calibrated to Kendall's force; ``--tips 8 16
--tip-brush 32 --tip-grid 1.109 --exact-elements 0 --calibrate``, and ``--tips 4 --tip-brush 100``):

    pillars  tips/radius   CPU s    F_A          calibrated: CPU s, F_A
    1024     4.0 (grid)     3.15    1.4958e-3    2.74    1.4030e-3
    1024     8.0            8.97    1.4813e-3    9.79    1.4057e-3
    1024     16.0          43.3     1.3038e-3   45.6     1.3551e-3
    10^4     4.0 (grid)    41.3     1.0363e-5   45.0     9.4463e-6

With ``--peel`` (whole tips leaving at their continuum capacity, ``protocol.pillar_tip_peel``; ``--tips 4
--tip-brush 100 --exact-elements 0 --peel``, ``--sigma 0`` and ``--sigma 1``, k~ = 0.01, one run each, the
machine's other core busy): CPU s and F_A of the tips on their rasters and of the option (today's default), and
the option's time over the rasters':

    pillars  sigma~  tips/radius   raster: CPU s, F_A       peel: CPU s, F_A, time ratio
    10^4     0       3.6 (grid)    20.1    1.0869e-2        13.5    9.9701e-3   0.67
    10^4     0       7.2           45.8    1.0523e-2        21.8    1.0104e-2   0.48
    10^4     1       3.6 (grid)    19.4    9.7373e-6        16.8    9.0607e-6   0.86
    10^4     1       7.2           27.8    9.6328e-6        32.4    9.1962e-6   1.16

Again with tips beyond the gain's table peeling by their elements (``--tips 4 8 --sigma 1``, one run):

    10^4     1       3.6 (grid)    19.9    9.7373e-6        14.3    9.0607e-6   0.72
    10^4     1       7.2           27.1    9.6328e-6        31.8    9.1962e-6   1.17
    10^4     1       10.8          63.0    9.7711e-6        44.2    9.1197e-6   0.70

The 10^4-pillar brush at sigma~ = 0.5 on the chapter-5 grid (3.6 elements per radius; ``--tips 7.2 --tip-brush
100 --sigma 0.5 --exact-elements 0``, one run, 131 CPU-s in all): the grid's tips 58.0 s (F_A 2.9422e-4), tips at
7.2 per radius 74.4 s (2.8745e-4, -2.3 %), 1.28 times the grid tips' time.

With ``--proxy 4`` (``--tip-brush 100 --sigma 0.5``, one run, 68 CPU-s in all): the brush at the grid's tips
44.95 s (F_A 2.9422e-4), the 4 x 4 brush of the same kind at the grid's tips 0.07 s and at 28.9 elements per
radius, calibrated, 22.58 s: 1.50 times the brush's time; the ratio 0.930 gives 2.7359e-4 (the correction
``docs/pillars/proxy.py`` measures within 1 % on the validation families; this rough brush has no reference).

On this rough brush neither sequence is converged at 16 elements per radius (-12 % from 8 to 16 without the
calibration, -3.6 % with it).  At 32 elements per radius (``--tips 32 --tip-brush 32 --tip-grid 1.109
--exact-elements 0``, uncalibrated) 552.8 CPU-s (3301 states, 3.2 GB resident) against the grid tips' 2.12 s in
the same run, F_A 1.3827e-3: +6.0 % from 16, so this brush is not converged there either (its F_A is a small net
of pulled and compressed pillars).  A peel's rounds and every raster's basis grow with the tip.  The 10^4-pillar
rough brush of ``benchmarks/large_brush.py --sizes 100 --sigma 0.5 --exact-max 0 --before cc45de7``
(the default, before and after the calibration and the pillar-level loading's changes, one run): 51.2 s
(loading 10.7 s, pull-off 40.5 s) against 57.0 s (17.2 s, 39.8 s), F_A and the work the same to 1e-14.

Where the tips' cost goes (cProfile of the 1024-pillar line at 16 elements per radius against the grid's
tips, the same brush): 3339 states and 2010 solves against 619 and 554 (a fine tip peels in more steps,
each a state and a solve of the brush); the peeling 51 % of the time, almost all of it the bases of the
peeled rasters (9031 computed, 7290 of them through the footprint's kept inverse at 4.7 ms each); the
states' global pressure 11 % (then written only where the tips press; now kept by element, `TipRaster.pressed`); the
near-field blocks 5 % (cached by shape and offset: on a lattice one footprint shape, computed once); the
solves 6 %; the model's build (bases and blocks of the full tips) 4 %.  The pillar-level system is the
same size at every tip resolution (M pillars, 6 modes).  Outside the peeled bases the run costs 6.7 times
the grid tips' (the states and solves alone).  A peeled raster's modes now cost O(n |E| m) in place of
O(n^2 m) (`brushbem.pillars.modes`): 41.8 s against 51.6 s in the
same run (medians of two, alternating; F_A to 2e-15).

    nice python benchmarks/pillars.py
    nice python benchmarks/pillars.py --compare 16 --sizes 16 32 48 100
    nice python benchmarks/pillars.py --tips 4 8 16 32 --tip-brush 8 --exact-elements 600
    nice python benchmarks/pillars.py --tips 4 8 16 32 --tip-brush 32 --exact-elements 0
"""

from __future__ import annotations

import argparse
import json
import math
import statistics
import time

from brushbem.runs.case import brush_scales
from brushbem.protocol import ContactProblem, LoadPath, record_pull_off
from brushbem.pillars.basis import DENSE_PILLARS
from brushbem.pillars import MODES
from brushbem.pillars.tips import tip_factor
from brushbem.physics.structure import Grid, brush

PHI, RADIUS_ELEMENTS = 0.16, 3.6
E, DGAMMA = 1.0, 1e-4


def _problem(per_side: int, ratio: float, sigma: float, seed: int, tip_grid: float = 1.0,
             factor: int = 1) -> tuple[ContactProblem, float]:
    """The brush and its preload F_c on the grid of ``tip_grid`` x 16 elements per pitch, or on that grid
    times ``factor`` with the same tip heights (sigma~ times d_c of the first grid)."""
    elements = round(16 * per_side * tip_grid)
    radius = math.sqrt(PHI / math.pi) / per_side

    def build(roughness: float, elements: int) -> ContactProblem:
        grid = Grid(1.0, elements)
        indenter = brush(grid, layout="square", pillars_per_side=per_side, pillar_radius=radius, contact_modulus=E,
                         work_of_adhesion=DGAMMA, stiffness=ratio * E * grid.size, roughness=roughness, seed=seed)
        return ContactProblem(grid, indenter, contact_modulus=E, work_of_adhesion=DGAMMA)

    scales = brush_scales(build(0.0, elements))
    return build(sigma * scales["rigid_brush_displacement"], elements * factor), scales["rigid_brush_force"]


def _run(problem: ContactProblem, method: str, preload: float, tips: float | None = None,
         calibrate: bool = False, peel: bool = False) -> tuple[float, dict]:
    """The CPU time of a pull-off (``time.process_time``: other processes on a shared machine do not count) and
    its summary; ``calibrate``: the tips' criterion calibrated to Kendall's force; ``peel``: whole tips leaving
    at their continuum capacity (else the tips peel on their rasters: the model the exact path checks)."""
    extra = {} if tips is None else {"pillar_tip_resolution": tips}
    if calibrate:
        extra["pillar_tip_calibration"] = True
    start = time.process_time()
    record = record_pull_off(problem, LoadPath(method=method, preload_force=preload, max_steps=10**7,
                                               pillar_tip_peel=peel, **extra))
    return time.process_time() - start, record.summary


def _dense_bytes(pillars: int, modes: int) -> int:
    """The pillar model's dense arrays on a lattice at most: the kept G00 and its entries' refresh steps (up to
    `DENSE_PILLARS` pillars) and the kept inverse if every pillar were attached (the higher modes' far field is
    an FFT over the lattice)."""
    return (12 * pillars * pillars if pillars <= DENSE_PILLARS else 0) + 8 * pillars * pillars


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--compare", type=int, default=32, help="pillars per side of the comparison (0: none)")
    parser.add_argument("--sizes", type=int, nargs="*", default=[48, 100], help="pillars per side, model alone")
    parser.add_argument("--stiffness-ratio", type=float, default=0.01)
    parser.add_argument("--sigma", type=float, default=1.0, help="sigma~ = sigma / d_c")
    parser.add_argument("--seed", type=int, default=3)
    parser.add_argument("--memory-gb", type=float, default=4.0)
    parser.add_argument("--repeat", type=int, default=3, help="runs of the model in the comparison (median)")
    parser.add_argument("--tips", type=float, nargs="*", default=None,
                        help="instead: tip resolutions (elements per pillar radius) of the pillar model")
    parser.add_argument("--tip-brush", type=int, default=8, help="pillars per side of --tips")
    parser.add_argument("--tip-grid", type=float, default=1.0,
                        help="the grid of --tips: this times 16 elements per pitch (3.6 per radius)")
    parser.add_argument("--exact-elements", type=int, default=600, help="largest grid of the exact path in --tips")
    parser.add_argument("--peel", action="store_true",
                        help="--tips: every resolution also with whole tips leaving at their continuum capacity")
    parser.add_argument("--calibrate", action="store_true",
                        help="--tips: every resolution also with the tips' criterion calibrated to Kendall's force")
    parser.add_argument("--proxy", type=int, default=0,
                        help="pillars per side of a small brush of the same tips whose F_A at 28.9 elements per radius "
                             "over the grid tips' corrects --tip-brush's (docs/pillars/proxy.py): its time beside")
    args = parser.parse_args()
    if args.proxy:
        _proxy(args)
        return
    if args.tips:
        _tip_resolutions(args)
        return
    modes = len(MODES["quadratic"])
    if args.compare:
        problem, preload = _problem(args.compare, args.stiffness_ratio, args.sigma, args.seed)
        t_exact, exact = _run(problem, "events", preload)
        runs = [_run(problem, "pillars", preload) for _ in range(args.repeat)]
        times = [seconds for seconds, _ in runs]
        t_model, model = statistics.median(times), runs[0][1]
        print(json.dumps({
            "pillars": problem.indenter.n_pillars, "elements": problem.grid.elements,
            "stiffness_ratio": args.stiffness_ratio, "sigma_by_dc": args.sigma,
            "events_cpu_seconds": round(t_exact, 2), "pillars_cpu_seconds": round(t_model, 2),
            "pillars_cpu_seconds_each": [round(seconds, 2) for seconds in times],
            "speedup": round(t_exact / t_model, 2),
            "events_adhesive_force": exact["adhesive_force"], "pillars_adhesive_force": model["adhesive_force"],
            "adhesive_force_rel_diff": model["adhesive_force"] / exact["adhesive_force"] - 1,
            "events_work": exact["work_of_separation"], "pillars_work": model["work_of_separation"],
            "work_rel_diff": model["work_of_separation"] / exact["work_of_separation"] - 1,
            "events_attached_at_pull_off": exact["attached_pillars_at_pull_off"],
            "pillars_attached_at_pull_off": model["attached_pillars_at_pull_off"],
            "converged": [exact["converged"], model["converged"]],
        }), flush=True)
    for per_side in args.sizes:
        memory = _dense_bytes(per_side**2, modes)
        line = {"pillars": per_side**2, "elements": 16 * per_side, "dense_arrays_gb": round(memory / 2**30, 2)}
        if memory > args.memory_gb * 2**30:
            line["skipped"] = (f"the dense pillar-level arrays need {memory / 2**30:.1f} GB (> --memory-gb = "
                               f"{args.memory_gb:g}) and every event costs O(M^2) = {per_side**4:.1e} operations")
            print(json.dumps(line), flush=True)
            continue
        problem, preload = _problem(per_side, args.stiffness_ratio, args.sigma, args.seed)
        seconds, summary = _run(problem, "pillars", preload)
        line.update({"cpu_seconds": round(seconds, 2), "states": summary["n_states"], "solves": summary["n_solves"],
                     "adhesive_force": summary["adhesive_force"], "work": summary["work_of_separation"],
                     "converged": summary["converged"]})
        print(json.dumps(line), flush=True)


def _tip_resolutions(args: argparse.Namespace) -> None:
    """``--tips``: the pillar model against the tips' resolution on one grid, the exact path on the grids that
    resolve the tips as much (where at most ``--exact-elements``)."""
    problem, preload = _problem(args.tip_brush, args.stiffness_ratio, args.sigma, args.seed, args.tip_grid)
    grid_tips = problem.indenter.description.pillar_radius / problem.grid.element_size
    for tip in [None, *args.tips]:
        factor = tip_factor(problem, tip)
        if tip is not None and factor == 1:
            continue  # the grid's own tips: the first line
        seconds, model = _run(problem, "pillars", preload, tip)
        line = {"pillars": problem.indenter.n_pillars, "elements": problem.grid.elements,
                "sigma_by_dc": args.sigma, "stiffness_ratio": args.stiffness_ratio,
                "pillar_tip_resolution": tip, "tip_elements_per_radius": round(factor * grid_tips, 3),
                "pillars_cpu_seconds": round(seconds, 2), "pillars_adhesive_force": model["adhesive_force"],
                "pillars_work": model["work_of_separation"], "pillars_states": model["n_states"],
                "converged": model["converged"]}
        if args.calibrate:
            seconds, calibrated = _run(problem, "pillars", preload, tip, calibrate=True)
            line.update({"calibrated_cpu_seconds": round(seconds, 2),
                         "calibrated_adhesive_force": calibrated["adhesive_force"],
                         "calibrated_work": calibrated["work_of_separation"]})
        if args.peel:
            seconds, peeled = _run(problem, "pillars", preload, tip, peel=True)
            line.update({"peel_cpu_seconds": round(seconds, 2), "peel_time_ratio": round(seconds / line[
                "pillars_cpu_seconds"], 3), "peel_adhesive_force": peeled["adhesive_force"],
                "peel_work": peeled["work_of_separation"]})
        if factor * problem.grid.elements <= args.exact_elements and tip is not None:
            fine, _ = _problem(args.tip_brush, args.stiffness_ratio, args.sigma, args.seed, args.tip_grid, factor)
            t_exact, exact = _run(fine, "events", preload)
            line.update({"exact_elements": fine.grid.elements, "events_cpu_seconds": round(t_exact, 2),
                         "events_adhesive_force": exact["adhesive_force"], "events_work": exact["work_of_separation"],
                         "adhesive_force_rel_diff": model["adhesive_force"] / exact["adhesive_force"] - 1,
                         "work_rel_diff": model["work_of_separation"] / exact["work_of_separation"] - 1})
            if args.calibrate:
                line["calibrated_adhesive_force_rel_diff"] = calibrated["adhesive_force"] / exact["adhesive_force"] - 1
        print(json.dumps(line), flush=True)


def _proxy(args: argparse.Namespace) -> None:
    """``--proxy n``: the ``--tip-brush`` brush at the grid's tips and an n x n brush of the same kind (the same
    k~, sigma~ and seed, 3.6 elements per radius) at the grid's tips and at tips 8 times finer, calibrated: the
    brush's F_A times the small brush's ratio, and the time of all three over the brush's alone (one run)."""
    problem, preload = _problem(args.tip_brush, args.stiffness_ratio, args.sigma, args.seed, args.tip_grid)
    small, small_preload = _problem(args.proxy, args.stiffness_ratio, args.sigma, args.seed, args.tip_grid)
    per_radius = 8 * small.indenter.description.pillar_radius / small.grid.element_size
    t_brush, brush_summary = _run(problem, "pillars", preload)
    t_coarse, coarse = _run(small, "pillars", small_preload)
    t_fine, fine = _run(small, "pillars", small_preload, per_radius, calibrate=True)
    ratio = fine["adhesive_force"] / coarse["adhesive_force"]
    print(json.dumps({"pillars": problem.indenter.n_pillars, "proxy_pillars": small.indenter.n_pillars,
                      "sigma_by_dc": args.sigma, "stiffness_ratio": args.stiffness_ratio,
                      "brush_cpu_seconds": round(t_brush, 2), "proxy_coarse_cpu_seconds": round(t_coarse, 2),
                      "proxy_fine_cpu_seconds": round(t_fine, 2), "proxy_tip_elements_per_radius": round(per_radius, 3),
                      "time_ratio": round((t_brush + t_coarse + t_fine) / t_brush, 3),
                      "brush_adhesive_force": brush_summary["adhesive_force"], "proxy_ratio": ratio,
                      "corrected_adhesive_force": brush_summary["adhesive_force"] * ratio}), flush=True)


if __name__ == "__main__":
    main()
