"""Write the sampled subsets of the full thesis sweeps (``*.sampled.toml``).

Chapter 5 (``rough_brush.preload``):

The full chapter-5 preload sweep (``rough_brush.preload.toml``: the thesis's 1188
points, then the 192 of `EXTRA_SIGMA` that this script appends; x 10 realisations)
costs hundreds of CPU hours at our full grid (N = 512; the thesis states none for chapter 5).  The thesis's stated numbers need only some of its points (``plan.md``, section 3):

* the plateaus (5a-5e, 5m): k~ {10, 1, 0.55, 0.001} x sigma~ {0.01, 0.07, 2.1}
  x F~_P {20, 15, 10};
* the adhesion coefficient c and Table 1 (5f-5k): every k~ x every sigma~ at
  the two smallest shipped preloads where c F~_P lies in [0.05, 0.6] by the
  thesis's own Table 1 (c = alpha/sigma~ - beta): below 0.05 a single touching
  pillar dominates c, above about half the plateau the response is no longer
  linear.  Where no shipped preload is small enough (the soft brushes at
  sigma~ = 0.01: c F~_P = 1.7 at F~_P = 0.005, k~ = 0.001) the smallest one is
  taken, as the thesis's c at its smallest preload.  A (k~, sigma~) beyond
  sigma~_c (c <= 0) has no linear region and is left out.  The points of the
  added roughnesses (`EXTRA_SIGMA`) are in the set ``table1_stiff`` only.

Chapter 5's other sets run the points of the rows over the seeds, as sampled
sets of their own: ``plateau_c``, ``table1_soft``, ``table1_stiff`` and
``rough_plateau`` (the comments at their rules below).

Chapter 6 (``hierarchy.one``, ``.two``, ``.three``; 81 points x 10
realisations each, N = 1024): the plateau points of the numbers the text
states (L1176-L1197), sigma~ = 0.04 at F~_P = 20 and 14.3 -- the plateaus
1.6 / 1.65 / 1.9, and "the strongest adhesive forces ... appear" at
F~_P = 14.3.  One to two CPU-minutes a case.  The small-preload points at
sigma~ = 1.6 (Fig. 6-4 e; the thesis does not state the preload) take 3 to 8
CPU-minutes a case at this grid; they are a second sampled set,
``hierarchy.<level>.small_preload.sampled.toml`` (a sweep runs seed by seed, so
with them in the plateau file no level would have reached ten seeds of its
plateau in a working day on two cores): sigma~ = 1.6 at F~_P = 1 for every
level (one and two levels "tend to zero", three "nearly 0.4") and at F~_P = 0.2
for three levels, the rows of Fig. 6-4 e.  A study runs a named set with
``brushbem study hierarchy --sampled-set small_preload``, into its own folder;
``brushbem export-tables`` takes both folders and writes one table per level.
Two more sets: ``rough`` (sigma~ = 2.5 at F~_P = 20, every level: "all curves
go close to each other" for sigma~ > 2) and ``stiffness`` (Fig. 6-7 b and
6-8 b: one level at seven k~1 from 2e-5 to 2e-3 and three levels, at sigma~
0.04 and 0.8, F~_P = 14.3, for the k~1' that matches the three-level plateau;
k~3 of 2e-3 and 2e-2 alone at sigma~ 0.04, 0.2 and 0.4), the parts of a set
run as processes of their own (``--parts``).

Every point is copied from the full sweep with its base, seed and realisations,
so a sampled case has the full sweep's seed and case hash (its id after the
index).  The order puts the points that carry numbers first (a sweep runs
realisation by realisation, in this order); chapter 5: the largest-preload plateaus, c at sigma~ = 0.01, the other
plateau preloads, then the Table 1 points by k~.

    python docs/reproduction/make_sampled.py      # rewrites the sampled files
"""

from __future__ import annotations

import itertools
import math
import tomllib
from pathlib import Path

