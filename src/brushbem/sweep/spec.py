"""The sweep file and its expansion into cases.

`SweepSpec` is the sweep file as written; `parse_sweep` (a mapping) and
`load_sweep` (a TOML file) validate it, report every problem of the file and
of every expanded case at once (`SweepError`), draw the per-realization
seeds and give each case its id (index and hash of the resolved
configuration and seed): a `Sweep` of
`SweepCase` objects.  The file's size (`MAX_SWEEP_BYTES`), its nesting
(`MAX_SWEEP_DEPTH`) and the number of cases it expands to
(`MAX_SWEEP_CASES`, counted before any case is built) are bounded
(`brushbem.config.limits`).
"""

from __future__ import annotations

import copy
import dataclasses
import functools
import hashlib
import itertools
import json
import math
import os
import re
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Annotated, Any, Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationError

from brushbem import __version__
from brushbem.runs.assembly import parse_config
from brushbem.config import (
    MAX_CONFIG_BYTES,
    MAX_SWEEP_BYTES,
    MAX_SWEEP_CASES,
    MAX_SWEEP_DEPTH,
    ConfigError,
    RunConfig,
    case_identity,
    config_to_dict,
    nesting_depth,
    read_toml,
)
from brushbem.results.plain import to_json_safe
from brushbem.sweep.errors import SweepError, _show

