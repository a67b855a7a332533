"""Cost before compute: the expected time of a whole sweep from a few of its cases.

``estimate_sweep(sweep, samples=3)`` runs ``samples`` cases of the sweep, one
after the other in this process, spread evenly over its expansion order (the
first and the last case and equally spaced ones between, so that every swept
axis is visited at its ends), and extrapolates: the expected CPU time of the
whole sweep is the number of cases times the mean sampled time, with the
standard error of that mean; the wall time on W workers is that over
min(W, cases) (a worker runs one case at a time, and the cases of one
sweep cost roughly alike except where a swept key changes the grid or the
brush, which the spread of the samples then shows).  Nothing is written.
"""

from __future__ import annotations

import math
import statistics
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from .sweep import Sweep, compute_case

__all__ = ["SweepEstimate", "estimate_sweep", "sample_indices"]


@dataclass(frozen=True)
class SweepEstimate:
    """The sampled cost of a sweep.

    Attributes
    ----------
    cases : int
        Cases of the whole sweep.
    sampled : tuple of str
        Case ids that were run.
    seconds : tuple of float
        Their wall times (each alone in this process), in seconds.
    statuses : tuple of str
        Their outcomes ("finished", "unconverged", "failed").
    """

    cases: int
    sampled: tuple[str, ...]
    seconds: tuple[float, ...]
    statuses: tuple[str, ...]

    @property
    def mean_seconds(self) -> float:
        return statistics.fmean(self.seconds) if self.seconds else 0.0

    @property
    def cpu_hours(self) -> float:
        """Expected time of the whole sweep on one worker, in hours."""
        return self.cases * self.mean_seconds / 3600.0

    @property
    def cpu_hours_error(self) -> float:
        """Standard error of ``cpu_hours`` from the spread of the samples (0 for one sample)."""
        if len(self.seconds) < 2:
            return 0.0
        return self.cases * statistics.stdev(self.seconds) / math.sqrt(len(self.seconds)) / 3600.0

    def wall_hours(self, workers: int) -> float:
        """Expected wall time on ``workers`` workers, in hours."""
        if workers < 1:
            raise ValueError(f"workers = {workers} must be >= 1")
        return self.cpu_hours / min(workers, max(self.cases, 1))


def sample_indices(cases: int, samples: int) -> list[int]:
    """``samples`` distinct case indices spread evenly from the first to the last case."""
    if cases <= 0:
        return []
    samples = max(1, min(samples, cases))
    return sorted({round(x) for x in np.linspace(0, cases - 1, samples)})


def estimate_sweep(
    sweep: Sweep,
    samples: int = 3,
    progress: Callable[[str], None] | None = None,
) -> SweepEstimate:
    """Run ``samples`` cases of ``sweep`` (spread over it) and return the estimate."""
    if samples < 1:
        raise ValueError(f"samples = {samples} must be >= 1")
    chosen = [sweep.cases[i] for i in sample_indices(len(sweep.cases), samples)]
    seconds, statuses = [], []
    for k, case in enumerate(chosen, 1):
        if progress is not None:
            progress(f"sample {k}/{len(chosen)}: case {case.case_id}")
        start = time.perf_counter()
        outcome = compute_case(case.config)
        seconds.append(time.perf_counter() - start)
        statuses.append(outcome.status)
    return SweepEstimate(
        cases=len(sweep.cases),
        sampled=tuple(case.case_id for case in chosen),
        seconds=tuple(seconds),
        statuses=tuple(statuses),
    )
