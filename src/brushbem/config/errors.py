"""`ConfigError` and the problem lines it lists.

Every problem is one line, ``"`dotted.key`: value — what is allowed"``: the
value is shown short (`show_value`), and what is allowed is derived from the
field's type and constraints (`_describe_allowed`), so a message never
disagrees with the check.  `_problem_lines` turns a pydantic ValidationError
into such lines, including the problems of the rules between keys
(`brushbem.config.rules`), which travel through pydantic as ``config_rules``
errors.
"""

from __future__ import annotations

from types import NoneType, UnionType
from typing import Any, Literal, Union, get_args, get_origin

from pydantic import BaseModel, ValidationError

from brushbem.config.limits import _MAX_PROBLEMS, _MAX_SHOWN, MAGNITUDE_RANGE

__all__ = ["ConfigError", "show_value"]


class ConfigError(ValueError):
    """A run configuration that cannot be used.

    Parameters
    ----------
    problems : list of str
        One human-readable line per problem, each of the form
        ``"`dotted.key`: value — what is allowed"``.
    """

    def __init__(self, problems: list[str]) -> None:
        self.problems = list(problems)
        super().__init__("\n".join(self.problems))


def show_value(value: Any) -> str:
    """Short representation of a user value for a problem line."""
    return _show(value)


def _show(value: Any) -> str:
    """Short representation of a user value for a problem line."""
    if value is None:  # an optional key left out (TOML has no null)
        return "not given"
    value = _as_given(value)
    # repr gives "nan", "inf", "0.003" for floats: what the user wrote in TOML.
    text = repr(value)
    if len(text) > _MAX_SHOWN:
        text = text[: _MAX_SHOWN - 3] + "..."
    return text


def _as_given(value: Any) -> Any:
    """A validated table (or a tuple of them) as the keys the user gave, not as the model's repr."""
    if isinstance(value, BaseModel):
        return {key: _as_given(getattr(value, key)) for key in type(value).model_fields if key in value.model_fields_set}
    if isinstance(value, tuple):  # a TOML array, stored as a tuple by the frozen models
        return [_as_given(item) for item in value]
    return value


def _dotted(loc: tuple[Any, ...]) -> str:
    return ".".join(str(part) for part in loc if part != "")


def _field_at(model: type[BaseModel], loc: tuple[Any, ...]) -> Any:
    """The pydantic FieldInfo at ``loc`` below ``model``, or None."""
    field = None
    current: Any = model
    for part in loc:
        if get_origin(current) in (Union, UnionType):  # X | None
            members = [a for a in get_args(current) if a is not NoneType]
            current = members[0] if len(members) == 1 else current
        if isinstance(part, int) and get_origin(current) is tuple:  # tuple[Model, ...] item
            current = get_args(current)[0]
            continue
        if not (isinstance(current, type) and issubclass(current, BaseModel)):
            return None
        field = current.model_fields.get(part) if isinstance(part, str) else None
        if field is None:
            return None
        current = field.annotation
    return field


def _describe_allowed(field: Any) -> str:
    """What a field accepts, derived from its type and constraints (or its ``description``, where it has one)."""
    if getattr(field, "description", None):  # a field whose type alone does not say it (a number or a file)
        return field.description
    annotation = field.annotation
    if get_origin(annotation) in (Union, UnionType):
        members = [a for a in get_args(annotation) if a is not NoneType]
        annotation = members[0] if len(members) == 1 else annotation
    finite = any(getattr(m, "allow_inf_nan", None) is False for m in field.metadata)
    if get_origin(annotation) is Literal:
        return "one of " + ", ".join(repr(a) for a in get_args(annotation))
    if annotation is int:
        kind = "an integer"
    elif annotation is float:
        kind = "a finite number" if finite else "a number"
    elif annotation is str:
        kind = "a string"
    elif isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return "a table with keys " + ", ".join(annotation.model_fields)
    elif get_origin(annotation) is tuple:
        item = get_args(annotation)[0] if get_args(annotation) else None
        if isinstance(item, type) and issubclass(item, BaseModel):
            return "an array of tables with keys " + ", ".join(item.model_fields)
        low, high = MAGNITUDE_RANGE
        return f"an array of numbers, each 0 or between {low:g} and {high:g} in magnitude"
    elif get_origin(annotation) in (Union, UnionType):
        names = {float: "a number", int: "an integer", str: "a string"}
        kinds = [names.get(a, getattr(a, "__name__", str(a))) for a in get_args(annotation) if a is not NoneType]
        return " or ".join(kinds)
    else:
        kind = "a value"
    # Field(gt=..., le=...) stores one annotated-types object per bound, each
    # with an attribute named after the bound.
    low = high = None
    for m in field.metadata:
        if getattr(m, "gt", None) is not None:
            low = f"> {m.gt:g}", "(", m.gt
        elif getattr(m, "ge", None) is not None:
            low = f">= {m.ge:g}", "[", m.ge
        elif getattr(m, "lt", None) is not None:
            high = f"< {m.lt:g}", ")", m.lt
        elif getattr(m, "le", None) is not None:
            high = f"<= {m.le:g}", "]", m.le
    if low and high:
        text = f"{kind} in {low[1]}{low[2]:g}, {high[2]:g}{high[1]}"
    elif low or high:
        text = f"{kind} {(low or high)[0]}"
    else:
        text = kind
    if annotation is float:
        text += _magnitude_clause(low, high)
    if annotation is float and not finite:
        text += ", or inf"
    return text


