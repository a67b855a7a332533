"""Record the reference outputs that a refactor must leave unchanged: ``python tests/references/record.py``.

Writes ``tests/references/references.json``: the summary and the pull-off
curve of the default example and of the Kendall punch, the punch on a
spring, the JKR sphere on a spring and a small brush; and the tables of three
studies at their quick grids.  ``tests/test_references.py`` runs the same
cases with the code of the working tree and compares (1e-12, relative).
Rerun it only on purpose: when a change of the numbers is intended and
explained in its commit.
"""

from __future__ import annotations

import json
import math
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
OUT = HERE / "references.json"

#: The pull-off cases: name -> configuration (a mapping, as `brushbem.run` takes it).
CASES: dict[str, dict] = {
    "kendall_punch": {
        "halfspace": {"contact_modulus": 1.0, "work_of_adhesion": 1e-4},
        "grid": {"size": 1.0, "elements": 64},
        "indenter": {"shape": "flat_punch", "radius": 0.25, "stiffness": "inf"},
        "protocol": {"method": "events", "preload_displacement": 1e-3},
    },
    "punch_on_spring": {
        "halfspace": {"contact_modulus": 1.0, "work_of_adhesion": 1e-4},
        "grid": {"size": 1.0, "elements": 64},
        "indenter": {"shape": "flat_punch", "radius": 0.25, "stiffness": 0.1},
        "protocol": {"method": "events", "preload_displacement": 1e-3},
    },
    "jkr_sphere_on_spring": {
        "halfspace": {"contact_modulus": 1.0, "work_of_adhesion": 1e-3},
        "grid": {"size": 1.0, "elements": 64},
        "indenter": {"shape": "sphere", "radius": 1.0, "stiffness": 0.5},
        "protocol": {"method": "events", "preload_displacement": 0.02},
    },
    "brush_8x8": {
        "halfspace": {"contact_modulus": 1.0, "work_of_adhesion": 1e-4},
        "grid": {"size": 1.0, "elements": 128},
        "indenter": {"shape": "brush", "layout": "square", "region": "square", "pillars_per_side": 8,
                     "pillar_radius": 0.025, "stiffness_ratio": 0.05, "roughness": {"sigma": 2e-4}, "seed": 3},
        "protocol": {"method": "events", "preload_displacement": 1e-3},
    },
}

#: The studies (name, parts) whose quick tables are recorded.
STUDIES = (("punch_spring", None), ("sphere_spring", None), ("flat_brush", "regular"))


#: Columns of a study table that are not results (timings, memory): not compared.
UNRECORDED = ("time", "seconds", "memory", "rss")


def _floats(values) -> list[float]:
    return [float(v) for v in values]


def run_case(config: dict) -> dict:
    """Summary numbers and the curve of one pull-off, JSON-ready."""
    import brushbem

    result = brushbem.run(config)
    summary = result.summary
    return {
        "adhesive_force": float(result.adhesive_force),
        "work_of_separation": float(result.work_of_separation),
        "pull_off_displacement": float(result.pull_off_displacement),
        "n_solves": int(summary["n_solves"]),
        "displacement": _floats(result.curve.displacement),
        "force": _floats(result.curve.force),
    }


def run_default() -> dict:
    from importlib.resources import files

    return run_case(str(files("brushbem.examples") / "default.toml"))


def run_study(name: str, parts: str | None) -> dict[str, dict[str, list]]:
    """The numeric columns of every part's summary table of ``brushbem study NAME --quick``."""
    import pandas as pd
    from click.testing import CliRunner

    from brushbem.cli import main

    with tempfile.TemporaryDirectory() as scratch:
        out = Path(scratch) / name
        args = ["study", name, "--quick", "--out", str(out)] + ([] if parts is None else ["--parts", parts])
        done = CliRunner().invoke(main, args, catch_exceptions=False)
        if done.exit_code != 0:
            raise SystemExit(f"study {name}: exit {done.exit_code}\n{done.output}")
        tables = {}
        for table in sorted(out.glob("*/summary.parquet")):
            frame = pd.read_parquet(table)
            frame = frame.sort_values(list(frame.columns[:1])).reset_index(drop=True) if "case" not in frame else \
                frame.sort_values("case").reset_index(drop=True)
            numeric = frame.select_dtypes("number")
            numeric = numeric[[c for c in numeric.columns if not any(w in c for w in UNRECORDED)]]
            tables[table.parent.name] = {
                column: [None if isinstance(v, float) and math.isnan(v) else float(v) for v in numeric[column]]
                for column in numeric.columns
            }
        return tables


def main() -> None:
    record = {"cases": {name: run_case(config) for name, config in CASES.items()}}
    record["cases"]["default_example"] = run_default()
    record["studies"] = {name: run_study(name, parts) for name, parts in STUDIES}
    OUT.write_text(json.dumps(record, indent=1) + "\n", encoding="utf-8")
    print(f"wrote {OUT}", file=sys.stderr)


if __name__ == "__main__":
    main()
