"""Does a flat tip's stable peel survive h -> 0?  One tip's exact path at 29 to 160 elements per radius.

``tilted.py`` found that a flat rigid tip whose stress intensity varies along
its edge, K(theta) = K_0 (1 + eps cos theta), holds beyond its first point
(max K = K_c) on a raster, by a gain that falls with h with no order that
7.2-40 elements per radius agree on.  Whether that gain tends to zero (the
brush's limit is its first point) or to a positive value (the front peels
stably in the continuum) decided the brush's continuum limit, then known to 2.9 %.

This script runs the same exact event path (Pohrt-Popov's Sigma_c(h),
elements leaving one event at a time, the load held while they cascade:
force control) matrix-free, so that it reaches finer rasters than the dense
inverse of ``tilted.py``: the footprint's pressure by conjugate gradients on
the padded FFT product of the Love kernel, preconditioned by the padded
grid's inverse spectrum, warm-started from the previous solve.  It records,
with F_A, what peeled before the runaway: the elements gone at the last
stable state, their largest depth from the rim and their angular span, in
units of the radius.  A peel that the raster pins (a staircase effect)
keeps a depth of a few elements and a span that shrinks with h; a
continuum peel keeps a depth and a span that converge in units of a.

Measured (``fine_tip.csv``, eps = 0.2, four placements and two directions a
resolution): the gain over the first point 2.67 / 2.65 / 2.20 / 1.94 / 1.97 /
1.79 / 1.65 % at 14.4 / 28.9 / 40 / 57.8 / 80 / 115.5 / 160 elements per radius
(160: one placement); from 57.8 on the peel spans 84-93 degrees and recedes 0.043-0.055 a, its elements
growing with the area: the continuum's peel (``front.py``: 88 degrees,
0.044 a, a first-order gain of 1.19 %).  The rows at 14.4 and 28.9 equal
``tilted.py``'s dense ones to seven digits.  160 per radius takes about 12
CPU-min a placement; its second placement is the next row the script runs.

``--brush`` (``fine_tip_brush.csv``, 286 CPU-s): the 8 x 8 flat brush's four
weakest tips at k~ = 1e-5, each alone in the others' continuum deflection
(``tilted.py --brush`` on this path), at 57.8 and 80 elements per radius,
four placements each: beyond their first points the middle of an edge holds
2.54 / 2.57 %, the next 2.32 / 2.33 %, the next 1.59 / 1.66 %, the corner
0.08 / 0.12 % - the edge tips' gains level from 57.8 to 80 (the tilt's were
too, then fell 0.3 % by 160); their least capacity at 80 is the upper end of the brush's limit (``limit.py``).

    nice python docs/pillars/fine_tip.py              # resumes; rows to fine_tip.csv as each completes
    nice python docs/pillars/fine_tip.py --check      # the dense tilted.py's rows at 14.4 reproduced
    nice python docs/pillars/fine_tip.py --brush      # the 8 x 8 brush's four weakest tips (fine_tip_brush.csv)

The tip: radius a = 1, E* = 1, dgamma = 0.5 (K_c = 1, F_K = 2 sqrt(pi)).
"""

from __future__ import annotations

import math
import sys
import time
from pathlib import Path

import numpy as np
import scipy.fft

from brushbem.physics.adhesion import critical_stress
from brushbem.physics.halfspace import influence_coefficients

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import calibration  # noqa: E402
import reference  # noqa: E402

TABLE = HERE / "fine_tip.csv"
FIELDS = ("elements_per_radius", "placement", "direction_degrees", "tilt_ratio", "adhesive_force_by_kendall",
          "level_adhesive_force_by_kendall", "ratio", "first_point_ratio", "gain", "events", "elements",
          "peeled_elements", "peel_depth", "peel_span_degrees", "iterations", "cpu_seconds")
#: Centre offsets of the circle from an element's corner (in elements): ``tilted.py``'s four.
PLACEMENTS = ((0.0, 0.0), (0.5, 0.5), (0.25, 0.1), (0.37, 0.71))
KENDALL = 2 * math.sqrt(math.pi)
#: Relative residual of the CG solves: the stresses enter the criterion to about this, far below the
#: 1e-4 steps of F_A that the gains resolve.
TOLERANCE = 1e-10


