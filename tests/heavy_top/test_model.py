"""The heavy top's model (stability.heavy_top.model): tilted starts, the sleeping top's threshold
and rates, and the tops it refuses."""

import math

import numpy as np
import pytest

from stability.heavy_top.model import (HeavyTop, critical_spin, sleeping_frequencies,
                                       sleeping_growth_rate, tilted_starts)

#: The literature's worked example (notes 5.3): a 0.1 kg disk of radius 3 cm, 4 cm from the pivot.
DISK = HeavyTop.disk(0.1, 0.03, 0.04)


def test_tilted_starts_have_the_asked_tilt_spin_and_tilt_rate():
    top = HeavyTop.disk(0.1, 0.03, 0.04)
    x = tilted_starts(300.0, 0.2, 50, top=top, seed=1, tilt_rate=0.5)
    A, _, C = top.pivot_moments
    assert np.allclose(np.arccos(x[:, 5]), 0.2)
    assert np.allclose(x[:, 2] / C, 300.0)
    # theta' = (g x w)_3 / -sin(theta) for g3 = cos(theta): the asked rate.
    w = x[:, :3] / top.pivot_moments
    g3_rate = x[:, 3] * w[:, 1] - x[:, 4] * w[:, 0]
    assert np.allclose(-g3_rate / np.sin(0.2), 0.5)


def test_critical_spin_and_rates_of_the_worked_gyroscope():
    """Disk M = 0.1 kg, r = 3 cm, l = 4 cm (literature notes 5.3): threshold ~119 rad/s."""
    top = HeavyTop.disk(0.1, 0.03, 0.04, gravity=9.81)
    assert critical_spin(top) == pytest.approx(118.9, abs=0.1)
    assert sleeping_growth_rate(top, 0.0) == pytest.approx(math.sqrt(top.mgl / 1.825e-4))
    assert sleeping_growth_rate(top, 200.0) == 0.0
    slow, fast = sleeping_frequencies(top, 300.0)
    A, _, C = top.pivot_moments
    assert slow * fast == pytest.approx(top.mgl / A) and slow + fast == pytest.approx(C * 300 / A)


@pytest.mark.parametrize("kwargs,match", [
    ({"mass": -1.0, "length": 0.04, "central_moments": (1, 1, 2)}, "mass must be"),
    ({"mass": 0.1, "length": -0.01, "central_moments": (1, 1, 2)}, "length"),
    ({"mass": 0.1, "length": 0.04, "central_moments": (1, 1, 3)}, "triangle inequality"),
    ({"mass": 0.1, "length": 0.04, "central_moments": (1, 2)}, "3 principal moments"),
    ({"mass": 0.1, "length": 0.04, "central_moments": (1, 1, 1), "gravity": -9.8},
     "gravity"),
])
def test_unphysical_tops_are_refused_with_one_line(kwargs, match):
    with pytest.raises(ValueError, match=match):
        HeavyTop(**kwargs)


def test_pivot_moments_below_m_l_squared_are_refused():
    with pytest.raises(ValueError, match="parallel-axis"):
        HeavyTop.from_pivot_moments((1e-4, 1e-4, 4.5e-5), 0.1, 0.04)
    top = HeavyTop.from_pivot_moments((1.825e-4, 1.825e-4, 4.5e-5), 0.1, 0.04)
    assert np.allclose(top.central_moments, (2.25e-5, 2.25e-5, 4.5e-5))


def test_linear_theory_is_refused_for_an_asymmetric_top():
    top = HeavyTop(0.1, 0.04, (2e-5, 3e-5, 4.5e-5))
    with pytest.raises(ValueError, match="symmetric top"):
        critical_spin(top)


def test_tilted_starts_set_the_euler_angle_rates():
    """phi' = (w1 g1 + w2 g2) / (g1^2 + g2^2), theta' = -u' / sin(theta), w3 = spin."""
    x = tilted_starts(300.0, 0.7, 5, top=DISK, seed=3, tilt_rate=0.4,
                      precession_rate=np.linspace(-2.0, 2.0, 5))
    A, B, C = DISK.pivot_moments
    w = x[:, :3] / [A, B, C]
    g = x[:, 3:]
    assert np.allclose(np.linalg.norm(g, axis=1), 1.0, atol=1e-15)
    assert np.allclose(w[:, 2], 300.0, rtol=1e-15)
    phi_rate = (w[:, 0] * g[:, 0] + w[:, 1] * g[:, 1]) / (g[:, 0] ** 2 + g[:, 1] ** 2)
    assert np.allclose(phi_rate, np.linspace(-2.0, 2.0, 5), atol=1e-12)
    u_rate = np.cross(g, w)[:, 2]
    assert np.allclose(-u_rate / np.sin(0.7), 0.4, atol=1e-12)
