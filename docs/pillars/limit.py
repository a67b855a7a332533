"""Can tips of 3-4 elements per radius give F_A within 1 % of the continuum limit?  Decided on the measured tables.

The route tried: take the raster's noise out of the fine tips by averaging
the pillar model's F_A over placements of the lattice on the tips' own
raster (``placement.csv``: six placements at 3.6, 7.2 and 14.4 elements per
radius, four at 28.9, up to four at 39.7 as ``placement.py --finer`` adds
them), then extrapolate the means in the tips' elements per radius q with
an order: the one the means show over three successive resolutions, the
first order a lone punch shows (``brushbem/data/resolution_error.csv``) and
1/2, each over the placements its resolutions share.  The means are of the
plain criterion (the raster's Sigma_c: the calibrated F_A times the lone
tip's 1 + e_R of that placement, exact for a brush of level tips whose F_A
is proportional to Sigma_c, ``tests/test_pillar_reference.py``) and of the
calibrated one (the lone tip's raster error removed).  The route succeeds
where the extrapolated mean lies within 1 % of the limit's whole interval
(`interval`: at k~ = 1e-5 from the brush with every tip's first-order
continuum peel, ``front_brush.csv``, to the edge tips' capacity alone in
their field at the finest resolution measured, 80 elements per radius, `edge_bound`; at k~ = 10 the lower
end only, the errors quoted against it and the old extrapolation).

Rows (``limit.csv``): ``stiffness_ratio``, ``route``, ``plain`` or
``calibrated``, ``tips`` (elements per radius; the finest the extrapolation
used), ``order``, ``placements``, ``adhesive_force``, ``spread`` (over the
placements, of the mean), ``error_lower`` / ``error_middle`` /
``error_upper`` (against the interval's ends and middle; the middle at
k~ = 10 is the old extrapolation, ``tips_extrapolated.csv``), ``within``
(both ends within 1 %), ``cpu_seconds`` (summed over the placements, 8 x 8
brush, separate runs).

The brush against its tips (``limit_tips.csv``): the calibrated placement
mean over 64 F_K against each of the four weakest tips' capacity alone in
its continuum field at the same resolution (``tilted_brush.csv``: first
point times 1 + gain), whose least among the tips the brush follows (the
edge tips; not the corner) is the upper end.

The other tables on the new reference (``rereferenced.csv``): every F_A of
``criteria.csv``, ``proxy.csv`` and ``calibration.csv`` on a case that the
continuum limit covers (the flat, hierarchical and concave 8 x 8 brushes at
k~ = 1e-5), its error as quoted (against ``tips_extrapolated.csv``) and
against the limit's middle and ends; and the factor ``periodic.csv``'s
proxies were judged by (F_ref / F_plain) on the new reference.

Measured (the verdict in ``docs/pillars/accuracy.md``, "Tips of 3-4
elements per radius" and "The peel survives the continuum"): at k~ = 1e-5
the limit is known to 1.0 % (0.0120385 .. 0.0121588, the neighbours' field
entering the raster tips negated: "The neighbours' field's sign"); no plain
placement mean is within 1 % of both ends; 8 of the 18 extrapolations are;
the brush follows its weakest tip (the middle of an edge); the per-element
criterion tends to the first point, 1.9 % below the lower end.

No pull-off runs here: ``nice python docs/pillars/placement.py --finer``
adds the 39.7 rows (about 3-6 CPU-min each); this script only reads.

    python docs/pillars/limit.py
"""

from __future__ import annotations

import csv
import math
import statistics
import sys
from collections import defaultdict
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import reference  # noqa: E402

LIMIT, TIPS, REREFERENCED = HERE / "limit.csv", HERE / "limit_tips.csv", HERE / "rereferenced.csv"
#: The brush's own discretisation error that a run reports (`brushbem.config.advice`).
BRUSH_TABLE = HERE.parents[1] / "src" / "brushbem" / "data" / "brush_resolution_error.csv"
BRUSH_FIELDS = ("elements_per_radius", "placements", "force_error_mean", "force_error_min", "force_error_max")
FIELDS = ("stiffness_ratio", "route", "criterion", "tips", "order", "placements", "adhesive_force", "spread",
          "error_lower", "error_middle", "error_upper", "error_edge", "within", "cpu_seconds")
#: Tips whose capacity alone the brush follows at the finest common resolution within this (``limit_tips.csv``).
FOLLOWS = 0.005
TIP_FIELDS = ("elements_per_radius", "placements", "brush_by_kendall", "tip", "tip_capacity_by_kendall",
              "brush_over_tip")
