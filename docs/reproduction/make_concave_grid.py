"""Chapter 7's candidates: the concave sweeps' points again on N = `GRID` and on the identified 24 x 24, N = 512.

Chapter 7's one identification (`brushbem.studies._ch7_identify`, the rule declared in the docstring of
``probe_concave_count.py``, its error the reading alone) picks 24 x 24 pillars on N = 512; with the error
widened after that was known (a sensitivity) it picks 16 x 16 pillars on N = 320 (2.76 elements a pillar radius;
the thesis states neither count nor grid for chapter 7).  `write` appends to each full concave sweep
(``concave.curves``, ``.amplification``, ``.stiffness``) its own points once more with ``grid.elements`` = `GRID`,
after the recorded ones: the recorded points get ``grid.elements`` = 512, their base's value, so their
configurations, indices and case ids are unchanged (the case hash is over the resolved configuration).  It writes
the appended points as the named set ``concave.<part>.n320.sampled.toml`` (same base, seed and case hashes as the
full sweep), which runs with

    brushbem study concave --sampled-set n320 --parts stiffness --out out/concave_n320 --workers 1

A rerun leaves a sweep that already has ``grid.elements`` alone (the files are then up to date).

Chapter 7's identification rule as first declared (the reading error alone, `brushbem.studies._ch7_identify`)
picks 24 x 24 pillars on N = 512 (2.95 elements a pillar radius).  `write_count` appends every point once more
on that candidate, after the N = 320 points: ``indenter.pillars_per_side`` = `COUNT_SIDE`, the pillar radius
sqrt(phi / pi) / 24 and the preload 2 n^2 F_K (F_K = sqrt(8 pi E* dgamma r^3), eq. 7.4) of the new lattice, as
``probe_concave_count.py`` runs them, h~ (runs' unit) unchanged; the recorded points get
``indenter.pillars_per_side`` = 16, their base's value, so their case ids are unchanged.  The named set
`COUNT_SET` lists the same points with the counted chapter-7 rows' points first (`counted_first`), so that a
stopped run has them:

    brushbem study concave --sampled-set n512x24 --parts curves,amplification,stiffness \
        --out out/concave-n512x24 --workers 1

    python docs/reproduction/make_concave_grid.py
"""

from __future__ import annotations

import json
import math
import tomllib
from pathlib import Path

from brushbem.studies import SWEEPS_DIR

#: The grid of set n320 (16 x 16, chapter 7's count and grid sensitivity) and of the recorded points (the base).
GRID, RECORDED_GRID = 320, 512
SET = f"n{GRID}"
PARTS = ("curves", "amplification", "stiffness")


def _value(value) -> str:
    return json.dumps(value) if isinstance(value, str) else repr(value)


def _sweep_lines(sweep: dict[str, list]) -> list[str]:
    return ["[sweep]", *(f"{json.dumps(key)} = [{', '.join(_value(v) for v in values)}]"
                         for key, values in sweep.items())]


def write(part: str) -> None:
    path = SWEEPS_DIR / f"concave.{part}.toml"
    text = path.read_text(encoding="utf-8")
    spec = tomllib.loads(text)
    head = text[:text.index("[sweep]")].rstrip("\n").split("\n")
    comment = [line for line in head if line.startswith("#")]
    settings = [line for line in head if line and not line.startswith("#")]
    sweep = spec["sweep"]
    if "grid.elements" in sweep:
        return
    n = len(next(iter(sweep.values())))
    note = (f"# Added after those: every point again on N = {GRID}, the pick of chapter 7's identification with its "
            f"error widened, now its grid sensitivity (docs/reproduction/make_concave_grid.py); the points before it "
            f"are on N = {RECORDED_GRID}.")
    full = {key: values + values for key, values in sweep.items()}
    full["grid.elements"] = [RECORDED_GRID] * n + [GRID] * n
    path.write_text("\n".join([*comment, note, *settings, "", *_sweep_lines(full)]) + "\n", encoding="utf-8")
    sampled = {key: list(values) for key, values in sweep.items()}
    sampled["grid.elements"] = [GRID] * n
    header = [f"# Named set '{SET}' of concave.{part}.toml (docs/reproduction/make_concave_grid.py writes this file): "
              f"its {n} points on N = {GRID},", "# the pick of chapter 7's identification with its error widened, now "
              "its count and grid sensitivity (16 x 16 pillars, 2.76 elements a pillar radius; the thesis states "
              "neither).", *comment[:1]]
    (SWEEPS_DIR / f"concave.{part}.{SET}.sampled.toml").write_text(
        "\n".join([*header, *settings, "", *_sweep_lines(sampled)]) + "\n", encoding="utf-8")


