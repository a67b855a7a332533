"""Shared test helpers."""

from __future__ import annotations

import concurrent.futures

from brushbem.studies import STUDIES, sweep_file
from brushbem.sweep import load_summary, run_sweep


def run_quick_study(name, tmp_path_factory):
    """Run every part of a study's quick sweep (one thread) and draw its figures.

    Returns (study, results by part, written figure paths).  Every part must
    ship both its full and its quick sweep file.
    """
    study = STUDIES[name]
    out = tmp_path_factory.mktemp(name)
    results = {}
    for part in study.parts:
        path = sweep_file(name, part, quick=True)
        assert path.exists() and sweep_file(name, part, quick=False).exists()
        run_sweep(path, out / part, executor=concurrent.futures.ThreadPoolExecutor(1))
        results[part] = load_summary(out / part)
    return study, results, study.draw(results, out / "figures")
