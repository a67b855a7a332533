"""Is the small brush's correction the raster error of a tip in an infinite lattice of identical tips?

``proxy.py`` measured that on every lattice family the pillar model's F_A at
3.6 elements per radius needs one factor, F(28.9, calibrated) / F(3.6) =
0.9348 (a 4 x 4 proxy, k~ = 10 and 1e-5 alike), where the lone tip's is
F_K / F_R = 1 / 1.0419 (the lone tip on that raster +4.19 %; +3.44 % is what
the calibrated 8 x 8 brush keeps).  Here the same factor of a tip in an infinite square
lattice of identical tips, all at one displacement: a periodic cell.

The lattice: pitch p, tips of radius r = p sqrt(phi / pi) (phi = 0.16, the
families', `validation.PHI`), E* = 1, dgamma = 1e-4, p = 1/8 (the 8 x 8
families' physical brush).  A raster: ``pitch`` elements per p (h = p /
pitch), the circle centred on a grid corner (``corner``, the families' own
placement at 16 elements' pitch) or an element's centre (``element``), its
footprint the elements whose centres lie inside (`rasterise_pillars`'s rule).

The periodic influence of one element on another of the same tip raster is
the Love kernel (`influence_coefficients`) summed over the images of a
(2 m + 1)^2 lattice, plus the continuum tail of the images beyond it to
second order in the offset (|x|^2 / 4 times the integral of 1 / r^3 outside
the square of half side (m + 1/2) p, 4 sqrt(2) / s, over the cell area):
a constant added to the kernel does not change the tip's pressure per unit
force (Sherman-Morrison), so the tail's next term (fourth order) is what the
truncation leaves; ``IMAGES`` and twice it agree to the digits printed
(``tests/test_pillar_periodic.py``).

Pull-off of the lattice: every tip carries the same force F (the lattice is
infinite, so its displacement for a given force is not bounded: force
control), its pressure F psi on the attached raster S, psi = K_S^-1 1 /
sum(K_S^-1 1); elements at F psi >= Sigma_c leave, round by round at that F,
until S is stable or gone; F rises to the next event.  F_A per tip is the
largest F held (`lattice_pull_off`).  Sigma_c: the raster's (``plain``), or
calibrated as the code does (`calibrated_criteria`: Sigma_c F_K / F_R of the
lone tip's raster, the lone tip's pull-off by `lone_pull_off`).

A second, finite layout tells the cell's answer apart from the proxy's: a
rigid 2 x 2 array of the families' tips at one displacement (the 2 x 2
proxy's geometry, pitch 1/2, k~ -> infinity), pulled off by the exact event
path of all its elements (`array`; no pillar model), every tip at the
array's edge.

Rows (``periodic.csv``), F per tip: ``part`` ``family`` (the periodic cell
on the families' raster, pitch 16 corner, and its tips 2, 4, 8 times finer
as ``LoadPath.pillar_tip_resolution`` gives them), ``canonical`` (the cell on
every raster of ``criteria.py``'s canonical part, pitch 13 to 18, corner and
element), ``array`` (the 2 x 2 array at tips 1, 2, 4 times the families'),
``array_canonical`` (the 2 x 2 array on every canonical raster),
``proxy_canonical`` (the pillar model's 4 x 4 flat proxy on every canonical
raster at k~ = 10 and 1e-5, plain, against the proxy's 28.9-elements F_A of
``proxy.csv``: the layout that ``proxy.py`` uses, on the other rasters):
the footprint, the lone tip's F_R / F_K - 1, the first event's F and the
number of events, F_A plain and calibrated, and the factors: ``ratio`` =
F_A(the part's finest tips, calibrated) / F_A(this raster, plain),
``lone_ratio`` = F_K / F_R, ``proxy_ratio`` the pillar model's (the 4 x 4
proxy's beside the cell, the 2 x 2 proxy's beside the array, flat, k~ = 10,
``proxy.csv``), and, where the 8 x 8 flat brush on this raster has a
reference (``criteria.csv``'s canonical rows; k~ = 10 for the cell and the
rigid array, the proxy's own k~ for the proxy), the factor that brush
needs, F_ref / F_plain; ``stiffness_ratio`` the proxy's k~ (``inf``: the
rigid array; empty: the cell, whose tips all carry one force).  About 25
CPU-s (55 on a busy machine): the 28.9-elements cell 13 to 36, the array
at 14.4 elements per radius 7 to 9, every other row under 0.1.

    nice python docs/pillars/periodic.py
"""

