"""The discretisation error of F_A and of the work against the elements per radius: the table of every run's estimate.

A flat punch of radius r = 1 (E* = 1, dgamma = 1e-3, preload d = 0.01) on a spring of k~ = k / (2 E* r) = 1
(thesis eq. 2.17) is pulled off by the exact event path at q = r / h elements per radius, on a grid just larger
than the punch (the half-space is not periodic: the domain only has to hold the footprint).  Each q is run at
eleven radii q (1 + s), s from -10 % to +10 % in steps of 2 %, because the rasterised circle's staircase makes the error at one
q scatter by a few per cent; the row holds their mean, smallest and largest relative error of

* F_A against Kendall's force at the radius typed, F_K = sqrt(8 pi E* dgamma r^3) (eq. 2.4), and
* the work of separation against eq. 2.18-2.19, 2 pi dgamma r^2 (1 + 1/k~);

and the same two at the radius of the rasterised footprint, sqrt(A / pi) (``mesh_...``): what the mesh
criterion alone adds, apart from the staircase's area.

The error is what a designer's number carries at that resolution: the radius they type, not the rasterised
area's.  `brushbem.config.advice` reads the committed table (``src/brushbem/data/resolution_error.csv``)::

    python benchmarks/resolution_error.py --out src/brushbem/data/resolution_error.csv

``--sphere`` measures the sphere's table (``src/brushbem/data/sphere_resolution_error.csv``), a rigid JKR
sphere at 2 to 24 elements across its pull-off contact radius a_JKR against JKR::

    python benchmarks/resolution_error.py --sphere --out src/brushbem/data/sphere_resolution_error.csv

``--brush`` measures how far a brush's error follows the single punch's: a 4 x 4 brush of pillars on springs
at each resolution against the first-order extrapolation of its two finest::

    python benchmarks/resolution_error.py --brush --resolutions 3,4,6,8,12,16
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import time

import numpy as np

import brushbem
from brushbem.physics import theory
from brushbem.runs.assembly import parse
from brushbem.runs.case import run_problem

MODULUS, DGAMMA, RADIUS, RATIO = 1.0, 1e-3, 1.0, 1.0
RESOLUTIONS = (2.25, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0, 11.0, 16.0, 23.0, 32.0)
SHIFTS = tuple(np.linspace(-0.1, 0.1, 11))


def errors(q: float) -> tuple[float, float, float, float, float]:
    """The punch at q elements per radius: F_A and work errors at the radius typed, at the footprint's, seconds."""
    h = RADIUS / q
    elements = max(8, math.ceil(2 * q) + 6)
    stiffness = RATIO * 2 * MODULUS * RADIUS
    start = time.perf_counter()
    pulled = brushbem.run({
        "halfspace": {"contact_modulus": MODULUS, "work_of_adhesion": DGAMMA},
        "grid": {"size": elements * h, "elements": elements},
        "indenter": {"shape": "flat_punch", "radius": RADIUS, "stiffness": stiffness},
        "protocol": {"method": "events", "preload_displacement": 0.01},
    })
    seconds = time.perf_counter() - start
    assert pulled.converged, pulled.summary.get("reason")
    footprint = math.sqrt(int(np.count_nonzero(pulled.snapshots["max_preload"].contact)) / math.pi) * h
    found = []
    for radius in (RADIUS, footprint):
        force = theory.kendall_force(radius, contact_modulus=MODULUS, work_of_adhesion=DGAMMA)
        work = theory.punch_spring_work_of_separation(radius, stiffness, contact_modulus=MODULUS,
                                                      work_of_adhesion=DGAMMA)
        found += [pulled.adhesive_force / force - 1.0, pulled.work_of_separation / work - 1.0]
    return (*found, seconds)


def brush(q: float, pillars_per_side: int = 4) -> tuple[float, float, float]:
    """(F_A, work, seconds) of a square brush of pillars of radius 1 at pitch 4 (phi = 0.196) at q elements per
    radius, each pillar on the spring of the PDMS fibril of the documentation scaled to r = 1 (k~ = k / (2 E* r)
    = 0.147: k = pi r^2 E_f / l = 3.93 uN/um on E* = 2.67 MPa, r = 5 um)."""
    h = RADIUS / q
    region = 4.0 * pillars_per_side
    elements = math.ceil((region + 4.0) / h)
    start = time.perf_counter()
    pulled = brushbem.run({
        "halfspace": {"contact_modulus": MODULUS, "work_of_adhesion": DGAMMA},
        "grid": {"size": elements * h, "elements": elements},
        "indenter": {"shape": "brush", "layout": "square", "pillars_per_side": pillars_per_side,
                     "pillar_radius": RADIUS, "region_size": region, "stiffness": 0.294 * MODULUS * RADIUS},
        "protocol": {"method": "events", "preload_displacement": 0.01},
    })
    assert pulled.converged, pulled.summary.get("reason")
    return pulled.adhesive_force, pulled.work_of_separation, time.perf_counter() - start


