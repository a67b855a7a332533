"""The tables of the body and the domain: `HalfSpaceConfig` (the elastic half-space) and `GridConfig`."""

from __future__ import annotations

from typing import ClassVar

from pydantic import Field

from brushbem.config.errors import _show
from brushbem.config.rules import Problem
from brushbem.config.sections_base import _MODEL_CONFIG, _Model, _Section
from brushbem.physics import scales


class HalfSpaceConfig(_Section):
    """The elastic half-space.

    Give either ``contact_modulus`` (E*) or both ``youngs_modulus`` and
    ``poisson_ratio``; the numerics use only E*, see `effective_modulus`.

    Attributes
    ----------
    contact_modulus : float or None
        E*, in units of stress.
    youngs_modulus : float or None
        Young's modulus E of the half-space, in units of stress.
    poisson_ratio : float or None
        Poisson's ratio nu of the half-space, dimensionless, in [0, 0.5] (0.5: incompressible, every elastomer; E* = 4 E / 3).
    work_of_adhesion : float
        Delta gamma, in units of energy per area (stress x length); 0 means no
        adhesion.
    """

    model_config = _MODEL_CONFIG
    #: What a missing [halfspace] must give (the message names it).
    REQUIRED_TEXT: ClassVar[str] = "contact_modulus, or youngs_modulus and poisson_ratio"

    contact_modulus: float | None = Field(None, gt=0, allow_inf_nan=False)
    youngs_modulus: float | None = Field(None, gt=0, allow_inf_nan=False)
    poisson_ratio: float | None = Field(None, ge=0, le=0.5, allow_inf_nan=False)
    work_of_adhesion: float = Field(0.0, ge=0, allow_inf_nan=False)

    def _rule_problems(self) -> list[Problem]:
        by_contact = self.contact_modulus is not None
        by_young = self.youngs_modulus is not None or self.poisson_ratio is not None
        complete_young = self.youngs_modulus is not None and self.poisson_ratio is not None
        if by_contact == by_young or (by_young and not complete_young):
            given = ", ".join(
                f"{name} = {_show(getattr(self, name))}"
                for name in ("contact_modulus", "youngs_modulus", "poisson_ratio")
            )
            return [Problem("", given, "give either contact_modulus (E*) or both youngs_modulus and poisson_ratio")]
        return []

    @property
    def effective_modulus(self) -> float:
        """E* = E / (1 - nu^2), in units of stress."""
        if self.contact_modulus is not None:
            return self.contact_modulus
        # The validator guarantees both are set when contact_modulus is not.
        assert self.youngs_modulus is not None and self.poisson_ratio is not None
        return scales.contact_modulus(self.youngs_modulus, self.poisson_ratio)


class GridConfig(_Model):
    """The square computational domain.

    Attributes
    ----------
    size : float
        Side L of the square domain, in units of length.
    elements : int
        Number N of elements along each side (N x N elements in all).
    """

    model_config = _MODEL_CONFIG

    size: float = Field(gt=0, allow_inf_nan=False)
    elements: int = Field(ge=8, le=8192)

    @property
    def element_size(self) -> float:
        """h = L / N, in units of length."""
        return self.size / self.elements
