"""Reading a configuration (a TOML file or a mapping) into a `RunConfig`, and writing one back.

`load_config` reads the file within its limits (`brushbem.config.limits`,
`read_toml`, which reads sweep files within theirs too);
`parse_config` validates each section on its own and the rules between
sections on those that validated, so that one `ConfigError` lists every
problem.  `config_to_dict` gives the resolved configuration as JSON-able data
that re-parses to an equal `RunConfig`.
"""

from __future__ import annotations

import math
import os
import re
import tomllib
from collections.abc import Mapping
from pathlib import Path
from types import NoneType, UnionType
from typing import Any, Union, get_args, get_origin

from pydantic import BaseModel, ValidationError

from brushbem.results.plain import to_json_safe
from brushbem.config.errors import ConfigError, _capped, _dotted, _problem_lines, _show, did_you_mean
from brushbem.config.limits import _MAX_DEPTH, MAX_CONFIG_BYTES
from brushbem.config.rules import StructureRules, _cross_section_problems
from brushbem.config.schema import _SECTIONS, HalfSpaceConfig, IndenterConfig, RunConfig, _Section

__all__ = ["case_identity", "config_to_dict", "load_config", "nesting_depth", "parse_config", "read_toml"]


def _skipped_rule_lines(
    items: list[dict[str, Any]], model: type[BaseModel], raw: Any, prefix: tuple[Any, ...]
) -> list[str]:
    """Problems of the rules between keys that pydantic skipped in a failed table.

    ``items`` are the table's pydantic errors (locations relative to it).  If
    any of its values failed, its after-validator did not run; its rules are
    applied here to the keys as given, so that one pass reports them too.
    The same holds for each ``[[indenter.levels]]`` table and each sub-table
    with rules (``[indenter.tip]``, ``[indenter.grading]``).
    """
    if not (isinstance(raw, Mapping) and isinstance(model, type) and issubclass(model, _Section)):
        return []
    lines = []
    rules_ran = any(item["type"] == "config_rules" and not item["loc"] for item in items)
    if items and not rules_ran and any(item["loc"] for item in items):
        given = model.model_construct(**{k: v for k, v in raw.items() if k in model.model_fields})
        try:
            found = given._rule_problems()
        except (TypeError, ValueError, AttributeError, ArithmeticError):  # values of a type the fields refuse
            found = []
        for problem in found:
            lines.append(f"`{_dotted(prefix + (problem.key,))}`: {problem.value} — {problem.allowed}")
    for name, field in model.model_fields.items():  # lists of tables, e.g. [[indenter.levels]]
        annotation = field.annotation
        if get_origin(annotation) in (Union, UnionType):  # X | None
            annotation = next(a for a in get_args(annotation) if a is not NoneType)
        if isinstance(annotation, type) and issubclass(annotation, _Section) and isinstance(raw.get(name), Mapping):
            # A sub-table with rules of its own, e.g. [indenter.tip].
            nested = [{**item, "loc": tuple(item["loc"])[1:]} for item in items if tuple(item["loc"])[:1] == (name,)]
            lines.extend(_skipped_rule_lines(nested, annotation, raw[name], prefix + (name,)))
            continue
        if get_origin(annotation) is not tuple or not isinstance(raw.get(name), list):
            continue
        for i, table in enumerate(raw[name]):
            nested = [
                {**item, "loc": tuple(item["loc"])[2:]}
                for item in items
                if tuple(item["loc"])[:2] == (name, i)
            ]
            lines.extend(_skipped_rule_lines(nested, get_args(annotation)[0], table, prefix + (name, i)))
    return lines


