"""Write chapter 5's sweeps at 16 x 16 pillars: the pillar-count identification and Table 1.

The thesis states no pillar count for chapter 5 (phi = 0.16 only, L862; its
F_c and d_c, eq. 5.3-5.4, depend on A0 and phi alone).  Chapter 5 is
identified once, on its three plateau numbers (L896-L899: F~_A -> 1 at
k~ = 10, sigma~ = 0.07; -> 2 at k~ = 0.001, sigma~ -> 0; 1.5 at k~ = 0.001,
sigma~ = 2.1), among 16 x 16 and 32 x 32 pillars at the same resolution per
pillar (16 elements per pitch, pillar radius 3.6 elements): 32 x 32 is the
committed ``preload`` part, 16 x 16 the part ``count`` written here
(N = 256, radius 0.0141047, so phi = 0.16).  The part ``count`` also holds
the other plateau rows of chapter 5 at 16 x 16 (k~ = 1 and 0.55 at
sigma~ = 0.07), held out from the identification; ``count_rough`` the stiff
rough plateau (k~ = 1, sigma~ = 2.1), one seed (ten times the others' cost).

``table1``: Table 1 at 16 x 16 pillars, every column (k~ = 0.55 ... 0.001,
and k~ = 10 for the rigid limit) x the thesis's thirteen roughnesses
sigma~ = 0.01 ... 3 x ten realisations, with one reading rule for c declared
before computing: c = F~_A / F~_P at the one preload F~_P = 0.1 for every
column and roughness (the thesis states no preload for its linear region,
L907-L911).  It runs the pillar-level model (``protocol.method = "pillars"``,
docs/pillars/validation.md: within 0.2 % of the event path on rough brushes
of 256 pillars at N = 256); Each column is also a named sampled set (``rough_brush.table1.k0p55.sampled.toml``, ...), run into
its own folder, so that a column reaches its ten seeds before the next begins.  ``table1_events`` runs k~ = 10 and 0.001 over the
thirteen roughnesses with the event path, one realisation of the same seed,
which measures that error on these cases.

``preload16``: F~_A against the preload (Fig. 5-3 and 5-4) at 16 x 16 pillars, F~_P = 0.1 to 20, the
stiff (k~ = 10) and the softest (k~ = 0.001) brush at sigma~ = 0.07, 0.5 and 2.1, two realisations, the
pillar-level model: the claims L885-887 (linear, then a plateau) and L905 (the softer brush reaches its
plateau earlier).  The points are ours (the thesis shows curves and states no sampled preloads).

    python docs/reproduction/make_count_sweeps.py      # rewrites the files and their quick files
"""

from __future__ import annotations

from pathlib import Path

SWEEPS = Path(__file__).resolve().parents[2] / "src" / "brushbem" / "studies" / "sweeps"

F_C = 0.00849802  # eq. 5.3, A0 = 1, phi = 0.16, E* = 1, dgamma = 1e-4
D_C = 0.00753117  # eq. 5.4
#: The thesis's thirteen roughnesses of Fig. 5-5 (sigma~ = sigma / d_c).
SIGMAS = (0.01, 0.03, 0.07, 0.12, 0.2, 0.28, 0.4, 0.5, 0.7, 1.0, 1.4, 2.1, 3.0)
#: Table 1's columns (k~ >= 0.55 as 0.55) and the rigid brush k~ = 10.
COLUMNS = (10.0, 0.55, 0.1, 0.055, 0.02, 0.01, 0.008, 0.004, 0.002, 0.001)
#: The declared reading preload of c (F~_P), the same for every column.
READING_PRELOAD = 0.1
#: The plateau rows: (k~, sigma~), the identification's three first.
PLATEAUS = ((10.0, 0.07), (0.001, 0.01), (0.001, 2.1), (1.0, 0.07), (0.55, 0.07))
#: The stiff rough plateau (k~ = 1, sigma~ = 2.1, "almost vanishes"): 10 times the others' cost, one seed.
ROUGH_PLATEAU = (1.0, 2.1)
#: Plateau preload F~_P: the first seed's F~_P = 10 and 20 gave the same F~_A to every digit at all six
#: plateau points (the cases stay in the first run's folder), so the seeds run F~_P = 20 alone.
PLATEAU_PRELOADS = (20.0,)
#: F~_A against the preload at 16 x 16 (part preload16): stiffnesses, roughnesses, preloads (ours).
CURVE_STIFFNESSES = (10.0, 0.001)
CURVE_SIGMAS = (0.07, 0.5, 2.1)
CURVE_PRELOADS = (0.1, 0.3, 1.0, 3.0, 10.0, 20.0)