REREFERENCED_FIELDS = ("table", "part", "family", "criterion", "tips", "key", "adhesive_force", "error_quoted",
                       "error_lower", "error_middle", "error_upper")
#: The flat brush's first points (``continuum_reference.csv``, exact to 2e-9) and the old extrapolation.
FIRST = {1e-5: 0.0118133, 10.0: 0.0081111414}
PILLARS = 64
#: Kendall's force of one tip of the families (r = sqrt(0.16 / pi) / 8, E* = 1, dgamma = 1e-4): sqrt(8 pi r^3 E* dg).
KENDALL = math.sqrt(8 * math.pi * (math.sqrt(0.16 / math.pi) / 8) ** 3 * 1e-4)
#: Within 1 % of the whole interval.
TARGET = 0.01
#: The finest resolution that the brush (``placement.csv``) and the tips alone (``tilted_brush.csv``) both hold.
COMMON = 28.887


def _rows(name: str) -> list[dict]:
    return reference.load(HERE / name)


def interval(stiffness: float) -> tuple[float, float | None, float]:
    """(lower, upper or None, middle) of the flat brush's F_A at ``stiffness``.  Below: the brush with every tip
    leaving at its first-order continuum capacity (``front_brush.csv``, ``front.py``: the first point plus the
    tips' stable peel; the raster's gains lie above the first-order ones at every resolution, ``fine_tip.csv``).
    Above, at k~ = 1e-5: the edge tips' capacity alone in their continuum field at 40 elements per radius
    (`edge_bound`, the raster's gains still falling).  The middle at 1e-5 is the two's; at 10, where no upper
    end is known, the old extrapolation of the exact path (``tips_extrapolated.csv``, 0.07 % above the
    lower end)."""
    (row,) = [r for r in _rows("front_brush.csv") if float(r["stiffness_ratio"]) == stiffness]
    lower = float(row["adhesive_force"])
    if stiffness == 1e-5:
        upper = edge_bound()
        return lower, upper, (lower + upper) / 2
    old = next(r for r in _rows("tips_extrapolated.csv") if r["family"] == "flat" and float(r["stiffness_ratio"]) == 10)
    return lower, None, float(old["extrapolated_adhesive_force"])


def placement_forces() -> dict[tuple[float, str], dict[float, dict[tuple[str, str], float]]]:
    """{(k~, criterion): {q: {shift: F_A}}} of the flat 8 x 8 brush (``placement.csv``), plain and calibrated."""
    out: dict = defaultdict(lambda: defaultdict(dict))
    for row in _rows("placement.csv"):
        if row["family"] != "flat":
            continue
        stiffness, q = float(row["stiffness_ratio"]), float(row["tip_elements_per_radius"])
        shift = (row["shift_y"], row["shift_x"])
        calibrated = float(row["calibrated_adhesive_force"])
        out[(stiffness, "calibrated")][q][shift] = calibrated
        out[(stiffness, "plain")][q][shift] = calibrated * (1 + float(row["lone_tip_error"]))
    return out


def placement_means() -> dict[tuple[float, str], dict[float, tuple[float, float, int, float]]]:
    """{(k~, criterion): {q: (mean, spread, placements, CPU-s)}} of the flat 8 x 8 brush (``placement.csv``)."""
    seconds = defaultdict(float)
    for row in _rows("placement.csv"):
        if row["family"] == "flat":
            seconds[(float(row["stiffness_ratio"]), float(row["tip_elements_per_radius"]))] += float(row["cpu_seconds"])
    out: dict = defaultdict(dict)
    for (stiffness, criterion), table in placement_forces().items():
        for q, by_shift in table.items():
            values = list(by_shift.values())
            mean = statistics.fmean(values)
            out[(stiffness, criterion)][q] = (mean, (max(values) - min(values)) / mean, len(values),
                                              seconds[(stiffness, q)])
    return out


def matched(by_q: dict[float, dict], qs: list[float]) -> tuple[list[float], int]:
    """The means at ``qs`` over the placements that every one of them holds (an extrapolation compares like with
    like: the finest resolutions hold the first placements only), and their number."""
    common = set.intersection(*(set(by_q[q]) for q in qs))
    return [statistics.fmean(by_q[q][shift] for shift in common) for q in qs], len(common)


def extrapolated(q: list[float], f: list[float], order: float) -> float:
    """F at q -> infinity from the last two of ``f`` at the resolutions ``q``, error ~ q^-order."""
    (q1, f1), (q2, f2) = (q[-2], f[-2]), (q[-1], f[-1])
    r = (q2 / q1) ** order
    return f2 + (f2 - f1) / (r - 1)


