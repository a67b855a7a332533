"""Does a flat tip in a tilting field hold more than its first point at K_c?  The exact path of one tip, finer and finer.

``continuum.py`` puts the brush's F_A where the first tip's largest stress
intensity reaches K_c (a flat tip's peel being unstable once started).  In a
brush on soft springs every tip carries the same load P, and the
neighbours' deflection over a tip is proportional to P: mostly a tilt
(``continuum.py``: the tilt moment is 0.05-0.06 P a on the edge tips, the
edge's largest K 1.19-1.29 times the lone tip's).  This script isolates that
case: one rigid flat tip of radius a, under the load P, that cannot rotate,
in a field whose tilt grows with P, so that its stress intensity is
K(theta) = P / (2 a sqrt(pi a)) (1 + eps cos theta).  The closed form of its
first point at K_c is F_K / (1 + eps).  The exact event path of that tip
(Pohrt-Popov's Sigma_c(h), elements leaving one event at a time, the load
held while they cascade: force control) on rasters of 7.2 to 40 elements per
radius, on several placements of the circle on the grid and two tilt
directions, gives its F_A; the ratio F_A(eps) / F_A(0) on the same raster
removes the lone tip's raster error.  If the ratio tends to 1 / (1 + eps)
the tip holds no more than its first point (the brush's limit is
``continuum.py``'s); what it tends to above that is the peel's gain.

Measured, eps = 0.2 (``tilted.csv``, eight rows a resolution: four
placements, two directions): F_A(eps) / F_A(0) is above 1 / (1 + eps) by
4.5 % (mean; 2.9-6.7) at 7.2 elements per radius, 2.7 % (1.3-4.0) at 14.4,
2.1 and 2.4 % at 28.9 (one placement), the peel taking 1-3, 1-5 and 7-10
events.  So a flat tip does hold beyond its first point on a raster, and
the gain falls slowly with h.

The brush's tips (``--brush`` -> ``tilted_brush.csv``; 652 CPU-s): the
8 x 8 flat brush at k~ = 1e-5, each of its four weakest tips alone in the
other tips' continuum deflection (`continuum.Brush.external`, the tips'
loads equal), on four placements at 7.2, 14.4, 28.9 and 40 elements per
radius.  The gain over each tip's first point (mean over the placements,
its standard error):

    tip            first point    7.2      14.4     28.9     40
    edge middle    0.7771         5.23 %   3.85 %   3.26 %   2.88 % (0.12)
    next           0.7800         4.28     3.26     2.93     2.49   (0.10)
    next           0.7860         3.49     2.28     2.17     1.73   (0.13)
    corner         0.7839         2.65     0.86     0.81     0.49   (0.11)

Every tip's gain still falls from 28.9 to 40, with no order the four
resolutions agree on; whether it tends to zero (the first point the limit)
or to a small positive value (the local peel is stabilised by the front's
own curvature; ours, the thesis states none) these resolutions do not
decide.

The limit (``continuum_limit.csv``, `limit`; ``--limit`` rewrites it):
the flat brush's F_A at k~ = 1e-5 lies between the first point,
0.0118133 (no tip peeling stably; exact to 2e-9), and the weakest tip's
capacity at 40 elements per radius, the corner's 0.7839 x 1.0049 n^2 F_K =
0.0119750 (the gains fall with h; each tip alone in a field its neighbours'
peel does not change).  The reference is the middle, 0.0118942, with
error 0.68 % (the half-width); it holds for the hierarchical and concave
brushes too (on soft springs every tip carries the same load; the exact
path on N = 512 has the three within 0.07 %).  The exact path's
first-order extrapolation (``tips_extrapolated.csv``, 0.0120796, its own
estimate 1.3 %) lies 1.56 % above it and 0.87 % above the upper bound.

Rows go to ``tilted.csv`` and ``tilted_brush.csv`` as each completes
(atomically; a rerun skips the rows already there).

    nice python docs/pillars/tilted.py             # the single tilt, resuming (about 100 CPU-s)
    nice python docs/pillars/tilted.py --brush     # the brush's tips, resuming, then continuum_limit.csv
    python docs/pillars/tilted.py --limit          # only rewrite continuum_limit.csv
"""

from __future__ import annotations

import csv
import math
import sys
import time
from pathlib import Path

import numpy as np
import scipy.linalg

from brushbem.physics.adhesion import critical_stress
from brushbem.physics.halfspace import influence_coefficients

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import calibration  # noqa: E402
import continuum  # noqa: E402
import reference  # noqa: E402

