"""Running a sweep: `run_sweep` and what it returns, `SweepRun`.

The driver: it takes the folder (lock, stale temporaries, the folder's
sweep), skips the cases already recorded (moving corrupt files aside,
retrying failed ones when asked), submits the rest to an executor, writes
each case file as its outcome arrives, records lost workers and
interruptions, and rebuilds the summary.
"""

from __future__ import annotations

import contextlib
import dataclasses
import math
import traceback
from collections import Counter
from collections.abc import Collection, Mapping
from concurrent.futures import (
    FIRST_COMPLETED,
    Executor,
    Future,
    wait,
)
from pathlib import Path
from typing import TYPE_CHECKING, Any

from brushbem.sweep.errors import _brief
from brushbem.sweep.executors import (
    _is_lost,
    _process_pool,
    _stop_workers,
    default_workers,
)
from brushbem.sweep.progress import _Reporter
from brushbem.sweep.spec import Sweep, SweepCase, case_hash, load_sweep, parse_sweep
from brushbem.sweep.store import (
    CASES_DIR,
    SWEEP_FILE,
    _case_path,
    _check_folder,
    _exclusive,
    _read_case_record,
    _record_incident,
    _remove_stale_temporaries,
    _set_aside,
    _write_case_file,
    _write_json,
)
from brushbem.sweep.summary import build_summary
from brushbem.sweep.worker import CaseOutcome, compute_case

if TYPE_CHECKING:
    import pandas as pd
    from rich.console import Console


@dataclasses.dataclass(frozen=True)
class SweepRun:
    """What one call of `run_sweep` did.

    Attributes
    ----------
    computed : dict
        Case id -> status, for the cases computed by this call.
    skipped : dict
        Case id -> status, for the cases found already recorded (``recorded``:
        finished in the tables of an earlier run elsewhere, not computed here).
    lost : tuple of str
        Cases whose worker died (a crashed process pool); a rerun computes them.
    summary : pandas.DataFrame or None
        The rebuilt summary (None if the run was interrupted).
    """

    computed: dict[str, str]
    skipped: dict[str, str]
    lost: tuple[str, ...]
    summary: pd.DataFrame | None

    @property
    def counts(self) -> Counter[str]:
        """Cases of the sweep by status, computed now or before (lost ones as ``missing``)."""
        counts = Counter(self.computed.values()) + Counter(self.skipped.values())
        counts["missing"] += len(self.lost)
        return +counts

    @property
    def complete(self) -> bool:
        """Every case of the sweep finished (converged)."""
        return not self.lost and set(self.counts) <= {"finished", RECORDED}


#: The status of a case that `run_sweep` leaves to the tables of an earlier run (``recorded``).
RECORDED = "recorded"


def _as_sweep(sweep: Sweep | str | Path | Mapping[str, Any], base_dir: str | Path | None) -> Sweep:
    if isinstance(sweep, Sweep):
        return sweep
    if isinstance(sweep, Mapping):
        return parse_sweep(sweep, base_dir)
    return load_sweep(sweep)


