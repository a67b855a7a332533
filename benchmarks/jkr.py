"""Full JKR pull-off of a rigid sphere: press, pull off, separate.

Paraboloid R = 1 on the 1 x 1 domain, E* = 1, work of adhesion 1e-3 (a_JKR =
0.152, so a_JKR / h = 39 at N = 256), pressed to d = 0.04 (Hertz radius 0.2 >
a_JKR) and pulled off to complete separation.  Prints one JSON line per method
with the wall time and the process CPU time (medians of --repeat runs; the CPU
time is the steadier of the two on a shared machine), recorded states, CG
iterations and F_A / F_JKR.

    python benchmarks/jkr.py --elements 256 --method events
"""

from __future__ import annotations

import argparse
import json
import statistics
import time

from brushbem.physics import theory
from brushbem.protocol import ContactProblem, LoadPath, record_pull_off
from brushbem.physics.structure import Grid, sphere


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--elements", type=int, default=256)
    parser.add_argument("--method", choices=["events", "fixed"], default="events")
    parser.add_argument("--step", type=float, default=1e-4)
    parser.add_argument("--repeat", type=int, default=1)
    args = parser.parse_args()
    grid = Grid(1.0, args.elements)
    problem = ContactProblem(grid, sphere(grid, 1.0), contact_modulus=1.0, work_of_adhesion=1e-3)
    path = LoadPath(method=args.method, preload_displacement=0.04, step=args.step)
    times, cpu_times, record = [], [], None
    for _ in range(args.repeat):
        start, cpu_start = time.perf_counter(), time.process_time()
        record = record_pull_off(problem, path)
        times.append(time.perf_counter() - start)
        cpu_times.append(time.process_time() - cpu_start)
    summary = record.summary
    print(json.dumps({
        "elements": args.elements,
        "method": args.method,
        "seconds": round(statistics.median(times), 3),
        "cpu_seconds": round(statistics.median(cpu_times), 3),
        "states": summary["n_states"],
        "cg_iterations": summary["n_cg_iterations"],
        "converged": summary["converged"],
        "force_over_jkr": summary["adhesive_force"] / theory.jkr_pull_off_force(1.0, work_of_adhesion=1e-3),
        "work_over_jkr": summary["work_of_separation"] / theory.jkr_work_of_separation(1.0, contact_modulus=1.0, work_of_adhesion=1e-3),
    }))


if __name__ == "__main__":
    main()
