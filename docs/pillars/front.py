"""A flat tip's peel in the continuum: the first-order perturbation of its contact edge, with no raster.

A rigid flat circular tip (radius a) in full contact with the half-space
carries along its edge the stress intensity K(theta).  When the largest K
reaches K_c = sqrt(2 E* dgamma) (the tip's *first point*) its contact starts
to recede there.  Whether it then holds more load (a stable peel) or comes
off at once (Kendall's instability) is the question ``tilted.py`` and
``fine_tip.py`` put to rasters of 7 to 160 elements per radius.  This script
answers it in the continuum, to first order in the edge's advance
A(theta) (in units of a; A >= 0 where the contact has receded):

    K(theta) = K_0 [ g(theta) + sum_n f(n) A_n cos(n theta) ],

with g = K / K_0 of the full circle (K_0 its uniform part, P / (2 a sqrt(pi a))
for the tip's load P) and the response f(n) of the circular contact to an
advance A_n cos(n theta):

* f(0) = 3/2 at a fixed load (K_0 = P / (2 c sqrt(pi c)) on a circle of
  radius c = a - A_0): Kendall's instability; 1/2 at a fixed displacement
  (K_0 = E* d / sqrt(pi c)); ``load_control`` between the two for a tip on
  a spring: 3/2 - (the contact's share of the tip's compliance).
* f(1) = 0: a shifted circle carries the same K (translation).
* f(n) = -(n - 1) / 2 for n >= 1: for n = 2 the rigid elliptical punch's
  closed form (K ~ (x^2 / a^4 + y^2 / b^2)^(-1/4) / (a b), checked in
  ``tests/test_pillar_front.py``), for large n the half-plane crack's
  -|k| / 2 (Rice 1985): a receding bump lowers its own K, the front's
  stiffness that can hold a peel.

The edge recedes where K = K_c and stays where K <= K_c (A >= 0, no
re-attachment): a linear complementarity problem in A on ``angles`` points
of the edge, solved by primal-dual active sets while the load rises from
the first point; the tip's capacity is the largest load with a solution.
Left out (second order in A, or of order eps A with eps K's relative
variation, about 0.2 on a brush's edge tips): the change of the neighbours'
part of K as the edge moves, and A's own squares.  The gains below are
therefore first-order estimates, with an error of the order of eps times
themselves.

Measured (``front.csv``; the same within 0.13 % on 128, 256 and 512 angles):
g = 1 + eps cos(theta) (``tilted.py``'s tilt) holds 0.34 / 0.64 / 1.19 /
1.65 % beyond its first point at eps = 0.05 / 0.1 / 0.2 / 0.3, the peel
spanning 88-90 degrees of the edge and receding by 0.044 a at eps = 0.2.
The raster's exact path (``fine_tip.csv``) peels the same region: a span of
83-93 degrees and a depth of 0.04-0.055 a at 57.8-160 elements per radius,
the peeled elements growing with the area (h^-2), so its stable peel is the
continuum's, not a staircase's; its gain falls from 1.9-2.0 % there to 1.65 %
at 160, above the first-order 1.19 % by less than eps times the depth
(0.2 x 0.044 = 0.9 %, the order of what the model leaves out).

The ``random`` family's brush (``--random`` -> ``front_random.csv``; its 64
centres from `validation.problem`, the closest two 2.561 radii apart, a gap
of 0.561 a or 2.03 elements at N = 128; k~ = 1e-5): the first point
0.01042651 (tip 15 first, its centre 1.4 radii from the domain's side);
every tip at its capacity 0.0106793 = 0.7025 n^2 F_K, again at the first
event (tip 15, gain 2.42 %).  Twelve events hold F_A: the 13th to 32nd stay
12 % below it with the peel, the 13th to 63rd 11 % below on the first
point's path.  Degrees 12 and 16 give the same F_A to 1e-9 and the same
first point to 2e-8; the close pairs on 12 x 48 instead of 24 x 96 points
(and the norms on them) the same first event to 5e-10.  K's relative n = 1
amplitude reaches 0.54 (tip 58; 0.48 on tip 15, 25 tips above 0.3): the
gains are first-order estimates beyond the range checked (eps <= 0.3),
their error of the order of eps times themselves (1.2 % of F_A on tip 15),
and at eps = 0.2 the raster's converged gain was above the first-order one,
so this F_A is the random brush's lower end.  Against it the pillar model
with ``pillar_tip_peel`` (``peel.csv``) is +0.33 % (3.6 elements per
radius) and -0.19 % (7.2); the exact path (``tips_extrapolated.csv``)
+5.0 / +3.4 / +2.8 % at N = 128 / 256 / 512 and its first-order
extrapolation +2.21 % (the flat brush's N = 512: +2.45 % above its lower
end).

Those gains are half the rasters' (``--random-tips`` ->
``front_random_tips.csv``: the four weakest tips, 15, 58, 44 and 40, each
on `tilted.Tip` alone in the others' continuum deflection, four
placements): 6.3 / 4.9 / 5.8 / 5.6 % at 7.2 elements per radius, 4.8 / 4.1 /
4.5 / 4.6 % at 14.4, 4.8 / 3.7 / 4.3 / 4.3 % at 28.9, against first-order
2.4 / 1.9 / 2.1 / 2.2 %.  The least capacity, tip 58's, puts the brush at
0.0109980 / 0.0109185 / 0.0108703: 0.41 % below the exact path's
extrapolation at 28.9 per radius, and an upper end if these gains fall
toward the limit from above as the flat tips' do.  ``--random-tips-fine``
takes them on ``fine_tip.py``'s matrix-free path at 57.8 and 80 per radius
(about 25 CPU-min): gains 4.1 / 3.0 / 3.5 / 3.5 % and 4.1 / 3.1 / 3.6 /
3.5 %, level from 57.8 as the flat brush's edge tips' are; the least,
tip 58's, puts the upper end at 0.0108091 (the limit 1.2 % wide).

    python docs/pillars/front.py          # front.csv (about 2 CPU-min)
    python docs/pillars/front.py --brush  # front_brush.csv (about 2.5 CPU-min)
    python docs/pillars/front.py --random # front_random.csv (the random family's brush; about 8 CPU-min)
    python docs/pillars/front.py --random-tips  # front_random_tips.csv (its weakest tips' rasters; 7 CPU-min)
    nice python docs/pillars/front.py --random-tips-fine  # the same at 57.8 and 80 per radius, matrix-free (resumes)
    python docs/pillars/front.py --table  # src/brushbem/data/peel_gain.csv (the criterion's gains)
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import calibration  # noqa: E402
import continuum  # noqa: E402
from brushbem.pillars.peel import AXES, TABLE_ANGLES, capacity, response, shape  # noqa: E402,F401
TABLE = HERE / "front.csv"
#: The gains `brushbem.pillars.peel.gain` interpolates (``--table``).
GAIN_TABLE = HERE.parents[1] / "src" / "brushbem" / "data" / "peel_gain.csv"
FIELDS = ("profile", "tilt_ratio", "angles", "load_control", "gain", "span_degrees", "depth")


BRUSH_TABLE = HERE / "front_brush.csv"
BRUSH_FIELDS = ("pillars_per_side", "stiffness_ratio", "angles", "load_control", "first_point_adhesive_force",
                "adhesive_force", "force_by_ideal_sharing", "gain_over_first_point", "attached_at_pull_off",
                "deciding_tip", "deciding_gain")

#: The ``random`` family's brush (``--random``): per resolution (degree, nodes x angles a disk, and the pairs
#: closer than 5 radii on 24 x 96 points) the first point and the capacity rule's F_A at k~ = 1e-5.
RANDOM_TABLE = HERE / "front_random.csv"
RANDOM_FIELDS = ("family", "pillars", "stiffness_ratio", "degree", "nodes", "disk_angles", "near_distance",
                 "near_nodes", "near_angles", "angles", "load_control", "first_point_adhesive_force",
                 "adhesive_force", "force_by_ideal_sharing", "gain_over_first_point", "attached_at_pull_off",
                 "deciding_tip", "deciding_gain", "events_at_pull_off", "events", "largest_tilt")
RANDOM_RESOLUTIONS = ((12, 12, 48, (5.0, 24, 96)), (16, 12, 48, (5.0, 24, 96)))


def random_row(resolution: tuple, first: dict, out: dict, stiffness: float = 1e-5) -> dict:
    """One row of ``front_random.csv`` from `brush_pull_off`'s first point (``peel=False``) and capacity runs."""
    degree, nodes, points, near = resolution
    top = [event[0] for event in out["events"]].index(out["adhesive_force"])
    return {"family": "random", "pillars": out["events"][0][1], "stiffness_ratio": stiffness,
            "degree": degree, "nodes": nodes, "disk_angles": points, "near_distance": near[0],
            "near_nodes": near[1], "near_angles": near[2], "angles": 128, "load_control": float(out["load_control"]),
            "first_point_adhesive_force": float(first["adhesive_force"]),
            "adhesive_force": float(out["adhesive_force"]),
            "force_by_ideal_sharing": float(out["force_by_ideal_sharing"]),
            "gain_over_first_point": float(out["adhesive_force"] / first["adhesive_force"] - 1),
            "attached_at_pull_off": out["attached_at_pull_off"], "deciding_tip": int(out["deciding_tip"][0]),
            "deciding_gain": float(out["deciding_gain"]), "events_at_pull_off": top + 1,
            "events": len(out["events"]), "largest_tilt": float(out["tilt"])}


