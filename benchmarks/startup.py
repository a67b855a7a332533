"""Start-up of the command line: `brushbem --help` and `brushbem --version`, median of repeated runs.

Printed beside the bare interpreter's start-up (`python -c pass`) measured in the same run, so the
ratio, not the machine's speed, is the number to compare.  Run: ``python benchmarks/startup.py``.
"""

from __future__ import annotations

import shutil
import statistics
import subprocess
import sys
import time

REPEATS = 5


def median_seconds(command: list[str]) -> float:
    times = []
    for _ in range(REPEATS):
        start = time.perf_counter()
        subprocess.run(command, check=True, stdout=subprocess.DEVNULL)
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def main() -> None:
    script = shutil.which("brushbem") or str(__import__("pathlib").Path(sys.executable).with_name("brushbem"))
    baseline = median_seconds([sys.executable, "-c", "pass"])
    print(f"python -c pass: {baseline:.3f} s (median of {REPEATS})")
    for args in (["--help"], ["--version"]):
        seconds = median_seconds([script, *args])
        print(f"brushbem {' '.join(args)}: {seconds:.3f} s, {seconds / baseline:.1f} x the bare interpreter")


if __name__ == "__main__":
    main()
