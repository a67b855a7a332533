"""A flat tip's peel in the continuum, and the criterion that lets every tip leave at it (``LoadPath.pillar_tip_peel``).

A rigid flat circular tip (radius a) in full contact carries along its
edge the stress intensity K(theta).  When the largest K reaches K_c =
sqrt(2 E* dgamma) (the tip's *first point*) its contact starts to recede
there.  Where K varies along the edge (a tip in a brush: its neighbours
tilt and bend the field across it) the tip then holds more load before it
runs away: a stable peel.  To first order in the edge's advance A(theta)
(units of a, A >= 0 where the contact has receded):

    K(theta) = K_0 [ g(theta) + sum_n f(n) A_n cos(n theta) ],

g = K / K_0 of the full circle, and the response f(n) of the circular
contact to an advance A_n cos(n theta):

* f(0) = 3/2 at a fixed load (Kendall's instability); 1/2 at a fixed
  displacement; ``load_control`` between the two for a tip on a spring:
  3/2 - (the contact's share of the tip's compliance, `load_control`).
* f(1) = 0: a shifted circle carries the same K.
* f(n) = -(n - 1) / 2 for n >= 1: the rigid elliptical punch's closed form
  for n = 2 (``tests/test_pillar_front.py``), the half-plane crack's
  -|k| / 2 (Rice 1985) for large n.

The edge recedes where K = K_c and stays where K <= K_c: a linear
complementarity problem in A, solved by primal-dual active sets as the
load rises from the first point; the tip's capacity is the largest load
with a solution (`capacity`).  Left out: the change of the neighbours' part
of K as the edge moves, and A's own squares (second order; the gains carry
an error of the order of eps times themselves, eps K's relative variation).
Measured in ``docs/pillars/front.py`` and ``docs/pillars/accuracy.md``
("The peel survives the continuum"): the raster's exact path of one tip at
57.8-160 elements per radius peels the same region of the edge.

The criterion (``LoadPath.pillar_tip_peel``).  On a coarse raster a tip's
own peel is the raster's (a staircase of a few elements), not the
continuum's, and where its edge elements fall decides where it starts.
With this option a whole tip leaves, whole, when its tensile force reaches
its strength (`strength`): Kendall's force F_K (a lone tip's first point)
over the largest g = K / K_P along its edge (its first point in its field)
times 1 + `gain` (its stable peel).  K(theta) comes from the tip's modes
(`tip_intensity`): the pressure of a rigid circle under the displacement
polynomial the modes carry has a closed form (Galin; `INTENSITY`); the
raster enters through that polynomial and the tip's force only.  A tip in
part contact (a rough brush pressed into partial contact) peels by its
elements' criterion, the raster's Sigma_c, as the exact path's do.  Its n = 0, 1, 2 parts are what the quadratic modes
hold: on the flat 8 x 8 brush's continuum solution (``docs/pillars/
continuum.py``) the gains of its edge tips from K's n <= 2 parts are within
0.05 % (absolute) of those from its whole K(theta); interior tips, whose
K varies by 2-4 %, lose 0.2-0.3 % (absolute) of a gain of 0.4 %.

`gain` reads a table (``data/peel_gain.csv``, written by
``docs/pillars/front.py --table``) over K's relative n = 1 and n = 2
amplitudes, their phase and ``load_control``, linearly interpolated
(within 0.0013 of the capacity afresh over its range, median 0.0002).  A
tip whose K varies beyond the table (`TABLE_LIMITS`) has no strength: the
first-order model is outside its domain there, and such a tip peels by its
elements' criterion, as the exact path's do (on a stiff rough brush the
tips that barely carry load, K varying by up to 30 times its mean: taking
the table's edge gain instead left the rough 8 x 8 family at k~ = 0.1 11.4 %
below its own F_A with tips at 28.9 elements per radius, against 1.1 % so,
``docs/pillars/rough.csv``).  A run whose tips leave whole with K varying
by more than `brushbem.pillars.domain.PEEL_TILT` warns.
"""

