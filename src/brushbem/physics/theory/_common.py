"""Input validation and output helpers shared by the closed forms of :mod:`brushbem.physics.theory`.

The conventions every closed form follows:

Sign convention (the same as everywhere in brushbem)
----------------------------------------------------
* The base displacement ``d`` is positive when the indenter presses *into* the
  half-space; a negative ``d`` means the indenter is pulled away from the surface.
* Forces and pressures are positive when *compressive*.  A curve ``F(a)`` or
  ``F(d)`` (for example :func:`~brushbem.physics.theory.jkr_force_from_radius`) is therefore negative in the
  adhesive (tensile) part of a pull-off.
* Characteristic adhesive forces (Kendall, JKR, DMT, rigid and soft brushes,
  functions named ``..._force``) are returned as POSITIVE MAGNITUDES: the adhesive
  force ``F_A = -min F`` of DESIGN.md.
* Critical displacements (functions named ``..._displacement``) are returned
  SIGNED in the brushbem convention: negative means pulled away from the surface.
  The thesis writes some of them with a sign (eq. 2.4a, 2.20b) and some as
  magnitudes (eq. 2.15, 4.12, 5.4); here they all carry their sign.

Material and units
------------------
The half-space enters only through the contact modulus ``contact_modulus``
``E* = E / (1 - nu**2)`` (a rigid indenter on an elastic half-space; see
:func:`~brushbem.physics.theory.contact_modulus_from`) and the work of adhesion ``work_of_adhesion``
``dgamma`` (energy per unit area, the thesis's "surface energy per unit area").
Any consistent system of units works: lengths in L, stresses and moduli in F/L**2,
works of adhesion in F/L, forces in F, stiffnesses in F/L, energies in F*L.

The material arguments are keyword-only: ``contact_modulus`` and
``work_of_adhesion`` (and ``youngs_modulus``, ``poisson_ratio``,
``adhesive_stress``, ``equilibrium_separation`` where they appear) follow a ``*``
after the geometric and load arguments, e.g.
``kendall_force(radius, contact_modulus=E, work_of_adhesion=dgamma)``.  E* and
dgamma are both plain floats, so passing them by position could swap them
silently; a positional material argument raises :class:`TypeError` instead.

Input validation
----------------
Every function checks its arguments and raises :class:`ValueError` naming the
parameter, the offending value and the allowed range (NaN, zero or negative
moduli, radii, areas and so on).  A spring ``stiffness`` may be ``inf`` where that
means a rigid connection.  The work of adhesion may be zero in the curve formulas
(which then reduce to the non-adhesive solution) but must be positive where it sets
a scale.

References are to equation numbers of the thesis (seed document): Kendall flat
punch eq. 2.1-2.8, punch on a spring eq. 2.17-2.19, JKR eq. 2.20-2.24, sphere on a
spring eq. 2.32-2.39, brushes eq. 4.5-4.18 and 5.3-5.8, hierarchy eq. 6.20-6.28,
concave profile eq. 7.1-7.4, Tabor and Maugis eq. 1.3-1.5.
"""

from __future__ import annotations

import numpy as np

# ---------------------------------------------------------------------------
# Input validation (private helpers)
# ---------------------------------------------------------------------------


def _as_real_array(name: str, value: object) -> np.ndarray:
    """Return ``value`` as a float array or raise ValueError naming ``name``."""
    if np.iscomplexobj(value):
        raise ValueError(f"{name} must be real; got {value!r}")
    try:
        array = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as error:
        raise ValueError(f"{name} must be a real number or an array of real numbers; got {value!r}") from error
    return array


def _first_offender(array: np.ndarray, bad: np.ndarray) -> str:
    """Describe the first element of ``array`` flagged by ``bad`` (for messages)."""
    if array.ndim == 0:
        return repr(float(array))
    index = tuple(int(i) for i in np.argwhere(bad)[0])
    return f"{float(array[index])!r} at index {index}"


def _check(name: str, value: object, allowed: str, is_ok) -> np.ndarray:
    """Validate ``value`` elementwise with ``is_ok``; ``allowed`` goes in the message."""
    array = _as_real_array(name, value)
    bad = ~is_ok(array)  # NaN fails every comparison, so it is always flagged
    if np.any(bad):
        raise ValueError(f"{name} must be {allowed}; got {_first_offender(array, bad)}")
    return array


def _positive(name: str, value: object, *, allow_inf: bool = False) -> np.ndarray:
    if allow_inf:
        return _check(name, value, f"positive (0 < {name} <= inf)", lambda x: x > 0)
    return _check(name, value, f"positive and finite (0 < {name} < inf)", lambda x: (x > 0) & np.isfinite(x))


def _nonnegative(name: str, value: object) -> np.ndarray:
    return _check(name, value, f"non-negative and finite (0 <= {name} < inf)", lambda x: (x >= 0) & np.isfinite(x))


def _finite(name: str, value: object) -> np.ndarray:
    return _check(name, value, f"a finite real number (-inf < {name} < inf)", np.isfinite)


def _filling_factor(name: str, value: object) -> np.ndarray:
    return _check(name, value, f"a filling factor in (0, 1] (0 < {name} <= 1)", lambda x: (x > 0) & (x <= 1))


def _count(name: str, value: object) -> np.ndarray:
    return _check(name, value, f"at least one and finite (1 <= {name} < inf)", lambda x: (x >= 1) & np.isfinite(x))


def _out(value: np.ndarray | float) -> float | np.ndarray:
    """Return a Python float for 0-d results, the array otherwise."""
    array = np.asarray(value, dtype=float)
    return float(array) if array.ndim == 0 else array
