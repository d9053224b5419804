"""Estimators on signals whose rate, frequency and flips are known exactly."""

import math

import numpy as np
import pytest
import xarray as xr

from stability.analysis.estimates import measured_frequency, measured_growth_rate
from stability.free_body.measure import measured_omega_squared
from stability.util.conventions import REGIME_EXPONENTIAL, REGIME_OSCILLATION

from ..helpers import LAM, SPIN, oscillation, separatrix, series_dataset, summaries_from_separatrix


def linear_phase(n_members, lam=LAM, dt=0.05, t_end=25.0, seed=1):
    """Linearised motion near an unstable axis: growing plus decaying mode, random starts.

    d(t) = a_+ e^{lam t} v_+ + a_- e^{-lam t} v_- with v_+- = (1, +-r): the decaying mode
    contaminates ln A near the start, which the window must skip.
    """
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, t_end + dt / 2, dt)
    r = 0.4
    start = 1e-7 * rng.standard_normal((n_members, 2))
    a_plus = 0.5 * (start[:, 0] + start[:, 1] / r)
    a_minus = 0.5 * (start[:, 0] - start[:, 1] / r)
    grow = np.exp(lam * t)[None, :]
    decay = np.exp(-lam * t)[None, :]
    w = np.empty((n_members, t.size, 3))
    w[:, :, 0] = a_plus[:, None] * grow + a_minus[:, None] * decay
    w[:, :, 2] = r * (a_plus[:, None] * grow - a_minus[:, None] * decay)
    w[:, :, 1] = SPIN
    return t, w


def test_growth_rate_of_saturating_flip_is_the_linear_rate():
    # The window [100 a0, 1e-2 A_max) sees ln A = lam t + O((A / A_max)^2): bias <= 1e-5.
    t, w, _, _ = separatrix(32)
    fit = measured_growth_rate(series_dataset(w, t, axis=2))
    assert int(fit.n_fitted) == 32
    assert abs(float(fit.growth_rate) / LAM - 1) < 1e-5
    # Without the upper edge the fit runs into saturation and is badly biased.
    wide = measured_growth_rate(series_dataset(w, t, axis=2), high_fraction=0.9)
    assert abs(float(wide.growth_rate) / LAM - 1) > 1e-3


def test_growth_rate_skips_the_decaying_mode():
    t, w = linear_phase(64)
    ds = series_dataset(w, t, axis=2)
    fit = measured_growth_rate(ds)
    assert int(fit.n_fitted) == 64
    assert abs(float(fit.growth_rate) / LAM - 1) < 1e-4
    # Starting the window at the initial amplitude lets the decaying mode bias the slope.
    early = measured_growth_rate(ds, low_factor=1.0)
    assert abs(float(early.growth_rate) / LAM - 1) > 1e-3


def test_growth_rate_from_passage_times_equals_the_linear_rate():
    levels = SPIN * np.logspace(-7, -1, 49)
    ds = summaries_from_separatrix(20, levels)
    fit = measured_growth_rate(ds)
    assert int(fit.n_fitted) == 20
    assert abs(float(fit.growth_rate) / LAM - 1) < 1e-5
    assert measured_omega_squared(ds).regime == REGIME_EXPONENTIAL


def test_growth_rate_uncertainty_shrinks_like_one_over_sqrt_members():
    def spread_ensemble(n, seed):
        rng = np.random.default_rng(seed)
        rates = LAM * (1 + 0.01 * rng.standard_normal(n))
        t = np.arange(0.0, 30.0, 0.05)
        w = np.zeros((n, t.size, 3))
        w[:, :, 0] = 1e-7 * np.exp(rates[:, None] * t[None, :])
        w[:, :, 1] = SPIN
        return series_dataset(w, t, axis=2)

    small = measured_growth_rate(spread_ensemble(32, 4))
    large = measured_growth_rate(spread_ensemble(512, 5))
    ratio = float(small.growth_rate_stderr) / float(large.growth_rate_stderr)
    assert 3.0 < ratio < 5.3  # sqrt(512 / 32) = 4
    for fit in (small, large):
        assert abs(float(fit.growth_rate) - LAM) < 4 * float(fit.growth_rate_stderr)
        # stderr = sd / sqrt(n) with sd = 0.01 lam
        n = int(fit.n_fitted)
        assert float(fit.growth_rate_stderr) == pytest.approx(0.01 * LAM / math.sqrt(n), rel=0.3)


@pytest.mark.parametrize("omega", [0.05, 0.8, 2.0])
def test_frequency_from_zero_crossings(omega):
    # dt = 0.05 s: linear interpolation of a crossing errs by O((omega dt)^3), over 12 periods.
    t, w = oscillation(16, omega)
    ds = series_dataset(w, t, axis=3)
    fit = measured_frequency(ds)
    assert int(fit.n_fitted) == 16
    assert abs(float(fit.oscillation_frequency) / omega - 1) < 1e-6
    omega2 = measured_omega_squared(ds, analytic=omega**2)
    assert omega2.regime == REGIME_OSCILLATION
    assert abs(float(omega2.relative_error)) < 2e-6
    assert bool(omega2.sign_agrees)
    assert math.isnan(float(measured_growth_rate(ds).growth_rate))


def test_bad_input_is_refused_clearly():
    t, w, _, _ = separatrix(2)
    ds = series_dataset(w, t, axis=2)
    with pytest.raises(ValueError, match="axis must be 1, 2 or 3"):
        measured_growth_rate(ds, axis=4)
    with pytest.raises(ValueError, match="neither a time series"):
        measured_growth_rate(xr.Dataset({"x": ("member", [1.0])}))
    with pytest.raises(ValueError, match="xarray.Dataset"):
        measured_growth_rate(w)

