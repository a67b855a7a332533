"""Any benchmark script under an older commit and under the working tree, in turns, in one run.

For every script (with its arguments) it runs ``old`` (the script and the
package's ``src`` at ``--baseline``, from ``git archive``: the script as it
was, for the layout it was written for) and ``new`` (the working tree)
alternately for ``--rounds`` rounds, each a fresh process, and measures the
CPU time of the whole process (its user + system time, children included):
imports, set-up and the script's own repeats.  It prints one JSON line per
run and then per script the medians and their ratio ``old / new`` (> 1: the
working tree is faster).  Alternating rounds make a busy machine slow both
alike; read the ratio, not the seconds.

    nice python benchmarks/ab.py --baseline bda345c --rounds 3 \\
        "benchmarks/hertz.py --elements 256" "benchmarks/jkr.py --elements 256 --method events"
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import shlex
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _checkout(revision: str, into: Path) -> Path:
    """``src`` and ``benchmarks`` at ``revision``, extracted under ``into``."""
    archive = subprocess.run(["git", "-C", str(ROOT), "archive", revision, "src", "benchmarks"], check=True,
                             capture_output=True)
    subprocess.run(["tar", "-x", "-C", str(into)], input=archive.stdout, check=True)
    return into


def _cpu_of(command: list[str], root: Path) -> float:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(p for p in (str(root / "src"), os.environ.get("PYTHONPATH")) if p)
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run(command, env=env, check=True, cwd=root, stdout=subprocess.DEVNULL)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scripts", nargs="+", help='a script and its arguments, quoted: "benchmarks/hertz.py --elements 256"')
    parser.add_argument("--baseline", required=True, help="the older commit")
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as scratch:
        sources = {"old": _checkout(args.baseline, Path(scratch)), "new": ROOT}
        for script in args.scripts:
            command = [sys.executable, *shlex.split(script)]
            cpu: dict[str, list[float]] = {"old": [], "new": []}
            for round_ in range(args.rounds):
                for name, source in sources.items():
                    cpu[name].append(_cpu_of(command, source))
                    print(json.dumps({"script": script, "round": round_, "variant": name, "cpu": round(cpu[name][-1], 3)}),
                          flush=True)
            old, new = statistics.median(cpu["old"]), statistics.median(cpu["new"])
            print(json.dumps({"script": script, "baseline": args.baseline, "rounds": args.rounds,
                              "old_cpu_median": round(old, 2), "new_cpu_median": round(new, 2),
                              "old_over_new": round(old / new, 3)}), flush=True)


if __name__ == "__main__":
    main()
