"""The Earth's model (stability.earth.model): its moments reproduce the published ratios; the
averaged model's axis precesses at the formula's rate."""

import math

import pytest

from stability.earth import model
from stability.earth.measure import equinox_angles
from stability.earth.model import (DYNAMICAL_ELLIPTICITY, SIDEREAL_DAY, earth_moments,
                                   oblate_euler_period)
from stability.engine import propagate_groups
from stability.registry import SCENES

SPIN = 2.0 * math.pi / SIDEREAL_DAY
AVERAGED = SCENES["precessing_axis"]


def test_moments_reproduce_the_published_ratios():
    A, B, C = earth_moments()
    assert (C - 0.5 * (A + B)) / C == pytest.approx(DYNAMICAL_ELLIPTICITY, rel=1e-12)
    assert C / (5.9722e24 * 6378136.6**2) == pytest.approx(0.3307, rel=1e-12)
    # Literature notes 5.1: A / (C - A) = 304.46 sidereal days = 303.6 solar days.
    assert oblate_euler_period((A, B, C), SPIN) / SIDEREAL_DAY == pytest.approx(304.46, abs=0.01)
    assert oblate_euler_period((A, B, C), SPIN) / 86400 == pytest.approx(303.6, abs=0.05)


def test_averaged_model_precesses_at_the_formula():
    """The Sun alone (its ring fixed): the averaged model's axis turns about the ecliptic pole at
    the formula's rate to 1e-9 over 100 years, at a fixed obliquity."""
    spec = AVERAGED.method("rk4")
    sun, moon = model.orbit_elements("sun"), model.orbit_elements("moon", strength=0.0)
    h = 10 * model.DAY
    steps = int(100 * 365.25 / 10)
    x0 = model.averaged_start(1)
    out = propagate_groups(AVERAGED, spec, x0, spec.params(model.averaged_parameters(sun, moon),
                                                           h)[None, :], [1], h, steps,
                           progress=False)
    phi, eps = equinox_angles(out.x_final[:, :3])
    rate = -phi[0] / (steps * h)
    assert rate == pytest.approx(model.precession_formula("sun"), rel=1e-9)
    assert eps[0] == pytest.approx(model.OBLIQUITY, abs=1e-12)