def _describe_item(field: Any) -> str:
    """What one item of an array field accepts."""
    annotation = field.annotation
    if get_origin(annotation) in (Union, UnionType):
        annotation = next((a for a in get_args(annotation) if a is not NoneType), annotation)
    item = get_args(annotation)[0] if get_origin(annotation) is tuple and get_args(annotation) else None
    if isinstance(item, type) and issubclass(item, BaseModel):
        return "a table with keys " + ", ".join(item.model_fields)
    return "a number"


def _magnitude_clause(low: tuple | None, high: tuple | None) -> str:
    """The part of `MAGNITUDE_RANGE` that a float field's own bounds do not already imply.

    ``low`` and ``high`` are the ``(text, bracket, value)`` bounds of
    `_describe_allowed` (None where unbounded).
    """
    smallest, largest = MAGNITUDE_RANGE
    below = low is None or low[2] < smallest  # nonzero values under `smallest` pass the bounds
    above = high is None or high[2] > largest
    negative = low is None or low[2] < 0
    zero = (low is None or low[2] < 0 or (low[2] == 0 and low[1] == "[")) and (high is None or high[2] > 0)
    what = "in magnitude" if negative else ""
    zero_text = "0 or " if zero else ""
    sep = ": " if zero else ", "
    if below and above:
        return f"{sep}{zero_text}between {smallest:g} and {largest:g}{' ' + what if what else ''}"
    if below:
        return f"{sep}{zero_text}at least {smallest:g}{' ' + what if what else ''}"
    if above:
        return f", at most {largest:g}"
    return ""


def _problem_lines(
    error: ValidationError, model: type[BaseModel], prefix: tuple[str, ...]
) -> list[str]:
    """One line per pydantic error, ``"`dotted.key`: value — what is allowed"``."""
    lines = []
    for item in error.errors(include_url=False):
        loc = tuple(item["loc"])
        kind = item["type"]
        if kind == "config_rules":
            for problem in item["ctx"]["problems"]:
                key = _dotted(prefix + loc + (problem.key,))
                lines.append(f"`{key}`: {problem.value} — {problem.allowed}")
            continue
        key = _dotted(prefix + loc)
        field = _field_at(model, loc)
        if kind == "extra_forbidden":
            parent = _field_at(model, loc[:-1]) if len(loc) > 1 else None
            owner = _model_of(parent.annotation) if parent is not None else model
            names = list(owner.model_fields) if hasattr(owner, "model_fields") else []
            lines.append(f"`{key}`: {_show(item['input'])} — unknown key{did_you_mean(str(loc[-1]), names)} "
                         f"(allowed: {', '.join(names)})")
        elif kind == "missing":
            allowed = _describe_allowed(field) if field is not None else "a value"
            lines.append(f"`{key}`: missing — required, {allowed}")
        elif kind == "value_error" and not key:
            # A rule between sections that failed as a whole: never echo the whole document back.
            lines.append(f"`configuration`: the sections as given — {item['ctx']['error']}")
        elif kind == "value_error":
            # Raised by our own field validators: their message is the explanation.
            lines.append(f"`{key}`: {_show(item['input'])} — {item['ctx']['error']}")
        elif kind == "model_type" and not loc:
            # The whole section is not a table (e.g. ``grid = 5``).
            allowed = "a table with keys " + ", ".join(model.model_fields)
            lines.append(f"`{key}`: {_show(item['input'])} — must be {allowed}")
        elif field is not None:
            allowed = _describe_allowed(field)
            if loc and isinstance(loc[-1], int):  # one item of an array
                allowed = _describe_item(field)
            lines.append(f"`{key}`: {_show(item['input'])} — must be {allowed}")
        else:
            lines.append(f"`{key}`: {_show(item['input'])} — {item['msg']}")
    return lines


def _capped(problems: list[str]) -> list[str]:
    """At most `_MAX_PROBLEMS` lines; a file with thousands of problems is counted, not listed."""
    if len(problems) <= _MAX_PROBLEMS:
        return problems
    return [*problems[:_MAX_PROBLEMS], f"`...`: {len(problems) - _MAX_PROBLEMS} more problems not shown"]


def did_you_mean(name: str, candidates) -> str:
    """`` — did you mean `x`?`` for the closest known name, or "" when none is close."""
    import difflib

    match = difflib.get_close_matches(name, list(candidates), n=1, cutoff=0.75)
    return f" — did you mean `{match[0]}`?" if match else ""


def _model_of(annotation):
    """The model class of an annotation (``X | None`` and ``tuple[X, ...]`` unwrapped), or the annotation."""
    import typing

    for arg in typing.get_args(annotation) or ():
        if hasattr(arg, "model_fields"):
            return arg
        inner = _model_of(arg)
        if hasattr(inner, "model_fields"):
            return inner
    return annotation