def random_rows(last: int = 12) -> list[dict]:
    """The ``random`` family's 8 x 8 brush at k~ = 1e-5 (`random_centres`) at each of ``RANDOM_RESOLUTIONS``."""
    centres, rows = random_centres(), []
    a = math.sqrt(continuum.PHI / math.pi) / 8
    for resolution in RANDOM_RESOLUTIONS:
        degree, nodes, points, near = resolution
        brush = continuum.Brush(8, 1 / 8 / a, degree, nodes, points, centres=centres, near=near)
        first = brush_pull_off(8, 1e-5, last=last, peel=False, brush=brush)
        rows.append(random_row(resolution, first, brush_pull_off(8, 1e-5, last=last, brush=brush)))
        print(rows[-1], flush=True)
    return rows


#: The random brush's weakest tips on rasters, each alone in the others' continuum field (``--random-tips``).
RANDOM_TIPS_TABLE = HERE / "front_random_tips.csv"
#: The resolutions of ``--random-tips-fine`` (the flat brush's upper end's, ``fine_tip.py --brush``).
RANDOM_FINE = (57.774, 80.0)
RANDOM_TIPS_FIELDS = ("tip", "elements_per_radius", "placement", "first_point_adhesive_force", "first_point_ratio",
                      "first_order_gain", "tilt", "gain", "capacity_adhesive_force", "events")