def parse_config(mapping: Mapping[str, Any], base_dir: str | Path | None = None, *,
                 rules: StructureRules | None = None) -> RunConfig:
    """Validate a configuration mapping (a parsed TOML document).

    Parameters
    ----------
    mapping : mapping
        The document: tables ``halfspace``, ``grid``, ``indenter``,
        ``protocol`` and optionally ``solver``.
    base_dir : path, optional
        Folder against which relative file names (``indenter.file``) are
        resolved; the current directory if not given.
    rules : StructureRules, optional
        The rules on the rasterised structure (`brushbem.runs.assembly`); without
        them only the schema and the rules between keys are checked.

    Returns
    -------
    RunConfig

    Raises
    ------
    ConfigError
        Listing every problem found: each section is validated on its own, and
        the rules between sections run on every section that validated, so one
        pass reports them all.
    """
    if not isinstance(mapping, Mapping):
        raise ConfigError([f"``: {_show(mapping)} — must be a table of sections"])
    deep = _too_deep(mapping)
    if deep is not None:
        where = _dotted(deep)
        raise ConfigError([f"`{where}`: nested more than {_MAX_DEPTH} levels deep — a configuration nests at most 4"])
    context = {"base_dir": Path(base_dir) if base_dir is not None else Path.cwd()}
    problems: list[str] = []
    for key in mapping:
        if key not in _SECTIONS:
            problems.append(
                f"`{key}`: {_show(mapping[key])} — unknown key{did_you_mean(str(key), _SECTIONS)} "
                f"(allowed: {', '.join(_SECTIONS)})"
            )
    sections: dict[str, BaseModel] = {}
    for name, model in _SECTIONS.items():
        if name not in mapping:
            if RunConfig.model_fields[name].is_required():
                one_of = tuple(getattr(model, "REQUIRED_ONE_OF", ()))
                required = [key for key, field in model.model_fields.items() if field.is_required()]
                stated = getattr(model, "REQUIRED_TEXT", "")
                named = set(one_of) | {key for key in model.model_fields if key in stated.replace(",", " ").split()}
                optional = [key for key in model.model_fields if key not in required and key not in named]
                if sum(key.startswith("pillar_") for key in optional) > 1:
                    # The pillar model's options, one family: named once.
                    optional = [key for key in optional if not key.startswith("pillar_")] + \
                        ["pillar_* (method = 'pillars')"]
                needs = ([", ".join(required)] if required else []) + (
                    [f"exactly one of {' and '.join(one_of)}"] if one_of else []) + ([stated] if stated else [])
                others = (f" (optional: {', '.join(optional)})" if len(optional) <= 10 else
                          " (its other keys depend on these: docs/site/configuration.md)")
                problems.append(f"`{name}`: missing — a required table; give {'; '.join(needs) or 'the table'}"
                                + (others if optional else ""))
            continue
        try:
            sections[name] = model.model_validate(mapping[name], context=context)
        except ValidationError as exc:
            problems.extend(_problem_lines(exc, model, (name,)))
            problems.extend(
                _skipped_rule_lines(exc.errors(include_url=False), model, mapping[name], (name,))
            )
    if problems:
        for problem in _cross_section_problems(
            sections.get("grid"), sections.get("indenter"), sections.get("halfspace"), rules
        ):
            problems.append(f"`{problem.key}`: {problem.value} — {problem.allowed}")
        if "indenter" not in sections and "grid" in sections and rules is not None:
            # The layout's own keys may be valid where other indenter keys are not: its rasterised
            # checks (overlap, resolution, tiling) are reported in the same pass.
            geometry = _geometry_only(mapping.get("indenter"), context)
            if geometry is not None:
                halfspace = sections.get("halfspace") or HalfSpaceConfig(contact_modulus=1.0, work_of_adhesion=0.0)
                for problem in rules.structure_problems(sections["grid"], geometry, halfspace):
                    problems.append(f"`{problem.key}`: {problem.value} — {problem.allowed}")
        raise ConfigError(_capped(_one_line_per_mistake(problems)))
    try:
        # The sections are already validated instances: this runs only the
        # rules between sections.
        return RunConfig.model_validate(sections, context={"rules": rules})
    except ValidationError as exc:
        raise ConfigError(_problem_lines(exc, RunConfig, ())) from None


