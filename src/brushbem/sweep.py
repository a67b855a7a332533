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
"""

from __future__ import annotations

import contextlib
import copy
import dataclasses
import hashlib
import itertools
import json
import math
import multiprocessing
import os
import re
import sys
import threading
import time
import tomllib
import traceback
import warnings
from collections import Counter
from collections.abc import Iterator, Mapping, Sequence
from concurrent.futures import (
    FIRST_COMPLETED,
    BrokenExecutor,
    CancelledError,
    Executor,
    Future,
    InvalidStateError,
    ProcessPoolExecutor,
    wait,
)
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, Literal, Self

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationError

from brushbem import __version__
from brushbem.assembly import parse_config
from brushbem.config import (
    ConfigError,
    RunConfig,
    config_to_dict,
    to_json_safe,
)

if TYPE_CHECKING:  # pandas is imported where needed: loading a sweep file does not need it
    import pandas as pd
    from rich.console import Console

    from brushbem.results import CaseResult

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

SWEEP_FILE = "sweep.json"
SUMMARY_FILE = "summary.parquet"
CASES_DIR = "cases"
#: Where a rerun moves case files it cannot read (nothing is deleted).
CORRUPT_DIR = "corrupt"
#: What happened to a sweep folder, one JSON object per line (`read_incidents`).
INCIDENTS_FILE = "incidents.jsonl"
_LOCK_FILE = ".sweep.lock"

#: Seconds between two checks of a local worker that its driver is alive.
WATCH_INTERVAL_S = 0.5

#: Seconds between plain progress lines when stderr is not a terminal.
LOG_INTERVAL_S = 30.0

#: Statuses of a case: ``finished`` (converged), ``unconverged`` (the run ended
#: but some solve did not converge), ``failed`` (it raised), ``missing`` (no
#: case file yet) and ``corrupt`` (a case file that cannot be read as a
#: result); the last two only in summaries.
Status = Literal["finished", "unconverged", "failed", "missing", "corrupt"]
_RECORDED = ("finished", "unconverged", "failed")

# A dotted run-config key: bare TOML names joined by dots.
_DOTTED_KEY = re.compile(r"[A-Za-z0-9_-]+(\.[A-Za-z0-9_-]+)*")
_MAX_SHOWN = 60


class SweepError(ConfigError):
    """A sweep that cannot run: every problem, one line each, in ``.problems``."""


class SweepFolderError(SweepError):
    """An output folder that holds another sweep, or whose ``sweep.json`` cannot be read."""


class SweepWarning(UserWarning):
    """Something in a sweep folder was repaired on reading (an unreadable summary rebuilt)."""


class SweepSpec(BaseModel):
    """The sweep file, as written (before expansion).

    Attributes
    ----------
    base : str or dict
        The base run configuration: a TOML file name, relative to the sweep
        file's folder, or an inline table.
    mode : {"product", "zip"}
        ``"product"``: every combination of the listed values; ``"zip"``: the
        i-th value of every list together (lists of equal length).
    realizations : int
        Realizations of every parameter point, each with its own seed.
    seed : int
        Entropy of the `numpy.random.SeedSequence` the case seeds come from.
    sweep : dict
        Dotted run-config key -> non-empty list of values.
    """

    model_config = ConfigDict(extra="forbid", frozen=True, strict=True)

    base: str | dict[str, Any]
    mode: Literal["product", "zip"] = "product"
    realizations: int = Field(1, ge=1, le=1_000_000)
    seed: int = Field(0, ge=0)
    sweep: dict[str, Annotated[list[Any], Field(min_length=1)]] = Field(default_factory=dict)


_ALLOWED = {
    "base": "a run-configuration file name (relative to the sweep file) or an inline [base] table",
    "mode": "one of 'product', 'zip'",
    "realizations": "an integer in [1, 1000000]",
    "seed": "an integer >= 0 (the entropy of numpy.random.SeedSequence)",
    "sweep": "a table of dotted run-configuration keys, each with a list of values",
}


@dataclasses.dataclass(frozen=True)
class SweepCase:
    """One case of a sweep.

    Attributes
    ----------
    case_id : str
        ``<index>-<hash>``; the file name of its result, stable across reruns.
    index : int
        Position in expansion order.
    realization : int
        Which realization (0-based); equal realizations share ``seed``.
    seed : int
        The realization's seed.
    seed_applied : bool
        Whether ``seed`` was written to ``indenter.seed`` (the indenter takes a
        seed and the sweep does not set one itself).
    values : dict
        The swept values of this case, by dotted key.
    config : RunConfig
        The validated configuration.
    """

    case_id: str
    index: int
    realization: int
    seed: int
    seed_applied: bool
    values: dict[str, Any]
    config: RunConfig

    def record(self) -> dict[str, Any]:
        """The case as JSON-able data (its entry in ``sweep.json``)."""
        return to_json_safe({
            "case_id": self.case_id,
            "index": self.index,
            "realization": self.realization,
            "seed": self.seed,
            "seed_applied": self.seed_applied,
            "values": self.values,
            "config": config_to_dict(self.config),
        })


@dataclasses.dataclass(frozen=True)
class Sweep:
    """A validated, expanded sweep.

    Attributes
    ----------
    spec : SweepSpec
    base : dict
        The base run-configuration mapping (as read, before the sweep's values).
    base_file : Path or None
        Where the base was read from; None for an inline base.
    base_dir : Path
        Folder against which relative file names in the cases are resolved.
    source : Path or None
        The sweep file, if the sweep came from one.
    cases : tuple of SweepCase
    warnings : tuple of str
        Things that are allowed but probably not meant.
    """

    spec: SweepSpec
    base: dict[str, Any]
    base_file: Path | None
    base_dir: Path
    source: Path | None
    cases: tuple[SweepCase, ...]
    warnings: tuple[str, ...] = ()

    @property
    def keys(self) -> tuple[str, ...]:
        """The swept dotted keys, in the order of the sweep table."""
        return tuple(self.spec.sweep)

    def record(self) -> dict[str, Any]:
        """The resolved sweep as JSON-able data (``sweep.json``)."""
        return to_json_safe({
            "brushbem_version": __version__,
            "source": str(self.source) if self.source else None,
            "base_file": str(self.base_file) if self.base_file else None,
            "base_dir": str(self.base_dir),
            "mode": self.spec.mode,
            "realizations": self.spec.realizations,
            "seed": self.spec.seed,
            "seed_policy": (
                "numpy.random.SeedSequence(seed).spawn(realizations): one child per "
                "realization, shared by all parameter points; its first 32-bit word "
                "generate_state(1, uint32)[0] is the case seed"
            ),
            "sweep": self.spec.sweep,
            "base": self.base,
            "cases": [case.record() for case in self.cases],
        })


def _show(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= _MAX_SHOWN else text[: _MAX_SHOWN - 3] + "..."


def _brief(error: BaseException) -> str:
    """``Type: message`` of an exception, its first line, at most 160 characters."""
    try:
        lines = str(error).strip().splitlines()
    except Exception:  # noqa: BLE001 - an exception that cannot say what it is still has a type
        lines = []
    text = f"{type(error).__name__}: {lines[0] if lines else ''}".rstrip(": ")
    return text if len(text) <= 160 else text[:157] + "..."


def _quoted(key: str) -> str:
    """A sweep-table key as it is written in TOML: ``sweep."indenter.radius"``."""
    return f'sweep."{key}"'


def _spec_problems(error: ValidationError) -> list[str]:
    """One line per offending sweep-file key (a union type yields one error per member)."""
    lines: dict[str, str] = {}
    for item in error.errors(include_url=False):
        loc = tuple(item["loc"])
        if item["type"] == "extra_forbidden":
            lines[loc[0]] = (
                f"`{loc[0]}`: {_show(item['input'])} — unknown key "
                f"(allowed: {', '.join(SweepSpec.model_fields)})"
            )
        elif item["type"] == "missing":
            lines[loc[0]] = f"`{loc[0]}`: missing — required, {_ALLOWED[loc[0]]}"
        elif loc[0] == "sweep" and len(loc) >= 2:
            key = str(loc[1])
            lines.setdefault(
                _quoted(key),
                f"`{_quoted(key)}`: {_show(item['input'])} — must be a non-empty list of values",
            )
        else:
            name = str(loc[0])
            lines.setdefault(name, f"`{name}`: {_show(item['input'])} — must be {_ALLOWED[name]}")
    return list(lines.values())


def _key_problems(spec: SweepSpec) -> list[str]:
    """Rules between the sweep's keys: dotted syntax, no overlaps, zip lengths."""
    problems = []
    keys = list(spec.sweep)
    for key in keys:
        if not _DOTTED_KEY.fullmatch(key):
            problems.append(
                f"`{_quoted(key)}`: {_show(key)} — must be a dotted key of bare names, "
                'e.g. "indenter.radius"'
            )
    for a, b in itertools.permutations(keys, 2):
        if b.startswith(a + "."):
            problems.append(f"`{_quoted(b)}`: overlaps `{_quoted(a)}` — set each value once")
    if spec.mode == "zip" and len({len(values) for values in spec.sweep.values()}) > 1:
        lengths = ", ".join(f"{key} has {len(values)}" for key, values in spec.sweep.items())
        problems.append(f"`sweep`: lists of different lengths ({lengths}) — mode 'zip' needs equal lengths")
    return problems


def _set_dotted(mapping: dict[str, Any], key: str, value: Any) -> str | None:
    """Set ``key`` (dotted) in ``mapping``, creating tables; the problem, if it cannot."""
    parts = key.split(".")
    node: Any = mapping
    for depth, part in enumerate(parts):
        last = depth == len(parts) - 1
        where = ".".join(parts[:depth]) or "the base"
        if isinstance(node, dict):
            if last:
                node[part] = copy.deepcopy(value)
                return None
            node = node.setdefault(part, {})
        elif isinstance(node, list):
            if not (part.isdigit() and int(part) < len(node)):
                return (
                    f"`{_quoted(key)}`: cannot set it — `{where}` is an array of "
                    f"{len(node)} elements and {part!r} is not an index into it"
                )
            if last:
                node[int(part)] = copy.deepcopy(value)
                return None
            node = node[int(part)]
        else:
            return f"`{_quoted(key)}`: cannot set it — `{where}` is {_show(node)}, not a table"
    return None  # unreachable: the loop returns on the last part


def _realization_seeds(seed: int, realizations: int) -> list[int]:
    """One seed per realization from one SeedSequence (see the module docstring)."""
    children = np.random.SeedSequence(seed).spawn(realizations)
    return [int(child.generate_state(1, dtype=np.uint32)[0]) for child in children]


def _case_hash(config: RunConfig, seed: int) -> str:
    """First 10 hex digits of SHA-256 over the resolved configuration and the seed."""
    text = json.dumps(
        {"config": config_to_dict(config), "seed": seed},
        sort_keys=True, separators=(",", ":"), allow_nan=False,
    )
    return hashlib.sha256(text.encode()).hexdigest()[:10]


def _ranges(indices: Sequence[int]) -> str:
    """``[0, 1, 2, 5]`` -> ``"0-2, 5"``."""
    parts = []
    for _, group in itertools.groupby(enumerate(sorted(indices)), lambda item: item[1] - item[0]):
        run = [i for _, i in group]
        parts.append(str(run[0]) if len(run) == 1 else f"{run[0]}-{run[-1]}")
    return ", ".join(parts)


def _validate_case(
    mapping: dict[str, Any], seed: int, inject_seed: bool, base_dir: Path
) -> tuple[RunConfig | None, bool, list[str]]:
    """Validate one case; write ``seed`` to ``indenter.seed`` if the indenter takes it.

    Whether the indenter takes a seed is found by trying: with the seed first
    (a shape may require one), then without.  If both fail, the problems shown
    are those of the attempt whose failure is not about ``indenter.seed``.
    """
    if inject_seed and isinstance(mapping.get("indenter"), dict):
        seeded = copy.deepcopy(mapping)
        seeded["indenter"]["seed"] = seed
        try:
            return parse_config(seeded, base_dir), True, []
        except ConfigError as error:
            seeded_problems = error.problems
        unseeded = copy.deepcopy(mapping)
        unseeded["indenter"].pop("seed", None)
        try:
            return parse_config(unseeded, base_dir), False, []
        except ConfigError as error:
            about_seed = any(p.startswith("`indenter.seed`") for p in error.problems)
            return None, False, seeded_problems if about_seed else error.problems
    try:
        return parse_config(mapping, base_dir), False, []
    except ConfigError as error:
        return None, False, error.problems


def _read_base(base: str | dict[str, Any], folder: Path) -> tuple[dict[str, Any], Path | None, Path]:
    """The base run configuration: (document, its file or None, the folder its file names are relative to)."""
    if not isinstance(base, str):
        return copy.deepcopy(base), None, folder
    base_file = (folder / base).resolve()
    try:
        document = tomllib.loads(base_file.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise SweepError([f"`base`: {_show(base)} — file not found (looked for {base_file})"]) from None
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as exc:
        raise SweepError([f"`base`: {_show(base)} — cannot be read as TOML ({exc})"]) from None
    return document, base_file, base_file.parent


def parse_sweep(
    document: Mapping[str, Any],
    base_dir: str | Path | None = None,
    *,
    source: str | Path | None = None,
) -> Sweep:
    """Validate and expand a sweep mapping (a parsed sweep file).

    Parameters
    ----------
    document : mapping
        Keys ``base``, ``mode``, ``realizations``, ``seed``, ``sweep``.
    base_dir : path, optional
        Folder of the sweep file: a ``base`` file name is relative to it, and
        so are file names in an inline base.  The current directory if absent.
    source : path, optional
        The sweep file, recorded for provenance.

    Returns
    -------
    Sweep

    Raises
    ------
    SweepError
        With every problem: of the sweep file itself, or else of every
        expanded case (identical problems of several cases on one line).
    """
    folder = Path(base_dir).resolve() if base_dir is not None else Path.cwd()
    if not isinstance(document, Mapping):
        raise SweepError([f"``: {_show(document)} — must be a table (the sweep file)"])
    try:
        spec = SweepSpec.model_validate(dict(document))
    except ValidationError as error:
        # The keys that did validate are still checked, so that one pass
        # reports the sweep table's rules and a missing base file too.
        failed = {item["loc"][0] for item in error.errors(include_url=False) if item["loc"]}
        given = {k: v for k, v in document.items() if k in SweepSpec.model_fields and k not in failed}
        partial = SweepSpec.model_construct(**given)
        problems = _spec_problems(error)
        if not failed & {"sweep", "mode"}:
            problems += _key_problems(partial)
        if "base" in given:
            try:
                _read_base(partial.base, folder)
            except SweepError as base_error:
                problems += base_error.problems
        raise SweepError(problems) from None
    problems = _key_problems(spec)
    if problems:
        raise SweepError(problems)
    base, base_file, case_dir = _read_base(spec.base, folder)

    keys = list(spec.sweep)
    columns = [spec.sweep[key] for key in keys]
    points = list(zip(*columns) if spec.mode == "zip" else itertools.product(*columns))
    seeds = _realization_seeds(spec.seed, spec.realizations)
    inject_seed = "indenter.seed" not in spec.sweep
    width = max(4, len(str(len(points) * spec.realizations - 1)))

    case_problems: dict[str, list[int]] = {}
    valid: list[tuple[int, int, dict[str, Any], RunConfig, bool]] = []
    index = 0
    for realization, seed in enumerate(seeds):
        for point in points:
            values = dict(zip(keys, point))
            mapping = copy.deepcopy(base)
            # A key that cannot be set is a problem; the case is still validated
            # with the others so that their problems are reported in this pass too.
            lines = [line for key, value in values.items() if (line := _set_dotted(mapping, key, value))]
            config, applied, case_lines = _validate_case(mapping, seed, inject_seed, case_dir)
            lines += case_lines
            if lines:
                config = None
            for line in lines:
                case_problems.setdefault(line, []).append(index)
            if config is not None:
                valid.append((index, realization, values, config, applied))
            index += 1
    total = index

    cases = []
    by_hash: dict[str, int] = {}
    for index, realization, values, config, applied in valid:
        digest = _case_hash(config, seeds[realization])
        if digest in by_hash:
            first = by_hash[digest]
            case_problems.setdefault(
                f"cases {first} and {index} have the same configuration and seed "
                f"({_show(values)}) — list each value once",
                [],
            )
        by_hash.setdefault(digest, index)
        cases.append(SweepCase(
            case_id=f"{index:0{width}d}-{digest}",
            index=index,
            realization=realization,
            seed=seeds[realization],
            seed_applied=applied,
            values=values,
            config=config,
        ))
    if case_problems:
        lines = []
        for line, indices in case_problems.items():
            if not indices:
                lines.append(line)
            elif len(indices) == total:
                lines.append(f"{line} (all {total} cases)")
            else:
                lines.append(f"{line} (case{'s' if len(indices) > 1 else ''} {_ranges(indices)})")
        raise SweepError(lines)

    warnings = []
    if spec.realizations > 1 and not any(case.seed_applied for case in cases):
        warnings.append(
            f"the indenter takes no seed: the {spec.realizations} realizations of each "
            "parameter point are identical computations"
        )
    return Sweep(
        spec=spec,
        base=base,
        base_file=base_file,
        base_dir=case_dir,
        source=Path(source).resolve() if source is not None else None,
        cases=tuple(cases),
        warnings=tuple(warnings),
    )


def load_sweep(path: str | Path) -> Sweep:
    """Read, validate and expand a sweep file (TOML).

    Raises
    ------
    SweepError
        If the file cannot be read or any case is invalid (every problem listed).
    """
    path = Path(path)
    try:
        document = tomllib.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise SweepError([f"`{path}`: file not found"]) from None
    except (OSError, UnicodeDecodeError) as exc:
        raise SweepError([f"`{path}`: cannot be read ({exc})"]) from None
    except tomllib.TOMLDecodeError as exc:
        raise SweepError([f"`{path}`: not valid TOML ({exc})"]) from None
    return parse_sweep(document, path.resolve().parent, source=path)


# --------------------------------------------------------------------------- running


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


def compute_case(config: RunConfig) -> CaseOutcome:
    """Run one case in a worker; any exception becomes a ``failed`` outcome.

    Catching here, not in the driver, keeps one bad case from taking down its
    neighbours, and turns the exception into text: an exception object may not
    unpickle in the driver.
    """
    from brushbem import case as case_module  # looked up at call time: tests patch it

    start = time.perf_counter()
    try:
        result, _reference = case_module.run_case(config)
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


def _case_path(out_dir: Path, case_id: str) -> Path:
    return out_dir / CASES_DIR / f"{case_id}.nc"


def _local_files() -> contextlib.AbstractContextManager[Any]:
    """Read and write files with local locks, whatever dask scheduler is the default.

    With a `dask.distributed.Client` as the default scheduler, xarray guards
    NetCDF files with the cluster's distributed locks: the driver's files
    would then depend on the cluster's health (a restarted worker has lost
    such a lock: "Semaphore or Lock ... not known").  The driver's files are
    its own; dask's synchronous scheduler gives xarray ordinary locks.
    """
    dask = sys.modules.get("dask")
    if dask is None or not hasattr(dask, "config"):
        return contextlib.nullcontext()
    return dask.config.set(scheduler="synchronous")


def _write_case_file(out_dir: Path, case: SweepCase, outcome: CaseOutcome) -> None:
    """Record one case in ``cases/<case-id>.nc``, atomically (a failed one as attributes only)."""
    with _local_files():
        _write_case_dataset(out_dir, case, outcome)


def _write_case_dataset(out_dir: Path, case: SweepCase, outcome: CaseOutcome) -> None:
    import xarray as xr

    from brushbem.io import atomic_path, netcdf_attributes, write_dataset

    attributes: dict[str, Any] = {
        "case_id": case.case_id,
        "index": case.index,
        "realization": case.realization,
        "seed": case.seed,
        "seed_applied": case.seed_applied,
        "seeds": [case.seed],
        "swept": case.values,
        "status": outcome.status,
        "reason": outcome.reason,
        "wall_time_s": outcome.wall_time_s,
    }
    path = _case_path(out_dir, case.case_id)
    if outcome.result is not None:
        result = dataclasses.replace(
            outcome.result, attributes={**outcome.result.attributes, **attributes}
        )
        write_dataset(result, path, config=case.config)
        return
    attributes.update({
        "brushbem_version": __version__,
        "config": config_to_dict(case.config),
        "backend": "unknown",
        "traceback": outcome.traceback,
    })
    with atomic_path(path) as temporary:
        xr.Dataset(attrs=netcdf_attributes(attributes)).to_netcdf(temporary, engine="h5netcdf")


def _case_attributes(path: Path) -> dict[str, Any]:
    """The global attributes of a case file (no data is read)."""
    import xarray as xr

    with xr.open_dataset(path, engine="h5netcdf") as dataset:
        return dict(dataset.attrs)


def _read_case_record(path: Path, case_id: str) -> tuple[dict[str, Any] | None, str]:
    """The attributes of the case file of ``case_id``, or None and why it is not a result.

    A case file is a result when it opens, its ``status`` is one a case is
    recorded with, its ``case_id`` is its own, and a finished or unconverged
    case has its load path.  No data is read beyond the file's metadata.
    """
    import xarray as xr

    try:
        with _local_files(), xr.open_dataset(path, engine="h5netcdf") as dataset:
            attributes = dict(dataset.attrs)
            variables = set(dataset.variables)
    except Exception as exc:  # noqa: BLE001 - any unreadable file is corrupt, whatever the library says
        return None, f"cannot be read ({_brief(exc)})"
    status = attributes.get("status")
    if status not in _RECORDED:
        return None, f"no case status (found {_show(status)})"
    if attributes.get("case_id") != case_id:
        return None, f"records case {_show(attributes.get('case_id'))}, not {case_id}"
    if status != "failed" and not {"displacement", "force"} <= variables:
        return None, f"a {status} case without its load path"
    return attributes, ""


def _set_aside(out_dir: Path, path: Path) -> Path:
    """Move an unreadable case file to ``corrupt/`` under a free name; the new path."""
    folder = out_dir / CORRUPT_DIR
    folder.mkdir(exist_ok=True)
    target = folder / path.name
    number = 0
    while target.exists():
        number += 1
        target = folder / f"{path.stem}.{number}{path.suffix}"
    os.replace(path, target)
    return target


def _record_incident(out_dir: Path, event: str, detail: str, **fields: Any) -> None:
    """Append one incident to ``incidents.jsonl`` (a line per incident, flushed at once)."""
    entry = {"time": time.strftime("%Y-%m-%dT%H:%M:%S%z"), "event": event, **fields, "detail": detail}
    line = json.dumps(to_json_safe(entry), allow_nan=False) + "\n"
    with open(out_dir / INCIDENTS_FILE, "a", encoding="utf-8") as handle:
        handle.write(line)
        handle.flush()
        os.fsync(handle.fileno())


def read_incidents(out_dir: str | Path) -> list[dict[str, Any]]:
    """What happened to a sweep folder, oldest first (see the module docstring).

    Every entry has ``time``, ``event`` and ``detail``; ``case_id`` and
    ``moved_to`` where they apply.  Events: ``corrupt`` (a case file moved
    aside and recomputed), ``lost`` (a case lost with its worker, left
    missing), ``interrupted`` (a run stopped by a signal), ``extended`` (a
    sweep grown by new cases), ``unreadable-record`` (``sweep.json``
    unreadable, the folder identified by its case files), ``stale-temporary``
    (half-written files of a killed driver removed).  A line that does not
    parse (a driver killed while appending it) is skipped.

    Returns
    -------
    list of dict
        Empty if the folder has no incidents file.
    """
    path = Path(out_dir) / INCIDENTS_FILE
    try:
        lines = path.read_text(encoding="utf-8", errors="replace").splitlines()
    except FileNotFoundError:
        return []
    incidents = []
    for line in lines:
        try:
            entry = json.loads(line)
        except ValueError:
            continue
        if isinstance(entry, dict) and "event" in entry:
            incidents.append(entry)
    return incidents


def _read_record(out_dir: Path) -> dict[str, Any]:
    """The ``sweep.json`` of ``out_dir``.

    Raises
    ------
    FileNotFoundError
        If there is none.
    SweepFolderError
        If it cannot be read as a sweep record (the file named).
    """
    path = out_dir / SWEEP_FILE
    try:
        record = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise
    except (OSError, UnicodeDecodeError, ValueError) as exc:
        raise SweepFolderError([f"`{path}`: cannot be read as a sweep record ({_brief(exc)})"]) from None
    cases = record.get("cases") if isinstance(record, dict) else None
    if not (isinstance(cases, list) and all(isinstance(c, dict) and "case_id" in c for c in cases)):
        raise SweepFolderError([f"`{path}`: not a sweep record (no list of cases with their ids)"])
    return record


def _check_folder(out_dir: Path, sweep: Sweep) -> None:
    """Refuse a folder that holds another sweep; record an extension or a lost record.

    The folder's sweep is what ``sweep.json`` records, or, if that is
    unreadable, the case files in ``cases/``.  ``sweep`` may run there when
    it keeps every one of those cases (the same ids).
    """
    ids = {case.case_id for case in sweep.cases}
    try:
        recorded = [str(case["case_id"]) for case in _read_record(out_dir)["cases"]]
    except FileNotFoundError:
        return
    except SweepFolderError as error:
        found = sorted(path.stem for path in (out_dir / CASES_DIR).glob("*.nc"))
        foreign = [case_id for case_id in found if case_id not in ids]
        if foreign:
            raise SweepFolderError([
                *error.problems,
                (f"`{out_dir}`: holds case files of a different sweep (e.g. {foreign[0]}); "
                 "run this sweep into a new --out folder"),
            ]) from None
        _record_incident(out_dir, "unreadable-record",
                         f"{error.problems[0]}; rewritten: its {len(found)} case files belong to this sweep")
        return
    dropped = [case_id for case_id in recorded if case_id not in ids]
    if dropped:
        raise SweepFolderError([(
            f"`{out_dir}`: holds a different sweep ({len(recorded)} cases in {out_dir / SWEEP_FILE}, "
            f"{len(dropped)} of them not in this sweep, e.g. {dropped[0]}); a folder takes one sweep, "
            "or one that only adds cases (more realizations): run this sweep into a new --out folder"
        )])
    if len(ids) > len(recorded):
        _record_incident(out_dir, "extended",
                         f"the sweep grew from {len(recorded)} to {len(ids)} cases")


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


@dataclasses.dataclass(frozen=True)
class SweepRun:
    """What one call of `run_sweep` did.

    Attributes
    ----------
    computed : dict
        Case id -> status, for the cases computed by this call.
    skipped : dict
        Case id -> status, for the cases found already recorded.
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
        return not self.lost and set(self.counts) <= {"finished"}


def default_workers() -> int:
    """The cores this process may use (its CPU affinity where the OS tells it)."""
    if hasattr(os, "sched_getaffinity"):
        return max(1, len(os.sched_getaffinity(0)))
    return max(1, os.cpu_count() or 1)


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
    with (
        LocalCluster(
            n_workers=workers or default_workers(),
            threads_per_worker=1,
            processes=processes,
            **cluster_options,
        ) as cluster,
        Client(cluster) as client,
    ):
        yield client


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


@contextlib.contextmanager
def _exclusive(out_dir: Path) -> Iterator[None]:
    """Refuse a second sweep driver on the same folder (the kernel drops the lock if one is killed)."""
    try:
        import fcntl
    except ImportError:  # not on POSIX: no lock
        yield
        return
    with open(out_dir / _LOCK_FILE, "w") as handle:
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            raise RuntimeError(f"another sweep is running in {out_dir}") from None
        yield


def _write_json(path: Path, value: Any) -> None:
    from brushbem.io import atomic_path

    with atomic_path(path) as temporary:
        temporary.write_text(json.dumps(to_json_safe(value), indent=1, allow_nan=False) + "\n")


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
        for case in sweep.cases:
            path = _case_path(out_dir, case.case_id)
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
                    futures[executor.submit(compute_case, case.config)] = case
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


def _remove_stale_temporaries(out_dir: Path) -> None:
    """Remove what a driver killed while writing left: temporaries of its files, never complete files."""
    stale = [*(out_dir / CASES_DIR).glob(".*.tmp"),
             *(path for name in (SWEEP_FILE, SUMMARY_FILE) for path in out_dir.glob(f".{name}.*.tmp"))]
    for path in stale:
        path.unlink(missing_ok=True)
    if stale:
        _record_incident(out_dir, "stale-temporary",
                         f"removed {len(stale)} half-written file(s) of a killed run: "
                         + ", ".join(sorted(str(path.relative_to(out_dir)) for path in stale)[:5])
                         + (", ..." if len(stale) > 5 else ""))


# --------------------------------------------------------------------------- summary

_NON_FINITE = {"inf": math.inf, "-inf": -math.inf, "nan": math.nan}


def _arrow_safe(frame: pd.DataFrame) -> pd.DataFrame:
    """Make object columns storable in Parquet.

    JSON wrote non-finite floats as ``"inf"``/``"-inf"``/``"nan"``; a column of
    numbers and such strings becomes float again.  A column still mixing types
    (or holding tables/arrays) is stored as JSON text, one value per cell.
    """
    import pandas as pd

    for name in frame.columns:
        column = frame[name]
        if not (column.dtype == object or pd.api.types.is_string_dtype(column)):
            continue
        values = [v for v in column if not (v is None or (isinstance(v, float) and math.isnan(v)))]
        restored = [_NON_FINITE.get(v, v) if isinstance(v, str) else v for v in values]
        if values and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in restored):
            frame[name] = pd.to_numeric(
                column.map(lambda v: _NON_FINITE.get(v, v) if isinstance(v, str) else v)
            )
        elif len({type(v) for v in values}) > 1 or any(isinstance(v, (dict, list)) for v in values):
            frame[name] = column.map(
                lambda v: None if v is None or (isinstance(v, float) and math.isnan(v))
                else json.dumps(to_json_safe(v), sort_keys=True)
            )
    return frame


def build_summary(out_dir: str | Path, *, write: bool = True) -> pd.DataFrame:
    """One row per case of the sweep in ``out_dir``, from its case files.

    Columns: ``case_id``, ``index``, ``realization``, ``seed``,
    ``seed_applied``, the swept values under their dotted keys, ``status``,
    ``reason``, ``wall_time_s`` (of the whole case, in its worker), then the
    ``summary.json`` fields flattened with dots (``theory.ratios.adhesive_force``;
    its own ``reason`` and ``wall_time_s`` give way to the case's), and
    ``brushbem_version``, ``backend``.  A case without a file has status
    ``missing`` (its reason says so when its worker was lost), a case whose
    file cannot be read as a result has status ``corrupt`` (nothing of it is
    read).  Case files of other sweeps in the folder are ignored.

    Parameters
    ----------
    out_dir : path
        A folder written by `run_sweep` (it needs ``sweep.json``).
    write : bool
        Also write ``summary.parquet`` (atomically).

    Returns
    -------
    pandas.DataFrame

    Raises
    ------
    FileNotFoundError
        If ``out_dir`` has no ``sweep.json``.
    SweepFolderError
        If its ``sweep.json`` cannot be read.
    """
    import pandas as pd

    from brushbem.io import atomic_path

    out_dir = Path(out_dir)
    record = _read_record(out_dir)
    lost = {entry.get("case_id"): entry.get("detail", "") for entry in read_incidents(out_dir)
            if entry["event"] == "lost"}
    rows, summaries = [], []
    for entry in record["cases"]:
        row: dict[str, Any] = {
            key: entry[key] for key in ("case_id", "index", "realization", "seed", "seed_applied")
        }
        row.update(entry["values"])
        path = _case_path(out_dir, entry["case_id"])
        summary: dict[str, Any] = {}
        provenance: dict[str, Any] = {"brushbem_version": None, "backend": None}
        attributes, problem = _read_case_record(path, entry["case_id"]) if path.exists() else (None, "")
        if attributes is not None:
            row["status"] = attributes.get("status")
            row["reason"] = attributes.get("reason")
            row["wall_time_s"] = attributes.get("wall_time_s")
            try:
                summary = json.loads(attributes.get("summary", "null")) or {}
            except (TypeError, ValueError):
                summary = {}
            provenance = {key: attributes.get(key) for key in ("brushbem_version", "backend")}
        elif problem:
            row.update(status="corrupt", wall_time_s=math.nan,
                       reason=f"case file {problem}; a rerun moves it to {CORRUPT_DIR}/ and recomputes it")
        elif entry["case_id"] in lost:
            row.update(status="missing", wall_time_s=math.nan,
                       reason=f"its worker was lost ({lost[entry['case_id']]})")
        else:
            row.update(status="missing", reason="not computed yet", wall_time_s=math.nan)
        rows.append(row)
        summaries.append((summary, provenance))
    frame = pd.DataFrame(rows, columns=[
        "case_id", "index", "realization", "seed", "seed_applied", *record["sweep"],
        "status", "reason", "wall_time_s",
    ])
    flat = pd.json_normalize([s for s, _ in summaries], sep=".")
    flat = flat.drop(columns=[c for c in flat.columns if c in frame.columns])
    provenance = pd.DataFrame([p for _, p in summaries], columns=["brushbem_version", "backend"])
    frame = _arrow_safe(pd.concat([frame, flat, provenance], axis=1))
    if write:
        with atomic_path(out_dir / SUMMARY_FILE) as temporary:
            frame.to_parquet(temporary, engine="pyarrow", index=False)
    return frame


def load_summary(out_dir: str | Path, *, rebuild: bool = False) -> pd.DataFrame:
    """The summary of the sweep in ``out_dir`` (one row per case).

    ``summary.parquet`` is read as it is unless it is missing, older than a
    case file, the ``cases/`` folder or ``sweep.json`` (a killed or extended
    sweep, a case file replaced or damaged since), or ``rebuild``
    is set; then it is rebuilt with `build_summary` (and written where the
    folder is writable).  A ``summary.parquet`` that cannot be read (corrupt,
    or written by a newer format) is rebuilt too, with a `SweepWarning`.

    Returns
    -------
    pandas.DataFrame

    Raises
    ------
    FileNotFoundError
        If ``out_dir`` has no ``sweep.json``.
    SweepFolderError
        If its ``sweep.json`` cannot be read.
    """
    import pandas as pd

    out_dir = Path(out_dir)
    path = out_dir / SUMMARY_FILE
    if not rebuild and path.exists():
        written = path.stat().st_mtime_ns
        newest = max(
            (out_dir / name).stat().st_mtime_ns
            for name in (SWEEP_FILE, CASES_DIR) if (out_dir / name).exists()
        )
        with contextlib.suppress(FileNotFoundError), os.scandir(out_dir / CASES_DIR) as entries:
            for entry in entries:
                with contextlib.suppress(FileNotFoundError):
                    newest = max(newest, entry.stat().st_mtime_ns)
        if newest <= written:
            try:
                return pd.read_parquet(path, engine="pyarrow")
            except Exception as exc:  # noqa: BLE001 - a derived file: rebuilt, whatever the reader says
                warnings.warn(f"{path} cannot be read ({_brief(exc)}); "
                              "rebuilt from the case files", SweepWarning, stacklevel=2)
    try:
        return build_summary(out_dir)
    except OSError:  # a read-only results folder: summarise without writing
        return build_summary(out_dir, write=False)
