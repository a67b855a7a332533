"""Where the cases of a sweep run.

The local process pool (`_process_pool`: forkserver workers that watch
their driver; `_stop_workers` ends them on an interruption), a
`dask.distributed` client (`dask_client`), the default number of workers,
and which failures of a case's future are the infrastructure's, a lost
worker or connection (`_is_lost`), not the case's.
"""

from __future__ import annotations

import contextlib
import multiprocessing
import os
import sys
import threading
from collections.abc import Iterator
from concurrent.futures import (
    BrokenExecutor,
    CancelledError,
    InvalidStateError,
    ProcessPoolExecutor,
)
from pathlib import Path
from typing import Any

from brushbem.sweep.worker import _start_time, _watch_driver


def default_workers() -> int:
    """The cores this process may use (its CPU affinity where the OS tells it)."""
    if hasattr(os, "sched_getaffinity"):
        return max(1, len(os.sched_getaffinity(0)))
    return max(1, os.cpu_count() or 1)


def _process_pool(workers: int) -> ProcessPoolExecutor:
    """A local process pool that does not fork the (threaded) driver, and dies with it.

    ``fork`` from a process running threads (rich's refresh thread, the
    executor's own) can deadlock; ``forkserver`` forks from a clean server.
    Every worker watches the driver (`_watch_driver`).
    """
    methods = multiprocessing.get_all_start_methods()
    context = multiprocessing.get_context("forkserver" if "forkserver" in methods else "spawn")
    driver = os.getpid()
    return ProcessPoolExecutor(max_workers=workers, mp_context=context,
                               initializer=_watch_driver, initargs=(driver, _start_time(driver)))


def _ignore_cancelled_broken_pool(args: threading.ExceptHookArgs, previous=threading.excepthook) -> None:
    """``threading.excepthook`` that drops the pool manager's race with a cancelled future.

    When the workers of an interrupted pool are ended, the pool's manager
    thread marks every pending future broken, including those the driver has
    just cancelled; Python 3.11's ``terminate_broken`` then raises
    ``InvalidStateError`` in that thread, which prints a traceback after the
    clean interrupt (seen under load in 2 of 6 SIGTERM runs).  Nothing is lost:
    those futures are cancelled on purpose.  Any other exception goes to the
    previous hook.
    """
    if isinstance(args.exc_value, InvalidStateError) and type(args.thread).__name__ == "_ExecutorManagerThread":
        return
    previous(args)


def _stop_workers(pool: ProcessPoolExecutor) -> None:
    """Shut an interrupted local pool down: cancel what waits, end the running workers."""
    threading.excepthook = _ignore_cancelled_broken_pool
    terminate = getattr(pool, "terminate_workers", None)  # Python >= 3.14
    if terminate is not None:
        terminate()
        return
    processes = list((getattr(pool, "_processes", None) or {}).values())  # shutdown forgets them
    for process in processes:
        with contextlib.suppress(OSError, ValueError):
            process.terminate()
    # Joined, not left to the interpreter's exit: its atexit hook would wake the
    # pool's manager thread through a pipe that may be closed by then, which
    # prints a traceback after the clean exit.  The workers are gone, so the
    # manager sees a broken pool and ends at once.
    pool.shutdown(wait=True, cancel_futures=True)


@contextlib.contextmanager
def dask_client(
    *,
    address: str | None = None,
    scheduler_file: str | Path | None = None,
    workers: int | None = None,
    processes: bool = True,
    **cluster_options: Any,
) -> Iterator[Any]:
    """A `dask.distributed.Client`: to ``address``/``scheduler_file``, or a new LocalCluster.

    dask.distributed is an optional dependency (``pip install
    'brushbem[distributed]'``); it is imported only here.

    Parameters
    ----------
    address, scheduler_file : optional
        Connect to a running scheduler instead of starting a cluster.
    workers : int, optional
        Workers of a new LocalCluster (default: `default_workers`), one
        thread each: a case is single-threaded, so processes give parallelism.
    processes : bool
        Whether the LocalCluster's workers are processes (threads if False).
    **cluster_options
        Passed to `LocalCluster`.

    Raises
    ------
    ImportError
        With the install instruction, if dask.distributed is missing.
    """
    try:
        from dask.distributed import Client, LocalCluster
    except ImportError as exc:
        raise ImportError(
            "running a sweep on dask needs dask.distributed: pip install 'brushbem[distributed]'"
        ) from exc
    if address is not None or scheduler_file is not None:
        with Client(address=address, scheduler_file=str(scheduler_file) if scheduler_file else None) as client:
            yield client
        return
    # The dashboard on a free port: a second sweep on the same machine (or a notebook's cluster) holds
    # dask's default 8787, and dask would warn and retry.
    cluster_options = {"dashboard_address": ":0", **cluster_options}
    with (
        LocalCluster(
            n_workers=workers or default_workers(),
            threads_per_worker=1,
            processes=processes,
            **cluster_options,
        ) as cluster,
        Client(cluster) as client,
    ):
        if processes:
            # Worker processes log to the user's terminal; threads log to the
            # driver's own loggers, which the plugin's filter would outlive.
            from brushbem.sweep.dask_quiet import QuietShutdown

            client.register_plugin(QuietShutdown())
        yield client


def _is_lost(error: BaseException) -> bool:
    """Whether a case's future failed for the infrastructure (its worker, a connection), not the case.

    `compute_case` turns every exception of the computation into a failed
    outcome, so what reaches the driver is a broken local pool, a cancelled
    future, a connection error, or dask's ``KilledWorker`` (the case's worker
    died more often than the scheduler allows).
    """
    if isinstance(error, (BrokenExecutor, CancelledError, OSError)):
        return True
    scheduler = sys.modules.get("distributed.scheduler")
    killed = getattr(scheduler, "KilledWorker", None)
    return killed is not None and isinstance(error, killed)