from __future__ import annotations

import csv
import math
import sys
import time
from pathlib import Path

import numpy as np

from brushbem.physics.adhesion import critical_stress
from brushbem.physics.halfspace import influence_coefficients
from brushbem.physics.theory.punch import kendall_force
from brushbem.pillars.calibration import lone_pull_off
from brushbem.pillars.modes import MODES, Bases

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import calibration  # noqa: E402
import criteria  # noqa: E402
import validation  # noqa: E402

TABLE = HERE / "periodic.csv"
FIELDS = ("part", "tips", "stiffness_ratio", "pitch_elements", "centring", "tip_factor", "tip_elements_per_radius",
          "footprint_elements", "lone_error", "first_event_force", "events", "adhesive_force_plain",
          "adhesive_force_calibrated", "lone_ratio", "ratio", "proxy_ratio", "brush_needed_ratio", "cpu_seconds")
#: The 8 x 8 families' pitch (the domain of side 1) and tip radius.
PITCH = 1.0 / 8
PHI = validation.PHI
RADIUS = PITCH * math.sqrt(PHI / math.pi)
E_STAR, DGAMMA = 1.0, validation.DGAMMA
#: Images per side of the periodic sum, each way (a 33 x 33 lattice and the tail beyond).
IMAGES = 16
#: The families' raster and its finer tips (``proxy.FINE`` = 8: 28.9 elements per radius); the 2 x 2 array's
#: finest (its 2592 elements; 8 would be 10^4, a dense solve per event).
FAMILY_PITCH, FACTORS, FINE, ARRAY_FACTORS = 16, (1, 2, 4, 8), 8, (1, 2, 4)
PITCHES, CENTRINGS = (13, 14, 15, 16, 17, 18), ("corner", "element")


def footprint(pitch: int, centring: str, length: float = PITCH) -> np.ndarray:
    """(n, 2) element offsets (row, column) of a tip of radius ``length`` sqrt(phi / pi) on a raster of ``pitch``
    elements per ``length`` (the lattice's pitch), centred on a grid corner or an element's centre: the elements
    whose centres lie inside (`rasterise_pillars`'s rule)."""
    h = length / pitch
    radius = length * math.sqrt(PHI / math.pi)
    centre = 0.0 if centring == "corner" else 0.5  # in elements, from a grid corner
    reach = int(math.ceil(radius / h)) + 1
    index = np.arange(-reach, reach + 1)
    y = (index[:, None] + 0.5 - centre) * h
    x = (index[None, :] + 0.5 - centre) * h
    rows, cols = np.nonzero(x * x + y * y <= radius * radius)
    offsets = np.stack([rows, cols], axis=1)
    return offsets - offsets.min(axis=0)


def lone_table(span: int, h: float) -> np.ndarray:
    """ktab[|dy|, |dx|] of one tip alone (the pillar model's)."""
    i = np.arange(span) * h
    return influence_coefficients(i[:, None], i[None, :], h, E_STAR)


def periodic_table(span: int, h: float, pitch: int, images: int = IMAGES) -> np.ndarray:
    """ktab[|dy|, |dx|] of a tip in the square lattice of period ``pitch`` elements: the Love kernel over the
    (2 ``images`` + 1)^2 lattice plus the images beyond to second order (module docstring)."""
    d = np.arange(span) * h
    period = pitch * h
    total = np.zeros((span, span))
    shifts = np.arange(-images, images + 1) * period
    for sy in shifts:
        total += influence_coefficients(d[:, None, None] + sy, d[None, :, None] + shifts[None, None, :], h,
                                        E_STAR).sum(axis=2)
    half = (images + 0.5) * period
    # Point force h^2 / (pi E* r); the images beyond: |x|^2 / 4 x (4 sqrt(2) / s) / period^2 per unit force.
    tail = (d[:, None] ** 2 + d[None, :] ** 2) / 4 * (4 * math.sqrt(2) / half) / period**2 * h * h / (math.pi * E_STAR)
    return total + tail


