"""The exact event path against an older commit and with each of its speed-ups switched off, in one run.

The case is the chapter-5 rough brush of ``benchmarks/rough_brush.py`` (a
square n x n lattice of flat pillars at phi = 0.16, Gaussian lengths of
sigma~ d_c, pressed to F~_P F_c and pulled off to separation with
``method = "events"``); the default is its largest, 32 x 32 pillars at
N = 512, k~ = 0.01, sigma~ = 1.

Every run is a fresh process, and the variants take turns, round after
round, so that a busy machine slows them alike:

* ``old`` - the package at ``--baseline`` (a commit; by default 2a34b4b,
  the last one before these speed-ups), taken from ``git archive`` into a
  temporary directory;
* ``new`` - the working tree;
* ``new - <change>`` - the working tree with one speed-up switched off
  (``--without``, default: each of them in turn).

It prints one JSON line per run (CPU time by ``time.process_time``, wall
time, solves, F_A and the work of separation) and then one line per variant:
the medians over the rounds, the ratio of ``old``'s median CPU and wall time
to the variant's (``speedup_cpu``, ``speedup_wall``: > 1 is faster than
``old``), the median of the per-round ratios, and the largest relative
difference of F_A and of the work from ``old``'s.  Run it under ``nice`` on a
shared machine and read the CPU times; the wall times count every other
process.

    nice python benchmarks/event_path_speedups.py --rounds 3
    nice python benchmarks/event_path_speedups.py --elements 256 --pillars-per-side 16 --rounds 5
    nice python benchmarks/event_path_speedups.py --without coarse_updates --fft-workers 1 2
"""

from __future__ import annotations

import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: Each speed-up and the module attribute that switches it off (module, attribute, value).
CHANGES = {
    "coarse_updates": ("brushbem.numerics.solver.preconditioners", "COARSE_UPDATE_RANK", 0),
    "set_reuse": ("brushbem.numerics.solver.set_solve", "REUSE_SET_SOLVER", False),
    "solution_deflection": ("brushbem.numerics.solver.set_solve", "KEEP_SOLUTION_DEFLECTION", False),
    "empty_rows": ("brushbem.backend", "SKIP_EMPTY_ROWS", False),
    "snapped_periods": ("brushbem.numerics.periods", "SNAP_PERIODS", False),
    "cascade_deflection": ("brushbem.numerics.solver.cascade_deflection", "KEEP_CASCADE_DEFLECTION", False),
    "symmetric_guess": ("brushbem.protocol.unit_guess", "SYMMETRIC_PRODUCTS", False),
    "compact_event_search": ("brushbem.protocol.events", "COMPACT_EVENT_SEARCH", False),
    "preload_model": ("brushbem.protocol.contact_loading", "PRELOAD_MODEL", False),
}
#: Each speed-up's field of `brushbem.settings.Switches` (the module attributes above are older commits').
SWITCHES = {"coarse_updates": "coarse_update_rank", "set_reuse": "reuse_set_solver",
            "solution_deflection": "keep_solution_deflection", "empty_rows": "skip_empty_rows",
            "snapped_periods": "snap_periods", "cascade_deflection": "keep_cascade_deflection",
            "symmetric_guess": "symmetric_products", "compact_event_search": "compact_event_search",
            "preload_model": "preload_model"}


def _child(args) -> None:
    """One pull-off in this process: print its CPU and wall time, solves, F_A and work as JSON."""
    import importlib

    try:
        from brushbem import settings

        if not hasattr(settings, "using"):
            raise ImportError
    except ImportError:  # a commit whose switches were module attributes
        for name in args.switch_off:
            module, attribute, value = CHANGES[name]
            setattr(importlib.import_module(module), attribute, value)
    else:
        switched = settings.using(**{SWITCHES[name]: CHANGES[name][2] for name in args.switch_off})
        switched.__enter__()  # for the rest of this child process
    from brushbem import Grid, brush  # the public names: the same in an older commit's layout
    from brushbem.protocol import ContactProblem, LoadPath, record_pull_off

    try:
        from brushbem.runs.case import brush_scales
    except ImportError:  # a commit before the package's re-layout
        from brushbem.workflow.case import brush_scales

    grid = Grid(1.0, args.elements)
    n = args.pillars_per_side

    def problem(roughness: float) -> ContactProblem:
        indenter = brush(grid, layout="square", pillars_per_side=n,
                         pillar_radius=math.sqrt(args.filling_factor / math.pi) / n, contact_modulus=1.0,
                         work_of_adhesion=1e-4, stiffness=args.stiffness_ratio * grid.size, roughness=roughness,
                         seed=args.seed)
        return ContactProblem(grid, indenter, contact_modulus=1.0, work_of_adhesion=1e-4)

    scales = brush_scales(problem(0.0))
    d_c = abs(scales["rigid_brush_displacement"])
    f_c = scales["rigid_brush_force"]
    case = problem(args.sigma * d_c)
    path = LoadPath(method="events", preload_force=args.preload * f_c, max_steps=10**7)
    cpu, wall = time.process_time(), time.perf_counter()
    summary = record_pull_off(case, path).summary
    cpu, wall = time.process_time() - cpu, time.perf_counter() - wall
    print(json.dumps({"cpu": cpu, "wall": wall, "solves": summary["n_solves"], "converged": summary["converged"],
                      "adhesive_force": summary["adhesive_force"],
                      "work_of_separation": summary["work_of_separation"]}))


