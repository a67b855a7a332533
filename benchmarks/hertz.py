"""Non-periodic Hertz benchmark: paraboloid R = 1 on the 1 x 1 domain, E* = 1, d = 0.04.

Prints one JSON line: elements, seconds (median of --repeat runs, kernel
spectra built inside the timed region), iterations, force_rel_error (against
4/3 E* sqrt(R) d^1.5), fft_pair_seconds (median of one padded rfft2 + irfft2
pair on the full 2N x 2N grid, timed in the same run) and the ratio
seconds / (iterations * fft_pair_seconds), the cost of one iteration in full-grid
FFT pairs (the solver works on a window around the contact, so this can be < 1).

    python benchmarks/hertz.py --elements 512
"""

from __future__ import annotations

import argparse
import json
import statistics
import time

import numpy as np
import scipy.fft

from brushbem.physics import theory
from brushbem.backend import fft_workers
from brushbem.protocol import ContactProblem, indent
from brushbem.physics.structure import Grid, sphere


def fft_pair_seconds(n: int, repeat: int = 7) -> float:
    pressure = np.random.default_rng(0).random((n, n))
    spectrum = np.random.default_rng(1).random((2 * n, n + 1))
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        product = scipy.fft.rfft2(pressure, s=(2 * n, 2 * n), workers=fft_workers()) * spectrum
        scipy.fft.irfft2(product, s=(2 * n, 2 * n), workers=fft_workers())[:n, :n]
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--elements", type=int, default=256)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--tolerance", type=float, default=1e-8)
    args = parser.parse_args()
    n = args.elements
    displacement = 0.04
    times, state = [], None
    for _ in range(args.repeat):
        grid = Grid(1.0, n)
        problem = ContactProblem(grid, sphere(grid, 1.0), contact_modulus=1.0, work_of_adhesion=0.0)
        start = time.perf_counter()
        state = indent(problem, displacement, tolerance=args.tolerance)
        times.append(time.perf_counter() - start)
    seconds = statistics.median(times)
    pair = fft_pair_seconds(n)
    force = theory.hertz_force(1.0, displacement, contact_modulus=1.0)
    print(json.dumps({
        "elements": n,
        "seconds": round(seconds, 4),
        "iterations": state.cg_iterations,
        "converged": state.converged,
        "force_rel_error": abs(state.force / force - 1.0),
        "fft_pair_seconds": round(pair, 5),
        "iteration_cost_in_fft_pairs": round(seconds / (state.cg_iterations * pair), 3),
    }))


if __name__ == "__main__":
    main()
