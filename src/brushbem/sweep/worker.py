"""What runs in a worker process.

`compute_case` runs one case and returns a `CaseOutcome` (plain data, so
it pickles to any executor; an exception of the case becomes a ``failed``
outcome), and `_watch_driver`, the initializer of a local worker, ends the
worker when its driver is gone.
"""

from __future__ import annotations

import dataclasses
import os
import threading
import time
import traceback
from pathlib import Path
from typing import TYPE_CHECKING, Literal

from brushbem.config import RunConfig

if TYPE_CHECKING:
    from brushbem.results import CaseResult

#: Seconds between two checks of a local worker that its driver is alive.
WATCH_INTERVAL_S = 0.5

#: Statuses of a case: ``finished`` (converged), ``unconverged`` (the run ended
#: but some solve did not converge), ``failed`` (it raised), ``missing`` (no
#: case file yet) and ``corrupt`` (a case file that cannot be read as a
#: result); the last two only in summaries.
Status = Literal["finished", "unconverged", "failed", "missing", "corrupt"]
_RECORDED = ("finished", "unconverged", "failed")


@dataclasses.dataclass(frozen=True)
class CaseOutcome:
    """What a worker returns for one case (plain data, so it pickles to any executor).

    Attributes
    ----------
    status : {"finished", "unconverged", "failed"}
    reason : str
        The run's own reason for ending, or the exception of a failed case.
    wall_time_s : float
        Wall time of the case in the worker, building the problem included.
    result : CaseResult or None
        None for a failed case.
    traceback : str
        The traceback of a failed case, else empty.
    """

    status: Status
    reason: str
    wall_time_s: float
    result: CaseResult | None = None
    traceback: str = ""


def compute_case(config: RunConfig, refine: int | None = None) -> CaseOutcome:
    """Run one case in a worker (on ``refine`` grids, if given); any exception becomes a ``failed`` outcome.

    Catching here, not in the driver, keeps one bad case from taking down its
    neighbours, and turns the exception into text: an exception object may not
    unpickle in the driver.
    """
    # `run` runs `brushbem.runs.case.run_case`, looked up at call time: tests patch it.
    from brushbem.api import run

    start = time.perf_counter()
    try:
        result = run(config, refine=refine).result
    except Exception as exc:  # noqa: BLE001 - reported, not raised
        return CaseOutcome(
            status="failed",
            reason=f"{type(exc).__name__}: {exc}",
            wall_time_s=time.perf_counter() - start,
            traceback=traceback.format_exc(),
        )
    converged = bool(result.summary.get("converged", False))
    return CaseOutcome(
        status="finished" if converged else "unconverged",
        reason=str(result.summary.get("reason", "")),
        wall_time_s=time.perf_counter() - start,
        result=result,
    )


def _start_time(pid: int) -> str | None:
    """The start time of process ``pid`` (Linux ``/proc``); "" if it is gone or a zombie, None if unknown."""
    try:
        text = Path(f"/proc/{pid}/stat").read_text()
    except FileNotFoundError:
        return "" if Path("/proc/self/stat").exists() else None
    except OSError:
        return None
    fields = text[text.rfind(")") + 2:].split()  # after the command name, which may hold spaces
    return "" if fields[0] in "ZX" else fields[19]


def _driver_alive(pid: int, started: str | None) -> bool:
    """Whether the driver ``pid`` (started at ``started``, if known) still runs."""
    now = _start_time(pid)
    if now is not None:
        return now != "" and (started is None or now == started)
    try:  # no /proc: a signal 0 finds the process, if not yet reaped
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:
        return True
    return True


def _watch_driver(pid: int, started: str | None) -> None:
    """Initializer of a local worker: exit as soon as the driving process ``pid`` is gone.

    A worker's parent is the fork server, which outlives a driver killed
    with SIGKILL; without the watch its workers would compute on, orphaned.
    A daemon thread checks every `WATCH_INTERVAL_S` (a process id taken over
    by a new process is told apart by its start time, where ``/proc`` gives it).
    """
    def watch() -> None:
        while _driver_alive(pid, started):
            time.sleep(WATCH_INTERVAL_S)
        os._exit(1)  # nothing to report to: end at once, mid-computation too

    threading.Thread(target=watch, name="brushbem-driver-watch", daemon=True).start()
