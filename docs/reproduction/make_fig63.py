"""Write chapter 6's sweeps on the clustered layout of Fig. 6-3 by the pillar-level model (``hierarchy.fig63_*``).

Parts ``fig63_one``, ``fig63_two``, ``fig63_three``: the brushes of ``hierarchy.clustered_*`` (the
layout of Fig. 6-3, phi1 = 0.12, phi2 = phi3 = 0.45 of L1163, k~1 = 1e-3, k~2 = 9e-3 and k~3 = 2e-2 as eq.
6.25-6.26 print them; clusters of 5 x 5 sub-pillars, 4 x 4 of those per level-3 cluster: N1 = 25,
N2 = 16, eq. 6.28's 4.21e-5) run by ``method = "pillars"`` (`brushbem.pillars`), which follows the
exact path within 0.8 % on F~_A on these brushes (the chapter-6 notes), at a pillar radius of 4.5
elements (ours: the thesis states no grid).  One, two and three levels share the positions, radius and
drawn lengths of each seed.

Named sets (``brushbem study hierarchy --sampled-set SET --parts fig63_one,fig63_two,fig63_three``):

* ``identify`` and ``identify16``: the plateau sigma~ = 0.04, F~_P = 14.3 (L1197) for N3 = 4 and 9, and
  16, level-3 clusters (40 x 40, 60 x 60 and 80 x 80 sub-pillars; N1 N2 = 400 for each, so eq. 6.28
  gives 4.21e-5 for each), at N = 2048, 3072 and 4096 elements (4.5 elements a radius): chapter 6's
  identification (the 80 x 80 brush, several CPU-minutes a case, in a set of its own).
* ``mesh``: the same plateau at the identified N3 on 1024 and 4096 elements (2.25 and 9 elements a
  radius; 2048 is in ``identify``): the mesh refinement of the plateau; ``mesh1536`` the same on 1536
  (3.375 elements a radius).  At 1024 and 1536 also the pillar-level model's error against the exact path
  on the same brush (parts ``clustered_*``, their cases and their set ``mesh``, N = 1536).
* ``rows``: the points of the held-out rows at the identified N3 and N = 2048: sigma~ = 0.04, 0.8
  and 1.6 at the small preload F~_P = 1 (Fig. 6-4 a, c, e; ours: the thesis states none), and
  sigma~ = 2.5 at F~_P = 20 (Fig. 6-6 b, "close to each other" for sigma~ > 2).
* ``rows16``: the point sigma~ = 1.6, F~_P = 1 of ``rows`` alone (Fig. 6-4 e, L1183, L1185, L1199), to add
  seeds there without the other points of ``rows`` (the same cases: ``rows`` recomputes them).
* ``rows25``: the point sigma~ = 2.5, F~_P = 20 of ``rows`` alone (Fig. 6-6 b, 6-7 b; L1197, L1201, L1234),
  and ``plateau``: the plateau point sigma~ = 0.04, F~_P = 14.3 of ``identify`` at the identified N3 alone
  (Fig. 6-5; L1185, L1195, L1197): to add seeds there (the same cases as those sets').
* ``stiffness`` (one and three levels): k~1 = 5e-4 and 5e-2 (k~2 = 9 k~1, k~3 = 20 k~1 as eq. 6.26
  scales them; Fig. 6-8 a, L1240) at the plateau point; three levels with k~3 = 2e-3 (0.1 k~3,
  Fig. 6-8 b, L1249) at sigma~ = 0.04 and 0.2, and k~3 = 2e-2 at sigma~ = 0.2.

Parts ``fig63_tips_one``, ``fig63_tips_two`` and ``fig63_tips`` (one, two and three levels): the tips on
rasters of their own (``protocol.pillar_tip_resolution``, `brushbem.pillars.tips`).  They are parts of
their own because the key has no value that means "the grid's own tips" in a sweep list (the other
parts' cases leave it at its default).  Named sets (``--sampled-set SET --parts fig63_tips_one,
fig63_tips_two,fig63_tips``):

* ``tips``: the plateau point sigma~ = 0.04, F~_P = 14.3 at the identified N3 on the rows' grid
  N = 2048 with the tips at 9, 13.5 and 18 elements a radius (twice, three and four times the grid's
  4.5): the discretisation of the tips at a fixed global grid.
* ``tips1024`` (three levels): the tips at 9 on N = 1024 (2.25 elements a radius on the global grid, as
  N3 = 16's N = 2048): the global grid at fixed tips.
* ``identify_tips`` (every level): chapter 6's identification with resolved tips: the plateau point
  for N3 = 4, 9 and 16 on N = 2048 (4.5, 3 and 2.25 elements a radius on the global grid) with the
  tips at 9 elements a radius (factors 2, 3, 4: the footprints of N = 4096, 6144, 8192).

Each part's full sweep is the union of its sets (zip mode), so a set's case has the full sweep's
seed and hash.  Every set lists the thesis's ten realisations (L1187), those of one and three levels
fifteen (`REALIZATIONS`: L1199 needs them, set ``rows16`` ran them; the first ten keep their seeds and
ids); a sweep runs
them one after the other and resumes, so a run stopped after some seeds leaves those seeds complete (the rows read
the seeds that have every point they need).  ``python docs/reproduction/make_fig63.py`` rewrites the files.
"""