from __future__ import annotations

import functools
import math
from importlib import resources

import numpy as np

__all__ = ["AXES", "INTENSITY", "TABLE_LIMITS", "capacity", "circle_load", "gain", "load_control", "response", "shape",
           "shape_parameters", "strength", "tip_intensity"]

#: K(theta) of a rigid circle (radius a, contact modulus E*) pressed by the displacement r^n cos(n theta):
#: p = (E* / pi) kappa_n r^n cos(n theta) / sqrt(a^2 - r^2) with kappa_n = (2^n n!)^2 / (2n)! (Galin), so
#: K(theta) = (E* / sqrt(pi a)) kappa_n a^n cos(n theta); and by r^2: p = (E* / pi) (2 a^2 / sqrt(a^2 - r^2) -
#: 4 sqrt(a^2 - r^2)), K = (E* / sqrt(pi a)) 2 a^2.  kappa_0 = 1, kappa_1 = 2, kappa_2 = 8 / 3; the r^2 term's 2.
INTENSITY = {"uniform": 1.0, "tilt": 2.0, "r2": 2.0, "cos2": 8.0 / 3.0}

#: The table's axes: K's relative n = 1 amplitude, its n = 2 amplitude, the phase 2 alpha_1 - alpha_2 folded
#: into [0, pi], and ``load_control``.
AXES = {
    "tilt": (0.0, 0.01, 0.02, 0.04, 0.06, 0.08, 0.1, 0.125, 0.15, 0.2, 0.25, 0.3, 0.4, 0.5, 0.6),
    "bend": (0.0, 0.005, 0.01, 0.02, 0.03, 0.05, 0.075, 0.1, 0.15),
    "phase": tuple(np.linspace(0.0, math.pi, 9)),
    "load_control": (0.5, 0.75, 1.0, 1.25, 1.5),
}

#: The largest n = 1 and n = 2 amplitudes the table holds.
TABLE_LIMITS = {"tilt": AXES["tilt"][-1], "bend": AXES["bend"][-1]}

#: Edge points of the table's capacities (64: the gains of g = 1 + eps cos(theta) within 1e-4 of 128's).
TABLE_ANGLES = 64


def response(angles: int, load_control: float = 1.5) -> np.ndarray:
    """The circulant M with (M A)(theta_i) = sum_n f(n) A_n cos(n theta_i) on ``angles`` equal points."""
    n = np.fft.rfftfreq(angles, 1.0 / angles)
    f = np.where(n == 0, load_control, -(n - 1) / 2)
    column = np.fft.irfft(f, angles)
    index = (np.arange(angles)[:, None] - np.arange(angles)[None, :]) % angles
    return column[index]


def _equilibrium(s: float, g: np.ndarray, m: np.ndarray, start: np.ndarray) -> tuple[np.ndarray, bool]:
    """A >= 0 with w = 1 / s - g - M A >= 0 and A w = 0 (primal-dual active sets from ``start``)."""
    q = 1 / s - g
    a = start.copy()
    for _ in range(200):
        w = q - m @ a
        active = (a - w) > 0
        if not active.any():
            return np.zeros_like(a), bool((q >= -1e-12).all())
        new = np.zeros_like(a)
        new[active] = np.linalg.solve(m[np.ix_(active, active)], q[active])
        w = q - m @ new
        if np.array_equal(active, (new - w) > 0):
            return new, bool((new >= -1e-12).all() and (w[~active] >= -1e-12).all())
        a = new
    return a, False


def capacity(g: np.ndarray, load_control: float = 1.5, precision: float = 1e-8) -> dict:
    """The tip's capacity beyond its first point for K / K_0 = ``g`` on equal edge points: gain (the load at
    the last equilibrium over the first point's, minus 1; to ``precision``), the receded edge's span in
    degrees and its largest depth in units of a.  The load rises from the first point in steps of 0.2 %,
    halved where no equilibrium follows from the last."""
    m = response(g.size, load_control)
    first = 1 / g.max()
    s, step, a = first, 2e-3 * first, np.zeros(g.size)
    while step > precision * first:
        trial, ok = _equilibrium(s + step, g, m, a)
        if ok and trial.max() < 0.5:  # first order: an advance of half the radius is far outside its domain
            s, a = s + step, trial
        else:
            step /= 2
    return {"gain": s / first - 1, "span_degrees": float(np.count_nonzero(a > 0) / g.size * 360),
            "depth": float(a.max())}