#: The strict pick of chapter 7's identification: pillars per side, grid N; its named set.
COUNT_SIDE, COUNT_GRID, RECORDED_SIDE = 24, 512, 16
COUNT_SET = f"n{COUNT_GRID}x{COUNT_SIDE}"
#: The shipped 16 x 16 radii by phi (pillar radius sqrt(phi / pi) / 16).
PHI_BY_RADIUS = {0.00863735: 0.06, 0.0136569: 0.15}
#: (phi, k~) of the part ``stiffness`` that a counted chapter-7 row reads (``brushbem.studies.concave``): the
#: stiff optimum and its neighbours, Fig. 7-3's k~ = 0.1, the soft maxima and their ratios; k~ = 1.5e-4 only flat.
COUNTED_STIFFNESS = {(0.06, 10.0), (0.06, 0.1), (0.06, 6e-4), (0.15, 10.0), (0.15, 6e-4)}


def counted(part: str, point: dict) -> bool:
    """Whether a counted chapter-7 row reads ``point`` (every point of ``curves`` and ``amplification``)."""
    if part != "stiffness":
        return True
    phi, k = PHI_BY_RADIUS[point["indenter.pillar_radius"]], point["indenter.stiffness_ratio"]
    return (phi, k) in COUNTED_STIFFNESS or (phi, k, point["indenter.profile.amplification"]) == (0.06, 1.5e-4, 0.0)


def counted_first(part: str, points: list[dict]) -> list[dict]:
    """``points`` with those of the counted rows first, each group in its sweep order."""
    return [p for p in points if counted(part, p)] + [p for p in points if not counted(part, p)]


def on_count(point: dict) -> dict:
    """``point`` on `COUNT_SIDE` pillars a side and N = `COUNT_GRID`: its phi's radius and 2 n^2 F_K."""
    phi = PHI_BY_RADIUS[point["indenter.pillar_radius"]]
    radius = math.sqrt(phi / math.pi) / COUNT_SIDE
    preload = 2 * COUNT_SIDE**2 * math.sqrt(8 * math.pi * 1.0 * 1e-4 * radius**3)
    return {**point, "indenter.pillar_radius": radius, "protocol.preload_force": preload,
            "grid.elements": COUNT_GRID, "indenter.pillars_per_side": COUNT_SIDE}


def write_count(part: str) -> None:
    """Appends to ``concave.<part>.toml`` its points on `COUNT_SIDE` x `COUNT_SIDE`, N = `COUNT_GRID`, and writes
    the named set `COUNT_SET` (counted rows' points first).  A sweep that has ``indenter.pillars_per_side``
    is left alone."""
    path = SWEEPS_DIR / f"concave.{part}.toml"
    text = path.read_text(encoding="utf-8")
    spec = tomllib.loads(text)
    head = text[:text.index("[sweep]")].rstrip("\n").split("\n")
    comment = [line for line in head if line.startswith("#")]
    settings = [line for line in head if line and not line.startswith("#")]
    sweep = spec["sweep"]
    if "indenter.pillars_per_side" in sweep or "grid.elements" not in sweep:
        return
    n = len(sweep["grid.elements"]) // 2
    first = [{key: values[i] for key, values in sweep.items()} for i in range(n)]
    new = [on_count(p) for p in first]
    note = (f"# Added after those: every point again on {COUNT_SIDE} x {COUNT_SIDE} pillars, N = {COUNT_GRID} "
            "(pillar radius and preload 2 N F_K of that lattice), the strict pick of chapter 7's identification "
            "(docs/reproduction/make_concave_grid.py); the points before it have 16 x 16.")
    full = {key: values + [p[key] for p in new] for key, values in sweep.items()}
    full["indenter.pillars_per_side"] = [RECORDED_SIDE] * (2 * n) + [COUNT_SIDE] * n
    path.write_text("\n".join([*comment, note, *settings, "", *_sweep_lines(full)]) + "\n", encoding="utf-8")
    ordered = [on_count(p) for p in counted_first(part, first)]
    sampled = {key: [p[key] for p in ordered] for key in full}
    header = [f"# Named set '{COUNT_SET}' of concave.{part}.toml (docs/reproduction/make_concave_grid.py writes this "
              f"file): its {n} points on {COUNT_SIDE} x {COUNT_SIDE} pillars, N = {COUNT_GRID},",
              "# the strict pick of chapter 7's identification (2.95 elements a pillar radius; the thesis states "
              "neither); the points of the counted rows first.", *comment[:1]]
    (SWEEPS_DIR / f"concave.{part}.{COUNT_SET}.sampled.toml").write_text(
        "\n".join([*header, *settings, "", *_sweep_lines(sampled)]) + "\n", encoding="utf-8")
    # The set n320 lists every key of the full sweep, its pillars per side (16) too: its case ids are unchanged.
    grid_set = SWEEPS_DIR / f"concave.{part}.{SET}.sampled.toml"
    grid_text = grid_set.read_text(encoding="utf-8")
    if "indenter.pillars_per_side" not in grid_text:
        grid_set.write_text(grid_text.rstrip("\n") + f"\n\"indenter.pillars_per_side\" = [{', '.join(['16'] * n)}]\n",
                            encoding="utf-8")


