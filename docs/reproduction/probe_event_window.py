"""How much the event window (`protocol.event_window`, `brushbem.protocol.problem.event_tie`) moves F_A.

Events closer than event_window x h along the path are taken together.  On the validation families,
small grids (a Kendall punch, a JKR sphere, a punch on a spring, the 4 x 4 brush of k~ = 0.1 by the
event path and by the pillar model, a rough 4 x 4 brush by the event path) each window's F_A against
the tight window 1e-12, and with a loose CG (solver.tolerance = 1e-3) at the default window.
Prints a Markdown table; run from the repository root:
``python docs/reproduction/probe_event_window.py`` (about 1 CPU-min).
"""

from __future__ import annotations

import copy

from brushbem.runs.assembly import parse_config
from brushbem.runs.case import run_case

BRUSH = {"shape": "brush", "layout": "square", "region": "square", "pillars_per_side": 4,
         "pillar_radius": 0.056, "stiffness_ratio": 0.1}
FAMILIES = {
    "Kendall punch, N = 64": ({"shape": "flat_punch", "radius": 0.25}, "events", 0.01),
    "JKR sphere, N = 64": ({"shape": "sphere", "radius": 0.5}, "events", 0.01),
    "punch on a spring k~ = 0.5 (eq. 2.17), N = 64": ({"shape": "flat_punch", "radius": 0.25, "stiffness": 0.25},
                                          "events", 0.01),
    "4 x 4 brush k~ = 0.1, events": (BRUSH, "events", 0.002),
    "4 x 4 brush k~ = 0.1, pillar model": (BRUSH, "pillars", 0.002),
    "rough 4 x 4 brush, events": ({**BRUSH, "roughness": {"sigma": 0.5}, "seed": 3}, "events", 0.004),
}
WINDOWS = (1e-12, 1e-9, 1e-7, 1e-5, 1e-3)


def adhesive_force(indenter, method, preload, window, tolerance=1e-8):
    config = parse_config({
        "halfspace": {"contact_modulus": 1.0, "work_of_adhesion": 1e-4},
        "grid": {"size": 1.0, "elements": 64},
        "indenter": copy.deepcopy(indenter),
        "protocol": {"method": method, "preload_displacement": preload, "event_window": window,
                     "pillar_tip_peel": False},
        **({"solver": {"tolerance": tolerance}} if method != "pillars" else {}),
    })
    summary = run_case(config).result.summary
    assert summary["converged"], summary["reason"]
    return summary["adhesive_force"], summary["n_states"]


print("| family | " + " | ".join(f"window {w:g}" for w in WINDOWS[1:]) + " | tolerance 1e-3 |")
print("| --- |" + " --- |" * len(WINDOWS))
for name, (indenter, method, preload) in FAMILIES.items():
    tight, _ = adhesive_force(indenter, method, preload, WINDOWS[0])
    cells = [f"{adhesive_force(indenter, method, preload, w)[0] / tight - 1:+.1e}" for w in WINDOWS[1:]]
    loose = ("not used" if method == "pillars"
             else f"{adhesive_force(indenter, method, preload, 1e-7, tolerance=1e-3)[0] / tight - 1:+.1e}")
    print(f"| {name} | " + " | ".join(cells) + f" | {loose} |", flush=True)