def shape(tilt: float, bend: float, phase: float, angles: int = TABLE_ANGLES) -> np.ndarray:
    """g(theta) = 1 + tilt cos(theta) + bend cos(2 theta + phase) on ``angles`` equal points."""
    theta = 2 * np.pi * np.arange(angles) / angles
    return 1 + tilt * np.cos(theta) + bend * np.cos(2 * theta + phase)


def shape_parameters(intensity: np.ndarray) -> np.ndarray:
    """(tilt, bend, phase) of K(theta)'s Fourier parts ``intensity`` (..., 5): k0, k1 cos, k1 sin, k2 cos,
    k2 sin; tilt and bend relative to k0, the phase 2 alpha_1 - alpha_2 folded into [0, pi] (K's gain is
    the same under a rotation and a reflection of theta)."""
    k0 = intensity[..., 0]
    with np.errstate(divide="ignore", invalid="ignore"):
        # Relative to k0 with its sign (a tip in tension has k0 < 0): the phase of the n = 1 and n = 2 parts
        # turns by pi when both change sign.
        k = np.where((k0 != 0)[..., None], intensity[..., 1:] / k0[..., None], np.nan)
    tilt = np.hypot(k[..., 0], k[..., 1])
    bend = np.hypot(k[..., 2], k[..., 3])
    phase = 2 * np.arctan2(k[..., 1], k[..., 0]) - np.arctan2(k[..., 3], k[..., 2])
    phase = np.abs(np.mod(phase + np.pi, 2 * np.pi) - np.pi)
    return np.stack([tilt, bend, phase], axis=-1)


def tip_intensity(coefficients: np.ndarray, size: np.ndarray, radius: np.ndarray) -> np.ndarray:
    """K(theta)'s Fourier parts (k0, k1 cos, k1 sin, k2 cos, k2 sin), in units of E* / sqrt(pi a), of rigid
    circles of ``radius`` pressed by the displacement polynomials of the quadratic modes: ``coefficients``
    (n, 6) of 1, y, x, y^2, y x, x^2 in the scaled offsets (offset - centroid) / ``size`` (`Basis.polynomials`;
    theta from the x axis towards y)."""
    c = np.asarray(coefficients, dtype=np.float64)
    t = (radius / size)[:, None]
    k = np.empty((c.shape[0], 5))
    # x^2 + y^2 = r^2, x^2 - y^2 = r^2 cos(2 theta), 2 x y = r^2 sin(2 theta).
    k[:, 0] = c[:, 0] + INTENSITY["r2"] * t[:, 0] ** 2 * (c[:, 3] + c[:, 5]) / 2
    k[:, 1] = INTENSITY["tilt"] * t[:, 0] * c[:, 2]
    k[:, 2] = INTENSITY["tilt"] * t[:, 0] * c[:, 1]
    k[:, 3] = INTENSITY["cos2"] * t[:, 0] ** 2 * (c[:, 5] - c[:, 3]) / 2
    k[:, 4] = INTENSITY["cos2"] * t[:, 0] ** 2 * c[:, 4] / 2
    return k


def circle_load(coefficients: np.ndarray, size: np.ndarray, radius: np.ndarray) -> np.ndarray:
    """P / (2 E* a) of the rigid circles of `tip_intensity` (the load's K_P = P / (2 a sqrt(pi a)) in its units):
    the uniform part c_0 and the r^2 term's (4/3) E* a^3 q (from its pressure in `INTENSITY`)."""
    c = np.asarray(coefficients, dtype=np.float64)
    return c[:, 0] + (radius / size) ** 2 * (c[:, 3] + c[:, 5]) / 3