class FineTip:
    """One rigid flat circular tip of radius 1 on a raster of ``per_radius`` elements per radius, matrix-free."""

    def __init__(self, per_radius: float, placement: tuple[float, float]) -> None:
        h = 1.0 / per_radius
        span = int(math.ceil(per_radius)) + 1
        index = np.arange(-span, span + 1)
        n = index.size
        y, x = np.meshgrid((index + 0.5 - placement[1]) * h, (index + 0.5 - placement[0]) * h, indexing="ij")
        self.inside = x**2 + y**2 < 1.0
        self.x, self.y = x[self.inside], y[self.inside]
        self.n = n
        self.padded = (scipy.fft.next_fast_len(2 * n), scipy.fft.next_fast_len(2 * n, real=True))
        py, px = self.padded
        di = np.fft.fftfreq(py, 1.0 / py)
        dj = np.fft.fftfreq(px, 1.0 / px)
        kernel = influence_coefficients(dj[None, :] * h, di[:, None] * h, h, 1.0)
        self.spectrum = scipy.fft.rfft2(kernel)
        # The periodic kernel's inverse as the preconditioner (positive: the kernel is a positive operator).
        self.inverse_spectrum = 1.0 / np.maximum(self.spectrum.real, 1e-12 * self.spectrum.real.max())
        self.h2 = h * h
        self.critical = critical_stress(1.0, 0.5, h)  # K_c = sqrt(2 E* dgamma) = 1
        self.iterations = 0

    def _grid(self, values: np.ndarray, keep: np.ndarray) -> np.ndarray:
        grid = np.zeros((values.shape[0], *self.padded))
        full = np.zeros((values.shape[0], self.n, self.n))
        sub = np.zeros((values.shape[0], self.x.size))
        sub[:, keep] = values
        full[:, self.inside] = sub
        grid[:, : self.n, : self.n] = full
        return grid

    def _restrict(self, grid: np.ndarray, keep: np.ndarray) -> np.ndarray:
        return grid[:, : self.n, : self.n][:, self.inside][:, keep]

    def _apply(self, spectrum: np.ndarray, values: np.ndarray, keep: np.ndarray) -> np.ndarray:
        grid = scipy.fft.irfft2(scipy.fft.rfft2(self._grid(values, keep)) * spectrum, s=self.padded)
        return self._restrict(grid, keep)

    def solve(self, keep: np.ndarray, rhs: np.ndarray, start: np.ndarray | None = None) -> np.ndarray:
        """K_SS^-1 rhs on the kept elements, for each row of ``rhs`` (preconditioned CG, all rows together)."""
        b = rhs[:, keep]
        norm = np.linalg.norm(b, axis=1)
        if not np.all(norm > 0):  # a zero right-hand side has the zero solution
            out = np.zeros_like(b)
            live = norm > 0
            if live.any():
                out[live] = self.solve(keep, rhs[live], None if start is None else start[live])
            return out
        x = np.zeros_like(b) if start is None else start.copy()
        r = b - self._apply(self.spectrum, x, keep)
        z = self._apply(self.inverse_spectrum, r, keep)
        p = z.copy()
        rz = np.einsum("ij,ij->i", r, z)
        for _ in range(20000):
            if np.all(np.linalg.norm(r, axis=1) <= TOLERANCE * norm):
                break
            q = self._apply(self.spectrum, p, keep)
            alpha = rz / np.einsum("ij,ij->i", p, q)
            x += alpha[:, None] * p
            r -= alpha[:, None] * q
            z = self._apply(self.inverse_spectrum, r, keep)
            new = np.einsum("ij,ij->i", r, z)
            p = z + (new / rz)[:, None] * p
            rz = new
            self.iterations += 1
        else:
            raise RuntimeError(f"CG did not reach {TOLERANCE} in 20000 iterations")
        return x

    def pull_off_in(self, field: np.ndarray, gone: float = 0.25) -> dict:
        """F_A / F_K under force control with ``field`` the surface's deflection per unit load across the tip
        (``tilted.Tip.pull_off_in``'s path), and what had peeled at the last stable state."""
        keep = np.ones(self.x.size, bool)
        load, best, events = 0.0, 0.0, 0
        peeled = keep.copy()
        rhs = np.stack([np.ones_like(self.x), field])
        guess = None

        def tension(keep, guess):
            ones_tilt = self.solve(keep, rhs, guess)
            delta = (1 / self.h2 - ones_tilt[1].sum()) / ones_tilt[0].sum()
            return delta * ones_tilt[0] + ones_tilt[1], ones_tilt

        while keep.any():
            q, solution = tension(keep, guess)
            pulled = q > 0
            new_load = float(np.min(self.critical / q[pulled]))
            if new_load > best:
                best = new_load
                peeled = keep.copy()
            load = max(load, new_load)
            events += 1
            while keep.any():  # the cascade at the load held
                if np.count_nonzero(~keep) > gone * keep.size:
                    return self._summary(best, events, peeled)
                leave = load * q >= self.critical * (1 - 1e-10)
                if not leave.any():
                    break
                stay = ~leave
                keep[np.flatnonzero(keep)[leave]] = False
                guess = solution[:, stay]
                q, solution = tension(keep, guess)
            guess = solution
        return self._summary(best, events, peeled)

    def _summary(self, best: float, events: int, kept: np.ndarray) -> dict:
        gone = ~kept
        radius = np.hypot(self.x, self.y)
        angle = np.degrees(np.arctan2(self.y, self.x))
        if gone.any():
            depth = float(1.0 - radius[gone].min())
            a = angle[gone]
            # the span of the peeled elements' angles about their circular mean
            mean = math.degrees(math.atan2(np.sin(np.radians(a)).mean(), np.cos(np.radians(a)).mean()))
            span = float(np.ptp((a - mean + 180.0) % 360.0 - 180.0))
        else:
            depth, span = 0.0, 0.0
        return {"force": best / KENDALL, "events": events, "peeled_elements": int(gone.sum()),
                "peel_depth": depth, "peel_span_degrees": span}


