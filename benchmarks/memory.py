"""Peak memory of ``brushbem run`` against `brushbem.config.resources.memory_estimate`.

Each case is one ``brushbem run`` in a fresh process; its peak resident set
size is the ``ru_maxrss`` that ``os.wait4`` reports for that process alone
(the interpreter, the imports, the numerics, writing result.nc and the
figure).  Cases: a rigid flat punch (radius L/4), a sphere on a spring (the
``sphere_spring`` example) and the default 16 x 16 brush, at every
``--elements``.  Each is pressed and retracted by a few fixed steps: the
arrays, and so the peak, are those of the exact path, which takes minutes
per case from N = 1024 on.  Prints one row per case: N, shape, the estimate, the
measured peak, their ratio, the estimated and the written result.nc size,
and the run's seconds.

    python benchmarks/memory.py --elements 1024 2048
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from brushbem.runs.assembly import parse_config
from brushbem.config.resources import format_bytes, memory_estimate, result_size_estimate

HALFSPACE = {"contact_modulus": 1.0, "work_of_adhesion": 1e-3}

CASES = {
    "punch": {
        "halfspace": HALFSPACE,
        "indenter": {"shape": "flat_punch", "radius": 0.25},
        "protocol": {"method": "fixed", "preload_displacement": 0.01, "step": 0.005},
    },
    "sphere": {
        "halfspace": HALFSPACE,
        "indenter": {"shape": "sphere", "radius": 1.0, "stiffness": 0.5},
        "protocol": {"method": "fixed", "preload_displacement": 0.03, "step": 0.005},
    },
    "brush": {
        "halfspace": {"contact_modulus": 1.0, "work_of_adhesion": 1e-4},
        "indenter": {
            "shape": "brush", "layout": "square", "pillars_per_side": 16,
            "pillar_radius": 0.0122, "stiffness_ratio": 0.455, "seed": 1,
        },
        "protocol": {"method": "fixed", "preload_displacement": 0.002, "step": 0.001},
    },
}


def _toml(document: dict) -> str:
    lines = []
    for section, table in document.items():
        lines.append(f"[{section}]")
        for key, value in table.items():
            lines.append(f"{key} = {value!r}".replace("'", '"'))
    return "\n".join(lines) + "\n"


def measure(shape: str, elements: int, folder: Path) -> dict:
    """Run one case in a fresh process; its peak RSS, result.nc size and seconds."""
    document = {**CASES[shape], "grid": {"size": 1.0, "elements": elements}}
    config_file = folder / f"{shape}_{elements}.toml"
    config_file.write_text(_toml(document))
    out = folder / f"{shape}_{elements}"
    start = time.perf_counter()
    process = subprocess.Popen(
        [sys.executable, "-m", "brushbem", "run", str(config_file), "--out", str(out), "--quiet"],
        stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
    )
    _, status, usage = os.wait4(process.pid, 0)
    seconds = time.perf_counter() - start
    process.returncode = os.waitstatus_to_exitcode(status)
    stderr = process.stderr.read().decode(errors="replace") if process.stderr else ""
    if process.returncode not in (0, 3):
        raise RuntimeError(f"{shape} N = {elements}: exit {process.returncode}\n{stderr}")
    config = parse_config(document)
    result = out / "result.nc"
    return {
        "elements": elements,
        "shape": shape,
        "estimate": memory_estimate(config),
        "peak": usage.ru_maxrss * 1024,  # kilobytes on Linux
        "result_estimate": result_size_estimate(config),
        "result": result.stat().st_size if result.exists() else 0,
        "seconds": seconds,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--elements", type=int, nargs="+", default=[512, 1024, 2048])
    parser.add_argument("--shapes", nargs="+", default=list(CASES), choices=list(CASES))
    args = parser.parse_args()
    print("| N | shape | estimate | measured peak | estimate / peak | result.nc estimate | result.nc | seconds |")
    print("| ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: |")
    with tempfile.TemporaryDirectory() as folder:
        for elements in args.elements:
            for shape in args.shapes:
                row = measure(shape, elements, Path(folder))
                print(
                    f"| {row['elements']} | {row['shape']} | {format_bytes(row['estimate'])} | "
                    f"{format_bytes(row['peak'])} | {row['estimate'] / row['peak']:.2f} | "
                    f"{format_bytes(row['result_estimate'])} | {format_bytes(row['result'])} | "
                    f"{row['seconds']:.0f} |",
                    flush=True,
                )


if __name__ == "__main__":
    main()
