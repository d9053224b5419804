"""The Earth under the Sun's and Moon's torques: orders, geometry, formula, the study."""


import numpy as np
import pytest

from stability.earth import precession as eq
from stability.engine import propagate_groups
from stability.registry import SCENES


FULL, AVERAGED = SCENES["lunisolar_earth"], SCENES["precessing_axis"]


def test_averaged_model_precesses_at_the_formula():
    """The Sun alone (its ring fixed): the averaged model's axis turns about the ecliptic pole at
    the formula's rate to 1e-9 over 100 years, at a fixed obliquity."""
    spec = AVERAGED.method("rk4")
    sun, moon = eq.orbit_elements("sun"), eq.orbit_elements("moon", strength=0.0)
    h = 10 * eq.DAY
    steps = int(100 * 365.25 / 10)
    x0 = eq.averaged_start(1)
    out = propagate_groups(AVERAGED, spec, x0, spec.params(eq.averaged_parameters(sun, moon),
                                                           h)[None, :], [1], h, steps,
                           progress=False)
    phi, eps = eq.equinox_angles(out.x_final[:, :3])
    rate = -phi[0] / (steps * h)
    assert rate == pytest.approx(eq.precession_formula("sun"), rel=1e-9)
    assert eps[0] == pytest.approx(eq.OBLIQUITY, abs=1e-12)


def test_fit_recovers_a_line_and_its_nutation():
    t = np.linspace(0.0, 100 * eq.YEAR, 5000)
    node = eq.nutation_frequencies("averaged")[0]
    phi = 0.3 - 2.4e-12 * t + 8.3e-5 * np.sin(node * t + 0.4) + 1e-6 * np.cos(2 * node * t)
    eps = 0.409 + 4.4e-5 * np.cos(node * t + 0.4)
    fit = eq.fit_precession(t, phi, eps, eq.nutation_frequencies("averaged"))
    assert fit["precession_rate"] == pytest.approx(2.4e-12, rel=1e-10)
    assert fit["nutation_longitude"] == pytest.approx(8.3e-5, rel=1e-10)
    assert fit["nutation_obliquity"] == pytest.approx(4.4e-5, rel=1e-10)
    assert abs(fit["obliquity_rate"]) < 1e-20

