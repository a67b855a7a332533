"""`ParameterError`: a bad parameter of a numerics object, named as the object and its parameter.

The numerics and physics name the Python parameters they check (``LoadPath.step``,
``brush(stiffness=...)``, ``Grid.elements``), never configuration keys; the
run layer (`brushbem.runs.assembly`) maps ``(owner, parameter)`` back to the
configuration key a user wrote.  Imports nothing from brushbem.
"""

from __future__ import annotations

__all__ = ["ParameterError"]


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
