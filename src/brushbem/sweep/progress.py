"""Progress of a running sweep on stderr: a rich bar on a terminal, else plain lines (`_Reporter`)."""

from __future__ import annotations

import time
from collections import Counter
from typing import TYPE_CHECKING, Any, Self

if TYPE_CHECKING:
    from rich.console import Console

    from brushbem.sweep.spec import SweepCase

#: Seconds between plain progress lines when stderr is not a terminal.
LOG_INTERVAL_S = 30.0


class _Reporter:
    """Progress on stderr: a rich bar with ETA on a terminal, else a plain line every `LOG_INTERVAL_S`."""

    def __init__(self, total: int, skipped: int, enabled: bool, console: Console | None) -> None:
        from rich.console import Console

        self.total, self.skipped, self.enabled = total, skipped, enabled
        self.console = console or Console(stderr=True)
        self.counts: Counter[str] = Counter()
        self.start = time.monotonic()
        self.next_line = self.start + LOG_INTERVAL_S
        self.bar: Any = None

    def __enter__(self) -> Self:
        if self.enabled and self.skipped:
            self.console.print(f"sweep: {self.skipped} cases already recorded, {self.total} to compute")
        # Nothing to compute: no bar and no progress lines.
        self.enabled = self.enabled and self.total > 0
        if not self.enabled:
            return self
        if self.console.is_terminal:
            from rich.progress import (
                BarColumn,
                MofNCompleteColumn,
                Progress,
                TextColumn,
                TimeElapsedColumn,
                TimeRemainingColumn,
            )

            self.bar = Progress(
                TextColumn("sweep"), BarColumn(), MofNCompleteColumn(),
                TextColumn("{task.fields[counts]}"), TimeElapsedColumn(),
                TextColumn("eta"), TimeRemainingColumn(),
                console=self.console,
            )
            self.bar.start()
            self.task = self.bar.add_task("sweep", total=self.total, counts="")
        else:
            self._line()
        return self

    def __exit__(self, *exc: object) -> None:
        if self.bar is not None:
            self.bar.stop()
        elif self.enabled:
            self._line()

    def _counts(self) -> str:
        return ", ".join(f"{n} {status}" for status, n in sorted(self.counts.items()))

    def _line(self) -> None:
        done = sum(self.counts.values())
        elapsed = time.monotonic() - self.start
        eta = f", eta {elapsed / done * (self.total - done):.0f} s" if done and done < self.total else ""
        counts = f" ({self._counts()})" if self.counts else ""
        self.console.print(f"sweep: {done}/{self.total} computed{counts}, {elapsed:.0f} s{eta}",
                           highlight=False, soft_wrap=True)
        self.next_line = time.monotonic() + LOG_INTERVAL_S

    def timeout(self) -> float | None:
        """How long the driver may block before the next plain line is due."""
        if not self.enabled or self.bar is not None:
            return None
        return max(0.0, self.next_line - time.monotonic())

    def record(self, case: SweepCase, status: str, reason: str) -> None:
        self.counts[status] += 1
        if not self.enabled:
            return
        if status != "finished":
            self.console.print(f"case {case.case_id} {status}: {reason}", highlight=False, soft_wrap=True)
        if self.bar is not None:
            self.bar.update(self.task, advance=1, counts=self._counts())

    def tick(self) -> None:
        if self.enabled and self.bar is None and time.monotonic() >= self.next_line:
            self._line()
