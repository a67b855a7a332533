"""The work of separation read off an unloading path (`brushbem.protocol.work_of_separation`).

Paths with hand-computed areas: the integrand is piecewise linear, so every
value below is exact up to rounding (compared at 1e-12).
"""

from __future__ import annotations

import numpy as np
import pytest

from brushbem.protocol import work_of_separation


def test_kendall_triangle_from_the_zero_crossing():
    # Rigid punch: F = 2 (d - 1) from the preload d = 3 to d_K = -1, then a
    # vertical drop to 0 (separation).  Tensile part: triangle 0.5 * 2 * 4.
    path = [(3.0, 4.0), (-1.0, -4.0), (-1.0, 0.0)]
    assert work_of_separation(path) == pytest.approx(0.5 * 2.0 * 4.0, rel=1e-12, abs=0.0)


def test_cascade_segments_add_nothing_and_the_tension_after_them_counts():
    # Zero crossing at d = 1, tension grows to -2 at d = 0, a cascade (vertical)
    # to -1, linear to -1 at d = -1, separation.
    path = [(2.0, 2.0), (0.0, -2.0), (0.0, -1.0), (-1.0, -1.0), (-1.0, 0.0)]
    expected = 0.5 * 1.0 * 2.0 + 1.0 * 1.0
    assert work_of_separation(path) == pytest.approx(expected, rel=1e-12, abs=0.0)


def test_a_compressive_stretch_after_the_first_crossing_adds_nothing():
    # Tension -1 at d = 0 (crossing at d = 0.5), a cascade leaves F = +1, the
    # force falls linearly to -3 at d = -2 (crossing at d = -0.5), separation.
    path = [(1.0, 1.0), (0.0, -1.0), (0.0, 1.0), (-2.0, -3.0), (-2.0, 0.0)]
    expected = 0.5 * 0.5 * 1.0 + 0.5 * 1.5 * 3.0
    assert work_of_separation(path) == pytest.approx(expected, rel=1e-12, abs=0.0)
    # The net integral of -F dd would be smaller (the compressive triangle,
    # 0.5 * 0.5 * 1, counts against it): that is not work against tension.
    d, f = np.array(path).T
    net = float(np.sum(0.5 * (-f[:-1] - f[1:]) * (d[:-1] - d[1:])))
    assert net < expected


def test_no_tension_no_work():
    assert work_of_separation([(1.0, 2.0), (0.5, 1.0), (0.0, 0.0)]) == 0.0
    assert work_of_separation([(1.0, 2.0)]) == 0.0
    assert work_of_separation([]) == 0.0
