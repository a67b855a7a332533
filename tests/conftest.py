"""Shared test helpers."""

from __future__ import annotations

import concurrent.futures
import os
import signal

import pytest
from hypothesis import settings

# Property tests check answers, not speed: on a shared machine one example can
# take ten times its usual time, so no example has a deadline (speed is measured
# in benchmarks/, never in unit tests).
settings.register_profile("brushbem", deadline=None)
settings.load_profile("brushbem")

from brushbem.studies import STUDIES, sweep_file
from brushbem.sweep import load_summary, run_sweep


def pytest_configure(config):
    """A pytest-xdist worker may start with SIGINT ignored, and its children would inherit that.

    The interrupted-run tests send SIGINT to a ``brushbem`` child process and
    expect its handler to run; Python installs that handler only where SIGINT
    is not ignored when it starts.  A worker therefore takes back the default.
    """
    if os.environ.get("PYTEST_XDIST_WORKER") and signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
        signal.signal(signal.SIGINT, signal.default_int_handler)


def run_quick_study(name, tmp_path_factory):
    """Run every part of a study's quick sweep (one thread) and draw its figures.

    Returns (study, results by part, written figure paths).  Every part must
    ship both its full and its quick sweep file.  The figures are written as
    PNG only (`brushbem.figures.figstyle.raster_only`): the PDF beside each
    is tested in tests/test_figures.py, and it is 40 % of the drawing's time.
    """
    from brushbem.figures import figstyle

    study = STUDIES[name]
    out = tmp_path_factory.mktemp(name)
    results = {}
    for part in study.parts:
        path = sweep_file(name, part, quick=True)
        assert path.exists() and sweep_file(name, part, quick=False).exists()
        run_sweep(path, out / part, executor=concurrent.futures.ThreadPoolExecutor(1))
        results[part] = load_summary(out / part)
    with figstyle.raster_only():
        return study, results, study.draw(results, out / "figures")


@pytest.fixture
def switches():
    """``switches(name=value, ...)`` sets `brushbem.settings.Switches` for the rest of the test (`settings.using`)."""
    import contextlib

    from brushbem import settings

    with contextlib.ExitStack() as stack:
        yield lambda **changes: stack.enter_context(settings.using(**changes))