#: The brush keys that decide its rasterised layout (checked on their own when other keys fail).
_GEOMETRY_KEYS = ("shape", "layout", "region", "region_size", "pillars_per_side", "filling_factors", "spacing", "pillar_count",
                  "min_gap", "pillar_radius", "seed")


def _geometry_only(raw: Any, context: dict) -> IndenterConfig | None:
    """A brush's layout keys alone, as a valid indenter table (rigid pillars), or None if they fail too."""
    if not isinstance(raw, Mapping) or raw.get("shape") != "brush":
        return None
    table = {key: raw[key] for key in _GEOMETRY_KEYS if key in raw}
    table["stiffness"] = math.inf
    levels = raw.get("levels")
    if isinstance(levels, list) and all(isinstance(lv, Mapping) and isinstance(lv.get("cluster"), int)
                                        and not isinstance(lv.get("cluster"), bool) for lv in levels):
        table["levels"] = [{"cluster": lv["cluster"], "stiffness": math.inf} for lv in levels]
    try:
        return IndenterConfig.model_validate(table, context=context)
    except ValidationError:
        return None


def _one_line_per_mistake(problems: list[str]) -> list[str]:
    """Drops what follows from a misspelt key: its known twin reported missing or not given."""
    suggested = set(re.findall(r"^`([^`]*)\.[^.`]*`: .* did you mean `([^`]*)`\?", "\n".join(problems), re.MULTILINE))
    twins = {f"{section}.{name}" for section, name in suggested}
    return [line for line in problems
            if not (line.split("`")[1] in twins and ("not given" in line or "missing" in line))]


def _too_deep(document: Any) -> tuple[Any, ...] | None:
    """Location of a value nested deeper than `_MAX_DEPTH`, or None (iterative: no recursion)."""
    stack: list[tuple[Any, tuple[Any, ...]]] = [(document, ())]
    while stack:
        value, loc = stack.pop()
        if len(loc) > _MAX_DEPTH:
            return loc[:_MAX_DEPTH]
        if isinstance(value, Mapping):
            stack.extend((item, (*loc, key)) for key, item in value.items())
        elif isinstance(value, (list, tuple)):
            stack.extend((item, (*loc, i)) for i, item in enumerate(value))
    return None


#: What a run configuration is, in the messages of `read_toml`.
_CONFIG_KIND = "a run configuration (a few kB of TOML)"
_CONFIG_NESTING = "a configuration nests at most 4"

# The tokens of TOML text that matter for its nesting: brackets and braces, and
# the strings and comments in which they do not count.
_TOML_TOKENS = re.compile(
    r'''"""(?:[^\\]|\\.)*?"""|\'\'\'.*?\'\'\'|"(?:[^"\\\n]|\\.)*"|'[^'\n]*'|#[^\n]*|[\[\]{}]''',
    re.DOTALL,
)


def _bracket_depth(text: str) -> tuple[int, int]:
    """Deepest nesting of arrays and inline tables in TOML ``text``, and the line where it is reached.

    Brackets inside strings and comments do not count.  Only for the message
    when the TOML reader runs out of recursion: an approximate count of
    invalid text is good enough there.
    """
    depth = deepest = position = 0
    for token in _TOML_TOKENS.finditer(text):
        mark = token.group()
        if mark in "[{":
            depth += 1
            if depth > deepest:
                deepest, position = depth, token.start()
        elif mark in "]}":
            depth = max(depth - 1, 0)
    return deepest, text.count("\n", 0, position) + 1


