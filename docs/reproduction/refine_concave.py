"""Refine the chapter-7 sweeps in h~ around each curve's maximum (Fig. 7-5 to 7-7).

The shipped ``concave.amplification.toml`` and ``concave.stiffness.toml`` run 13 and 17
values of h~ from 0 to 2.  Near the maximum of F~_A over h~ their spacing is 0.01 to
0.4, and a stiff brush's curve rises and falls within one step (k~ = 10, phi = 0.06:
0.886 at h~ = 0.05, 0.920 at 0.06, 0.814 at 0.08), so the grid decides where the maximum
lies and caps its height.  This script appends, for the circle form (the rows' form), the
h~ values `FINE` between the coarse grid's neighbours of each maximum: the full sweep's
points and indices before them stay as they are (the committed cases keep their ids), and
a study run with ``--skip-recorded docs/reproduction`` computes only the added ones.
After them, ``concave.stiffness.toml`` gets two brushes softer than the thesis's softest
(`SOFTER`), whose maxima show how the position of the maximum goes on with k~.

The neighbours come from the committed run of the coarse grid (``docs/reproduction/
concave``, commit 82c39a9): per (phi, k~), the coarse argmax and the grid points on
either side.  ``protocol.step`` follows the sweep's own rule, the h~ = 0 step times
(1 + 2 h~) (it applies only to the fixed-step protocol).

    python docs/reproduction/refine_concave.py     # idempotent
"""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

from make_sampled import _points, append_points  # this folder's writer of the sampled sweeps

SWEEPS = Path(__file__).resolve().parents[2] / "src" / "brushbem" / "studies" / "sweeps"
RADIUS, K, REGION, H, PRELOAD, STEP = ("indenter.pillar_radius", "indenter.stiffness_ratio", "indenter.region",
                                       "indenter.profile.amplification", "protocol.preload_force", "protocol.step")
PHI_RADIUS = {0.06: 0.00863735, 0.15: 0.0136569}

_STIFF_006 = (0.052, 0.054, 0.056, 0.058, 0.062, 0.064, 0.066, 0.068, 0.07, 0.075)
_SOFT_006 = (0.13, 0.14, 0.15, 0.17, 0.18, 0.2, 0.22)
_STIFF_015 = (0.13, 0.14, 0.15, 0.17, 0.18, 0.19, 0.2, 0.22)
_SOFT_015 = (0.8, 0.9, 1.1, 1.2, 1.3)
#: (phi, k~) -> h~ added; the coarse maximum (F~_A, h~) and its neighbours in the comment.
FINE = {
    (0.06, 10.0): _STIFF_006,  # 0.920 at 0.06 (0.886 at 0.05, 0.814 at 0.08)
    (0.06, 1.0): _STIFF_006,  # 0.920 at 0.06 (0.886, 0.816)
    (0.06, 0.1): _STIFF_006,  # 0.921 at 0.06 (0.887, 0.833)
    (0.06, 0.01): _STIFF_006,  # 0.919 at 0.06 (0.894, 0.910 at 0.08)
    (0.06, 0.001): (0.09, 0.1, 0.11, 0.13, 0.14),  # 0.932 at 0.12 (0.916 at 0.08, 0.930 at 0.16)
    (0.06, 0.0006): _SOFT_006,  # 0.932 at 0.16 (0.923 at 0.12, 0.923 at 0.25)
    (0.15, 10.0): _STIFF_015,  # 0.831 at 0.16 (0.788 at 0.12, 0.532 at 0.25)
    (0.15, 1.0): _STIFF_015,  # 0.832 at 0.16
    (0.15, 0.1): _STIFF_015,  # 0.835 at 0.16
    (0.15, 0.01): (0.18, 0.2, 0.22),  # 0.817 at 0.16 (0.786 at 0.12, 0.813 at 0.25)
    (0.15, 0.001): (0.6, 0.8, 0.9),  # 0.849 at 0.7 (0.838 at 0.5, 0.792 at 1.0)
    (0.15, 0.0006): _SOFT_015,  # 0.855 at 1.0 (0.836 at 0.7, 0.811 at 1.4)
}
HEADER = ("# Added after the coarse points: h~ refined around each circle curve's maximum"
          " (docs/reproduction/refine_concave.py).")

#: Softer brushes than the thesis's softest (k~ = 6e-4), circle, both phi, on `SOFTER_H`
#: (``stiffness`` only): how the position of the maximum goes on with k~, to read at which
#: k~ our maximum sits where the thesis puts its k~ = 6e-4 one (h~ = 0.5 at phi = 0.06).
SOFTER = (3e-4, 1.5e-4)
SOFTER_H = (0.0, 0.04, 0.08, 0.12, 0.16, 0.2, 0.25, 0.3, 0.35, 0.4, 0.5, 0.6, 0.7, 0.85, 1.0, 1.2, 1.4,
            1.7, 2.0)
SOFTER_HEADER = ("# Added after those: k~ = 3e-4 and 1.5e-4 (softer than the thesis's softest), circle, both phi"
                 " (docs/reproduction/refine_concave.py).")


def _group(p: dict) -> tuple:
    return (p[RADIUS], p[K], p[REGION], p[PRELOAD])


def _softer(points: list[dict], have: set) -> list[dict]:
    """The `SOFTER` points, circle, per pillar radius; the h~ = 0 step follows the sweep's
    a + b / k~ (through its k~ = 10 and 6e-4 steps), times (1 + 2 h~)."""
    added = []
    for radius in PHI_RADIUS.values():
        flat = {p[K]: p for p in points if p[H] == 0.0 and p[REGION] == "circle" and math.isclose(p[RADIUS], radius)}
        stiff, soft = flat[10.0], flat[0.0006]
        b = (soft[STEP] - stiff[STEP]) / (1 / 0.0006 - 1 / 10.0)
        a = stiff[STEP] - b / 10.0
        for k in SOFTER:
            for h in SOFTER_H:
                p = {**soft, K: k, H: h, STEP: float(f"{(a + b / k) * (1 + 2 * h):.6g}")}
                if (*_group(p), h) not in have:
                    added.append(p)
    return added


def refine(part: str) -> Path:
    """Append the `FINE` points to ``concave.<part>.toml`` (once; idempotent)."""
    path = SWEEPS / f"concave.{part}.toml"
    points = _points(tomllib.loads(path.read_text(encoding="utf-8")))
    have = {(*_group(p), p[H]) for p in points}
    flat = {_group(p): p for p in points if p[H] == 0.0}
    added = []
    for group, p0 in flat.items():
        if p0[REGION] != "circle":
            continue
        phi = next(phi for phi, r in PHI_RADIUS.items() if math.isclose(r, p0[RADIUS]))
        for h in FINE.get((phi, p0[K]), ()):
            if (*group, h) not in have:
                added.append({**p0, H: h, STEP: float(f"{p0[STEP] * (1 + 2 * h):.6g}")})
    append_points(path, added, [HEADER])
    if part == "stiffness":
        append_points(path, _softer(points, have | {(*_group(p), p[H]) for p in added}), [SOFTER_HEADER])
    return path


if __name__ == "__main__":
    for part in ("amplification", "stiffness"):
        print(refine(part))