from __future__ import annotations

from pathlib import Path

SWEEPS = Path(__file__).resolve().parents[2] / "src" / "brushbem" / "studies" / "sweeps"
F_C = 0.00331177  # eq. 6.23 at phi = 0.0243, L = 1 (independent of the pillar count)
D_C = 0.00293498
K1, K2, K3 = 1e-3, 9e-3, 2e-2  # eq. 6.25-6.26 as printed
#: Sub-pillars per side and elements per side for each candidate N3 (4.5 elements a pillar radius).
CANDIDATES = {4: (40, 2048), 9: (60, 3072), 16: (80, 4096)}
#: The identified N3 (chapter 6's identification; `brushbem.studies._ch6_fig63.N3_IDENTIFIED`).
N3 = 4
LEVELS = ("one", "two", "three")
#: The tips' own resolutions of part fig63_tips (elements a pillar radius; the grid's own is 4.5).
TIPS = (9.0, 13.5, 18.0)
#: The tips' resolution of set identify_tips (elements a pillar radius) and its global grid (every N3).
IDENTIFY_TIPS, IDENTIFY_GRID = 9.0, 2048
#: The parts with the tips on rasters of their own, per level.
TIPS_PARTS = {"one": "fig63_tips_one", "two": "fig63_tips_two", "three": "fig63_tips"}
TIP_KEY = "protocol.pillar_tip_resolution"
#: Parts whose sweeps list more than the thesis's ten realisations (L1187; L1199 needs fifteen of one and three
#: levels, run in set rows16): level -> realisations.  More realisations keep the seeds, and the case ids, of the
#: first ten (`brushbem.sweep`); a set's seeds not run are missing and no row reads them.
REALIZATIONS = {"one": 15, "three": 15}
KEYS = ("grid.elements", "indenter.pillars_per_side", "indenter.roughness.sigma", "protocol.preload_force",
        "indenter.stiffness_ratio", "indenter.levels.0.stiffness_ratio", "indenter.levels.1.stiffness_ratio")


def _g(x: float) -> float:
    return float(f"{x:.6g}")


def point(level: str, n3: int, sigma: float, preload: float, k1: float = K1, k2: float | None = None,
          k3: float | None = None, elements: int | None = None) -> dict:
    side, grid = CANDIDATES[n3]
    k2 = 9 * k1 if k2 is None else k2
    k3 = 20 * k1 if k3 is None else k3
    return {"grid.elements": elements or grid, "indenter.pillars_per_side": side,
            "indenter.roughness.sigma": _g(sigma * D_C), "protocol.preload_force": _g(preload * F_C),
            "indenter.stiffness_ratio": k1, "indenter.levels.0.stiffness_ratio": _g(k2),
            "indenter.levels.1.stiffness_ratio": _g(k3)}


def sets(level: str) -> dict[str, list[dict]]:
    out = {"identify": [point(level, n3, 0.04, 14.3) for n3 in (4, 9)],
           "identify16": [point(level, 16, 0.04, 14.3)],
           "mesh": [point(level, N3, 0.04, 14.3, elements=e) for e in (1024, 4096)],
           "mesh1536": [point(level, N3, 0.04, 14.3, elements=1536)],
           "rows": [point(level, N3, s, 1.0) for s in (0.04, 0.8, 1.6)] + [point(level, N3, 2.5, 20.0)],
           "rows16": [point(level, N3, 1.6, 1.0)],
           "rows25": [point(level, N3, 2.5, 20.0)],
           "plateau": [point(level, N3, 0.04, 14.3)]}
    if level != "two":
        out["stiffness"] = [point(level, N3, 0.04, 14.3, k1=k) for k in (5e-4, 5e-2)]
    if level == "three":
        out["stiffness"] += [point(level, N3, 0.04, 14.3, k3=2e-3), point(level, N3, 0.2, 14.3, k3=2e-3),
                             point(level, N3, 0.2, 14.3)]
    return out


def _keys(level: str) -> tuple[str, ...]:
    """The swept keys: a rigid level has no stiffness ratio to sweep."""
    return KEYS[:5] + {"one": (), "two": KEYS[5:6], "three": KEYS[5:]}[level]


def _levels(level: str) -> str:
    rigid = "stiffness = inf"
    k2 = rigid if level == "one" else f"stiffness_ratio = {K2}"
    k3 = rigid if level != "three" else f"stiffness_ratio = {K3}"
    return f"[{{ cluster = 5, {k2} }}, {{ cluster = 4, {k3} }}]"