SWEEPS = Path(__file__).resolve().parents[2] / "src" / "brushbem" / "studies" / "sweeps"
F_C = 0.00849802  # eq. 5.3 at the sweep's units (its header)
D_C = 0.00753117  # eq. 5.4-5.5
TABLE_1 = {0.55: (0.11, 3.67), 0.1: (0.15, 4.29), 0.055: (0.18, 5.14), 0.02: (0.28, 5.6), 0.01: (0.44, 5.5),
           0.008: (0.59, 6.56), 0.004: (0.91, 9.1), 0.002: (1.7, 15.45), 0.001: (3.32, 22.13)}
PLATEAU_K = (10.0, 1.0, 0.55, 0.001)
PLATEAU_SIGMA = (0.01, 0.07, 2.1)
PLATEAU_PRELOAD = (20.0, 15.0, 10.0)
LINEAR = (0.05, 0.6)

K, STEP, SIGMA, PRELOAD = ("indenter.stiffness_ratio", "protocol.step", "indenter.roughness.sigma",
                           "protocol.preload_force")


def _close(a: float, b: float) -> bool:
    return math.isclose(a, b, rel_tol=2e-3)


def thesis_c(k: float, sigma_tilde: float) -> float:
    alpha, critical = TABLE_1[min(k, 0.55)]
    return alpha / sigma_tilde - alpha / critical


#: Roughnesses added to the full chapter-5 sweep between the thesis's, for the stiff brushes only
#: (`EXTRA_K`: the Table 1 rows k~ >= 0.055 and the rigid case k~ = 10).  Our stiff brushes stop
#: adhering at sigma~ ~ 0.5 (notes: "Table 1 at k~ >= 0.55"), so of the thesis's sigma~ only 0.01,
#: 0.07, 0.2 and 0.4 have c > 0 there: four points, one fewer than a fit of eq. 5.8 counts
#: (`FIT_POINTS` in brushbem.studies.rough_brush).  With these four, seven or eight are in the adhering range.
#: They are appended to the full sweep (its points and indices before them unchanged) and run
#: in the set ``table1_stiff`` (`select_table1_stiff`), after the thesis's points there.
EXTRA_SIGMA = (0.03, 0.12, 0.28, 0.5)
EXTRA_K = (10.0, 0.55, 0.1, 0.055)
EXTRA_HEADER = ("# Added after the thesis's points: sigma~ {0.03, 0.12, 0.28, 0.5} at k~ {10, 0.55, 0.1, 0.055},"
                " every F~_P,\n# for the fit of eq. 5.8 where the stiff brushes adhere (sigma~ < 0.5;"
                " docs/reproduction/make_sampled.py).")


def _sigma_value(sigma_tilde: float) -> float:
    return float(f"{sigma_tilde * D_C:.6g}")


def extend_full_sweep() -> Path:
    """Append the `EXTRA_SIGMA` points to ``rough_brush.preload.toml`` (once; idempotent)."""
    path = SWEEPS / "rough_brush.preload.toml"
    text = path.read_text(encoding="utf-8")
    spec = tomllib.loads(text)
    points = _points(spec)
    have = {(p[K], p[SIGMA], p[PRELOAD]) for p in points}
    steps = {p[K]: p[STEP] for p in points}
    preloads = sorted({p[PRELOAD] for p in points})
    added = [{K: k, STEP: steps[k], SIGMA: _sigma_value(s), PRELOAD: f}
             for k in EXTRA_K for s in EXTRA_SIGMA for f in preloads]
    added = [p for p in added if (p[K], p[SIGMA], p[PRELOAD]) not in have]
    return append_points(path, added, EXTRA_HEADER.splitlines())


def append_points(path: Path, added: list[dict], header: list[str]) -> Path:
    """Append the points ``added`` to the zip sweep file ``path`` after its own (whose indices,
    hence the recorded case ids, stay as they are), with the ``header`` comment lines put
    before its base line once.  Nothing to add leaves the file untouched."""
    if not added:
        return path
    text = path.read_text(encoding="utf-8")
    spec = tomllib.loads(text)
    lines = text.splitlines()
    if header and header[0] not in lines:
        at = next(i for i, line in enumerate(lines) if line.startswith("base = "))
        lines[at:at] = header
    every = _points(spec) + added
    start = next(i for i, line in enumerate(lines) if line.strip() == "[sweep]")
    lines = lines[:start + 1] + ['"%s" = [' % key + ", ".join(_value(p[key]) for p in every) + "]"
                                 for key in spec["sweep"]]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def _extra(p: dict) -> bool:
    return any(_close(p[SIGMA] / D_C, s) for s in EXTRA_SIGMA)


