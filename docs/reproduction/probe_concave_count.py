"""Chapter 7: where the maximum over h~ lies, against the pillar count the thesis leaves open.

The shipped ``concave`` sweeps use a 16 x 16 lattice (192 pillars in the circle); the thesis
states phi, k~ and the form, not the count.  Its profile scale follows the count: the offsets
are h~ S_c with S_c ~ p_c R / E* and p_c = F_K / (pi r^2) ~ r^-1/2, so at one phi a lattice of
n x n pillars has offsets ~ n^1/2.  The homogenised estimate says where a stiff brush's
maximum should sit whatever n: the half-space feels the pillars' stress smeared over the
brush, phi_R p_c (phi_R = N r^2 / R^2, R the outermost pillar centre, the profile's radius),
so every pillar sees the same displacement at h~ = phi_R (`theory.concave_reference_stress`).

This runs the circle form at phi = 0.06 (or 0.15), k~ = 10 and 6e-4, on 8 x 8, 12 x 12 and
24 x 24 lattices (N = 512, phi = 0.06: 8.8, 5.9 and 2.9 elements per pillar radius; pressed to
2 n^2 F_K like the shipped sweeps) at h~ around each maximum, and prints per lattice phi_R, the
h~ of the largest F~_A and F~_A there, beside the committed 16 x 16 rows:

    python docs/reproduction/probe_concave_count.py                      # about 25 minutes on one core
    python docs/reproduction/probe_concave_count.py --phi 0.15 --lattices 8
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import numpy as np
import pandas as pd

import brushbem
from brushbem.studies import SWEEPS_DIR
from brushbem.physics.structure import square_lattice
from brushbem.sweep import load_sweep

TABLE = Path(__file__).resolve().parent / "concave" / "stiffness.csv"
RADIUS_16 = {0.06: 0.00863735, 0.15: 0.0136569}  # the shipped sweeps' 16 x 16 radii
H_GRID = {0.06: {10.0: (0.03, 0.04, 0.05, 0.055, 0.06, 0.065, 0.07, 0.075, 0.08, 0.09),
                 6e-4: (0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.4, 0.5, 0.7)},
          0.15: {10.0: (0.08, 0.1, 0.12, 0.14, 0.15, 0.16, 0.17, 0.18, 0.2, 0.22),
                 6e-4: (0.1, 0.16, 0.25, 0.35, 0.5, 0.7, 1.0, 1.4, 2.0)}}


def circle_brush(n: int, radius: float) -> tuple[int, float]:
    """Pillars kept in the circle of diameter 1 (wholly inside) and phi_R = N r^2 / R^2."""
    centres, _ = square_lattice(n, 1.0 / n)
    distance = np.hypot(centres[:, 0], centres[:, 1])
    kept = distance[distance + radius <= 0.5 * (1 + 1e-12)]
    return len(kept), len(kept) * radius**2 / kept.max() ** 2


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--phi", type=float, choices=sorted(RADIUS_16), default=0.06)
    parser.add_argument("--lattices", type=int, nargs="+", default=[8, 12, 24], help="pillars per side")
    args = parser.parse_args()
    base = next(c for c in load_sweep(SWEEPS_DIR / "concave.stiffness.toml").cases
                if c.values["indenter.region"] == "circle" and c.values["indenter.stiffness_ratio"] == 10.0
                and math.isclose(c.values["indenter.pillar_radius"], 0.00863735)
                and c.values["indenter.profile.amplification"] == 0.0)
    config = base.config.model_dump(mode="json", exclude_unset=True)
    e_star, gamma = config["halfspace"]["contact_modulus"], config["halfspace"]["work_of_adhesion"]
    table = pd.read_csv(TABLE)
    table = table[np.isclose(table["indenter.pillar_radius"], RADIUS_16[args.phi]) & (table["status"] == "finished")]
    for n in (16, *args.lattices):
        radius = math.sqrt(args.phi / math.pi) / n
        count, phi_r = circle_brush(n, radius)
        for k, hs in H_GRID[args.phi].items():
            if n == 16:  # the committed rows
                rows = table[np.isclose(table["indenter.stiffness_ratio"], k)]
                forces = rows.groupby("indenter.profile.amplification")["normalized.force_by_ideal_sharing"].mean()
            else:
                values = {}
                for h in hs:
                    c = {**config, "indenter": {**config["indenter"], "pillars_per_side": n, "pillar_radius": radius,
                                                 "stiffness_ratio": k, "profile": {"amplification": h}},
                         "protocol": {**config["protocol"], "preload_force": 2 * n * n * math.sqrt(
                             8 * math.pi * e_star * gamma * radius**3)}}
                    result = brushbem.run(c)
                    if not result.converged:
                        print(f"  {n} x {n}, k~ = {k:g}, h~ = {h:g}: not converged ({result.summary.get('reason')})")
                        continue
                    values[h] = result.summary["normalized"]["force_by_ideal_sharing"]
                forces = pd.Series(values)
            best = forces.idxmax()
            print(f"{n:>2} x {n:<2} ({count} pillars, {radius * 512:.1f} elements per radius), phi_R = {phi_r:.4f}, "
                  f"k~ = {k:g}: max F~_A = {forces.max():.4f} at h~ = {best:g} "
                  f"(h~ / phi_R = {best / phi_r:.2f}); within 2 %: h~ = "
                  f"{forces[forces >= 0.98 * forces.max()].index.min():g}-"
                  f"{forces[forces >= 0.98 * forces.max()].index.max():g}", flush=True)


if __name__ == "__main__":
    main()
