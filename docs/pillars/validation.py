"""The pillar-level model (``method = "pillars"``) against the exact event path on seeded families of brushes.

Every case is pressed to the rigid flat brush's force F_c and pulled off to
separation by both methods on the same problem; the table gives the relative
errors of F_A, of the work of separation and of the number of pillars
attached at pull-off, and the CPU time of each method.

Families (square domain of side 1, E* = 1, work of adhesion 1e-4, pillars of
3.6 elements' radius at a filling factor phi = 0.16, N = 16 n for n x n
pillars; seed 3):

* ``flat``: a square lattice of level tips;
* ``rough``: the same with Gaussian lengths of sigma~ = 1 (sigma = d_c);
* ``random``: n^2 pillars placed at random (at least 2 elements apart);
* ``hierarchy``: the lattice in 2 x 2 clusters on springs of half the
  pillars' stiffness;
* ``concave``: the lattice under the concave length profile of ch. 7
  (h~ = 0.5, eq. 7.1-7.3).

Each at n = 8 and 16 and k~ = 10, 1e-2 and 1e-5; flat and rough also at
n = 32, and at n = 64 (4096 pillars, N = 1024) for k~ = 1e-2.  The grids are ours (the thesis's chapter-5 grid is n = 32 at
N = 512, which the 32 x 32 rows use).

The model's domain: flat, rough and random 8 x 8 brushes (N = 128) at the
filling factors ``DOMAIN_PHIS`` (0.05 to 0.78, the square lattice's
footprints nearly touching at pi / 4) and k~ = 10 and 1e-5; the random
layouts at phi >= 0.3 with their footprints at least one element apart
(``min_gap`` = h).  Each row names the smallest gap between two footprints
(elements), the quantity `brushbem.pillars.domain` warns on.

Results are appended to ``validation.jsonl`` one line per case as it
completes (a rerun skips the cases already there), and ``validation.md`` is
written from them.

    nice python docs/pillars/validation.py            # all cases, resuming
    nice python docs/pillars/validation.py --table    # only rewrite validation.md
"""

from __future__ import annotations

import argparse
import json
import math
import os
import time
from pathlib import Path

from brushbem.physics.structure import Grid, Level, Profile, brush
from brushbem.protocol import ContactProblem, LoadPath, record_pull_off
from brushbem.runs.case import brush_scales

HERE = Path(__file__).resolve().parent
RESULTS = HERE / "validation.jsonl"
TABLE = HERE / "validation.md"
PHI, DGAMMA, SEED = 0.16, 1e-4, 3
FAMILIES = ("flat", "rough", "random", "hierarchy", "concave")
STIFFNESSES = (10.0, 1e-2, 1e-5)


#: The filling factors of the domain rows (8 x 8 pillars; the 0.16 rows are the families' own).
DOMAIN_PHIS = (0.05, 0.3, 0.44, 0.6, 0.78)


def cases() -> list[tuple]:
    out = [(family, n, k) for n in (8, 16) for family in FAMILIES for k in STIFFNESSES]
    out += [(family, 32, k) for family in ("flat", "rough") for k in STIFFNESSES]
    out += [(family, 64, 1e-2) for family in ("flat", "rough")]
    out += [(family, 8, k, phi) for phi in DOMAIN_PHIS for family in ("flat", "rough", "random")
            for k in (10.0, 1e-5) if not (family == "random" and phi > 0.35)]
    return out


def problem(family: str, per_side: int, stiffness: float, phi: float = PHI,
            factor: int = 1) -> tuple[ContactProblem, float]:
    """The brush of a family and the rigid flat lattice's force F_c (the preload).

    ``factor``: the same brush (the same centres, lengths and preload, those of the grid N = 16 n) on the grid
    ``factor`` times finer (`docs/pillars/tips.py`).
    """
    elements = 16 * per_side
    grid = Grid(1.0, elements)
    radius = math.sqrt(phi / math.pi) / per_side

    def build(kind: str, roughness: float = 0.0, grid: Grid = grid) -> ContactProblem:
        common = dict(pillar_radius=radius, contact_modulus=1.0, work_of_adhesion=DGAMMA, stiffness=stiffness,
                      seed=SEED)
        if kind == "random":
            gap = (2.0 if phi == PHI else 1.0) / elements
            tips = brush(grid, layout="random", pillar_count=per_side**2, min_gap=gap, **common)
        else:
            extra = {}
            if kind == "hierarchy":
                extra["levels"] = (Level(cluster=2, stiffness=stiffness / 2),)
            if kind == "concave":
                extra["profile"] = Profile(amplification=0.5)
            tips = brush(grid, layout="square", pillars_per_side=per_side, roughness=roughness, **common, **extra)
        return ContactProblem(grid, tips, contact_modulus=1.0, work_of_adhesion=DGAMMA)

    scales = brush_scales(build("flat"))
    sigma = scales["rigid_brush_displacement"] if family == "rough" else 0.0
    return build(family, sigma, Grid(1.0, elements * factor)), scales["rigid_brush_force"]