TABLE = HERE / "tilted.csv"
BRUSH_TABLE = HERE / "tilted_brush.csv"
BRUSH_FIELDS = ("pillars_per_side", "stiffness_ratio", "tip", "elements_per_radius", "placement",
                "adhesive_force_by_kendall", "level_adhesive_force_by_kendall", "ratio", "first_point_ratio",
                "gain", "events", "cpu_seconds")
#: The 8 x 8 flat brush's weakest tips at k~ = 1e-5 (``continuum.py``; one of each class of symmetry): the middle
#: of an edge, the next two along it, the corner.
BRUSH_TIPS = ((0, 3), (0, 2), (0, 1), (0, 0))
FIELDS = ("elements_per_radius", "placement", "direction_degrees", "tilt_ratio", "adhesive_force_by_kendall",
          "level_adhesive_force_by_kendall", "ratio", "first_point_ratio", "ratio_error", "events", "cpu_seconds")
#: Elements per pillar radius (those of the families' tips, 3.611 times 2, 4, 8, and about 11).
RESOLUTIONS = (7.222, 14.443, 28.887, 40.0)
#: The single tilt's cases (``tilted.csv``): every placement at 7.2 and 14.4 elements per radius, one at 28.9.
TILT_CASES = tuple((res, p) for res in RESOLUTIONS[:2] for p in range(4)) + ((28.887, 0),)
#: Centre offsets of the circle from an element's corner (in elements).
PLACEMENTS = ((0.0, 0.0), (0.5, 0.5), (0.25, 0.1), (0.37, 0.71))
DIRECTIONS = (0.0, 45.0)
#: eps = K's tilt part over its uniform part (the brush's edge tips: 0.19-0.29).
TILTS = (0.2,)


class Tip:
    """One rigid flat circular tip on a raster: K_FF^-1 of its footprint and the exact event path."""

    def __init__(self, per_radius: float, placement: tuple[float, float]) -> None:
        h = 1.0 / per_radius  # a = 1
        span = int(math.ceil(per_radius)) + 2
        index = np.arange(-span, span + 1)
        y, x = np.meshgrid((index + 0.5 - placement[1]) * h, (index + 0.5 - placement[0]) * h, indexing="ij")
        inside = x**2 + y**2 < 1.0
        self.x, self.y = x[inside], y[inside]
        rows, cols = np.nonzero(inside)
        kernel = influence_coefficients((cols[:, None] - cols[None, :]) * h, (rows[:, None] - rows[None, :]) * h,
                                        h, 1.0)
        self.inverse = scipy.linalg.inv(kernel, overwrite_a=True, check_finite=False)
        self.h2 = h * h
        self.critical = critical_stress(1.0, 0.5, h)  # K_c = sqrt(2 E* dgamma) = 1
        self.kendall = 2 * math.sqrt(math.pi)  # F_K = 2 a sqrt(pi a) K_c

    def _solve(self, keep: np.ndarray, rhs: np.ndarray) -> np.ndarray:
        """K_SS^-1 rhs_S on the kept elements S (columns of ``rhs``) from K_FF^-1 (Schur complement of the
        removed R)."""
        removed = np.flatnonzero(~keep)
        full = np.where(keep[:, None], rhs, 0.0)
        out = (self.inverse @ full)[keep]
        if removed.size:
            a_rs = self.inverse[removed][:, keep]
            a_rr = self.inverse[np.ix_(removed, removed)]
            out -= a_rs.T @ scipy.linalg.solve(a_rr, a_rs @ rhs[keep], assume_a="pos", check_finite=False)
        return out

    def tension_per_load(self, keep: np.ndarray, field: np.ndarray) -> np.ndarray:
        """Tensile stress per unit load on the kept elements: the tip's uplift delta + ``field`` P (per element),
        the load P."""
        ones, tilt = self._solve(keep, np.stack([np.ones_like(self.x), field], axis=1)).T
        # P = h^2 (delta sum phi_1 + P sum phi_t)  ->  per unit P: delta = (1 / h^2 - sum phi_t) / sum phi_1
        delta = (1 / self.h2 - tilt.sum()) / ones.sum()
        return delta * ones + tilt

    def pull_off(self, eps: float, direction: float, gone: float = 0.25) -> tuple[float, int]:
        gamma = eps / 4
        angle = math.radians(direction)
        return self.pull_off_in(gamma * (math.cos(angle) * self.x + math.sin(angle) * self.y), gone)

    def pull_off_in(self, field: np.ndarray, gone: float = 0.25) -> tuple[float, int]:
        """(F_A / F_K, events) under force control; the tilt's slope per unit load gives K's tilt part eps times
        its uniform part on the continuum disk (4 E* gamma a^2 = eps).  A cascade that has taken ``gone`` of the
        footprint at the load held is taken to end in pull-off (the same as ``gone = 1`` at 7.2 and 14.4
        elements per radius in ``tests/test_pillar_continuum.py``)."""
        keep = np.ones(self.x.size, bool)
        load, best, events = 0.0, 0.0, 0
        while keep.any():
            q = self.tension_per_load(keep, field)
            pulled = q > 0
            load = max(load, float(np.min(self.critical / q[pulled])))
            best = max(best, load)
            events += 1
            while keep.any():  # the cascade at the load held
                if np.count_nonzero(~keep) > gone * keep.size:
                    return best / self.kendall, events  # a cascade past ``gone`` of the tip takes all of it
                q = self.tension_per_load(keep, field)
                leave = load * q >= self.critical * (1 - 1e-10)
                if not leave.any():
                    break
                keep[np.flatnonzero(keep)[leave]] = False
        return best / self.kendall, events