def observed_order(q: list[float], f: list[float]) -> float:
    """The order p with f = f_inf + C q^-p through the last three points (nan where the steps change sign or the
    second is not the smaller: no order)."""
    (q0, q1, q2), (f0, f1, f2) = q[-3:], f[-3:]
    d1, d2 = f0 - f1, f1 - f2
    if d1 * d2 <= 0 or abs(d2) >= abs(d1):
        return math.nan

    def gap(p: float) -> float:  # (q0^-p - q1^-p) / (q1^-p - q2^-p) - d1 / d2, decreasing in p
        return (q0 ** -p - q1 ** -p) / (q1 ** -p - q2 ** -p) - d1 / d2

    lo, hi = 1e-6, 20.0
    if gap(lo) * gap(hi) > 0:
        return math.nan
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if gap(lo) * gap(mid) > 0 else (lo, mid)
    return 0.5 * (lo + hi)


def _errors(force: float, stiffness: float) -> dict:
    lower, upper, middle = interval(stiffness)
    ends = [force / lower - 1] + ([] if upper is None else [force / upper - 1])
    edge = edge_bound() if stiffness == 1e-5 else None
    return {"error_lower": force / lower - 1, "error_middle": force / middle - 1,
            "error_upper": "" if upper is None else force / upper - 1,
            "error_edge": "" if edge is None else force / edge - 1,
            "within": upper is not None and max(abs(e) for e in ends) <= TARGET}


def capacities() -> dict[tuple[str, float], float]:
    """{(tip, q): the tip's capacity alone in its continuum field, over n^2 F_K (mean over the placements;
    ``tilted_brush.csv`` to 40 elements per radius, ``fine_tip_brush.csv`` beyond)}."""
    capacity = defaultdict(list)
    finer = HERE / "fine_tip_brush.csv"  # the same tips on the matrix-free path, beyond 40 per radius
    for row in _rows("tilted_brush.csv") + (_rows("fine_tip_brush.csv") if finer.exists() else []):
        capacity[(row["tip"], float(row["elements_per_radius"]))].append(
            float(row["first_point_ratio"]) * (1 + float(row["gain"])))
    return {key: statistics.fmean(values) for key, values in capacity.items()}


def edge_bound() -> float:
    """The upper bound of the tips the brush follows: the least capacity at the finest resolution of
    ``tilted_brush.csv`` among the tips that the calibrated brush (``placement.csv``) lies within `FOLLOWS` of at
    the finest resolution both hold (28.9; the corner's, which it exceeds by 1.6 %, left out), times n^2 F_K."""
    followed = [row for row in tips() if row["elements_per_radius"] == COMMON]
    kept = [row["tip"] for row in followed if abs(row["brush_over_tip"]) <= FOLLOWS]
    table = capacities()
    finest = max(q for _, q in table)
    return PILLARS * KENDALL * min(table[(tip, finest)] for tip in kept)