BASE_16 = ('{ halfspace = { contact_modulus = 1.0, work_of_adhesion = 0.0001 }, grid = { size = 1.0, elements = 256 }, '
           'indenter = { shape = "brush", layout = "square", region = "square", pillars_per_side = 16, '
           'pillar_radius = 0.01410474, stiffness_ratio = 1.0, seed = 0 }, '
           'protocol = { method = "%s", preload_force = 1.0%s } }')
BASE_QUICK = ('{ halfspace = { contact_modulus = 1.0, work_of_adhesion = 0.0001 }, grid = { size = 1.0, elements = 64 }, '
              'indenter = { shape = "brush", layout = "square", region = "square", pillars_per_side = 4, '
              'pillar_radius = 0.056419, stiffness_ratio = 1.0, seed = 0 }, '
              'protocol = { method = "%s", preload_force = 1.0%s } }')
#: The protocol's method and the rest of its table: the event path keeps the step of the other chapter-5
#: sweeps (unused by it), the pillar-level model its tips on their rasters (the criterion the sweeps were
#: recorded with).
EVENTS, PILLARS = ("events", ", step = 1.0"), ("pillars", ", pillar_tip_peel = false")


def _list(values) -> str:
    return "[" + ", ".join(repr(float(f"{v:.6g}")) for v in values) + "]"


def _write(name: str, header: str, base: str, realizations: int, points: list[tuple[float, float, float]]) -> None:
    k, sigma, preload = zip(*points)
    text = (header + f"base = {base}\nmode = \"zip\"\nrealizations = {realizations}\nseed = 5\n\n[sweep]\n"
            f"\"indenter.stiffness_ratio\" = {_list(k)}\n"
            f"\"indenter.roughness.sigma\" = {_list(s * D_C for s in sigma)}\n"
            f"\"protocol.preload_force\" = {_list(p * F_C for p in preload)}\n")
    (SWEEPS / name).write_text(text, encoding="utf-8")


def column_set(k: float) -> str:
    """The name of Table 1's sampled set of column k~ (``k0p55`` for 0.55)."""
    return "k" + f"{k:g}".replace(".", "p")


