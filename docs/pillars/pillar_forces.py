"""Every pillar's force at the preload and at pull-off: the pillar model with fine tips against the exact path.

For a family of ``docs/pillars/validation.py`` (8 x 8, k~ as given) the
pillar model with its tips f times finer than the grid N = 128 and the exact
event path on the grid f N (the same brush, `docs/pillars/tips.py`): the
states at the preload and at pull-off (the least force), and there each
pillar's force (the pressure summed over its footprint), the sum of their
magnitudes sum |F_i| and the two paths' difference in it.  Where F_A is the
net of compressed and pulled pillars, sum |F_i| is several times F_A, and a
small error on every pillar is a larger one on F_A.

    nice python docs/pillars/pillar_forces.py concave 10 4      # about 70 CPU-s
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

from brushbem.protocol import LoadPath
from brushbem.protocol.paths import pull_off

sys.path.insert(0, str(Path(__file__).resolve().parent))
from validation import problem  # noqa: E402


def pillar_forces(case, state) -> np.ndarray:
    """Each pillar's force in ``state`` (its pressure summed over the pillar's elements of ``case``'s grid)."""
    labels = np.asarray(case.indenter.pillar)
    inside = labels >= 0
    return np.bincount(labels[inside], weights=state.pressure[inside] * case.grid.element_size**2,
                       minlength=case.indenter.n_pillars)


def states(case, preload: float, **extra):
    """(preload state, pull-off state) of a pull-off of ``case``."""
    path = list(pull_off(case, LoadPath(preload_force=preload, max_steps=10**7, pillar_tip_peel=False, **extra)))
    return [s for s in path if s.loading][-1], min(path, key=lambda s: s.force)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("family")
    parser.add_argument("stiffness_ratio", type=float)
    parser.add_argument("factor", type=int, help="the tips' subdivision of N = 128 (the exact path on f N)")
    args = parser.parse_args()
    coarse, preload = problem(args.family, 8, args.stiffness_ratio)
    fine, _ = problem(args.family, 8, args.stiffness_ratio, factor=args.factor)
    per_radius = float(coarse.indenter.description.pillar_radius) / coarse.grid.element_size
    model = states(coarse, preload, method="pillars", pillar_tip_resolution=args.factor * per_radius)
    exact = states(fine, preload, method="events")
    for name, a, b in (("preload", model[0], exact[0]), ("pull-off", model[1], exact[1])):
        fa, fb = pillar_forces(coarse, a), pillar_forces(fine, b)
        total = float(np.abs(fb).sum())
        print(f"{name}: F = {a.force:.6g} (model) {b.force:.6g} (exact, N = {fine.grid.elements}), "
              f"d = {a.displacement:.6g} {b.displacement:.6g}, attached {a.attached_pillars} {b.attached_pillars}; "
              f"sum |F_i| = {total:.6g} = {total / abs(b.force):.2f} |F|; the model's F - exact's = "
              f"{a.force - b.force:+.3g} = {(a.force - b.force) / total:+.2%} of sum |F_i|, "
              f"largest pillar difference {np.abs(fa - fb).max():.3g}")


if __name__ == "__main__":
    main()