def nesting_depth(document: Any) -> tuple[int, tuple[Any, ...]]:
    """Length of the longest key path in ``document``, and that path (iterative: no recursion).

    ``{"a": {"b": 1}}`` nests 2 deep (``a.b``).  Only tables and arrays are
    pushed on the stack, so a list of 100 000 numbers costs one pass over it.
    """
    def container(value: Any) -> bool:  # the common scalars first: the Mapping check is slow
        return isinstance(value, (dict, list, tuple)) or (
            not isinstance(value, (int, float, str)) and isinstance(value, Mapping))

    deepest: tuple[Any, ...] = ()
    stack: list[tuple[Any, tuple[Any, ...]]] = [(document, ())] if container(document) else []
    while stack:
        value, loc = stack.pop()
        items = value.items() if isinstance(value, Mapping) else enumerate(value)
        if len(loc) > len(deepest):
            deepest = loc
        below = len(loc) + 1
        for key, item in items:
            if container(item):
                stack.append((item, (*loc, key)))
            elif below > len(deepest):
                deepest = (*loc, key)
    return len(deepest), deepest


def _where(loc: tuple[Any, ...]) -> str:
    """A long key path shown by its first parts."""
    shown = _dotted(loc[:6])
    return shown if len(loc) <= 6 else f"{shown}...(+{len(loc) - 6})"


def read_toml(
    path: str | Path,
    *,
    max_bytes: int = MAX_CONFIG_BYTES,
    max_depth: int = _MAX_DEPTH,
    kind: str = _CONFIG_KIND,
    nesting: str = _CONFIG_NESTING,
) -> dict[str, Any]:
    """Read a TOML file within a size and a nesting limit.

    The size is checked before the file is parsed; the nesting of the parsed
    document (and the TOML reader's own recursion) after.

    Parameters
    ----------
    path : path
        The file.
    max_bytes, max_depth : int
        The limits (`brushbem.config.limits`): a run configuration's by default.
    kind, nesting : str
        What the file is and how deep it needs to nest, for the messages.

    Returns
    -------
    dict
        The TOML document.

    Raises
    ------
    ConfigError
        If the file is missing, unreadable, too large, not UTF-8, not valid
        TOML or nested too deeply; each message names the file, the value
        found and the limit.
    """
    path = Path(path)
    try:
        with path.open("rb") as stream:
            data = stream.read(max_bytes + 1)
            size = os.fstat(stream.fileno()).st_size
    except FileNotFoundError:
        raise ConfigError([f"`{path}`: file not found"]) from None
    except OSError as exc:
        raise ConfigError([f"`{path}`: cannot be read ({exc.strerror or exc})"]) from None
    if len(data) > max_bytes:
        found = f"{size} bytes" if size > max_bytes else f"more than {max_bytes} bytes"
        raise ConfigError([f"`{path}`: {found} — larger than {max_bytes} bytes, the limit for {kind}"])
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise ConfigError([f"`{path}`: not UTF-8 text ({exc.reason} at byte {exc.start})"]) from None
    if text.startswith("\ufeff"):
        raise ConfigError([f"`{path}`: starts with a byte-order mark (U+FEFF), which TOML does not allow; save the "
                           "file as UTF-8 without BOM (e.g. in the editor's encoding menu, or: sed -i '1s/^\\xEF\\xBB"
                           "\\xBF//' FILE)"])
    try:
        document = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError([f"`{path}`: not valid TOML ({exc})"]) from None
    except RecursionError:  # tomllib recurses once per nested array or inline table
        depth, line = _bracket_depth(text)
        raise ConfigError([
            f"`{path}`: arrays or tables nested too deeply ({depth} levels, line {line}) — must not be "
            f"nested more than {max_depth} levels deep; {nesting}"
        ]) from None
    depth, loc = nesting_depth(document)
    if depth > max_depth:
        raise ConfigError([
            f"`{path}`: nested {depth} levels deep (at `{_where(loc)}`) — must not be nested more than "
            f"{max_depth} levels deep; {nesting}"
        ])
    return document


