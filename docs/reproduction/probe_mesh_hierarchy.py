"""Chapter 6: one case (seed 0) of each level at N = 1024 (the sweep's) and 2048.

The shipped sweeps resolve a pillar radius by 2.25 elements; this measures
what halving the element size does, per level named, at the plateau case
(sigma~ = 0.04, F~_P = 20) or, with ``--small-preload``, at Fig. 6-4 e's
small-preload case (sigma~ = 1.6, F~_P = 1; N = 2048 only, its N = 1024 value is the
table's, `docs/reproduction/hierarchy/`):

    python docs/reproduction/probe_mesh_hierarchy.py one three
    python docs/reproduction/probe_mesh_hierarchy.py --small-preload one two three
"""

import sys
import time

import brushbem
from brushbem.studies import SWEEPS_DIR
from brushbem.sweep import load_sweep

F_C = 0.00331177  # nominal (the sweeps' header)
small = "--small-preload" in sys.argv
preload, kind = (F_C, "small_preload.sampled") if small else (0.0662355, "sampled")
for part in [arg for arg in sys.argv[1:] if not arg.startswith("--")]:
    case = next(c for c in load_sweep(SWEEPS_DIR / f"hierarchy.{part}.{kind}.toml").cases if c.realization == 0
                and abs(c.values["protocol.preload_force"] - preload) < 1e-9)
    config = case.config.model_dump(mode="json", exclude_unset=True)
    for n in (2048,) if small else (1024, 2048):
        config["grid"]["elements"] = n
        t = time.perf_counter(); r = brushbem.run(config)
        print(part, 'N', n, 'F_A/F_c(nominal)', round(r.adhesive_force / F_C, 5), 'F~_A(rasterised)',
              round(r.summary['normalized']['force_by_rigid_brush'], 5), 'converged', r.converged,
              round(time.perf_counter() - t), 's', flush=True)