def select(points: list[dict], extra: bool = False) -> list[dict]:
    """The main sampled file's points (the thesis's roughnesses), with ``extra`` also those of
    `EXTRA_SIGMA`, after them (the main file leaves them out: a sweep's case index runs over its
    points realisation by realisation, so points added to it would renumber the recorded cases
    of every realisation after the first)."""
    if not extra:
        points = [p for p in points if not _extra(p)]

    def tilde(p):
        return p[K], p[SIGMA] / D_C, p[PRELOAD] / F_C

    chosen: list[dict] = []

    def take(p):
        if all(p is not q for q in chosen):
            chosen.append(p)

    def plateau(preloads):
        for p in points:
            k, s, f = tilde(p)
            if (any(_close(k, x) for x in PLATEAU_K) and any(_close(s, x) for x in PLATEAU_SIGMA)
                    and any(_close(f, x) for x in preloads)):
                take(p)

    def linear(p_list):
        groups: dict[tuple, list[dict]] = {}
        for p in p_list:
            k, s, _ = tilde(p)
            groups.setdefault((k, round(s, 4)), []).append(p)
        picked = []
        for (k, s), group in groups.items():
            c = thesis_c(k, s)
            if c <= 0:
                continue
            inside = sorted((p for p in group if LINEAR[0] <= c * tilde(p)[2] <= LINEAR[1]), key=lambda p: p[PRELOAD])
            picked += inside[:2] or sorted(group, key=lambda p: p[PRELOAD])[:1]
        return picked

    plateau(PLATEAU_PRELOAD[:1])
    for p in linear([p for p in points if _close(tilde(p)[1], 0.01)]):
        take(p)
    plateau(PLATEAU_PRELOAD[1:])
    table = sorted(linear(points), key=lambda p: (-p[K], p[SIGMA], p[PRELOAD]))
    for p in [p for p in table if not _extra(p)] + [p for p in table if _extra(p)]:
        take(p)
    return chosen


#: Chapter 5's second set, ``plateau_c``: the cheap points of the plateau and c rows, for the
#: standard errors of those rows over ten seeds (the Table 1 points run seed by seed in the main
#: file, 5.8 CPU-hours for seed 0).  The plateaus at the largest preload (F~_P = 10, 15 and 20 give
#: the same F~_A to 12 digits on seed 0, so the largest alone reads the plateau) without the stiff
#: sigma~ = 2.1 points (one pillar's force, 20 CPU-minutes a case), and c at sigma~ = 0.01.
RESOLVED_PLATEAUS = ((10.0, 0.01), (10.0, 0.07), (1.0, 0.01), (1.0, 0.07), (0.55, 0.01), (0.55, 0.07),
                     (0.001, 0.01), (0.001, 0.07), (0.001, 2.1))


def _largest_preload(points: list[dict], plateaus) -> list[dict]:
    """The main file's points at F~_P = 20 of the (k~, sigma~) in ``plateaus``, in its order."""
    return [p for p in select(points) if any(
        _close(p[K], k) and _close(p[SIGMA] / D_C, s) and _close(p[PRELOAD] / F_C, PLATEAU_PRELOAD[0])
        for k, s in plateaus)]


def select_plateau_c(points: list[dict]) -> list[dict]:
    """The ``plateau_c`` set of chapter 5: `RESOLVED_PLATEAUS` at F~_P = 20, then c at sigma~ = 0.01
    (the main file's points, in its order)."""
    return _largest_preload(points, RESOLVED_PLATEAUS) + [p for p in select(points) if _close(p[SIGMA] / D_C, 0.01) and p[PRELOAD] / F_C < 1.0]


#: Chapter 5's third set, ``table1_soft``: the Table 1 points of the soft brushes, whose c stays
#: linear over the decade of sigma~ a fit needs (seed 0: 5 to 7 CPU-minutes a k~ and seed, against
#: 15 to 45 for k~ >= 0.055, whose sigma~ >= 1 points pull off one pillar after another).  With
#: ``plateau_c`` (c at sigma~ = 0.01) they give alpha and sigma~_c of these k~ over the seeds.
SOFT_TABLE_1 = (0.001, 0.002, 0.004, 0.008, 0.01, 0.02)


