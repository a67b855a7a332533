"""A worker plugin that drops dask.distributed's shutdown-race log on the sweep's own LocalCluster.

A worker whose heartbeat is in flight while it closes logs "Failed to
communicate with scheduler during heartbeat." with the full traceback of
its closed connection pool, at ERROR level.  It says nothing about the
sweep (every case's outcome is already recorded) and, in the worker
processes of a LocalCluster, it lands in the terminal of the user who ran
``brushbem sweep --dask``.  `QuietShutdown` removes that one record, and
only while its worker is closing; every other message of the workers is
kept.  Imported only where dask.distributed is installed.
"""

from __future__ import annotations

import logging

from distributed.core import Status
from distributed.diagnostics.plugin import WorkerPlugin

HEARTBEAT_FAILED = "Failed to communicate with scheduler during heartbeat."
CLOSING = {Status.closing, Status.closing_gracefully, Status.closed}


class _ClosingHeartbeat(logging.Filter):
    def __init__(self, worker) -> None:
        super().__init__()
        self.worker = worker

    def filter(self, record: logging.LogRecord) -> bool:
        return not (record.msg == HEARTBEAT_FAILED and self.worker.status in CLOSING)


class QuietShutdown(WorkerPlugin):
    """Drops the heartbeat failure of a closing worker from the ``distributed.worker`` log."""

    name = "brushbem-quiet-shutdown"

    def setup(self, worker) -> None:
        self.filter = _ClosingHeartbeat(worker)
        # Kept after teardown: the record comes when the worker's pool closes, after its plugins.
        logging.getLogger("distributed.worker").addFilter(self.filter)