def _baseline_source(revision: str, into: Path) -> Path:
    """The package's ``src`` at ``revision``, extracted under ``into``."""
    archive = subprocess.run(["git", "-C", str(ROOT), "archive", revision, "src"], check=True, capture_output=True)
    subprocess.run(["tar", "-x", "-C", str(into)], input=archive.stdout, check=True)
    return into / "src"


def _run(variant: dict, case_args: list[str]) -> dict:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(p for p in (variant["source"], env.get("PYTHONPATH")) if p)
    if variant.get("fft_workers"):
        env["BRUSHBEM_FFT_WORKERS"] = str(variant["fft_workers"])
    command = [sys.executable, str(Path(__file__).resolve()), "--child", *case_args]
    for name in variant.get("off", ()):
        command += ["--switch-off", name]
    done = subprocess.run(command, env=env, check=True, capture_output=True, text=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--elements", type=int, default=512)
    parser.add_argument("--pillars-per-side", type=int, default=32)
    parser.add_argument("--filling-factor", type=float, default=0.16)
    parser.add_argument("--stiffness-ratio", type=float, default=0.01)
    parser.add_argument("--sigma", type=float, default=1.0, help="sigma~ = sigma / d_c")
    parser.add_argument("--preload", type=float, default=1.0, help="F~_P = F_P / F_c")
    parser.add_argument("--seed", type=int, default=3)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--baseline", default="2a34b4b", help="the commit to compare with ('none': no old run)")
    parser.add_argument("--without", nargs="*", choices=sorted(CHANGES), default=None,
                        help="the speed-ups to switch off one at a time (default: each)")
    parser.add_argument("--fft-workers", type=int, nargs="*", default=[],
                        help="also run the working tree with BRUSHBEM_FFT_WORKERS set to each of these")
    parser.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--switch-off", action="append", default=[], choices=sorted(CHANGES), help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        _child(args)
        return
    case_args = ["--elements", str(args.elements), "--pillars-per-side", str(args.pillars_per_side),
                 "--filling-factor", repr(args.filling_factor), "--stiffness-ratio", repr(args.stiffness_ratio),
                 "--sigma", repr(args.sigma), "--preload", repr(args.preload), "--seed", str(args.seed)]
    without = sorted(CHANGES) if args.without is None else args.without
    with tempfile.TemporaryDirectory() as scratch:
        variants = []
        if args.baseline != "none":
            variants.append({"name": "old", "source": str(_baseline_source(args.baseline, Path(scratch)))})
        variants.append({"name": "new", "source": str(ROOT / "src")})
        variants += [{"name": f"new - {name}", "source": str(ROOT / "src"), "off": [name]} for name in without]
        variants += [{"name": f"new, {w} FFT workers", "source": str(ROOT / "src"), "fft_workers": w}
                     for w in args.fft_workers]
        runs: dict[str, list[dict]] = {v["name"]: [] for v in variants}
        for round_ in range(args.rounds):
            for variant in variants:
                result = _run(variant, case_args)
                runs[variant["name"]].append(result)
                print(json.dumps({"round": round_, "variant": variant["name"], **result}), flush=True)
    reference = runs.get("old") or runs["new"]
    ref_cpu = statistics.median(r["cpu"] for r in reference)
    ref_wall = statistics.median(r["wall"] for r in reference)
    ref_force = reference[0]["adhesive_force"]
    ref_work = reference[0]["work_of_separation"]
    for name, results in runs.items():
        cpu = statistics.median(r["cpu"] for r in results)
        wall = statistics.median(r["wall"] for r in results)
        print(json.dumps({
            "variant": name,
            "elements": args.elements,
            "pillars": args.pillars_per_side**2,
            "rounds": len(results),
            "cpu_seconds": round(cpu, 2),
            "wall_seconds": round(wall, 2),
            "speedup_cpu": round(ref_cpu / cpu, 3),
            "speedup_wall": round(ref_wall / wall, 3),
            "speedup_cpu_paired": round(statistics.median(a["cpu"] / b["cpu"] for a, b in zip(reference, results)), 3),
            "solves": results[0]["solves"],
            "adhesive_force": results[0]["adhesive_force"],
            "work_of_separation": results[0]["work_of_separation"],
            "adhesive_force_rel_diff": max(abs(r["adhesive_force"] / ref_force - 1) for r in results),
            "work_rel_diff": max(abs(r["work_of_separation"] / ref_work - 1) for r in results),
        }), flush=True)


if __name__ == "__main__":
    main()