def text(level: str, points: list[dict], what: str, realizations: int = 10) -> str:
    base = ('base = { halfspace = { contact_modulus = 1.0, work_of_adhesion = 0.0001 }, grid = { size = 1.0, '
            'elements = 2048 }, indenter = { shape = "brush", layout = "clustered", region = "square", '
            'pillars_per_side = 40, filling_factors = [0.12, 0.45, 0.45], stiffness_ratio = 0.001, seed = 0, '
            f'levels = {_levels(level)} }}, protocol = {{ method = "pillars", preload_force = 1.0, '
            'pillar_tip_peel = false } }')
    header = [f"# {what} (docs/reproduction/make_fig63.py writes this file; its docstring names the points).",
              f"# Thesis ch. 6 on the clustered layout of Fig. 6-3, {level} level{'s' if level != 'one' else ''}, by the "
              "pillar-level model (method = \"pillars\").",
              "# phi1 = 0.12, phi2 = phi3 = 0.45 (L1163), k~1 = 1e-3, k~2 = 9e-3, k~3 = 2e-2 (eq. 6.25-6.26); clusters",
              "# 5 x 5 then 4 x 4 (N1 = 25, N2 = 16; ours: the thesis states neither).  F_c = 0.00331177,",
              "# d_c = 0.00293498.  Grid: 4.5 elements a pillar radius (ours: the thesis states none).",
              "# Units E* = 1, dgamma = 1e-4, L = 1."]
    lines = header + [base, 'mode = "zip"', f"realizations = {realizations}", "seed = 5", "", "[sweep]"]
    for key in _keys(level):
        lines.append(f'"{key}" = [' + ", ".join(f"{p[key]:g}" if isinstance(p[key], float) else str(p[key])
                                                for p in points) + "]")
    return "\n".join(lines) + "\n"


def tip_sets(level: str) -> dict[str, list[dict]]:
    """The named sets of the tips' part of ``level`` (`TIPS_PARTS`)."""
    out = {"tips": [{**point(level, N3, 0.04, 14.3), TIP_KEY: t} for t in TIPS]}
    if level == "three":  # (a set of its own: the set tips keeps the ids of the part's first sweep)
        out["tips1024"] = [{**point(level, N3, 0.04, 14.3, elements=1024), TIP_KEY: TIPS[0]}]
    out["identify_tips"] = [{**point(level, n3, 0.04, 14.3, elements=IDENTIFY_GRID), TIP_KEY: IDENTIFY_TIPS}
                            for n3 in CANDIDATES]
    return out


def tips_text(level: str, points: list[dict], what: str, realizations: int = 10) -> str:
    """A sweep file of a tips' part (`text`'s, with the tips' resolution swept)."""
    body = text(level, points, what, realizations)
    return body + f'"{TIP_KEY}" = [' + ", ".join(f"{p[TIP_KEY]:g}" for p in points) + "]\n"


def write_tips(level: str) -> None:
    """The full sweep (the union of the sets), the named sets and the quick sweep of ``level``'s tips part.

    The quick sweep: one plateau point, 20 x 20 sub-pillars (N3 = 1), N = 512 (2.25 elements a radius), the tips
    at twice the grid's resolution (4.5: a check of the machinery, not a number)."""
    part = f"hierarchy.{TIPS_PARTS[level]}"
    named = tip_sets(level)
    every: list[dict] = []
    for points in named.values():
        every += [p for p in points if p not in every]
    (SWEEPS / f"{part}.toml").write_text(tips_text(level, every, "Every point of the named sets of the tips' part"),
                                         encoding="utf-8")
    for name, points in named.items():
        (SWEEPS / f"{part}.{name}.sampled.toml").write_text(
            tips_text(level, points, f"Named set {name!r} of {part}.toml"), encoding="utf-8")
    quick = [{**point(level, N3, 0.04, 14.3), "grid.elements": 512, "indenter.pillars_per_side": 20, TIP_KEY: 4.5}]
    (SWEEPS / f"{part}.quick.toml").write_text(tips_text(
        level, quick, "Quick check of the machinery: 20 x 20 sub-pillars (N3 = 1), N = 512, tips at 4.5", 1),
        encoding="utf-8")


def main() -> None:
    for level in LEVELS:
        write_tips(level)
        named = sets(level)
        every: list[dict] = []
        for points in named.values():
            every += [p for p in points if p not in every]
        part = f"hierarchy.fig63_{level}"
        (SWEEPS / f"{part}.toml").write_text(text(level, every, "Every point of the named sets",
                                                  REALIZATIONS.get(level, 10)), encoding="utf-8")
        for name, points in named.items():
            (SWEEPS / f"{part}.{name}.sampled.toml").write_text(
                text(level, points, f"Named set {name!r} of {part}.toml", REALIZATIONS.get(level, 10)),
                encoding="utf-8")
        quick = [{**p, "grid.elements": 512, "indenter.pillars_per_side": 20} for p in named["rows"][:2]]
        (SWEEPS / f"{part}.quick.toml").write_text(
            text(level, quick, "Quick check of the machinery: 20 x 20 sub-pillars (N3 = 1), N = 512", 2),
            encoding="utf-8")


if __name__ == "__main__":
    main()