def routes() -> list[dict]:
    """The rows of ``limit.csv``: the default, every placement mean, their extrapolations."""
    means, out = placement_means(), []
    default = {float(r["stiffness_ratio"]): (float(r["adhesive_force"]), float(r["cpu_seconds"]))
               for r in _rows("calibration.csv") if r["family"] == "flat" and r["calibrated"] == "False"
               and float(r["tip_elements_per_radius"]) < 4}
    for stiffness in (10.0, 1e-5):
        force, seconds = default[stiffness]
        out.append({"stiffness_ratio": stiffness, "route": "default (the families' raster)", "criterion": "plain",
                    "tips": 3.611, "order": "", "placements": 1, "adhesive_force": force, "spread": "",
                    **_errors(force, stiffness), "cpu_seconds": seconds})
        per_element = defaultdict(list)
        for r in _rows("criteria.csv"):
            if r["criterion"] == "per_element" and r["family"] == "flat" and float(r["stiffness_ratio"]) == stiffness:
                if r["part"] in ("placement", "finest"):
                    per_element[float(r["tip_elements_per_radius"])].append(
                        (float(r["adhesive_force"]), float(r["cpu_seconds"])))
                elif r["part"] == "families" and float(r["tip_elements_per_radius"]) < 4:
                    force = float(r["adhesive_force"])
                    out.append({"stiffness_ratio": stiffness, "route": "per-element criterion (the families' raster)",
                                "criterion": "per_element", "tips": 3.611, "order": "", "placements": 1,
                                "adhesive_force": force, "spread": "", **_errors(force, stiffness),
                                "cpu_seconds": float(r["cpu_seconds"])})
        for q, values in sorted(per_element.items()):
            forces = [v[0] for v in values]
            mean = statistics.fmean(forces)
            out.append({"stiffness_ratio": stiffness, "route": "placement mean" if len(forces) > 1 else "own raster",
                        "criterion": "per_element", "tips": q, "order": "", "placements": len(forces),
                        "adhesive_force": mean, "spread": (max(forces) - min(forces)) / mean,
                        **_errors(mean, stiffness), "cpu_seconds": sum(v[1] for v in values)})
        for criterion in ("plain", "calibrated"):
            table = means[(stiffness, criterion)]
            q = sorted(table)
            for each in q:
                mean, spread, count, cpu = table[each]
                out.append({"stiffness_ratio": stiffness, "route": "placement mean", "criterion": criterion,
                            "tips": each, "order": "", "placements": count, "adhesive_force": mean,
                            "spread": spread, **_errors(mean, stiffness), "cpu_seconds": cpu})
            forces = placement_forces()[(stiffness, criterion)]
            for finest in range(3, len(q) + 1):  # every three successive resolutions, and their last two
                qs = q[finest - 3:finest]
                cpu = sum(table[each][3] for each in qs[-2:])
                three, _ = matched(forces, qs)
                two, count = matched(forces, qs[-2:])
                for name, order in (("observed", observed_order(qs, three)), ("first", 1.0), ("half", 0.5)):
                    fs = three if name == "observed" else two
                    force = extrapolated(qs, fs, order) if math.isfinite(order) else math.nan
                    row = {"stiffness_ratio": stiffness, "route": f"extrapolated ({name} order)",
                           "criterion": criterion, "tips": qs[-1], "order": order,
                           "placements": matched(forces, qs)[1] if name == "observed" else count,
                           "adhesive_force": force, "spread": "", "cpu_seconds": cpu}
                    row.update(_errors(force, stiffness) if math.isfinite(force) else
                               {"error_lower": "", "error_middle": "", "error_upper": "", "error_edge": "",
                                 "within": False})
                    out.append(row)
    return out


def tips() -> list[dict]:
    """The rows of ``limit_tips.csv``: the brush (calibrated placement means) against each tip alone."""
    means = placement_means()[(1e-5, "calibrated")]
    capacity = capacities()
    out = []
    for q, (mean, _, count, _) in sorted(means.items()):
        near = [key for key in capacity if abs(key[1] / q - 1) < 0.02]  # 39.7 against the tips' 40
        for tip, at in sorted(near):
            tip_capacity = capacity[(tip, at)]
            brush = mean / (PILLARS * KENDALL)
            out.append({"elements_per_radius": q, "placements": count, "brush_by_kendall": brush, "tip": tip,
                        "tip_capacity_by_kendall": tip_capacity, "brush_over_tip": brush / tip_capacity - 1})
    return out


def rereferenced() -> list[dict]:
    """The rows of ``rereferenced.csv``: every F_A on a case the continuum limit covers, on the new reference."""
    covered = {(family, 1e-5) for family in ("flat", "hierarchy", "concave")}
    old = {(r["family"], float(r["stiffness_ratio"])): float(r["extrapolated_adhesive_force"])
           for r in _rows("tips_extrapolated.csv") if r["extrapolated_adhesive_force"] not in ("", "nan")}
    out = []

    def add(table: str, part: str, family: str, criterion: str, q, key: str, force: float, quoted) -> None:
        errors = _errors(force, 1e-5)
        del errors["within"], errors["error_edge"]
        out.append({"table": table, "part": part, "family": family, "criterion": criterion, "tips": q, "key": key,
                    "adhesive_force": force, "error_quoted": quoted, **errors})

    for r in _rows("criteria.csv"):
        if (r["family"], float(r["stiffness_ratio"])) in covered and r["error"] != "":
            key = f"pitch {r['pitch_elements']} {r['centring']} shift {r['shift_y']} {r['shift_x']}"
            add("criteria", r["part"], r["family"], r["criterion"], float(r["tip_elements_per_radius"]), key,
                float(r["adhesive_force"]), float(r["error"]))
    for r in _rows("proxy.csv"):
        case = (r["family"], float(r["stiffness_ratio"]))
        if case in covered:
            key = f"proxy {r['proxy_pillars_per_side']} x {r['proxy_pillars_per_side']}"
            add("proxy", "brush", r["family"], "plain", 3.611, key, float(r["brush_adhesive_force"]),
                float(r["brush_error"]))
            add("proxy", "corrected", r["family"], "plain", 3.611, key, float(r["corrected_adhesive_force"]),
                float(r["corrected_error"]))
    for r in _rows("calibration.csv"):
        case = (r["family"], float(r["stiffness_ratio"]))
        if case in covered:
            criterion = "calibrated" if r["calibrated"] == "True" else "plain"
            quoted = r["force_error_extrapolated"]
            add("calibration", "families", r["family"], criterion, float(r["tip_elements_per_radius"]), "",
                float(r["adhesive_force"]), float(quoted) if quoted not in ("", "nan") else "")
    lower, upper, middle = interval(1e-5)
    for r in _rows("periodic.csv"):
        if r["part"] == "proxy_canonical" and r["stiffness_ratio"] and float(r["stiffness_ratio"]) == 1e-5 \
                and r["brush_needed_ratio"]:
            # F_ref / F_plain: on the new reference the same factor times middle / old.
            factor = float(r["brush_needed_ratio"]) * middle / old[("flat", 1e-5)]
            out.append({"table": "periodic", "part": "brush_needed_ratio", "family": "flat", "criterion": "plain",
                        "tips": float(r["tip_elements_per_radius"]),
                        "key": f"pitch {r['pitch_elements']} {r['centring']}", "adhesive_force": "",
                        "error_quoted": float(r["brush_needed_ratio"]), "error_lower": "",
                        "error_middle": factor, "error_upper": ""})
    return out