def run(per_radius: float, placement: int) -> list[dict]:
    start = time.process_time()
    tip = Tip(per_radius, PLACEMENTS[placement])
    level, _ = tip.pull_off(0.0, 0.0)
    rows = []
    for eps in TILTS:
        for direction in DIRECTIONS:
            force, events = tip.pull_off(eps, direction)
            first = 1 / (1 + eps)
            rows.append({"elements_per_radius": per_radius, "placement": placement, "direction_degrees": direction,
                         "tilt_ratio": eps, "adhesive_force_by_kendall": force,
                         "level_adhesive_force_by_kendall": level, "ratio": force / level,
                         "first_point_ratio": first, "ratio_error": force / level / first - 1, "events": events,
                         "cpu_seconds": 0.0})
    seconds = time.process_time() - start
    for row in rows:
        row["cpu_seconds"] = round(seconds / len(rows), 2)
    return rows


def brush_fields(per_side: int, stiffness: float):
    """Per tip of ``BRUSH_TIPS``: its continuum first-point ratio (F at its first point at K_c over F_K, the
    tips' loads in proportion) and the function giving the other tips' deflection per unit load at points of
    the tip (unit disk)."""
    a = math.sqrt(continuum.PHI / math.pi) / per_side
    brush = continuum.Brush(per_side, 1 / per_side / a, 12, 12, 48)
    c = brush.solve(np.ones(per_side**2, bool), 2 * math.pi * continuum.MODULUS * a / stiffness)
    intensity = math.sqrt(math.pi) * (c @ brush.edge.T)
    out = {}
    for tip in BRUSH_TIPS:
        i = tip[0] * per_side + tip[1]
        first = math.sqrt(math.pi) * c[i, 0] / intensity[i].max()
        # The tip's own pressure makes up its displacement less the others' deflection: the field enters
        # negated (`tests/test_pillar_front.py`: the raster then first peels where the continuum's K peaks).
        out[tip] = (first, lambda points, i=i: -brush.external(c, i, points))
    return out


def run_brush(per_side: int, stiffness: float, per_radius: float, placement: int, fields: dict) -> list[dict]:
    start = time.process_time()
    tip = Tip(per_radius, PLACEMENTS[placement])
    level, _ = tip.pull_off(0.0, 0.0)
    rows = []
    for name, (first, deflection) in fields.items():
        force, events = tip.pull_off_in(deflection(np.stack([tip.x, tip.y], axis=1)))
        rows.append({"pillars_per_side": per_side, "stiffness_ratio": stiffness, "tip": f"{name[0]}-{name[1]}",
                     "elements_per_radius": per_radius, "placement": placement, "adhesive_force_by_kendall": force,
                     "level_adhesive_force_by_kendall": level, "ratio": force / level, "first_point_ratio": first,
                     "gain": force / level / first - 1, "events": events, "cpu_seconds": 0.0})
    for row in rows:
        row["cpu_seconds"] = round((time.process_time() - start) / len(rows), 2)
    return rows


LIMIT = HERE / "continuum_limit.csv"
LIMIT_FIELDS = ("families", "pillars_per_side", "stiffness_ratio", "first_point_adhesive_force", "weakest_tip",
                "tip_first_point_ratio", "elements_per_radius", "placements", "gain", "gain_standard_error",
                "tip_adhesive_force", "adhesive_force", "error", "extrapolated_exact", "extrapolated_exact_error")