def random_tip_rows(weakest: int = 4, resolutions: tuple[float, ...] = (7.222, 14.444, 28.887),
                    done: frozenset = frozenset(), fine: bool = False, table: list[dict] | None = None) -> list[dict]:
    """The ``weakest`` tips of the random brush at k~ = 1e-5 (by first-order capacity, all 64 attached) on
    `tilted.Tip` rasters at ``resolutions`` (its four placements), each alone in the other tips' continuum
    deflection with the tips' loads in proportion: the raster's gain over the tip's continuum first point (F_A
    over the lone tip's raster F_A over the first-point ratio, minus 1) and the brush's force at that capacity.
    ``fine``: on the matrix-free tip of ``fine_tip.py`` instead (its exact path on the same criterion, equal to
    `tilted.Tip`'s to seven digits), skipping the (resolution, placement) pairs ``done`` and writing ``table``
    (the rows so far) with the new ones after each pair.

    The field's sign: a rigid tip's own pressure makes up its displacement less the others' deflection
    (`continuum.Brush.solve`), so it enters `tilted.Tip` (whose load makes the displacement delta + field)
    negated; so placed, the raster's first detached element lies where the continuum's K peaks (checked at
    14.4-40 elements per radius, within 25 degrees)."""
    import tilted

    centres = random_centres()
    a = math.sqrt(continuum.PHI / math.pi) / 8
    brush = continuum.Brush(8, 1 / 8 / a, 12, 12, 48, centres=centres, near=(5.0, 24, 96))
    spring = 2 * math.pi * continuum.MODULUS * a / (1e-5 * continuum.MODULUS)
    control = 1.5 - 1 / (1 + spring / math.pi)
    c = brush.solve(np.ones(len(centres), bool), spring)
    intensity = c @ brush.edge[::32].T
    scale = 2 * math.pi * c[:, 0].sum() * math.sqrt(2 * continuum.MODULUS * continuum.DGAMMA) * a**1.5
    tips = []
    for i in range(len(centres)):
        g = intensity[i] / c[i, 0]
        first = scale / (math.sqrt(math.pi) * intensity[i].max())
        gain = capacity(g, control)["gain"]
        tips.append({"tip": i, "first_point_adhesive_force": first, "first_point_ratio": c[i, 0] / intensity[i].max(),
                     "first_order_gain": gain, "tilt": 2 * abs(np.fft.rfft(g)[1]) / g.size,
                     "capacity": first * (1 + gain)})
    tips = sorted(tips, key=lambda tip: tip["capacity"])[:weakest]
    fields = {(tip["tip"], 0): (tip["first_point_ratio"], lambda points, i=tip["tip"]: -brush.external(c, i, points))
              for tip in tips}
    rows = []
    for per_radius in resolutions:
        for placement in range(len(tilted.PLACEMENTS)):
            if (per_radius, placement) in done:
                continue
            if fine:
                import fine_tip

                rasters = fine_tip.run_brush(per_radius, placement, fields)
            else:
                rasters = tilted.run_brush(8, 1e-5, per_radius, placement, fields)
            for raster in rasters:
                rows.append(random_tip_row(next(t for t in tips if f"{t['tip']}-0" == raster["tip"]), raster))
                print(rows[-1], flush=True)
            if table is not None:
                _write(table + rows, RANDOM_TIPS_TABLE, RANDOM_TIPS_FIELDS)
    return rows


