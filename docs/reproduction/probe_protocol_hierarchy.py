"""Chapter 6, Fig. 6-4 e: the small-preload case (sigma~ = 1.6, F~_P = 1, seed 0) of each level on the
fixed-step protocol (ours: the thesis states no step) against the exact event path.

The sweeps run the exact event path; the thesis pulls off by an 'incremental displacement' (L648)
and states no step, so the fixed step here is ours (``protocol.step`` of the sweep, about d_c / 5
scaled by the pillars' compliance).  This
measures F~_A at the fixed step and at half of it, per level named (the exact path's is in the
tables, `docs/reproduction/hierarchy/`):

    python docs/reproduction/probe_protocol_hierarchy.py one two three
"""

import sys
import time

import brushbem
from brushbem.studies import SWEEPS_DIR
from brushbem.sweep import load_sweep

PRELOAD = 0.00331177  # F~_P = 1 by the nominal F_c (the sweeps' header)
for part in sys.argv[1:]:
    case = next(c for c in load_sweep(SWEEPS_DIR / f"hierarchy.{part}.small_preload.sampled.toml").cases
                if c.realization == 0 and abs(c.values["protocol.preload_force"] - PRELOAD) < 1e-9)
    config = case.config.model_dump(mode="json", exclude_unset=True)
    step = config["protocol"]["step"]
    for method, scale in (("fixed", 1), ("fixed", 0.5)):
        config["protocol"].update(method=method, step=step * scale)
        t = time.perf_counter()
        r = brushbem.run(config)
        print(part, method, "step", "-" if method == "events" else f"{scale} x {step:.4g}",
              "F~_A(rasterised)", round(r.summary["normalized"]["force_by_rigid_brush"], 5),
              "converged", r.converged, round(time.perf_counter() - t), "s", flush=True)
