"""Kendall punch over rasterisations: F_A and d_A errors of the event-driven pull-off.

A rigid flat punch of radius q h (q from --radii) on the 1 x 1 domain with N
elements, E* = 1, dgamma = 1e-3, preload d = 0.01.  Prints one JSON line per
radius: q, the equivalent radius sqrt(A / pi) / h of the rasterised footprint,
the relative errors of F_A and d_A against Kendall (eq. 2.4) at that radius,
and the seconds of the pull-off; then a line with the ranges.  It measures how
much of the error at a given a/h is the staircase of the rasterised circle.

    python benchmarks/kendall.py --elements 128 --radii 31.5:32.5:21
"""

from __future__ import annotations

import argparse
import json
import math
import time

import numpy as np

from brushbem.physics import theory
from brushbem.protocol import ContactProblem, LoadPath, record_pull_off
from brushbem.physics.structure import Grid, flat_punch


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--elements", type=int, default=128)
    parser.add_argument("--radii", default="32:32:1", help="first:last:count, radii in elements")
    args = parser.parse_args()
    first, last, count = args.radii.split(":")
    grid = Grid(1.0, args.elements)
    h = grid.element_size
    rows = []
    for q in np.linspace(float(first), float(last), int(count)):
        punch = flat_punch(grid, q * h)
        radius = math.sqrt(punch.description["rasterised_area"] / math.pi)
        start = time.perf_counter()
        record = record_pull_off(
            ContactProblem(grid, punch, 1.0, 1e-3), LoadPath(method="events", preload_displacement=0.01)
        )
        seconds = time.perf_counter() - start
        summary = record.summary
        row = {
            "radius_elements": round(float(q), 4),
            "equivalent_radius_elements": radius / h,
            "force_error": summary["adhesive_force"] / theory.kendall_force(radius, contact_modulus=1.0, work_of_adhesion=1e-3) - 1.0,
            "displacement_error": summary["pull_off_displacement"] / theory.kendall_displacement(radius, contact_modulus=1.0, work_of_adhesion=1e-3)
            - 1.0,
            "converged": summary["converged"],
            "seconds": seconds,
        }
        rows.append(row)
        print(json.dumps(row), flush=True)
    print(json.dumps({
        "elements": args.elements,
        "radii": len(rows),
        "force_error_range": [min(r["force_error"] for r in rows), max(r["force_error"] for r in rows)],
        "displacement_error_range": [
            min(r["displacement_error"] for r in rows), max(r["displacement_error"] for r in rows)
        ],
    }))


if __name__ == "__main__":
    main()