def random_tip_row(tip: dict, raster: dict) -> dict:
    """One row of ``front_random_tips.csv``: the continuum tip and its raster row from `tilted.run_brush`."""
    return {"tip": tip["tip"], "elements_per_radius": raster["elements_per_radius"], "placement": raster["placement"],
            "first_point_adhesive_force": float(tip["first_point_adhesive_force"]),
            "first_point_ratio": float(tip["first_point_ratio"]), "first_order_gain": float(tip["first_order_gain"]),
            "tilt": float(tip["tilt"]), "gain": float(raster["gain"]),
            "capacity_adhesive_force": float(tip["first_point_adhesive_force"] * (1 + raster["gain"])),
            "events": raster["events"]}


def _write(rows: list[dict], table: Path, fields: tuple[str, ...]) -> None:
    calibration.write(rows, table, fields, digits=7)


def brush_rows() -> list[dict]:
    """The 8 x 8 flat brush at k~ = 1e-5 and 10 with and without the tips' peel (``front_brush.csv``)."""
    rows = []
    for stiffness, last in ((1e-5, 3), (10.0, 12)):
        first = brush_pull_off(8, stiffness, last=last, peel=False)
        out = brush_pull_off(8, stiffness, last=last)
        rows.append({"pillars_per_side": 8, "stiffness_ratio": stiffness, "angles": 128,
                     "load_control": float(out["load_control"]),
                     "first_point_adhesive_force": float(first["adhesive_force"]),
                     "adhesive_force": float(out["adhesive_force"]),
                     "force_by_ideal_sharing": float(out["force_by_ideal_sharing"]),
                     "gain_over_first_point": float(out["adhesive_force"] / first["adhesive_force"] - 1),
                     "attached_at_pull_off": out["attached_at_pull_off"],
                     "deciding_tip": "-".join(map(str, out["deciding_tip"])),
                     "deciding_gain": float(out["deciding_gain"])})
        print(rows[-1], flush=True)
    return rows


def gain_rows() -> list[dict]:
    """The continuum gain of g = 1 + tilt cos(theta) + bend cos(2 theta + phase) over `peel.AXES`
    (``data/peel_gain.csv``), on `peel.TABLE_ANGLES` edge points to a precision of 1e-6."""
    rows = []
    for control in AXES["load_control"]:
        for tilt in AXES["tilt"]:
            for bend in AXES["bend"]:
                for phase in AXES["phase"]:
                    out = capacity(shape(tilt, bend, phase), control, precision=1e-6)
                    rows.append({"tilt": tilt, "bend": bend, "phase": round(phase, 9), "load_control": control,
                                 "gain": out["gain"], "span_degrees": out["span_degrees"], "depth": out["depth"]})
        print(f"load_control {control}: {len(rows)} gains", flush=True)
    return rows


def main() -> None:
    if "--table" in sys.argv:
        _write(gain_rows(), GAIN_TABLE, ("tilt", "bend", "phase", "load_control", "gain", "span_degrees", "depth"))
        return
    if "--random-tips-fine" in sys.argv:
        import reference

        table = reference.load(RANDOM_TIPS_TABLE)
        done = frozenset((float(r["elements_per_radius"]), int(r["placement"])) for r in table)
        random_tip_rows(resolutions=RANDOM_FINE, done=done, fine=True, table=table)
        return
    if "--random-tips" in sys.argv:
        _write(random_tip_rows(), RANDOM_TIPS_TABLE, RANDOM_TIPS_FIELDS)
        return
    if "--random" in sys.argv:
        _write(random_rows(), RANDOM_TABLE, RANDOM_FIELDS)
        return
    if "--brush" in sys.argv:
        _write(brush_rows(), BRUSH_TABLE, BRUSH_FIELDS)
        return
    rows = []
    for eps in (0.05, 0.1, 0.2, 0.3):
        for angles in (128, 256, 512):
            theta = 2 * np.pi * np.arange(angles) / angles
            out = capacity(1 + eps * np.cos(theta))
            rows.append({"profile": "tilt", "tilt_ratio": eps, "angles": angles, "load_control": 1.5, **out})
            print(rows[-1], flush=True)
    _write(rows, TABLE, FIELDS)



