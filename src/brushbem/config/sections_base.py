"""The base models of the configuration's tables and the helpers their validators share.

`_Model` (strict, frozen, closed, numbers within `MAGNITUDE_RANGE`) and
`_Section` (a table with rules between its keys, `_rule_problems`), the
checks of a choice key's dependent keys (`_choice_problems`), of a
per-pillar ``.npy`` file (`_per_pillar_file`) and the ``"inf"`` string of a
recorded configuration (`_inf_from_string`).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from pydantic import (
    BaseModel,
    ConfigDict,
    ValidationInfo,
    field_validator,
    model_validator,
)

from brushbem.config.errors import _describe_allowed, _show
from brushbem.config.files import _existing_file, _read_numbers
from brushbem.config.limits import MAGNITUDE_RANGE
from brushbem.config.rules import Problem, _rules_error


# Strict: a TOML ``size = "1.0"`` or ``elements = true`` is a mistake to report,
# not a value to coerce.  Frozen: the numerics may cache on a config safely.
_MODEL_CONFIG = ConfigDict(extra="forbid", frozen=True, strict=True)


class _Model(BaseModel):
    """A table of the configuration: strict, frozen, closed, numbers within `MAGNITUDE_RANGE`."""

    model_config = _MODEL_CONFIG

    @field_validator("*", mode="after")
    @classmethod
    def _magnitude(cls, value: Any, info: ValidationInfo) -> Any:
        low, high = MAGNITUDE_RANGE
        number = isinstance(value, (int, float)) and not isinstance(value, bool)
        finite = number and (isinstance(value, int) or math.isfinite(value))  # a TOML integer may exceed 1e308
        if finite and value != 0 and not low <= abs(value) <= high:
            raise ValueError(f"must be {_describe_allowed(cls.model_fields[info.field_name])}")
        return value


class _Section(_Model):
    """A table of the configuration, with rules between its keys.

    A rule between keys ("exactly one of ...", "the keys each shape needs")
    is `_rule_problems`; it reads only which keys are given and the values of
    choice keys, so `rule_problems_of_raw` can apply it to a table whose values
    failed their own checks - pydantic skips an after-validator then, and the
    rule's problem would otherwise surface one run later.
    """

    model_config = _MODEL_CONFIG

    def _rule_problems(self) -> list[Problem]:
        return []

    @model_validator(mode="after")
    def _rules(self) -> _Section:
        problems = self._rule_problems()
        if problems:
            raise _rules_error(problems)
        return self


def _inf_from_string(value: Any) -> Any:
    # `config_to_dict` writes infinity as the string "inf" (JSON has no
    # infinity); accept it back so a recorded config re-parses.
    if isinstance(value, str) and value == "inf":
        return math.inf
    return value


def _per_pillar_file(value: Any, info: ValidationInfo) -> Any:
    """A tip parameter given as a file name: resolved and read as 1-D numbers > 0 (one per pillar)."""
    if not isinstance(value, str):
        return value
    path = _existing_file(value, info)
    numbers = _read_numbers(path)
    if numbers.ndim != 1:
        raise ValueError(f"holds an array of shape {numbers.shape} ({path}); must hold a 1-D array of one value > 0 "
                         "per pillar")
    if numbers.size and not bool(np.all(numbers > 0)):
        smallest = float(numbers.min())
        raise ValueError(f"holds values down to {smallest:g} (at index {int(np.argmin(numbers))}, {path}); every "
                         f"value must be > 0, between {MAGNITUDE_RANGE[0]:g} and {MAGNITUDE_RANGE[1]:g}")
    if numbers.size and float(numbers.min()) < MAGNITUDE_RANGE[0]:
        raise ValueError(f"holds values down to {float(numbers.min()):g} ({path}); every value must be at least "
                         f"{MAGNITUDE_RANGE[0]:g}")
    return str(path)


def _choice_problems(table: _Section, choice: str, uses: dict[str, tuple[tuple[str, ...], tuple[str, ...]]],
                     prefix: str) -> list[Problem]:
    """The keys a choice key's value needs and allows: ``uses[value] = (required, optional)``.

    A required key that is absent and a given key that this value does not
    use are problems; a value outside ``uses`` is the choice key's own
    problem (reported by its field).
    """
    value = getattr(table, choice, None)
    if not isinstance(value, str) or value not in uses:
        return []
    required, optional = uses[value]
    keys = sorted({key for need, allow in uses.values() for key in (*need, *allow)})
    problems = []
    for key in keys:
        given = getattr(table, key, None)
        if key in required and given is None:
            problems.append(Problem(key, "missing", f"required when {prefix}.{choice} = {value!r}"))
        elif key not in required and key not in optional and given is not None:
            users = " or ".join(repr(v) for v, (need, allow) in uses.items() if key in need or key in allow)
            problems.append(Problem(key, _show(given), f"only used with {prefix}.{choice} = {users}; remove it"))
    return problems
