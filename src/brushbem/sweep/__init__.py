"""User-defined parameter sweeps: many cases of one base run configuration.

A sweep file names a base run configuration and, for any of its keys, a list of
values::

    base = "brush.toml"          # path relative to this file, or an inline [base] table
    mode = "product"             # "product" (every combination) or "zip" (i-th with i-th)
    realizations = 2             # statistical realizations of every parameter point
    seed = 7                     # entropy of the per-realization seeds
    [sweep]
    "indenter.stiffness_ratio" = [10.0, 0.1, 0.001]
    "indenter.roughness.sigma" = [0.0, 0.002]

Each case is the base mapping with the dotted keys set (tables created as
needed, ``indenter.levels.0.x`` indexes an array of tables), validated as an
ordinary run configuration.  Every case is validated before anything runs and
every problem of every case is reported at once (`SweepError`), so a study
does not fail an hour in on its last parameter value.

Seeds
    ``numpy.random.SeedSequence(seed).spawn(realizations)`` gives one child per
    *realization*, shared by all parameter points: realization ``r`` of every
    point uses the same seed, so a comparison across stiffnesses (say) is made
    over the same random layouts/roughnesses, and the difference between points
    is not drowned in the difference between realizations (common random
    numbers).  A child's state depends only on ``(seed, r)``, so raising
    ``realizations`` later keeps the seeds, and the case ids, of the existing
    realizations.  The seed is a 32-bit unsigned integer (accepted by every
    NumPy generator).  It is written to ``indenter.seed`` when the case's
    indenter accepts that key, replacing any seed of the base, unless the sweep
    itself sets ``indenter.seed``; otherwise it is only recorded.

Cases and resume
    The case id is ``<index>-<hash>``: the index in expansion order
    (realization outermost, then the parameter points in the order of the
    sweep table, the last key varying fastest) and the first 10 hex digits of
    the SHA-256 of the resolved configuration and seed.  A rerun finds a case
    by its id, so a killed sweep computes exactly the missing cases.  Each
    case is one NetCDF file ``cases/<case-id>.nc``, written atomically by the
    process driving the sweep (workers return results, so no shared file
    system is needed with a remote dask cluster).  A case that raised is
    recorded too (status ``failed``, the exception as reason, the traceback),
    and is *not* retried by a rerun unless asked (``retry_failed``): most
    failures are deterministic and would fail again, and a silently retried
    case hides that it failed.  A case that did not converge is a result
    (status ``unconverged``) and is never retried.  A case lost to the
    infrastructure is not a failure of the case: a worker process that dies
    (a crash, the out-of-memory killer) breaks the local pool, a dask worker
    that dies again and again gives ``KilledWorker``, a lost connection
    ``CommClosedError``; such cases are left missing and a rerun computes
    them.  Local workers watch the driver and exit when it is gone (killed
    with SIGKILL, say), so no orphaned worker computes on.

Corrupt files and incidents
    A case file is a result only if it opens, carries a known ``status`` and
    its own ``case_id``, and (unless failed) its load path.  Anything else (a
    file truncated by a full disk, emptied, overwritten) is *corrupt*: the
    summary lists it with status ``corrupt`` and never reads it as a result,
    and a rerun moves it to ``corrupt/`` (nothing is deleted) and computes
    the case again.  An unreadable ``summary.parquet`` is rebuilt from the
    case files with a `SweepWarning`.  What happened to a folder (corrupt
    files moved aside, cases lost with their workers, interrupted runs, a
    sweep extended) is appended to ``incidents.jsonl``, one JSON object per
    line (`read_incidents`), which the report lists.

One folder, one sweep
    ``sweep.json`` records the case ids.  A sweep run into a folder that
    holds another sweep is refused (`SweepFolderError`) unless it keeps every
    recorded case: the same sweep resumes, and a sweep that only adds cases
    (more realizations: the ids of the existing ones are kept) extends it.
    A sweep that drops or changes a recorded case needs its own folder.

Outputs of ``run_sweep(sweep, DIR)``: ``DIR/sweep.json`` (the resolved sweep:
spec, base, every case with its id, seed, values and configuration),
``DIR/cases/<case-id>.nc``, ``DIR/summary.parquet`` (one row per case,
rebuilt from the case files by `build_summary`, read by `load_summary`) and,
when something went wrong, ``DIR/incidents.jsonl`` and ``DIR/corrupt/``.

Modules
    `brushbem.sweep.spec`
        The sweep file and its expansion: `SweepSpec`, `parse_sweep`,
        `load_sweep`, seeds and case ids, `Sweep` and `SweepCase`.
    `brushbem.sweep.errors`
        `SweepError`, `SweepFolderError`, `SweepWarning`.
    `brushbem.sweep.execution`
        `run_sweep` (the driver) and `SweepRun`.
    `brushbem.sweep.worker`
        What runs in a worker: `compute_case`, `CaseOutcome`, the watch of
        a local worker on its driver.
    `brushbem.sweep.executors`
        The local process pool, `dask_client`, `default_workers`, lost
        workers told from failed cases.
    `brushbem.sweep.progress`
        Progress on stderr.
    `brushbem.sweep.store`
        The folder on disk: file names, case files, ``sweep.json``,
        ``incidents.jsonl`` (`read_incidents`), ``corrupt/``, the lock.
    `brushbem.sweep.summary`
        `build_summary` and `load_summary`.

    This package re-exports their public names.  A setting or a function is
    read from the module that uses it: to change one (``LOG_INTERVAL_S``,
    ``_process_pool``), patch that module, not this package.
"""

from __future__ import annotations

# The ``X as X`` imports re-export names outside __all__ that code and tests
# read as `brushbem.sweep.X`.
from brushbem.sweep.errors import SweepError, SweepFolderError, SweepWarning
from brushbem.sweep.execution import SweepRun, run_sweep
from brushbem.sweep.executors import _process_pool as _process_pool
from brushbem.sweep.executors import dask_client, default_workers
from brushbem.sweep.progress import LOG_INTERVAL_S as LOG_INTERVAL_S
from brushbem.sweep.spec import Sweep, SweepCase, SweepSpec, load_sweep, parse_sweep
from brushbem.sweep.store import (
    CASES_DIR,
    CORRUPT_DIR,
    INCIDENTS_FILE,
    SUMMARY_FILE,
    SWEEP_FILE,
    read_incidents,
)
from brushbem.sweep.store import _case_attributes as _case_attributes
from brushbem.sweep.store import _exclusive as _exclusive
from brushbem.sweep.summary import build_summary, load_summary
from brushbem.sweep.worker import WATCH_INTERVAL_S as WATCH_INTERVAL_S
from brushbem.sweep.worker import CaseOutcome, compute_case
from brushbem.sweep.worker import Status as Status

__all__ = [
    "CASES_DIR",
    "CORRUPT_DIR",
    "INCIDENTS_FILE",
    "SUMMARY_FILE",
    "SWEEP_FILE",
    "CaseOutcome",
    "Sweep",
    "SweepCase",
    "SweepError",
    "SweepFolderError",
    "SweepRun",
    "SweepSpec",
    "SweepWarning",
    "build_summary",
    "compute_case",
    "dask_client",
    "default_workers",
    "load_summary",
    "load_sweep",
    "parse_sweep",
    "read_incidents",
    "run_sweep",
]