def brush_table() -> list[dict]:
    """The rows of ``brush_resolution_error.csv``: the flat 8 x 8 brush at k~ = 1e-5 (plain, the default
    criterion) per tips' resolution: its placement mean's error against the continuum limit's middle
    (``continuum_limit.csv``), and the range of every placement between the tips' upper bound (`edge_bound`) and
    the first point."""
    lower, _, middle = interval(1e-5)
    upper = edge_bound()
    forces = defaultdict(list)
    for row in _rows("placement.csv"):
        if row["family"] == "flat" and float(row["stiffness_ratio"]) == 1e-5:
            forces[float(row["tip_elements_per_radius"])].append(
                float(row["calibrated_adhesive_force"]) * (1 + float(row["lone_tip_error"])))
    return [{"elements_per_radius": q, "placements": len(values),
             "force_error_mean": statistics.fmean(values) / middle - 1, "force_error_min": min(values) / upper - 1,
             "force_error_max": max(values) / lower - 1} for q, values in sorted(forces.items())]


def write_brush_table(rows: list[dict]) -> None:
    """``brush_resolution_error.csv`` with its header line (what it is, where from), five digits, atomically."""
    temporary = BRUSH_TABLE.with_suffix(".csv.tmp")
    with temporary.open("w", newline="") as stream:
        stream.write("# the flat 8 x 8 brush at k~ = 1e-5 (phi = 0.16, plain criterion), the mean over placements of the "
                     "lattice on the tips' raster against the continuum limit's middle, the range of every placement "
                     "between its bounds; docs/pillars/limit.py\n")
        writer = csv.DictWriter(stream, fieldnames=BRUSH_FIELDS, lineterminator="\n")
        writer.writeheader()
        for row in rows:
            writer.writerow({name: (f"{row[name]:.5g}" if isinstance(row[name], float) else row[name])
                             for name in BRUSH_FIELDS})
    temporary.replace(BRUSH_TABLE)


def summary(rows: list[dict]) -> dict:
    """The ranges the docstrings quote: (table, part, criterion, q rounded) -> (min, max) of error_middle, and of
    error_quoted."""
    out: dict = defaultdict(list)
    for r in rows:
        if r["table"] != "periodic":
            out[(r["table"], r["part"], r["criterion"], round(float(r["tips"]), 1))].append(
                (float(r["error_middle"]), r["error_quoted"]))
    return {key: ((min(v[0] for v in values), max(v[0] for v in values)), len(values)) for key, values in out.items()}


def main() -> None:
    reference.write(routes(), LIMIT, FIELDS)
    reference.write(tips(), TIPS, TIP_FIELDS)
    rows = rereferenced()
    reference.write(rows, REREFERENCED, REREFERENCED_FIELDS)
    write_brush_table(brush_table())
    print(f"upper bound of the tips the brush follows: {edge_bound():.7g}")
    for row in reference.load(LIMIT):
        print(", ".join(f"{name}={row[name]}" for name in FIELDS))
    for row in reference.load(TIPS):
        print(", ".join(f"{name}={row[name]}" for name in TIP_FIELDS))
    for key, ((low, high), count) in sorted(summary(rows).items(), key=str):
        print(key, count, f"{100 * low:+.2f} .. {100 * high:+.2f} %")


if __name__ == "__main__":
    main()