def run(per_radius: float, placement: int, eps: float, directions=(0.0, 45.0)) -> list[dict]:
    start = time.process_time()
    tip = FineTip(per_radius, PLACEMENTS[placement])
    level = tip.pull_off_in(np.zeros_like(tip.x))["force"]
    rows = []
    for direction in directions:
        angle = math.radians(direction)
        # 4 E* gamma a^2 = eps: K's tilt part eps times its uniform part on the continuum disk
        out = tip.pull_off_in(eps / 4 * (math.cos(angle) * tip.x + math.sin(angle) * tip.y))
        first = 1 / (1 + eps)
        rows.append({"elements_per_radius": per_radius, "placement": placement, "direction_degrees": direction,
                     "tilt_ratio": eps, "adhesive_force_by_kendall": out["force"],
                     "level_adhesive_force_by_kendall": level, "ratio": out["force"] / level,
                     "first_point_ratio": first, "gain": out["force"] / level / first - 1,
                     "events": out["events"], "elements": tip.x.size, "peeled_elements": out["peeled_elements"],
                     "peel_depth": out["peel_depth"], "peel_span_degrees": out["peel_span_degrees"],
                     "iterations": tip.iterations, "cpu_seconds": 0.0})
    seconds = time.process_time() - start
    for row in rows:
        row["cpu_seconds"] = round(seconds / len(rows), 2)
    return rows


def load(table: Path = TABLE) -> list[dict]:
    return reference.load(table)


def write(rows: list[dict], table: Path = TABLE) -> None:
    calibration.write(rows, table, FIELDS, digits=7)


#: (elements per radius, placement) in the order they run: the dense script's resolutions first (a check),
#: then doubling.
CASES = tuple((res, p) for res in (14.443, 28.887, 40.0, 57.774, 80.0, 115.548) for p in range(4)) \
    + tuple((160.0, p) for p in range(2))
TILT = 0.2


BRUSH_TABLE = HERE / "fine_tip_brush.csv"
#: The brush's tips at the resolutions beyond ``tilted.py``'s (its 40 per radius): four placements each.
BRUSH_CASES = tuple((res, p) for res in (57.774, 80.0) for p in range(4))


def run_brush(per_radius: float, placement: int, fields: dict) -> list[dict]:
    """``tilted.run_brush`` on the matrix-free tip: each of the 8 x 8 brush's four weakest tips (k~ = 1e-5) alone
    in the other tips' continuum deflection (`tilted.brush_fields`)."""
    import tilted

    start = time.process_time()
    tip = FineTip(per_radius, PLACEMENTS[placement])
    level = tip.pull_off_in(np.zeros_like(tip.x))["force"]
    rows = []
    points = np.stack([tip.x, tip.y], axis=1)
    for name, (first, deflection) in fields.items():
        field = np.concatenate([deflection(chunk) for chunk in np.array_split(points, max(1, len(points) // 4000))])
        out = tip.pull_off_in(field)
        rows.append({"pillars_per_side": 8, "stiffness_ratio": 1e-5, "tip": f"{name[0]}-{name[1]}",
                     "elements_per_radius": per_radius, "placement": placement,
                     "adhesive_force_by_kendall": out["force"], "level_adhesive_force_by_kendall": level,
                     "ratio": out["force"] / level, "first_point_ratio": first,
                     "gain": out["force"] / level / first - 1, "events": out["events"], "cpu_seconds": 0.0})
    for row in rows:
        row["cpu_seconds"] = round((time.process_time() - start) / len(rows), 2)
    assert tuple(rows[0]) == tilted.BRUSH_FIELDS
    return rows


def main() -> None:
    if "--brush" in sys.argv:
        import tilted

        rows = reference.load(BRUSH_TABLE)
        done = {(float(r["elements_per_radius"]), int(r["placement"])) for r in rows}
        fields = tilted.brush_fields(8, 1e-5)
        for per_radius, placement in BRUSH_CASES:
            if (per_radius, placement) not in done:
                rows += run_brush(per_radius, placement, fields)
                calibration.write(rows, BRUSH_TABLE, tilted.BRUSH_FIELDS, digits=7)
                print(rows[-4:], flush=True)
        return
    if "--check" in sys.argv:
        for row in run(14.443, 0, TILT):
            print(row, flush=True)
        return
    rows = load()
    done = {(float(r["elements_per_radius"]), int(r["placement"])) for r in rows}
    for per_radius, placement in CASES:
        if (per_radius, placement) in done:
            continue
        new = run(per_radius, placement, TILT)
        rows += new
        write(rows)
        for row in new:
            print(", ".join(f"{k}={row[k]}" for k in FIELDS), flush=True)


if __name__ == "__main__":
    main()
