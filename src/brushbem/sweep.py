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
    (status ``unconverged``) and is never retried.  A worker process that dies
    (a crash, the out-of-memory killer) breaks the local pool: the cases it
    took down are left missing and a rerun computes them.

Outputs of ``run_sweep(sweep, DIR)``: ``DIR/sweep.json`` (the resolved sweep:
spec, base, every case with its id, seed, values and configuration),
``DIR/cases/<case-id>.nc`` and ``DIR/summary.parquet`` (one row per case,
rebuilt from the case files by `build_summary`, read by `load_summary`).
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
import time
import tomllib
import traceback
from collections import Counter
from collections.abc import Iterator, Mapping, Sequence
from concurrent.futures import (
    FIRST_COMPLETED,
    Executor,
    Future,
    ProcessPoolExecutor,
    wait,
)
from concurrent.futures.process import BrokenProcessPool
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, Literal, Self

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationError

from brushbem import __version__
from brushbem.config import (
    ConfigError,
    RunConfig,
    config_to_dict,
    parse_config,
    to_json_safe,
)

if TYPE_CHECKING:  # pandas is imported where needed: loading a sweep file does not need it
    import pandas as pd
    from rich.console import Console

    from brushbem.results import CaseResult

__all__ = [
    "CASES_DIR",
    "SUMMARY_FILE",
    "SWEEP_FILE",
    "CaseOutcome",
    "Sweep",
    "SweepCase",
    "SweepError",
    "SweepRun",
    "SweepSpec",
    "build_summary",
    "compute_case",
    "dask_client",
    "default_workers",
    "load_summary",
    "load_sweep",
    "parse_sweep",
    "run_sweep",
]

SWEEP_FILE = "sweep.json"
SUMMARY_FILE = "summary.parquet"
CASES_DIR = "cases"
_LOCK_FILE = ".sweep.lock"

#: Seconds between plain progress lines when stderr is not a terminal.
LOG_INTERVAL_S = 30.0

#: Statuses of a case: ``finished`` (converged), ``unconverged`` (the run ended
#: but some solve did not converge), ``failed`` (it raised), ``missing`` (no
#: case file yet; only in summaries).
Status = Literal["finished", "unconverged", "failed", "missing"]

# A dotted run-config key: bare TOML names joined by dots.
_DOTTED_KEY = re.compile(r"[A-Za-z0-9_-]+(\.[A-Za-z0-9_-]+)*")
_MAX_SHOWN = 60


class SweepError(ConfigError):
    """A sweep that cannot run: every problem, one line each, in ``.problems``."""


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


def _write_case_file(out_dir: Path, case: SweepCase, outcome: CaseOutcome) -> None:
    """Record one case in ``cases/<case-id>.nc``, atomically (a failed one as attributes only)."""
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


def _process_pool(workers: int) -> ProcessPoolExecutor:
    """A local process pool that does not fork the (threaded) driver.

    ``fork`` from a process running threads (rich's refresh thread, the
    executor's own) can deadlock; ``forkserver`` forks from a clean server.
    """
    methods = multiprocessing.get_all_start_methods()
    context = multiprocessing.get_context("forkserver" if "forkserver" in methods else "spawn")
    return ProcessPoolExecutor(max_workers=workers, mp_context=context)


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
    """
    sweep = _as_sweep(sweep, base_dir)
    out_dir = Path(out_dir)
    (out_dir / CASES_DIR).mkdir(parents=True, exist_ok=True)
    with _exclusive(out_dir):
        # Leftovers of a driver killed while writing: never a complete file.
        for stale in (out_dir / CASES_DIR).glob(".*.tmp"):
            stale.unlink(missing_ok=True)
        _write_json(out_dir / SWEEP_FILE, sweep.record())

        skipped: dict[str, str] = {}
        todo: list[SweepCase] = []
        for case in sweep.cases:
            path = _case_path(out_dir, case.case_id)
            if path.exists():
                status = str(_case_attributes(path).get("status", "failed"))
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
        try:
            with _Reporter(len(todo), len(skipped), progress, console) as reporter:
                for case in todo:
                    futures[executor.submit(compute_case, case.config)] = case
                pending = set(futures)
                while pending:
                    done, pending = wait(pending, timeout=reporter.timeout(), return_when=FIRST_COMPLETED)
                    for future in sorted(done, key=lambda f: futures[f].index):
                        case = futures.pop(future)
                        try:
                            outcome = future.result()
                        except BrokenProcessPool:
                            lost.append(case.case_id)
                            reporter.record(case, "missing", "a worker process died; rerun to compute it")
                            continue
                        except Exception as exc:  # noqa: BLE001 - reported, not raised
                            outcome = CaseOutcome("failed", f"{type(exc).__name__}: {exc}", math.nan,
                                                  traceback="".join(traceback.format_exception(exc)))
                        _write_case_file(out_dir, case, outcome)
                        computed[case.case_id] = outcome.status
                        reporter.record(case, outcome.status, outcome.reason)
                    reporter.tick()
        except BaseException:
            for future in futures:
                future.cancel()
            if owned is not None:
                owned.shutdown(wait=False, cancel_futures=True)
                owned = None
            raise
        finally:
            if owned is not None:
                owned.shutdown()
        summary = build_summary(out_dir)
    return SweepRun(computed=computed, skipped=skipped, lost=tuple(lost), summary=summary)


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
    ``missing``.  Case files of other sweeps in the folder are ignored.

    Parameters
    ----------
    out_dir : path
        A folder written by `run_sweep` (it needs ``sweep.json``).
    write : bool
        Also write ``summary.parquet`` (atomically).

    Returns
    -------
    pandas.DataFrame
    """
    import pandas as pd

    from brushbem.io import atomic_path

    out_dir = Path(out_dir)
    record = json.loads((out_dir / SWEEP_FILE).read_text(encoding="utf-8"))
    rows, summaries = [], []
    for entry in record["cases"]:
        row: dict[str, Any] = {
            key: entry[key] for key in ("case_id", "index", "realization", "seed", "seed_applied")
        }
        row.update(entry["values"])
        path = _case_path(out_dir, entry["case_id"])
        summary: dict[str, Any] = {}
        if path.exists():
            attributes = _case_attributes(path)
            row["status"] = attributes.get("status")
            row["reason"] = attributes.get("reason")
            row["wall_time_s"] = attributes.get("wall_time_s")
            summary = json.loads(attributes.get("summary", "null")) or {}
            provenance = {key: attributes.get(key) for key in ("brushbem_version", "backend")}
        else:
            row.update(status="missing", reason="not computed yet", wall_time_s=math.nan)
            provenance = {"brushbem_version": None, "backend": None}
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

    ``summary.parquet`` is read as it is unless it is missing, older than the
    case files or ``sweep.json`` (a killed or extended sweep), or ``rebuild``
    is set; then it is rebuilt with `build_summary` (and written where the
    folder is writable).

    Returns
    -------
    pandas.DataFrame
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
        if newest <= written:
            return pd.read_parquet(path, engine="pyarrow")
    try:
        return build_summary(out_dir)
    except OSError:  # a read-only results folder: summarise without writing
        return build_summary(out_dir, write=False)