def select_table1_soft(points: list[dict]) -> list[dict]:
    """The ``table1_soft`` set of chapter 5: the main file's Table 1 points of `SOFT_TABLE_1`, sigma~ > 0.01."""
    return [p for p in select(points) if any(_close(p[K], k) for k in SOFT_TABLE_1)
            and not _close(p[SIGMA] / D_C, 0.01) and p[PRELOAD] / F_C < 9.0]


#: Chapter 5's fourth set, ``table1_stiff``: the Table 1 points of the stiff brushes (`EXTRA_K`) where
#: they adhere, sigma~ between 0.01 and 1 (the thesis's 0.07 to 0.7 and `EXTRA_SIGMA`), at the
#: main file's preloads.  With ``plateau_c`` (c at sigma~ = 0.01) they give alpha, beta and
#: sigma~_c of k~ >= 0.055 over the seeds; sigma~ >= 1 is left out (one pillar's force there, 20
#: CPU-minutes a case, and no c: seed 0 has them all saturated).
def select_table1_stiff(points: list[dict]) -> list[dict]:
    """The ``table1_stiff`` set of chapter 5: the main file's Table 1 points of `EXTRA_K`, 0.01 < sigma~ < 1."""
    return [p for p in select(points, extra=True) if any(_close(p[K], k) for k in EXTRA_K)
            and 0.02 < p[SIGMA] / D_C < 0.9 and p[PRELOAD] / F_C < 9.0]


#: Chapter 5's fifth set, ``rough_plateau``: the one plateau row that `RESOLVED_PLATEAUS` leaves to the
#: main file, k~ = 1 at sigma~ = 2.1 ("almost vanishes"), at F~_P = 20 alone, for its standard error
#: over the seeds (seed 0: 21 CPU-minutes; the main file reaches it only after its k~ = 10 point).
ROUGH_PLATEAUS = ((1.0, 2.1),)


def select_rough_plateau(points: list[dict]) -> list[dict]:
    """The ``rough_plateau`` set of chapter 5: `ROUGH_PLATEAUS` at F~_P = 20 (the main file's points)."""
    return _largest_preload(points, ROUGH_PLATEAUS)


H_F_C = 0.00331177  # the hierarchy sweeps' header: F_c and d_c of one level
H_D_C = 0.00293498
HIERARCHY_POINTS = ((0.04, 20.0), (0.04, 14.3))  # (sigma~, F~_P), in run order
#: The second set, Fig. 6-4 e's small preload at sigma~ = 1.6, per level.
HIERARCHY_SMALL_PRELOAD = {"one": ((1.6, 1.0),), "two": ((1.6, 1.0),), "three": ((1.6, 1.0), (1.6, 0.2))}
#: The third set, ``rough``: sigma~ = 2.5 at the largest preload, F~_P = 20, every level -- "when
#: roughness becomes large (sigma~ > 2) ... all curves go close to each other" (L1201, Fig. 6-6 b).
HIERARCHY_ROUGH = ((2.5, 20.0),)


def select_hierarchy(points: list[dict], wanted=HIERARCHY_POINTS) -> list[dict]:
    chosen = []
    for sigma_tilde, preload in wanted:
        found = [p for p in points if _close(p[SIGMA] / H_D_C, sigma_tilde) and _close(p[PRELOAD] / H_F_C, preload)]
        if len(found) != 1:
            raise SystemExit(f"hierarchy: {len(found)} points at sigma~ = {sigma_tilde}, F~_P = {preload}")
        chosen += found
    return chosen