#: The sphere's table: elements across the JKR contact radius at pull-off, a_JKR / h.
SPHERE_RESOLUTIONS = (2.0, 3.0, 4.0, 6.0, 8.0, 12.0, 16.0, 24.0)


def sphere(q: float) -> tuple[float, float | None, float]:
    """A rigid JKR sphere (R = 1, a_JKR = 0.1) at q elements across a_JKR: its F_A and work errors against JKR
    (eq. 2.20, 2.37; `summary.theory.ratios`), and the seconds."""
    a_jkr = 0.1
    dgamma = a_jkr**3 * 8 * MODULUS / (9 * math.pi * RADIUS**2)
    h = a_jkr / q
    elements = math.ceil(8 * q)
    start = time.perf_counter()
    # The run without the configuration's advice (`run_problem`), which reads the table this measures.
    built = parse({
        "halfspace": {"contact_modulus": MODULUS, "work_of_adhesion": dgamma},
        "grid": {"size": elements * h, "elements": elements},
        "indenter": {"shape": "sphere", "radius": RADIUS},
        "protocol": {"method": "events", "preload_displacement": a_jkr**2 / RADIUS},
    })
    pulled = run_problem(built.problem, built.path)
    assert pulled.converged, pulled.summary.get("reason")
    ratios = pulled.summary["theory"]["ratios"]
    work = ratios.get("work_of_separation")
    return ratios["adhesive_force"] - 1.0, None if work is None else work - 1.0, time.perf_counter() - start


def brush_study(resolutions: list[float]) -> None:
    """The brush's F_A and work against q, and their errors against the first-order extrapolation of the two finest."""
    found = {q: brush(q) for q in resolutions}
    fine, finer = sorted(found)[-2:]
    ratio = finer / fine
    limit = [(ratio * found[finer][i] - found[fine][i]) / (ratio - 1) for i in (0, 1)]
    for q, (force, work, seconds) in found.items():
        print(json.dumps({"brush_elements_per_radius": q, "adhesive_force": force, "work_of_separation": work,
                          "force_error": force / limit[0] - 1, "work_error": work / limit[1] - 1,
                          "seconds": seconds}), flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=None, help="CSV file to write (default: print only)")
    parser.add_argument("--resolutions", default=",".join(f"{q:g}" for q in RESOLUTIONS))
    parser.add_argument("--sphere", action="store_true",
                        help="instead: the rigid JKR sphere at SPHERE_RESOLUTIONS elements across a_JKR (--out: CSV)")
    parser.add_argument("--brush", action="store_true",
                        help="instead: a 4 x 4 brush at --resolutions against its extrapolation (two finest, h^1)")
    args = parser.parse_args()
    if args.brush:
        brush_study([float(value) for value in args.resolutions.split(",")])
        return
    if args.sphere:
        sphere_rows = []
        for q in SPHERE_RESOLUTIONS:
            force, work, seconds = sphere(q)
            sphere_rows.append({"elements_per_radius": q, "force_error": force, "work_error": work})
            print(json.dumps({**sphere_rows[-1], "seconds": seconds}), flush=True)
        if args.out:
            with open(args.out, "w", newline="", encoding="utf-8") as handle:
                handle.write("# rigid JKR sphere (a_JKR = 0.1 R) by the exact event path against JKR (eq. 2.20, 2.37) at "
                             "q elements across a_JKR; benchmarks/resolution_error.py --sphere\n")
                writer = csv.DictWriter(handle, fieldnames=list(sphere_rows[0]), lineterminator="\n")
                writer.writeheader()
                for row in sphere_rows:
                    writer.writerow({key: (f"{value:.5g}" if isinstance(value, float) else value)
                                     for key, value in row.items()})
        return
    rows = []
    for q in (float(value) for value in args.resolutions.split(",")):
        measured = [errors(q * (1 + s)) for s in SHIFTS]
        force, work, mesh_force, mesh_work, seconds = (np.array(column) for column in zip(*measured, strict=True))
        row = {"elements_per_radius": q}
        for name, values in (("force_error", force), ("work_error", work), ("mesh_force_error", mesh_force),
                             ("mesh_work_error", mesh_work)):
            row.update({f"{name}_mean": float(values.mean()), f"{name}_min": float(values.min()),
                        f"{name}_max": float(values.max())})
        row["seconds"] = float(seconds.sum())
        rows.append(row)
        print(json.dumps(row), flush=True)
    if args.out:
        with open(args.out, "w", newline="", encoding="utf-8") as handle:
            handle.write("# flat punch on a spring k~ = 1 by the exact event path against Kendall (eq. 2.4) and "
                         "eq. 2.18-2.19 at the radius typed; benchmarks/resolution_error.py\n")
            writer = csv.DictWriter(handle, fieldnames=[key for key in rows[0] if key != "seconds"],
                                    extrasaction="ignore", lineterminator="\n")
            writer.writeheader()
            for row in rows:
                writer.writerow({key: (f"{value:.5g}" if isinstance(value, float) else value)
                                 for key, value in row.items()})


if __name__ == "__main__":
    main()