def run_sweep(
    sweep: Sweep | str | Path | Mapping[str, Any],
    out_dir: str | Path,
    executor: Executor | Any | None = None,
    *,
    workers: int | None = None,
    retry_failed: bool = False,
    progress: bool = False,
    console: Console | None = None,
    base_dir: str | Path | None = None,
    recorded: Collection[str] = (),
) -> SweepRun:
    """Run every case of a sweep not yet recorded in ``out_dir``.

    Parameters
    ----------
    sweep : Sweep, path or mapping
        A loaded sweep, a sweep file, or a sweep mapping (relative names
        resolved against ``base_dir``).
    out_dir : path
        Created if absent.  Cases already recorded there are not recomputed.
    executor : concurrent.futures.Executor or dask.distributed.Client, optional
        Where cases run; it is not shut down here.  Default: a local pool of
        ``workers`` processes.
    workers : int, optional
        Size of the default pool (default: `default_workers`).
    retry_failed : bool
        Recompute cases recorded as ``failed`` (never ``unconverged``: that
        is a deterministic result, not an accident).
    progress : bool
        Report progress on stderr (a bar on a terminal, else plain lines).
    console : rich.console.Console, optional
        Where progress goes (default: stderr).
    base_dir : path, optional
        For a mapping ``sweep``: the folder its file names are relative to.
    recorded : collection of str
        Case hashes (a case id without its index) finished in the tables of
        an earlier run whose folder is not here (another session or machine,
        `brushbem.reproduction.recorded_cases`): these cases are not computed,
        stay missing in ``out_dir`` and count as ``"recorded"``;
        ``brushbem export-tables --update`` merges the rest into those tables.

    Returns
    -------
    SweepRun

    Raises
    ------
    SweepError
        If the sweep is invalid; nothing is created then.
    SweepFolderError
        If ``out_dir`` holds a different sweep (one that this sweep does not
        contain case for case); nothing is changed then.
    RuntimeError
        If another sweep driver runs in ``out_dir``.
    KeyboardInterrupt
        Re-raised after an interruption: every case finished by then is
        written, the local pool's workers are ended, and the interruption is
        recorded in ``incidents.jsonl``.
    """
    sweep = _as_sweep(sweep, base_dir)
    out_dir = Path(out_dir)
    (out_dir / CASES_DIR).mkdir(parents=True, exist_ok=True)
    with _exclusive(out_dir):
        _remove_stale_temporaries(out_dir)
        _check_folder(out_dir, sweep)
        _write_json(out_dir / SWEEP_FILE, sweep.record())

        skipped: dict[str, str] = {}
        todo: list[SweepCase] = []
        recorded = set(recorded)
        for case in sweep.cases:
            path = _case_path(out_dir, case.case_id)
            if case_hash(case.case_id) in recorded and not path.exists():
                skipped[case.case_id] = RECORDED
                continue
            if path.exists():
                attributes, problem = _read_case_record(path, case.case_id)
                if attributes is None:
                    moved = _set_aside(out_dir, path)
                    _record_incident(out_dir, "corrupt", f"case file {problem}; recomputed",
                                     case_id=case.case_id, moved_to=str(moved.relative_to(out_dir)))
                else:
                    status = str(attributes["status"])
                    if not (retry_failed and status == "failed"):
                        skipped[case.case_id] = status
                        continue
            todo.append(case)

        computed: dict[str, str] = {}
        lost: list[str] = []
        owned = None
        if executor is None and todo:
            owned = executor = _process_pool(workers or default_workers())
        elif hasattr(executor, "get_executor"):  # a dask.distributed Client
            # pure=False: each case runs even if dask would deem two calls equal.
            executor = executor.get_executor(pure=False)
        futures: dict[Future[CaseOutcome], SweepCase] = {}

        def record(future: Future[CaseOutcome], case: SweepCase) -> tuple[str, str]:
            try:
                outcome = future.result()
            except Exception as exc:  # noqa: BLE001 - reported, not raised
                if _is_lost(exc):
                    lost.append(case.case_id)
                    _record_incident(out_dir, "lost", f"{_brief(exc)}; left missing, a rerun computes it",
                                     case_id=case.case_id)
                    return "missing", f"lost with its worker ({_brief(exc)}); rerun to compute it"
                outcome = CaseOutcome("failed", f"{type(exc).__name__}: {exc}", math.nan,
                                      traceback="".join(traceback.format_exception(exc)))
            _write_case_file(out_dir, case, outcome)
            computed[case.case_id] = outcome.status
            return outcome.status, outcome.reason

        try:
            with _Reporter(len(todo), len(skipped), progress, console) as reporter:
                for case in todo:
                    futures[executor.submit(compute_case, case.config, sweep.spec.refine)] = case
                pending = set(futures)
                while pending:
                    done, pending = wait(pending, timeout=reporter.timeout(), return_when=FIRST_COMPLETED)
                    for future in sorted(done, key=lambda f: futures[f].index):
                        case = futures.pop(future)
                        reporter.record(case, *record(future, case))
                    reporter.tick()
        except KeyboardInterrupt as interruption:
            # Keep what finished before the signal, then stop the rest.
            for future, case in sorted(futures.items(), key=lambda item: item[1].index):
                if future.done() and not future.cancelled():
                    with contextlib.suppress(Exception):
                        record(future, case)
            for future in futures:
                future.cancel()
            if owned is not None:
                _stop_workers(owned)
                owned = None
            with contextlib.suppress(OSError):
                missing = sum(not _case_path(out_dir, case.case_id).exists() for case in sweep.cases)
                _record_incident(out_dir, "interrupted",
                                 f"{type(interruption).__name__}: {len(computed)} cases computed by this run "
                                 f"kept, {missing} missing")
            raise
        except BaseException:
            for future in futures:
                future.cancel()
            if owned is not None:
                _stop_workers(owned)
                owned = None
            raise
        finally:
            if owned is not None:
                owned.shutdown()
        summary = build_summary(out_dir)
    return SweepRun(computed=computed, skipped=skipped, lost=tuple(lost), summary=summary)