def strength(intensity: np.ndarray, load: np.ndarray, control: np.ndarray, kendall: float,
             angles: int = TABLE_ANGLES, parameters: np.ndarray | None = None) -> np.ndarray:
    """The tensile force at which each tip leaves at its continuum capacity: Kendall's force ``kendall`` times
    (1 + `gain`) over the largest g = K / K_P along its edge (the first point of a lone tip is Kendall's);
    ``intensity`` and ``load`` as `tip_intensity` and `circle_load` give them.  NaN where K_P is 0 or g has
    no positive part (no tension at the edge to lead a peel), and where K varies beyond the gain's table
    (`TABLE_LIMITS`): the first-order peel has no gain to give there, and those tips peel by their elements'
    criterion, as the exact path's do.  ``parameters``: `shape_parameters` of ``intensity`` where the caller has
    them."""
    theta = 2 * np.pi * np.arange(angles) / angles
    harmonics = np.stack([np.ones(angles), np.cos(theta), np.sin(theta), np.cos(2 * theta), np.sin(2 * theta)])
    with np.errstate(divide="ignore", invalid="ignore"):
        top = np.max((intensity @ harmonics) / load[:, None], axis=1)
        shape_of = shape_parameters(intensity) if parameters is None else parameters
        out = kendall * (1 + gain(shape_of, control)) / top
    inside = (shape_of[:, 0] <= TABLE_LIMITS["tilt"]) & (shape_of[:, 1] <= TABLE_LIMITS["bend"])
    return np.where(np.isfinite(out) & (top > 0) & inside, out, np.nan)


def load_control(contact_share: np.ndarray) -> np.ndarray:
    """f(0) of a tip whose contact compliance 1 / (2 E* a) is ``contact_share`` of its whole (contact and
    springs): 3/2 at a fixed load (no contact share), 1/2 at a fixed displacement."""
    return 1.5 - np.clip(contact_share, 0.0, 1.0)


@functools.cache
def _table():
    from scipy.interpolate import RegularGridInterpolator

    values = np.zeros(tuple(len(axis) for axis in AXES.values()))
    text = resources.files("brushbem.data").joinpath("peel_gain.csv").read_text()
    lines = text.strip().splitlines()
    header = lines[0].split(",")
    columns = [header.index(name) for name in (*AXES, "gain")]
    axes = [np.asarray(axis) for axis in AXES.values()]
    seen = np.zeros(values.shape, dtype=bool)
    for line in lines[1:]:
        cells = line.split(",")
        # The table's values to 7 digits: each on the axis point nearest it.
        key = tuple(int(np.argmin(np.abs(axes[j] - float(cells[columns[j]])))) for j in range(4))
        values[key] = float(cells[columns[4]])
        seen[key] = True
    if not seen.all():
        raise RuntimeError(f"data/peel_gain.csv lacks {int((~seen).sum())} of the {values.size} gains of its axes")
    return RegularGridInterpolator(tuple(axes), values)


def gain(parameters: np.ndarray, control: np.ndarray) -> np.ndarray:
    """The continuum gain of tips beyond their first points (`capacity`'s), from the table: ``parameters``
    (n, 3) as `shape_parameters` gives them, ``control`` (n,) their `load_control`; amplitudes beyond the
    table take its edge's."""
    parameters = np.atleast_2d(parameters)
    # A tip that carries no load (K's uniform part 0) has no shape: its gain is 0 (no first point to raise).
    defined = np.all(np.isfinite(parameters), axis=1)
    points = np.column_stack([np.minimum(parameters[:, 0], TABLE_LIMITS["tilt"]),
                              np.minimum(parameters[:, 1], TABLE_LIMITS["bend"]),
                              np.clip(parameters[:, 2], 0.0, math.pi),
                              np.clip(np.broadcast_to(control, parameters.shape[:1]), 0.5, 1.5)])
    out = np.zeros(parameters.shape[0])
    if defined.any():
        out[defined] = _table()(points[defined])
    return out
