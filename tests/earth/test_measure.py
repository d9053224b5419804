"""What the Earth's runs measure (stability.earth.measure): the rigid Earth's free wobble (Euler's
period, the cones), and the fit of the equinox's line and nutation."""

import math

import numpy as np
import pytest

import stability
from stability.earth import model
from stability.earth.model import (
    ARCSEC, DYNAMICAL_ELLIPTICITY, SIDEREAL_DAY, earth, euler_period,
)
from stability.earth.figures import wobble_cones_figure
from stability.earth.measure import fit_precession, measure_free_wobble

from ..helpers import assert_readable

SPIN = 2.0 * math.pi / SIDEREAL_DAY


@pytest.fixture(scope="module")
def wobble():
    return measure_free_wobble(earth(), SPIN, 0.3 * ARCSEC, members=6, periods=2.0,
                               options=stability.RunOptions(progress=False))


def test_measured_period_is_eulers_to_1e_9(wobble):
    assert abs(float(wobble.relative_error)) < 1e-9
    assert float(wobble.wobble_period_euler) == pytest.approx(
        euler_period(earth().moments, SPIN) / 86400, rel=1e-15)
    assert 300 < float(wobble.wobble_period_measured) < 310
    assert "not rigid" in wobble.attrs["chandler_note"]
    assert wobble.attrs["chandler_period_days"] == 433.0


def test_cones_have_the_angles_of_the_theory(wobble):
    """The rotation axis stays 0.3 arcsec from the figure axis (the body cone, to the
    triaxial wobble's small ellipticity) and H times that from L (the space cone); the figure
    axis is (1 - H) times 0.3 arcsec from L."""
    body = wobble.body_cone_angle.values
    assert abs(body - 0.3).max() < 1e-3 * 0.3 * 20  # (B - A) / (C - A) ~ 0.7 % ellipticity
    ratio = float(wobble.space_cone_angle.mean()) / float(wobble.body_cone_angle.mean())
    assert ratio == pytest.approx(DYNAMICAL_ELLIPTICITY, rel=0.01)
    assert_readable(wobble_cones_figure(wobble))


def test_fit_recovers_a_line_and_its_nutation():
    t = np.linspace(0.0, 100 * model.YEAR, 5000)
    node = model.nutation_frequencies("averaged")[0]
    phi = 0.3 - 2.4e-12 * t + 8.3e-5 * np.sin(node * t + 0.4) + 1e-6 * np.cos(2 * node * t)
    eps = 0.409 + 4.4e-5 * np.cos(node * t + 0.4)
    fit = fit_precession(t, phi, eps, model.nutation_frequencies("averaged"))
    assert fit["precession_rate"] == pytest.approx(2.4e-12, rel=1e-10)
    assert fit["nutation_longitude"] == pytest.approx(8.3e-5, rel=1e-10)
    assert fit["nutation_obliquity"] == pytest.approx(4.4e-5, rel=1e-10)
    assert abs(fit["obliquity_rate"]) < 1e-20
