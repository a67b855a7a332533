"""`ParameterError`: a bad parameter of a numerics object, named as the object and its parameter;
`ParameterProblem`: the same as a value, what a rule returns.

The numerics and physics name the Python parameters they check (``LoadPath.step``,
``brush(stiffness=...)``, ``Grid.elements``), never configuration keys; the
run layer (`brushbem.runs.assembly`) maps ``(owner, parameter)`` back to the
configuration key a user wrote.  A rule between parameters lives with the
object that owns it, as a predicate that returns `ParameterProblem` values
(every problem at once); the load paths raise the first (`ParameterProblem.error`),
the configuration collects them all and names each by its key.  Imports
nothing from brushbem.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

__all__ = ["ParameterError", "ParameterProblem", "raise_first"]


class ParameterError(ValueError):
    """A parameter that cannot be used.

    Parameters
    ----------
    owner : str
        The object or function the parameter belongs to: ``"LoadPath"``, ``"Grid"``, ``"brush"``.
    parameter : str
        The parameter's name: ``"preload_displacement"``.
    message : str
        What is wrong, naming the parameter (``"LoadPath.step = -1 must be > 0"``).
    """

    def __init__(self, owner: str, parameter: str, message: str) -> None:
        self.owner = owner
        self.parameter = parameter
        self.message = message
        super().__init__(message)

    @property
    def name(self) -> str:
        """``owner.parameter``, as the message writes it."""
        return f"{self.owner}.{self.parameter}"


@dataclass(frozen=True)
class ParameterProblem:
    """One problem a rule found: whose parameter, its value, and what is allowed.

    ``allowed`` names other parameters as ``Owner.parameter`` (the configuration
    reads each as its key); ``value`` is the parameter's value as given (None:
    not given).
    """

    owner: str
    parameter: str
    value: Any
    allowed: str

    @property
    def name(self) -> str:
        """``owner.parameter``."""
        return f"{self.owner}.{self.parameter}"

    @property
    def message(self) -> str:
        """``Owner.parameter = value: allowed`` (``Owner.parameter: allowed`` where no value was given)."""
        shown = "" if self.value is None else f" = {self.value!r}"
        return f"{self.name}{shown}: {self.allowed}"

    def error(self) -> ParameterError:
        """The problem raised: a `ParameterError` of its owner and parameter."""
        return ParameterError(self.owner, self.parameter, self.message)


def raise_first(problems: list[ParameterProblem]) -> None:
    """Raise the first of ``problems`` as a `ParameterError` (nothing without problems)."""
    if problems:
        raise problems[0].error()