def lattice_pull_off(bases: Bases, offsets: np.ndarray, critical: float, h2: float) -> tuple[float, float, int]:
    """(F_A, first event's F, events) per tip of the infinite lattice under force control (module docstring);
    the pressure F psi / h^2 (``h2``: the element's area)."""
    mask = np.ones(offsets.shape[0], dtype=bool)
    force, first, events = 0.0, None, 0
    while mask.any():
        phi = bases.get(offsets, mask).phi[:, 0]
        psi = phi / phi.sum()
        force = max(force, critical * h2 / float(psi.max()))
        first = force if first is None else first
        events += 1
        while mask.any():
            psi = bases.get(offsets, mask).phi[:, 0]
            psi = psi / psi.sum()
            tense = force * psi >= critical * h2 * (1 - 1e-10)
            if not tense.any():
                break
            mask[np.flatnonzero(mask)[tense]] = False
    return force, first, events


def _lone(offsets: np.ndarray, h: float, length: float) -> tuple[float, float, float]:
    """(Sigma_c, F_K, F_R): the raster's criterion, Kendall's force and the lone tip's pull-off on the raster."""
    critical = critical_stress(E_STAR, DGAMMA, h)
    kendall = float(kendall_force(length * math.sqrt(PHI / math.pi), contact_modulus=E_STAR,
                                  work_of_adhesion=DGAMMA))
    span = int(offsets.max()) + 1
    return critical, kendall, lone_pull_off(Bases(lone_table(span, h), MODES["uniform"]), offsets, critical, h * h)[0]


def _row(offsets: np.ndarray, h: float, length: float, tips: int, pull) -> dict:
    """The lone tip's F_R and the layout's pull-off (``pull``: Sigma_c -> (F_A, first event's F, events))."""
    critical, kendall, lone = _lone(offsets, h, length)
    plain, first, events = pull(critical)
    # Calibrated: one stress for the footprint, Sigma_c F_K / F_R; the event path's forces scale with it.
    return {"tips": tips, "tip_elements_per_radius": round(length * math.sqrt(PHI / math.pi) / h, 3),
            "footprint_elements": offsets.shape[0], "lone_error": lone / kendall - 1, "first_event_force": first,
            "events": events, "adhesive_force_plain": plain, "adhesive_force_calibrated": plain * kendall / lone,
            "lone_ratio": kendall / lone}


def raster(pitch: int, centring: str, images: int = IMAGES) -> dict:
    """One raster's lone tip and periodic cell: F_A per tip, plain and calibrated."""
    start = time.process_time()
    offsets = footprint(pitch, centring)
    h = PITCH / pitch
    lattice = Bases(periodic_table(int(offsets.max()) + 1, h, pitch, images), MODES["uniform"])
    row = _row(offsets, h, PITCH, 1, lambda critical: lattice_pull_off(lattice, offsets, critical, h * h))
    return {"pitch_elements": pitch, "centring": centring, **row, "cpu_seconds": round(time.process_time() - start, 2)}


def array(pitch: int, centring: str = "corner", per_side: int = 2) -> dict:
    """A rigid ``per_side`` x ``per_side`` array of the families' tips (``centring``, ``pitch`` elements apart,
    the pitch of ``validation.problem(family, per_side)``: 1 / per_side) at one displacement, pulled off by the
    exact event path of its elements (`lone_pull_off` on the union of the footprints): k~ -> infinity, no pillar
    model.  F_A per tip (the array's over per_side^2)."""
    start = time.process_time()
    length = 1.0 / per_side
    h = length / pitch
    one = footprint(pitch, centring, length)
    union = np.concatenate([one + np.array([i * pitch, j * pitch]) for i in range(per_side)
                            for j in range(per_side)])
    union = union[np.lexsort((union[:, 1], union[:, 0]))]
    bases = Bases(lone_table(int(union.max()) + 1, h), MODES["uniform"])

    def pull(critical: float) -> tuple[float, float, int]:
        force, events = lone_pull_off(bases, union, critical, h * h)
        return force / per_side**2, "", events  # displacement control: the first event's F is not kept

    row = _row(one, h, length, per_side**2, pull)
    return {"pitch_elements": pitch, "centring": centring, **row, "cpu_seconds": round(time.process_time() - start, 2)}


