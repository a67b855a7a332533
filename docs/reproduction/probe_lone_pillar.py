"""Chapter 4, eq. 4.17-4.18: the spring energy a soft brush stores, against N lone pillars.

Eq. 4.17 takes every pillar of a soft brush (k~ -> 0) to detach at a lone
pillar's Kendall force F_a, so that the work of separation is the springs'
energy N F_a^2 / (2k).  This runs, for each lattice of the ``flat_brush``
part ``regular`` (N = 512, 12.5 to 2.1 elements per pillar radius), one pillar
alone on the same grid, with the same radius, spring and preload (the
lattice's base with ``pillars_per_side = 1``), at the smallest k~ (1e-6),
and prints against the committed table:

* the lone pillar's F_A / F_a and W / (F_a^2 / 2k): the mesh's error on eq. 4.17's one pillar;
* the brush's W / (N W_lone): what a pillar in the brush stores of a lone one's energy;
* the row's number with eq. 4.18's dropped factor 2/sqrt(pi) restored and the
  brush's measured share put in, beside the committed row.

Every lattice's line is written atomically to ``probe_lone_pillar.csv`` beside this file.

    python docs/reproduction/probe_lone_pillar.py        # seconds
"""

from __future__ import annotations

import math
from pathlib import Path

import pandas as pd

import brushbem
from brushbem.io import atomic_path
from brushbem.studies import SWEEPS_DIR
from brushbem.sweep import load_sweep

TABLE = Path(__file__).resolve().parent / "flat_brush" / "regular.csv"
SOFTEST = 1e-6
OUTPUT = Path(__file__).with_suffix(".csv")


def main() -> None:
    table = pd.read_csv(TABLE)
    brushes = table[(table["indenter.stiffness_ratio"] == SOFTEST) & (table["status"] == "finished")]
    sweep = load_sweep(SWEEPS_DIR / "flat_brush.regular.toml")
    shares, rows, records = [], [], []
    for case in sweep.cases:
        if case.values["indenter.stiffness_ratio"] != SOFTEST:
            continue
        config = case.config.model_dump(mode="json", exclude_unset=True)
        per_side = config["indenter"]["pillars_per_side"]
        radius = config["indenter"]["pillar_radius"]
        config["indenter"]["pillars_per_side"] = 1
        lone = brushbem.run(config)
        force, work = lone.summary["adhesive_force"], lone.summary["work_of_separation"]
        e_star = config["halfspace"]["contact_modulus"]
        gamma = config["halfspace"]["work_of_adhesion"]
        k = SOFTEST * e_star * config["grid"]["size"]
        kendall = math.sqrt(8 * math.pi * e_star * gamma * radius**3)
        brush = brushes[brushes["indenter.pillars_per_side"] == per_side].iloc[0]
        share = brush["work_of_separation"] / (per_side**2 * work)
        shares.append(share)
        records.append({"pillars_per_side": per_side, "pillar_radius": radius,
                        "lone_force_over_kendall": force / kendall,
                        "lone_work_over_spring_energy": work / (kendall**2 / (2 * k)), "brush_work_share": share,
                        "brush_work_over_spring_energy":
                            brush["work_of_separation"] / (per_side**2 * kendall**2 / (2 * k)),
                        "row_predicted": math.nan})
        rows.append(f"{per_side:>2} x {per_side:<2} r = {radius:.6f}: lone F_A / F_a = {force / kendall:.4f}, "
                    f"lone W / (F_a^2/2k) = {work / (kendall**2 / (2 * k)):.4f}, "
                    f"brush W / (N W_lone) = {share:.4f}, brush W / (N F_a^2/2k) = "
                    f"{brush['work_of_separation'] / (per_side**2 * kendall**2 / (2 * k)):.4f}")
    print("\n".join(rows))
    mean_share = sum(shares) / len(shares)
    for record in records:
        record["row_predicted"] = 2 / math.sqrt(math.pi) * mean_share
    with atomic_path(OUTPUT) as path:
        pd.DataFrame(records).to_csv(path, index=False)
    print(f"mean share {mean_share:.4f}; eq. 4.18 with 2/sqrt(pi) restored and this share predicts the row "
          f"{2 / math.sqrt(math.pi) * mean_share:.4f}")


if __name__ == "__main__":
    main()