# A dotted run-config key: bare TOML names joined by dots.
_DOTTED_KEY = re.compile(r"[A-Za-z0-9_-]+(\.[A-Za-z0-9_-]+)*")


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
    refine : int or None
        Run every case on 2 or 3 grids and record the Richardson-extrapolated
        F_A and work (`brushbem.runs.refine`, as ``brushbem run --refine``).
    sweep : dict
        Dotted run-config key -> non-empty list of values.
    """

    model_config = ConfigDict(extra="forbid", frozen=True, strict=True)

    base: str | dict[str, Any]
    mode: Literal["product", "zip"] = "product"
    realizations: int = Field(1, ge=1, le=1_000_000)
    seed: int = Field(0, ge=0)
    refine: int | None = Field(None, ge=2, le=3)
    sweep: dict[str, Annotated[list[Any], Field(min_length=1)]] = Field(default_factory=dict)


_ALLOWED = {
    "base": "a run-configuration file name (relative to the sweep file) or an inline [base] table",
    "mode": "one of 'product', 'zip'",
    "realizations": "an integer in [1, 1000000]",
    "seed": "an integer >= 0 (the entropy of numpy.random.SeedSequence)",
    "refine": "2 or 3: run every case on that many grids N / 2^k and extrapolate (brushbem run --refine)",
    "sweep": "a table of dotted run-configuration keys, each with a list of values",
}


def case_hash(case_id: Any) -> str:
    """A case's hash, its id ``<index>-<hash>`` without the index: the same case in two sweep files
    (a sampled subset and its full sweep) or in a committed table."""
    return str(case_id).split("-", 1)[-1]


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
            **({"refine": self.spec.refine} if self.spec.refine is not None else {}),
            "seed_policy": (
                "numpy.random.SeedSequence(seed).spawn(realizations): one child per "
                "realization, shared by all parameter points; its first 32-bit word "
                "generate_state(1, uint32)[0] is the case seed"
            ),
            "sweep": self.spec.sweep,
            "base": self.base,
            "cases": [case.record() for case in self.cases],
        })


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
    # Each key's dotted prefixes looked up, not every pair compared: a table of
    # thousands of keys is checked at once.
    order = {key: i for i, key in enumerate(keys)}
    overlaps = sorted(
        (order[a], order[b])
        for b in keys
        for a in (".".join(b.split(".")[:n]) for n in range(1, b.count(".") + 1))
        if a in order
    )
    for i, j in overlaps:
        problems.append(f"`{_quoted(keys[j])}`: overlaps `{_quoted(keys[i])}` — set each value once")
    if spec.mode == "zip" and len({len(values) for values in spec.sweep.values()}) > 1:
        lengths = ", ".join(f"{key} has {len(values)}" for key, values in spec.sweep.items())
        problems.append(f"`sweep`: lists of different lengths ({lengths}) — mode 'zip' needs equal lengths")
    return problems


def _case_count_problem(spec: SweepSpec) -> str | None:
    """The problem of a sweep expanding to more than `MAX_SWEEP_CASES` cases, counted without building one.

    The count is the product of the lists' lengths (mode "product") or their
    common length (mode "zip"), times ``realizations``; the keys that make it
    are named.
    """
    lengths = {key: len(values) for key, values in spec.sweep.items()}
    if spec.mode == "zip":
        points = next(iter(lengths.values()), 1)
        factors = [(f"`sweep` (mode 'zip': {', '.join(map(_quoted, lengths))})", points)] if points > 1 else []
    else:
        points = math.prod(lengths.values())
        factors = [(f"`{_quoted(key)}`", n) for key, n in lengths.items() if n > 1]
    if spec.realizations > 1:
        factors.append(("`realizations`", spec.realizations))
    count = points * spec.realizations
    if count <= MAX_SWEEP_CASES:
        return None
    names = " x ".join(name for name, _ in factors)
    product = " x ".join(str(n) for _, n in factors) + f" = {count}" if len(factors) > 1 else str(count)
    return (f"{names}: {product} cases — a sweep expands to at most {MAX_SWEEP_CASES} cases "
            "(brushbem.config.MAX_SWEEP_CASES); split it into several sweep files")


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
    """One seed per realization from one SeedSequence (see the `brushbem.sweep` docstring)."""
    children = np.random.SeedSequence(seed).spawn(realizations)
    return [int(child.generate_state(1, dtype=np.uint32)[0]) for child in children]


def _file_contents(node: Any) -> Any:
    """``node`` with every file it names replaced by the SHA-256 of the file's bytes.

    A validated configuration names its files (lengths, per-pillar radii, height
    maps) by absolute path; a case is what it computes, so its id must not
    change when the same file is read from another folder (a moved study, the
    package installed elsewhere).
    """
    if isinstance(node, dict):
        return {key: _file_contents(value) for key, value in node.items()}
    if isinstance(node, list):
        return [_file_contents(value) for value in node]
    if isinstance(node, str) and os.path.isabs(node) and os.path.isfile(node):
        stat = os.stat(node)
        return _file_digest(node, stat.st_size, stat.st_mtime_ns)
    return node


@functools.lru_cache(maxsize=256)
def _file_digest(path: str, size: int, mtime_ns: int) -> str:
    """SHA-256 of a file, read once per (path, size, modification time): a sweep names the same file
    in every case."""
    return "sha256:" + hashlib.sha256(Path(path).read_bytes()).hexdigest()


def _case_hash(config: RunConfig, seed: int) -> str:
    """First 10 hex digits of SHA-256 over the resolved configuration and the seed.

    Files named by the configuration enter by their contents, not their paths;
    ``[units]`` does not enter (it names the units, the case is the same).
    """
    resolved = case_identity(config)
    resolved.pop("units", None)
    text = json.dumps(
        {"config": _file_contents(resolved), "seed": seed},
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
    if not base_file.exists():
        raise SweepError([f"`base`: {_show(base)} — file not found (looked for {base_file})"])
    try:
        # A run configuration: read within a run configuration's limits.
        document = read_toml(base_file, max_bytes=MAX_CONFIG_BYTES)
    except ConfigError as error:
        raise SweepError([f"`base`: {_show(base)} — cannot be read as a run configuration: {problem}"
                          for problem in error.problems]) from None
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
    depth, deepest = nesting_depth(document)
    if depth > MAX_SWEEP_DEPTH:
        where = ".".join(str(part) for part in deepest[:6]) + (f"...(+{depth - 6})" if depth > 6 else "")
        raise SweepError([f"`{where}`: nested {depth} levels deep — a sweep nests at most {MAX_SWEEP_DEPTH} "
                          "levels (brushbem.config.MAX_SWEEP_DEPTH)"])
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
    too_many = _case_count_problem(spec)  # before the base is read or any case is built
    if too_many:
        raise SweepError([too_many])
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
        If the file cannot be read, is larger than `MAX_SWEEP_BYTES`, nests
        deeper than `MAX_SWEEP_DEPTH`, expands to more than `MAX_SWEEP_CASES`
        cases, or any case is invalid (every problem listed).
    """
    path = Path(path)
    try:
        document = read_toml(
            path, max_bytes=MAX_SWEEP_BYTES, max_depth=MAX_SWEEP_DEPTH,
            kind="a sweep file (the largest shipped one is 58 kB)",
            nesting="a sweep file needs at most 7 (a configuration's 4, and 3 more for a swept value)",
        )
    except ConfigError as error:
        raise SweepError(error.problems) from None
    return parse_sweep(document, path.resolve().parent, source=path)
