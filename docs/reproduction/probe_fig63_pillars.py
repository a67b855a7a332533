"""The pillar-level model against the exact path on chapter 6's clustered brushes (parts ``fig63_*``).

The parts ``fig63_*`` run ``method = "pillars"`` (`brushbem.pillars`).  This probe reruns, with that
model, cases that the exact path has in the committed tables ``docs/reproduction/hierarchy/clustered_*.csv``
(the clustered layout of Fig. 6-3 at N = 1024, 2.25 elements a radius, sigma~ = 0.04, F~_P = 14.3, the same
seeds), and prints F_A of both, their ratio and the CPU seconds of the model (the tables' ``wall_time_s``
is the exact path's, on a shared core).  Output: ``probe_fig63_pillars.json`` beside this file.

    python docs/reproduction/probe_fig63_pillars.py [SEEDS] [LEVELS]   # default: 2 seeds, one,two,three

The committed output holds ``python docs/reproduction/probe_fig63_pillars.py 1`` (16-20 CPU-s a case).
"""

from __future__ import annotations

import json
import math
import sys
import time
import tomllib
from pathlib import Path

import pandas as pd

import brushbem
from brushbem.io import atomic_path

HERE = Path(__file__).resolve().parent
SWEEPS = HERE.parents[1] / "src" / "brushbem" / "studies" / "sweeps"


def main() -> None:
    seeds = int(sys.argv[1]) if len(sys.argv) > 1 else 2
    levels = sys.argv[2].split(",") if len(sys.argv) > 2 else ["one", "two", "three"]
    out = HERE / "probe_fig63_pillars.json"
    found = json.loads(out.read_text()) if out.is_file() else []
    done = {(r["level"], r["seed"]) for r in found}
    for level in levels:
        table = pd.read_csv(HERE / "hierarchy" / f"clustered_{level}.csv")
        spec = tomllib.loads((SWEEPS / f"hierarchy.clustered_{level}.sampled.toml").read_text(encoding="utf-8"))
        for _, row in table[table["status"] == "finished"].sort_values("realization").head(seeds).iterrows():
            if (level, int(row["seed"])) in done:
                continue
            config = json.loads(json.dumps(spec["base"]))
            config["indenter"]["seed"] = int(row["seed"])
            config["indenter"]["roughness"] = {"sigma": float(row["indenter.roughness.sigma"])}
            config["protocol"]["preload_force"] = float(row["protocol.preload_force"])
            config["protocol"]["method"] = "pillars"
            config["protocol"]["pillar_tip_peel"] = False  # the tips on their rasters, as recorded
            start = time.process_time()
            result = brushbem.run(config)
            seconds = time.process_time() - start
            exact = float(row["adhesive_force"])
            found.append({"level": level, "seed": int(row["seed"]), "elements": config["grid"]["elements"],
                          "exact_adhesive_force": exact, "pillars_adhesive_force": result.adhesive_force,
                          "ratio": result.adhesive_force / exact, "pillars_cpu_s": round(seconds, 1),
                          "exact_wall_s": round(float(row["wall_time_s"]), 1)})
            with atomic_path(out) as path:  # after each case: a stopped run resumes
                path.write_text(json.dumps(found, indent=1) + "\n")
            print(f"{level} seed {int(row['seed'])}: exact {exact:.6g}, pillars {result.adhesive_force:.6g} "
                  f"({100 * (result.adhesive_force / exact - 1):+.2f} %), {seconds:.0f} CPU-s", flush=True)
    worst = max((abs(r["ratio"] - 1) for r in found), default=math.nan)
    print(f"{len(found)} cases, largest deviation {100 * worst:.2f} %")


if __name__ == "__main__":
    main()