def random_centres(per_side: int = 8) -> np.ndarray:
    """The ``random`` family's n^2 pillar centres (`validation.problem`, seed 3, footprints at least two elements
    apart on N = 16 n) in units of the pillar radius a = sqrt(phi / pi) / n."""
    from validation import problem

    case, _ = problem("random", per_side, 1e-5)
    geometry = case.indenter.description
    return np.asarray(geometry.centres, float) / float(geometry.pillar_radius)


def brush_pull_off(per_side: int, stiffness: float, angles: int = 128, degree: int = 12, last: int = 12,
                   peel: bool = True, centres: np.ndarray | None = None, nodes: int = 12, points: int = 48,
                   near: tuple[float, int, int] | None = None, brush: "continuum.Brush | None" = None) -> dict:
    """The families' flat n x n brush (``continuum.Brush``) pulled off with every tip leaving at its capacity
    (its first point times 1 + its peel's gain from `capacity` on its own K(theta)) instead of its first point:
    the events until ``last`` tips are gone, F_A the largest total force at one (in units of the brush's
    n^2 F_K and absolute, as ``continuum_reference.csv``).  With ``centres`` (in radii, e.g. `random_centres`)
    the same for n^2 tips of the same radius and springs there (``nodes`` x ``points`` a disk, ``near`` as
    `continuum.Brush`); the deciding tip is then its index.  Also returned: every event (force, tips attached
    before it, the tip leaving, its gain) and the largest relative n = 1 amplitude of K / K_0 on an attached
    tip up to F_A (``tilt``; the first-order model's gains are checked to 0.3).  ``brush``: one already built
    for these arguments (the other resolution arguments are then unused)."""
    a = math.sqrt(continuum.PHI / math.pi) / per_side
    if brush is None:
        brush = continuum.Brush(per_side, 1 / per_side / a, degree, nodes, points, centres=centres, near=near)
    count = len(brush.centres)
    spring = 2 * math.pi * continuum.MODULUS * a / (stiffness * continuum.MODULUS)
    # The tip's own contact compliance 1 / (2 E* a) against the spring's 1 / k, in the units of `Brush.solve`:
    # the contact's share of the compliance sets how far K_0 rises as the contact recedes at a fixed base.
    contact_share = 1 / (1 + spring / math.pi) if stiffness > 0 else 0.0
    load_control = 1.5 - contact_share
    stride = brush.edge.shape[0] // angles
    attached = np.ones(count, bool)
    events, tilts = [], []
    while attached.sum() > count - last:
        c = brush.solve(attached, spring)
        intensity = (c @ brush.edge[::stride].T)  # K / sqrt(pi) at d = 1, per tip and angle
        best, leaving, gain_of, tilt = np.inf, -1, 0.0, 0.0
        for i in np.flatnonzero(attached):
            g = intensity[i] / c[i, 0]  # K over its uniform part sqrt(pi) c_00
            tilt = max(tilt, 2 * abs(np.fft.rfft(g)[1]) / g.size)
            gain = capacity(g, load_control)["gain"] if peel else 0.0
            d = (1 + gain) / (math.sqrt(math.pi) * intensity[i].max())
            if d < best:
                best, leaving, gain_of = d, int(i), gain
        force = 2 * math.pi * c[:, 0].sum() * best
        events.append((force, int(attached.sum()), leaving, gain_of))
        tilts.append(tilt)
        attached[leaving] = False
    k_c = math.sqrt(2 * continuum.MODULUS * continuum.DGAMMA)
    kendall = math.sqrt(8 * math.pi * continuum.MODULUS * continuum.DGAMMA * a**3)
    forces = [force * k_c * a**1.5 for force, *_ in events]
    top = int(np.argmax(forces))
    deciding = divmod(events[top][2], per_side) if brush.grid is not None else (events[top][2],)
    return {"adhesive_force": forces[top], "force_by_ideal_sharing": forces[top] / (count * kendall),
            "attached_at_pull_off": events[top][1], "deciding_tip": deciding,
            "deciding_gain": events[top][3], "load_control": load_control,
            "events": [(f, *rest) for f, (_, *rest) in zip(forces, events)], "tilt": max(tilts[:top + 1])}


if __name__ == "__main__":
    main()