def main() -> None:
    common = ("# N = 256 and 16 x 16 pillars of radius 0.0141047 (16 elements per pitch, radius 3.6 elements, phi = 0.16)\n"
              "# are chapter 5's one identification (docs/reproduction/make_count_sweeps.py); F_c = 0.00849802 and\n"
              "# d_c = 0.00753117 (eq. 5.3-5.4) depend on A0 and phi only.  Units E* = 1, dgamma = 1e-4, L = 1.\n")
    plateau = [(k, s, p) for k, s in PLATEAUS for p in PLATEAU_PRELOADS]
    _write("rough_brush.count.toml",
           "# Chapter 5's pillar-count identification at 16 x 16 pillars: the plateau rows (F~_P = 10 and 20),\n"
           "# the exact event path.\n" + common, BASE_16 % EVENTS, 3, plateau)
    _write("rough_brush.count_rough.toml",
           "# The stiff rough plateau at 16 x 16 pillars (k~ = 1, sigma~ = 2.1, F~_P = 20: 'almost vanishes'), one\n"
           "# realisation (the seed of rough_brush.count.toml's first), the exact event path.\n" + common,
           BASE_16 % EVENTS, 1, [(*ROUGH_PLATEAU, p) for p in PLATEAU_PRELOADS])
    table = [(k, s, READING_PRELOAD) for k in COLUMNS for s in SIGMAS]
    _write("rough_brush.table1.toml",
           "# Table 1 at 16 x 16 pillars: c = F~_A / F~_P read at F~_P = 0.1 for every column and roughness\n"
           "# (the reading rule, declared before computing), the pillar-level model (docs/pillars/validation.md).\n"
           + common, BASE_16 % PILLARS, 10, table)
    for k in COLUMNS:  # one sampled set per column: a sweep runs seed by seed, a set finishes a column
        _write(f"rough_brush.table1.{column_set(k)}.sampled.toml",
               f"# Table 1's column k~ = {k:g} of rough_brush.table1.toml (same base, seeds and case hashes): a\n"
               "# named sampled set, so that a column reaches its ten seeds before the next begins.\n" + common,
               BASE_16 % PILLARS, 10, [(k, s, READING_PRELOAD) for s in SIGMAS])
    events = [(k, s, READING_PRELOAD) for k in (10.0, 0.001) for s in SIGMAS]
    _write("rough_brush.table1_events.toml",
           "# The pillar-level model's error on Table 1's cases: k~ = 10 and 0.001 over the thirteen roughnesses,\n"
           "# F~_P = 0.1, the exact event path, the first realisation of rough_brush.table1.toml's seeds.\n"
           + common, BASE_16 % EVENTS, 1, events)
    _write("rough_brush.preload16.toml",
           "# Fig. 5-3 and 5-4 at chapter 5's identification (16 x 16 pillars): F~_A against the preload, F~_P = 0.1,\n"
           "# 0.3, 1, 3, 10 and 20, for the stiff (k~ = 10, Fig. 5-3) and the softest (k~ = 0.001, Fig. 5-4 d) brush at\n"
           "# sigma~ = 0.07, 0.5 and 2.1, two realisations: the rows L885-887 (linear, then a plateau, for every\n"
           "# roughness) and L905 (the softer brush reaches its plateau at a smaller preload).  The preloads and\n"
           "# roughnesses sampled are ours (the thesis shows curves, Fig. 5-3 and 5-4, and states no points); the\n"
           "# pillar-level model (docs/pillars/validation.md; within about 1 % of the event path on Table 1's cases,\n"
           "# part table1_events).\n" + common, BASE_16 % PILLARS, 2,
           [(k, s, p) for k in CURVE_STIFFNESSES for s in CURVE_SIGMAS for p in CURVE_PRELOADS])
    quick = "# Quick check (4 x 4 pillars, N = 64): tests the machinery, not the thesis's numbers.\n"
    _write("rough_brush.count.quick.toml", quick, BASE_QUICK % EVENTS, 2,
           [(k, s, p) for k, s in PLATEAUS[:3] for p in PLATEAU_PRELOADS])
    _write("rough_brush.count_rough.quick.toml", quick, BASE_QUICK % EVENTS, 1,
           [(*ROUGH_PLATEAU, p) for p in PLATEAU_PRELOADS])
    _write("rough_brush.table1.quick.toml", quick, BASE_QUICK % PILLARS, 2,
           [(k, s, READING_PRELOAD) for k in (10.0, 0.001) for s in (0.01, 0.07, 0.5, 2.1, 3.0)])
    _write("rough_brush.table1_events.quick.toml", quick, BASE_QUICK % EVENTS, 1,
           [(k, s, READING_PRELOAD) for k in (10.0, 0.001) for s in (0.01, 2.1)])
    _write("rough_brush.preload16.quick.toml", quick, BASE_QUICK % PILLARS, 1,
           [(k, 0.07, p) for k in CURVE_STIFFNESSES for p in (0.1, 20.0)])


if __name__ == "__main__":
    main()