def proxy_fine() -> dict[tuple[float, int], float]:
    """The flat family's proxy at 28.9 elements per radius (calibrated), F_A per (k~, pillars per side), and its
    factor F(28.9, calibrated) / F(3.6) (``proxy.csv``)."""
    fine, ratio = {}, {}
    with (HERE / "proxy.csv").open(newline="") as stream:
        for line in csv.DictReader(stream):
            if line["family"] == "flat":
                key = (float(line["stiffness_ratio"]), int(line["proxy_pillars_per_side"]))
                fine[key] = float(line["proxy_fine_adhesive_force"])
                ratio[key] = fine[key] / float(line["proxy_coarse_adhesive_force"])
    return fine, ratio


def needed() -> dict[tuple[float, int, str], float]:
    """F_ref / F_plain of the 8 x 8 flat brush on each canonical raster per k~ (``criteria.csv``)."""
    out = {}
    with (HERE / "criteria.csv").open(newline="") as stream:
        for line in csv.DictReader(stream):
            if line["part"] == "canonical" and line["criterion"] == "plain" and line["family"] == "flat":
                out[(float(line["stiffness_ratio"]), int(line["pitch_elements"]), line["centring"])] = \
                    1.0 / (1.0 + float(line["error"]))
    return out


def proxy_canonical(stiffness: float, pitch: int, centring: str, fine: float, per_side: int = 4) -> dict:
    """The pillar model's 4 x 4 flat proxy on a canonical raster (``criteria.canonical_case``'s snapping on the
    grid of ``pitch`` elements between pillars) at the grid's tips, plain, and its factor against the proxy's
    28.9-elements F_A ``fine`` (the same physical brush: the snapping moves every pillar alike)."""
    start = time.process_time()
    _, preload = validation.problem("flat", per_side, stiffness)
    case = criteria.canonical_case("flat", stiffness, pitch, centring, per_side)
    h = case.grid.element_size
    force = criteria.pull_off(case, preload, "plain")[0]
    return {"tips": per_side**2, "stiffness_ratio": stiffness, "pitch_elements": pitch, "centring": centring,
            "tip_elements_per_radius": round(float(case.indenter.description.pillar_radius) / h, 3),
            "footprint_elements": footprint(pitch, centring).shape[0], "adhesive_force_plain": force / per_side**2,
            "ratio": fine / force, "cpu_seconds": round(time.process_time() - start, 2)}


def rows() -> list[dict]:
    (fine, proxies), targets = proxy_fine(), needed()
    family = [{"part": "family", "tip_factor": f, **raster(FAMILY_PITCH * f, "corner")} for f in FACTORS]
    canonical = [{"part": "canonical", "tip_factor": 1, **raster(p, c)} for p in PITCHES for c in CENTRINGS]
    pairs = [{"part": "array", "tip_factor": f, **array(FAMILY_PITCH * f)} for f in ARRAY_FACTORS]
    pairs += [{"part": "array_canonical", "tip_factor": 1, **array(p, c)} for p in PITCHES for c in CENTRINGS]
    # Each layout's factor: its finest calibrated tips (the families' raster refined) over this raster's plain ones.
    for part, finest in ((family + canonical, family[-1]), (pairs, pairs[len(ARRAY_FACTORS) - 1])):
        for line in part:
            line["ratio"] = finest["adhesive_force_calibrated"] / line["adhesive_force_plain"]
    brushes = [{"part": "proxy_canonical", "tip_factor": 1, **proxy_canonical(k, p, c, fine[(k, 4)])}
               for k in (10.0, 1e-5) for p in PITCHES for c in CENTRINGS]
    out = family + canonical + pairs + brushes
    for line in out:
        coarse = line["tip_factor"] == 1
        line.setdefault("stiffness_ratio", "inf" if line["tips"] == 4 else "")
        line["proxy_ratio"] = proxies[(10.0, {1: 4, 4: 2}[line["tips"]])] if coarse and line["tips"] < 16 \
            and line["pitch_elements"] == 16 and line["centring"] == "corner" else ""
        # The cell and the rigid array against the brush at k~ = 10, the proxy at its own k~.
        stiffness = line["stiffness_ratio"] if line["part"] == "proxy_canonical" else 10.0
        line["brush_needed_ratio"] = targets.get((stiffness, line["pitch_elements"], line["centring"]), "") \
            if line["part"] in ("canonical", "array_canonical", "proxy_canonical") else ""
        for name in FIELDS:
            line.setdefault(name, "")
    return out


if __name__ == "__main__":
    out = rows()
    for line in out:
        print(", ".join(f"{name}={line[name]}" for name in FIELDS), flush=True)
    calibration.write(out, TABLE, FIELDS, digits=6)
