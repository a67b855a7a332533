"""Chapter 7 at its identified grid: the concave sweeps' points again on N = `GRID`.

Chapter 7's one identification (`brushbem.studies.concave`, the rule in the docstring of
``probe_concave_count.py``) picks 16 x 16 pillars on N = 320 (2.76 elements a pillar radius; the
thesis states neither count nor grid for chapter 7).  This script appends to each full concave sweep
(``concave.curves``, ``.amplification``, ``.stiffness``) its own points once more with
``grid.elements`` = `GRID`, after the recorded ones: the recorded points get ``grid.elements`` =
512, their base's value, so their configurations, indices and case ids are unchanged (the case hash
is over the resolved configuration).  It writes the appended points as the named sampled set
``concave.<part>.n320.sampled.toml`` (same base, seed and case hashes as the full sweep), which
runs with

    brushbem study concave --sampled-set n320 --parts stiffness --out out/concave_n320 --workers 1

A rerun leaves a sweep that already has ``grid.elements`` alone (the files are then up to date).

    python docs/reproduction/make_concave_grid.py
"""

from __future__ import annotations

import json
import tomllib
from pathlib import Path

from brushbem.studies import SWEEPS_DIR

#: The identified grid of chapter 7 and the grid of the recorded points (the sweeps' base).
GRID, RECORDED_GRID = 320, 512
SET = f"n{GRID}"
PARTS = ("curves", "amplification", "stiffness")


def _value(value) -> str:
    return json.dumps(value) if isinstance(value, str) else repr(value)


def _sweep_lines(sweep: dict[str, list]) -> list[str]:
    return ["[sweep]", *(f"{json.dumps(key)} = [{', '.join(_value(v) for v in values)}]"
                         for key, values in sweep.items())]


def write(part: str) -> None:
    path = SWEEPS_DIR / f"concave.{part}.toml"
    text = path.read_text(encoding="utf-8")
    spec = tomllib.loads(text)
    head = text[:text.index("[sweep]")].rstrip("\n").split("\n")
    comment = [line for line in head if line.startswith("#")]
    settings = [line for line in head if line and not line.startswith("#")]
    sweep = spec["sweep"]
    if "grid.elements" in sweep:
        return
    n = len(next(iter(sweep.values())))
    note = (f"# Added after those: every point again on N = {GRID}, chapter 7's identified grid "
            f"(docs/reproduction/make_concave_grid.py); the points before it are on N = {RECORDED_GRID}.")
    full = {key: values + values for key, values in sweep.items()}
    full["grid.elements"] = [RECORDED_GRID] * n + [GRID] * n
    path.write_text("\n".join([*comment, note, *settings, "", *_sweep_lines(full)]) + "\n", encoding="utf-8")
    sampled = {key: list(values) for key, values in sweep.items()}
    sampled["grid.elements"] = [GRID] * n
    header = [f"# Named set '{SET}' of concave.{part}.toml (docs/reproduction/make_concave_grid.py writes this file): "
              f"its {n} points on N = {GRID},", "# chapter 7's identified grid (16 x 16 pillars, 2.76 elements a "
              "pillar radius; the thesis states neither).", *comment[:1]]
    (SWEEPS_DIR / f"concave.{part}.{SET}.sampled.toml").write_text(
        "\n".join([*header, *settings, "", *_sweep_lines(sampled)]) + "\n", encoding="utf-8")


if __name__ == "__main__":
    for name in PARTS:
        write(name)
