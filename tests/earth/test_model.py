"""The Earth's model (stability.earth.model): its moments reproduce the published ratios."""

import math

import pytest

from stability.earth.model import (DYNAMICAL_ELLIPTICITY, SIDEREAL_DAY, earth_moments,
                                   oblate_euler_period)

SPIN = 2.0 * math.pi / SIDEREAL_DAY


def test_moments_reproduce_the_published_ratios():
    A, B, C = earth_moments()
    assert (C - 0.5 * (A + B)) / C == pytest.approx(DYNAMICAL_ELLIPTICITY, rel=1e-12)
    assert C / (5.9722e24 * 6378136.6**2) == pytest.approx(0.3307, rel=1e-12)
    # Literature notes 5.1: A / (C - A) = 304.46 sidereal days = 303.6 solar days.
    assert oblate_euler_period((A, B, C), SPIN) / SIDEREAL_DAY == pytest.approx(304.46, abs=0.01)
    assert oblate_euler_period((A, B, C), SPIN) / 86400 == pytest.approx(303.6, abs=0.05)