def run_case(family: str, per_side: int, stiffness: float, phi: float = PHI) -> dict:
    from brushbem.pillars.domain import smallest_gap

    case, preload = problem(family, per_side, stiffness, phi)
    row = {"family": family, "pillars_per_side": per_side, "pillars": case.indenter.n_pillars,
           "elements": case.grid.elements, "stiffness_ratio": stiffness, "phi": phi,
           "smallest_gap_elements": round(smallest_gap(case), 3)}
    for method in ("events", "pillars"):
        start = time.process_time()
        summary = record_pull_off(case, LoadPath(method=method, preload_force=preload, max_steps=10**7,
                                                 pillar_tip_peel=False)).summary
        row[f"{method}_cpu_seconds"] = round(time.process_time() - start, 3)
        row[f"{method}_converged"] = bool(summary["converged"])
        for key in ("adhesive_force", "work_of_separation", "attached_pillars_at_pull_off"):
            row[f"{method}_{key}"] = summary[key]
    for key in ("adhesive_force", "work_of_separation", "attached_pillars_at_pull_off"):
        model, reference = row[f"pillars_{key}"], row[f"events_{key}"]
        if not row["events_converged"]:
            row[f"{key}_error"] = None  # no reference
        else:
            row[f"{key}_error"] = 0.0 if model == reference else (model / reference - 1 if reference else None)
    return row


def _percent(error: float | None, digits: int = 2) -> str:
    return "n/a" if error is None else f"{100 * error:+.{digits}f} %"


def _key(row: dict) -> tuple:
    phi = row.get("phi", PHI)
    key = (row["family"], row["pillars_per_side"], row["stiffness_ratio"])
    return key if phi == PHI else (*key, phi)


def load() -> list[dict]:
    if not RESULTS.exists():
        return []
    return [json.loads(line) for line in RESULTS.read_text().splitlines() if line.strip()]


def write_table(rows: list[dict]) -> None:
    order = {case: i for i, case in enumerate(cases())}
    rows = sorted(rows, key=lambda row: order.get(_key(row), len(order)))
    lines = [
        "# The pillar-level model against the exact event path",
        "",
        "Written by `docs/pillars/validation.py` from `validation.jsonl` (the families and grids are in its",
        "docstring; every case is pressed to the rigid flat lattice's force F_c and pulled off to separation).",
        "Errors are the pillar model's relative to `method = \"events\"` on the same problem; the targets are",
        "1 % on F_A, 3 % on the work and 2 % on the pillars attached at pull-off.  Times are CPU seconds of",
        "one process on a shared machine, both methods in the same run.",
        "",
        "| family | pillars | N | k~ | phi | gap (elements) | F_A error | work error | attached error | events (s) "
        "| pillars (s) |",
        "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |",
    ]
    for row in rows:
        gap = row.get("smallest_gap_elements")
        lines.append(
            f"| {row['family']} | {row['pillars']} | {row['elements']} | {row['stiffness_ratio']:g} "
            f"| {row.get('phi', PHI):g} | {'' if gap is None else f'{gap:.2f}'} "
            f"| {_percent(row['adhesive_force_error'])} | {_percent(row['work_of_separation_error'])} "
            f"| {_percent(row['attached_pillars_at_pull_off_error'], 1)} "
            f"| {row['events_cpu_seconds']:.1f} | {row['pillars_cpu_seconds']:.2f} |")
    if rows:
        keys = ("adhesive_force", "work_of_separation", "attached_pillars_at_pull_off")
        worst = {key: max((row for row in rows if row[f"{key}_error"] is not None),
                          key=lambda row: abs(row[f"{key}_error"])) for key in keys}
        lines += ["", f"{len(rows)} of {len(order)} cases.  Largest errors: "
                  + "; ".join(f"{key.replace('_', ' ')} {_percent(row[f'{key}_error'])} ({row['family']}, "
                              f"{row['pillars']} pillars, k~ = {row['stiffness_ratio']:g}, "
                              f"phi = {row.get('phi', PHI):g})"
                              for key, row in worst.items()) + ".  n/a: the exact path did not converge (it "
                  "stopped with F_A = 0), so there is no reference."]
    temporary = TABLE.with_suffix(".md.tmp")
    temporary.write_text("\n".join(lines) + "\n")
    os.replace(temporary, TABLE)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--table", action="store_true", help="only rewrite validation.md from validation.jsonl")
    args = parser.parse_args()
    rows = load()
    if not args.table:
        done = {_key(row) for row in rows}
        for case in cases():
            if case in done:
                continue
            row = run_case(*case)
            rows.append(row)
            with RESULTS.open("a") as stream:
                stream.write(json.dumps(row) + "\n")
                stream.flush()
                os.fsync(stream.fileno())
            print(json.dumps(row), flush=True)
            write_table(rows)
    write_table(rows)


if __name__ == "__main__":
    main()
