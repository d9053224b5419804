"""Each member's regime and the growth window (stability.analysis.regimes): a degenerate axis
drifts without growth, a sphere is neutral, the window a Dataset records is the estimators'
default."""

import math

import numpy as np
import pytest
import xarray as xr

import stability
from stability.analysis.estimates import measured_growth_rate
from stability.analysis.regimes import (WINDOW_ATTRS, WINDOW_HIGH_FRACTION, WINDOW_LOW_FACTOR,
                                        member_regimes)
from stability.free_body.measure import flip_statistics, measured_omega_squared
from stability.util.conventions import REGIME_ALGEBRAIC, REGIME_NEUTRAL

from ..helpers import SPIN, separatrix, series_dataset


def test_degenerate_axis_drifts_linearly_without_growth_or_flip():
    # ERRATA 3: I1 = I2, spin about axis 1: w3 exactly constant, w2 drifts linearly at
    # (I3 - I1) W w3 / I1, no exponential growth and no flip.
    body = stability.RigidBody(1.0, 1.0, 1.5)
    d2, d3 = 2e-7, 1e-6
    ds = stability.integrate(body, [SPIN, d2, d3], t_end=400.0, h=0.1, method="rk4", save_every=5)
    w = ds.w.values
    assert np.all(w[:, 2] == d3)  # I3 w3' = (I1 - I2) w1 w2 = 0 exactly
    drift = (body.I3 - body.I1) * SPIN * d3 / body.I1
    t = ds.time.values
    # Exactly, (w1, w2) turns at n = (I3 - I1) w3 / I1: w2 = d2 cos(nt) + w1(0) sin(nt) ~ line.
    np.testing.assert_allclose(w[:, 1], d2 + drift * t, rtol=1e-8, atol=1e-16)
    regimes = member_regimes(ds, axis=1)
    assert regimes.regime.item() == REGIME_ALGEBRAIC
    assert regimes.linear_residual.item() < 1e-2 < 0.1 < regimes.exponential_residual.item()
    assert regimes.drift_rate.item() == pytest.approx(drift, rel=1e-2)
    res = measured_omega_squared(ds, axis=1, analytic=0.0)
    assert res.regime == REGIME_ALGEBRAIC and bool(res.sign_agrees)
    assert math.isnan(float(res.omega_squared_measured))  # no rate forced
    assert math.isnan(float(measured_growth_rate(ds, axis=1).growth_rate))
    assert flip_statistics(ds, axis=1).flip_count.item() == 0


def test_sphere_is_neutral():
    body = stability.RigidBody(1.0, 1.0, 1.0)
    ds = stability.integrate(body, [1e-6, SPIN, 2e-6], t_end=50.0, h=0.1, method="rk4")
    res = measured_omega_squared(ds, axis=2, analytic=0.0)
    assert res.regime == REGIME_NEUTRAL and bool(res.sign_agrees)
    assert math.isnan(float(res.omega_squared_measured))


def test_a_recorded_window_is_the_default_of_the_estimators():
    t, w, _, _ = separatrix(6)
    ds = series_dataset(w, t, axis=2)
    wide = measured_growth_rate(ds, low_factor=10.0, high_fraction=0.05)
    ds.attrs.update({WINDOW_ATTRS["low_factor"]: 10.0,
                     WINDOW_ATTRS["high_fraction"]: 0.05})
    xr.testing.assert_identical(measured_growth_rate(ds), wide)
    xr.testing.assert_identical(ds.stability.measured_growth_rate(), wide)
    assert float(wide.growth_rate) != float(measured_growth_rate(
        ds, low_factor=WINDOW_LOW_FACTOR, high_fraction=WINDOW_HIGH_FRACTION).growth_rate)
    omega2 = measured_omega_squared(ds)
    assert float(omega2.growth_rate) == float(wide.growth_rate)