#: The soft maxima (k~ = 6e-4) of the identified 24 x 24 on N = 512, refined in h~ (runs' unit) between the
#: recorded neighbours of each maximum: (phi, region) -> h~ added; the recorded maximum (F~_A at h~) and its
#: neighbours in the comment.  The set `PEAK_SET` runs them (part ``amplification`` both forms, ``stiffness``
#: the circle: each part's rows read its own points).
PEAK_H = {
    # 0.8171 at 0.08 (0.8074 at 0.06, 0.7969 at 0.12)
    (0.06, "circle"): (0.065, 0.07, 0.075, 0.085, 0.09, 0.095, 0.1, 0.11),
    (0.15, "circle"): (0.4, 0.45, 0.475, 0.525, 0.55, 0.6),  # 0.8358 at 0.5 (0.8247 at 0.35, 0.7867 at 0.7)
    (0.06, "square"): (0.05, 0.06, 0.07, 0.09, 0.1, 0.11),  # 0.8140 at 0.08 (0.8087 at 0.04, 0.8107 at 0.12)
    (0.15, "square"): (0.55, 0.6, 0.65, 0.75, 0.8, 0.85),  # 0.7838 at 0.7 (0.7688 at 0.5, 0.7276 at 1.0)
}
PEAK_SET, SOFT = f"{COUNT_SET}peaks", 6e-4


def write_peaks(part: str) -> None:
    """Appends to ``concave.<part>.toml`` the `PEAK_H` points on `COUNT_SIDE` x `COUNT_SIDE`, N = `COUNT_GRID`
    (those of its forms; each from its recorded h~ = 0 point, ``protocol.step`` times 1 + 2 h~ as the sweep's
    rule), and writes the named set `PEAK_SET` with them.  Points already in the sweep are not added again."""
    path = SWEEPS_DIR / f"concave.{part}.toml"
    text = path.read_text(encoding="utf-8")
    spec = tomllib.loads(text)
    sweep = spec["sweep"]
    if "indenter.pillars_per_side" not in sweep:
        return
    points = [dict(zip(sweep, values)) for values in zip(*sweep.values())]
    ours = [p for p in points if p["indenter.pillars_per_side"] == COUNT_SIDE and p["indenter.stiffness_ratio"] == SOFT]
    have = {(p["indenter.pillar_radius"], p["indenter.region"], p["indenter.profile.amplification"]) for p in ours}
    peaks = []
    for (phi, region), hs in PEAK_H.items():
        flat = [p for p in ours if p["indenter.region"] == region and p["indenter.profile.amplification"] == 0.0
                and math.isclose(p["indenter.pillar_radius"], math.sqrt(phi / math.pi) / COUNT_SIDE)]
        if not flat:
            continue
        for h in hs:
            peaks.append({**flat[0], "indenter.profile.amplification": h,
                          "protocol.step": float(f"{flat[0]['protocol.step'] * (1 + 2 * h):.6g}")})
    added = [p for p in peaks if (p["indenter.pillar_radius"], p["indenter.region"],
                                  p["indenter.profile.amplification"]) not in have]
    if added:
        head = text[:text.index("[sweep]")].rstrip("\n").split("\n")
        note = ("# Added after those: the soft maxima (k~ = 6e-4) of the 24 x 24 lattice on N = 512 refined in h~ "
                "(docs/reproduction/make_concave_grid.py, PEAK_H).")
        comment = [line for line in head if line.startswith("#")]
        settings = [line for line in head if line and not line.startswith("#")]
        full = {key: values + [p[key] for p in added] for key, values in sweep.items()}
        path.write_text("\n".join([*comment, *([note] if note not in comment else []), *settings, "",
                                   *_sweep_lines(full)]) + "\n", encoding="utf-8")
    if not peaks:
        return
    settings = [line for line in text[:text.index("[sweep]")].split("\n") if line and not line.startswith("#")]
    header = [f"# Named set '{PEAK_SET}' of concave.{part}.toml (docs/reproduction/make_concave_grid.py writes this "
              f"file): its {len(peaks)} points that refine in h~ the soft maxima (k~ = 6e-4) of {COUNT_SIDE} x "
              f"{COUNT_SIDE} pillars on N = {COUNT_GRID},", "# chapter 7's identified candidate."]
    (SWEEPS_DIR / f"concave.{part}.{PEAK_SET}.sampled.toml").write_text(
        "\n".join([*header, *settings, "", *_sweep_lines({key: [p[key] for p in peaks] for key in sweep})]) + "\n",
        encoding="utf-8")


if __name__ == "__main__":
    for name in PARTS:
        write(name)
        write_count(name)
        write_peaks(name)