#: The fourth set, ``stiffness``: Fig. 6-7 b (the single-level k~1' whose plateau equals the three
#: levels', eq. 6.28 "only under a very smooth contact", L1226) and Fig. 6-8 b (k~3 alone, "for the
#: structure with 0.1 k3, roughness has little effect ... when sigma~ < 0.3", L1249), at the full
#: sweeps' preload F~_P = 14.3: one level at k~1 from 2e-5 to 2e-3 (brackets the three-level plateau)
#: at sigma~ 0.04 and 0.8, three levels at sigma~ = 0.8 (0.04 is the plateau file's), and k~3 of 2e-3
#: and 2e-2 at sigma~ 0.04, 0.2 and 0.4.
HIERARCHY_STIFFNESS = {
    "stiffness_one": {K: (2e-5, 4e-5, 1e-4, 2e-4, 5e-4, 1e-3, 2e-3), SIGMA: (0.04, 0.8)},
    "stiffness_k3": {"indenter.levels.1.stiffness_ratio": (2e-3, 2e-2), SIGMA: (0.04, 0.2, 0.4)},
}


def select_stiffness(points: list[dict], wanted: dict) -> list[dict]:
    """The points of a ``stiffness_*`` part whose values are all among ``wanted`` (sigma~ by d_c), by sigma~."""
    def among(p, key, values):
        x = p[key] / H_D_C if key == SIGMA else p[key]
        return any(_close(x, v) for v in values)
    chosen = [p for p in points if all(among(p, key, values) for key, values in wanted.items())]
    if len(chosen) != math.prod(len(v) for v in wanted.values()):
        raise SystemExit(f"hierarchy: {len(chosen)} points for {wanted}")
    return sorted(chosen, key=lambda p: p[SIGMA])


def _points(spec: dict) -> list[dict]:
    keys = list(spec["sweep"])
    if spec.get("mode", "zip") == "product":
        return [dict(zip(keys, values)) for values in itertools.product(*spec["sweep"].values())]
    return [dict(zip(keys, values)) for values in zip(*spec["sweep"].values())]


def _value(x) -> str:
    return f'"{x}"' if isinstance(x, str) else repr(float(x))


def write(study: str, part: str, rule=select, subset: str = "") -> Path:
    full = SWEEPS / f"{study}.{part}.toml"
    text = full.read_text(encoding="utf-8")
    spec = tomllib.loads(text)
    keys = list(spec["sweep"])
    points = _points(spec)
    chosen = rule(points)
    header = [line for line in text.splitlines() if line.startswith("#")]
    base_line = next(line for line in text.splitlines() if line.startswith("base = "))
    lines = header + [
        f"# SAMPLED subset of {full.name} ({len(chosen)} of its {len(points)} points, the same base, seed and",
        "# realisations, so the same case hashes after the index): the points that carry the thesis's",
        "# stated numbers, written by docs/reproduction/make_sampled.py (which states the rule)"
        + (f"; the set {subset!r}." if subset else "; plateaus first."),
        base_line,
        'mode = "zip"',
        f"realizations = {spec['realizations']}",
        f"seed = {spec['seed']}",
        "",
        "[sweep]",
    ]
    for key in keys:
        lines.append(f'"{key}" = [' + ", ".join(_value(p[key]) for p in chosen) + "]")
    out = SWEEPS / f"{study}.{part}.{subset + '.' if subset else ''}sampled.toml"
    out.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return out


if __name__ == "__main__":
    print(extend_full_sweep())
    print(write("rough_brush", "preload"))
    print(write("rough_brush", "preload", select_plateau_c, subset="plateau_c"))
    print(write("rough_brush", "preload", select_table1_soft, subset="table1_soft"))
    print(write("rough_brush", "preload", select_table1_stiff, subset="table1_stiff"))
    print(write("rough_brush", "preload", select_rough_plateau, subset="rough_plateau"))
    for level in ("one", "two", "three"):
        print(write("hierarchy", level, select_hierarchy))
        print(write("hierarchy", level, lambda points, level=level: select_hierarchy(
            points, HIERARCHY_SMALL_PRELOAD[level]), subset="small_preload"))
        print(write("hierarchy", level, lambda points: select_hierarchy(points, HIERARCHY_ROUGH), subset="rough"))
    print(write("hierarchy", "three", lambda points: select_hierarchy(points, ((0.8, 14.3),)), subset="stiffness"))
    for part, wanted in HIERARCHY_STIFFNESS.items():
        print(write("hierarchy", part, lambda points, wanted=wanted: select_stiffness(points, wanted), subset="stiffness"))