def load_config(path: str | Path, *, rules: StructureRules | None = None) -> RunConfig:
    """Read and validate a TOML run configuration (``rules``: see `parse_config`).

    Parameters
    ----------
    path : path
        The TOML file.  Relative file names inside it are resolved against its
        folder.

    Returns
    -------
    RunConfig

    Raises
    ------
    ConfigError
        If the file is missing or unreadable, larger than `MAX_CONFIG_BYTES`,
        nested too deeply, is not valid TOML, or any value is not allowed
        (every problem listed).
    """
    path = Path(path)
    document = read_toml(path)
    return parse_config(document, base_dir=path.resolve().parent, rules=rules)


def config_to_dict(config: RunConfig) -> dict[str, Any]:
    """The resolved configuration as plain JSON-able data.

    Defaults are filled in, ``indenter.file`` is absolute, and an infinite
    value (a rigid ``stiffness``) is written as the string ``"inf"``.  The
    result re-parses with `parse_config` to an equal `RunConfig`.

    Parameters
    ----------
    config : RunConfig

    Returns
    -------
    dict
    """
    data = config.model_dump(mode="python")
    indenter = data["indenter"]
    # Keys a shape does not use are dropped, and the default rigid
    # `stiffness` is not written beside a `stiffness_ratio` (exactly one of
    # them may be given), so the result re-parses to an equal config.
    for key in [k for k, v in indenter.items() if v is None]:
        del indenter[key]
    if indenter.get("stiffness_ratio") is not None:
        indenter.pop("stiffness", None)
    for level in indenter.get("levels") or ():
        for key in [k for k, v in level.items() if v is None]:
            del level[key]
    for table in ("roughness", "profile", "tip", "tilt", "grading", "viscoelastic", "pillar_law", "fibril"):
        if isinstance(indenter.get(table), dict):
            indenter[table] = {k: v for k, v in indenter[table].items() if v is not None}
    for level in indenter.get("levels") or ():
        if isinstance(level.get("grading"), dict):
            level["grading"] = {k: v for k, v in level["grading"].items() if v is not None}
    # Keys added to the schema later are left out while unset, so the resolved
    # configuration, and with it every sweep's case hashes, stays what it was
    # for a configuration that does not use them (a sweep folder resumes).
    for key in _LATER_PROTOCOL_KEYS:
        if key in data["protocol"] and data["protocol"][key] == type(config.protocol).model_fields[key].default:
            del data["protocol"][key]
    if not any(value is not None for value in data.get("units", {}).values()):
        data.pop("units", None)  # names only: the default (dimensionless) leaves case hashes as they were
    return to_json_safe(data)


def case_identity(config: RunConfig) -> dict[str, Any]:
    """`config_to_dict` as a case's identity (its hash, `brushbem.sweep.spec`) reads it: a key whose default
    changed after sweeps were recorded (`_RECORDED_PROTOCOL`) is left out at the value those sweeps ran at, and
    named otherwise, at the value the run takes.  So a sweep that names that value keeps its recorded case
    hashes, and a configuration that leaves the key to today's default is a case of its own."""
    data = config_to_dict(config)
    for key, recorded in _RECORDED_PROTOCOL.items():
        taken = getattr(config.protocol, _TAKEN[key])
        if taken == recorded:
            data["protocol"].pop(key, None)
        else:
            data["protocol"][key] = taken
    return data


#: Protocol keys whose default changed after sweeps were recorded, at the value those sweeps ran at
#: (`case_identity`): ``pillar_tip_peel`` unset was false until the pillar model's tips left at their
#: continuum capacity by default.
_RECORDED_PROTOCOL = {"pillar_tip_peel": False}
#: The attribute of `ProtocolConfig` that holds the value a run takes for each of them.
_TAKEN = {"pillar_tip_peel": "tip_peel"}

#: Protocol keys that arrived after sweeps were first recorded: omitted while at their schema default,
#: so the case hashes of the recorded sweeps stay what they were.
_LATER_PROTOCOL_KEYS = ("speed", "event_window", "pillar_modes", "pillar_near", "pillar_solve",
                        "pillar_tip_resolution", "pillar_tip_calibration", "pillar_tip_peel")