def limit(rows: list[dict]) -> list[dict]:
    """The 8 x 8 flat brush's F_A at k~ = 1e-5 as h -> 0, between two bounds (module docstring, "The limit").

    Below: the first point (``continuum_reference.csv``), no tip peeling stably.  Above: every tip at its
    capacity first_point_ratio (1 + gain) with its peel's gain at the finest resolution of ``tilted_brush.csv``
    (the mean over the placements), the tip of least capacity deciding, F_A = n^2 F_K times that capacity (every
    tip carries the same load on soft springs).  The reference is the middle, its error the half-width."""
    finest = max((float(row["elements_per_radius"]) for row in rows), default=0.0)
    tips = {}
    for tip in dict.fromkeys(row["tip"] for row in rows):
        gains = np.array([float(r["gain"]) for r in rows if r["tip"] == tip
                          and float(r["elements_per_radius"]) == finest])
        if len(gains) < 2:
            return []
        first = float(next(r["first_point_ratio"] for r in rows if r["tip"] == tip))
        tips[tip] = (first * (1 + gains.mean()), first, float(gains.mean()),
                     float(gains.std(ddof=1) / math.sqrt(len(gains))), len(gains))
    weakest = min(tips, key=lambda tip: tips[tip][0])
    capacity, first, gain, standard_error, placements = tips[weakest]
    per_side, stiffness = int(rows[0]["pillars_per_side"]), float(rows[0]["stiffness_ratio"])
    a = math.sqrt(continuum.PHI / math.pi) / per_side
    kendall = math.sqrt(8 * math.pi * continuum.MODULUS * continuum.DGAMMA * a**3)
    (lower,) = [float(r["adhesive_force"]) for r in reference.load(continuum.REFERENCE)
                if int(r["pillars_per_side"]) == per_side and float(r["stiffness_ratio"]) == stiffness]
    upper = per_side**2 * kendall * capacity
    force = (lower + upper) / 2
    with (HERE / "tips_extrapolated.csv").open(newline="") as stream:
        (old,) = [float(r["extrapolated_adhesive_force"]) for r in csv.DictReader(stream)
                  if r["family"] == "flat" and float(r["stiffness_ratio"]) == stiffness]
    return [{"families": "flat hierarchy concave", "pillars_per_side": per_side, "stiffness_ratio": stiffness,
             "first_point_adhesive_force": lower, "weakest_tip": weakest, "tip_first_point_ratio": first,
             "elements_per_radius": finest, "placements": placements, "gain": gain,
             "gain_standard_error": standard_error, "tip_adhesive_force": upper, "adhesive_force": force,
             "error": (upper - lower) / 2 / force, "extrapolated_exact": old,
             "extrapolated_exact_error": old / force - 1}]


def load(table: Path = TABLE) -> list[dict]:
    return reference.load(table)


def write(rows: list[dict], table: Path = TABLE, fields: tuple[str, ...] = FIELDS) -> None:
    calibration.write(rows, table, fields, digits=7)


def main() -> None:
    if "--brush" in sys.argv:
        rows = load(BRUSH_TABLE)
        done = {(float(row["elements_per_radius"]), int(row["placement"])) for row in rows}
        fields = brush_fields(8, 1e-5)
        for per_radius in RESOLUTIONS:
            for placement in range(len(PLACEMENTS)):
                if (per_radius, placement) not in done:
                    new = run_brush(8, 1e-5, per_radius, placement, fields)
                    rows += new
                    write(rows, BRUSH_TABLE, BRUSH_FIELDS)
                    for row in new:
                        print(", ".join(f"{name}={row[name]}" for name in BRUSH_FIELDS), flush=True)
        write(limit(rows), LIMIT, LIMIT_FIELDS)
        return
    if "--limit" in sys.argv:
        write(limit(load(BRUSH_TABLE)), LIMIT, LIMIT_FIELDS)
        return
    rows = load()
    done = {(float(row["elements_per_radius"]), int(row["placement"])) for row in rows}
    for per_radius, placement in TILT_CASES:
        if (per_radius, placement) in done:
            continue
        new = run(per_radius, placement)
        rows += new
        write(rows)
        for row in new:
            print(", ".join(f"{name}={row[name]}" for name in FIELDS), flush=True)


if __name__ == "__main__":
    main()
