"""Estimators on signals whose rate, frequency and flips are known exactly."""

import math

import numpy as np
import pytest
import xarray as xr

import stability
from stability.analysis.estimates import measured_frequency, measured_growth_rate
from stability.analysis.fits import growth_line, richardson_bias
from stability.analysis.members import perpendicular_amplitude, sign_change_times, zero_crossings
from stability.analysis.regimes import (WINDOW_ATTRS, WINDOW_HIGH_FRACTION, WINDOW_LOW_FACTOR,
                                        member_regimes)
from stability.free_body.measure import (complementary_moduli, exact_flip_intervals,
                                         flip_statistics, measured_omega_squared)
from stability.free_body.tennis_racket.analysis import analyse_ensemble
from stability.util.conventions import (REGIME_ALGEBRAIC, REGIME_EXPONENTIAL, REGIME_NEUTRAL,
                                        REGIME_OSCILLATION)

LAM = 0.7  # s-1
SPIN = 1.0  # rad/s


def series_dataset(w, t, axis, spin=SPIN):
    n = w.shape[0]
    return xr.Dataset(
        {"w": (("member", "time", "axis"), w, {"units": "rad s-1"})},
        coords={"member": np.arange(n), "time": t, "axis": [1, 2, 3]},
        attrs={"axis": axis, "spin": spin},
    )


def separatrix(n_members, lam=LAM, dt=0.05, t_end=60.0, seed=0):
    """One exact flip per member: the sech/tanh separatrix (literature 1.4) about axis 2.

    Perpendicular amplitude A_max sech(lam (t - t0)), spin-axis component -W tanh(lam (t - t0)):
    growth at exactly ``lam`` while small, saturation at A_max, one flip at t0.
    """
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, t_end + dt / 2, dt)
    t0 = rng.uniform(0.4 * t_end, 0.5 * t_end, n_members)
    phi = rng.uniform(0, 2 * np.pi, n_members)
    a_max = 0.6 * SPIN
    u = lam * (t[None, :] - t0[:, None])
    w = np.empty((n_members, t.size, 3))
    w[:, :, 0] = a_max * np.cos(phi)[:, None] / np.cosh(u)
    w[:, :, 2] = a_max * np.sin(phi)[:, None] / np.cosh(u)
    w[:, :, 1] = -SPIN * np.tanh(u)
    return t, w, t0, a_max


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


def oscillation(n_members, omega, dt=0.05, periods=12, aspect=3.0, seed=2):
    """Motion near a stable axis 3: an ellipse of aspect ``aspect`` at angular frequency omega."""
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, periods * 2 * np.pi / omega, dt)
    amp = 1e-4 * rng.uniform(0.5, 1.5, n_members)
    phase = rng.uniform(0, 2 * np.pi, n_members)
    arg = omega * t[None, :] + phase[:, None]
    w = np.empty((n_members, t.size, 3))
    w[:, :, 0] = amp[:, None] * np.cos(arg)
    w[:, :, 1] = aspect * amp[:, None] * np.sin(arg)
    w[:, :, 2] = SPIN
    return t, w


def summaries_from_separatrix(n_members, levels, lam=LAM, seed=3):
    """Summaries-only Dataset of the separatrix flip: passage times known in closed form."""
    rng = np.random.default_rng(seed)
    t0 = rng.uniform(20.0, 30.0, n_members)
    a_max = 0.6 * SPIN
    a0 = a_max / np.cosh(lam * t0)
    # First time a_max sech(lam (t - t0)) reaches the level, before the peak at t0.
    passage = t0[:, None] - np.arccosh(a_max / levels[None, :]) / lam
    passage = np.where(levels[None, :] <= a0[:, None], 0.0, passage)
    w0 = np.stack([a0, SPIN * np.tanh(lam * t0), np.zeros(n_members)], axis=1)
    nan = np.full(n_members, np.nan)
    return xr.Dataset(
        {
            "passage_time": (("member", "level"), passage),
            "flip_count": (("member",), np.ones(n_members)),
            "first_flip_time": (("member",), t0),
            "last_flip_time": (("member",), t0),
            "perp_crossing_count": (("member",), np.zeros(n_members)),
            "first_perp_crossing": (("member",), nan),
            "last_perp_crossing": (("member",), nan),
            "max_perp_amplitude": (("member",), np.full(n_members, a_max)),
            "w0": (("member", "axis"), w0),
        },
        coords={"member": np.arange(n_members), "level": levels, "axis": [1, 2, 3]},
        attrs={"axis": 2, "spin": SPIN},
    )


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


def test_omega_squared_is_minus_rate_squared_with_propagated_error():
    t, w, _, _ = separatrix(16)
    res = measured_omega_squared(series_dataset(w, t, axis=2), analytic=-(LAM**2))
    rate = float(res.growth_rate)
    assert float(res.omega_squared_measured) == pytest.approx(-(rate**2), rel=1e-15)
    assert float(res.omega_squared_measured_stderr) == pytest.approx(
        2 * rate * float(res.growth_rate_stderr), rel=1e-12
    )
    assert abs(float(res.relative_error)) < 2e-5
    assert bool(res.sign_agrees)
    assert res.omega_squared_measured.attrs["units"] == "s-2"


def test_flip_statistics_on_the_separatrix():
    t, w, t0, _ = separatrix(8)
    flips = flip_statistics(series_dataset(w, t, axis=2))
    assert np.all(flips.flip_count.values == 1)
    assert flips.flip_count.dtype.kind == "i"  # a count, named as in a run's Dataset
    # tanh is linear through its zero: interpolated crossing times are exact to (lam dt)^3.
    np.testing.assert_allclose(flips.first_flip_time.values, t0, atol=1e-6)
    assert np.all(np.isnan(flips.flip_interval.values))  # one flip: no interval
    assert flips.first_flip_time.attrs["units"] == "s"


def test_zero_crossings_interpolates_and_counts():
    t = np.linspace(0.0, 10.0, 1001)
    x = np.sin(np.array([[1.0], [2.0]]) * t[None, :] + 0.1)
    count, first, last = zero_crossings(t, x)
    np.testing.assert_array_equal(count, [3, 6])
    np.testing.assert_allclose(first, [np.pi - 0.1, (np.pi - 0.1) / 2], atol=1e-6)
    np.testing.assert_allclose(last, [3 * np.pi - 0.1, (6 * np.pi - 0.1) / 2], atol=1e-6)


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


def test_members_marked_bad_are_left_out():
    t, w, _, _ = separatrix(8)
    w[3, 100:, :] = np.nan
    ds = series_dataset(w, t, axis=2)
    ds["status"] = ("member", np.array([0, 0, 0, 1, 0, 0, 0, 0], dtype=np.int8))
    fit = measured_growth_rate(ds)
    assert int(fit.n_fitted) == 7 and np.isnan(fit.member_growth_rate.values[3])
    assert abs(float(fit.growth_rate) / LAM - 1) < 1e-5


def test_bad_input_is_refused_clearly():
    t, w, _, _ = separatrix(2)
    ds = series_dataset(w, t, axis=2)
    with pytest.raises(ValueError, match="axis must be 1, 2 or 3"):
        measured_growth_rate(ds, axis=4)
    with pytest.raises(ValueError, match="neither a time series"):
        measured_growth_rate(xr.Dataset({"x": ("member", [1.0])}))
    with pytest.raises(ValueError, match="xarray.Dataset"):
        measured_growth_rate(w)


def test_estimators_on_run_ensemble_datasets_series_and_summaries():
    # The same members, saved as time series or as summaries only, give the same Omega^2
    # (within the stderr of the passage-time interpolation) and match linear theory to 1e-4.
    body = stability.RigidBody(1.0, 2.0, 3.0)
    common = dict(h=0.05, t_end=130.0, method="rk4", seed=3,
                  options=stability.RunOptions(progress=False))
    levels = SPIN * 10.0 ** (np.arange(-56, 1) / 8)
    series = stability.run_ensemble(body, 2, SPIN, 1e-7, 64, keep=stability.Keep(levels=levels),
                                    **common)
    summaries = stability.run_ensemble(body, 2, SPIN, 1e-7, 64,
                                       keep=stability.Keep(save_every=0, levels=levels), **common)
    assert "w" not in summaries
    analytic = float(stability.omega_squared(body, 2, SPIN))
    results = [measured_omega_squared(ds, low_factor=300) for ds in (series, summaries)]
    for res in results:
        assert res.regime == REGIME_EXPONENTIAL and bool(res.sign_agrees)
        assert float(res.omega_squared) == analytic  # taken from the Dataset's attributes
        assert abs(float(res.relative_error)) < 1e-4
    a, b = (float(r.omega_squared_measured) for r in results)
    assert abs(a - b) < 4 * float(results[1].omega_squared_measured_stderr) + 1e-6 * abs(a)
    # Flips: every member flips at least twice in 130 s, at the exact interval 2K/nu.
    flips = flip_statistics(summaries)
    assert int(flips.n_with_interval) == 64
    assert abs(float(flips.flip_interval_relative_error)) < 1e-3
    exact = flips.flip_interval_exact.values
    assert np.all(np.isfinite(exact))
    np.testing.assert_allclose(flips.flip_interval_asymptote.values, exact, rtol=1e-6)
    # Stable axis 3 of the same body: oscillation at sqrt(Omega^2).
    stable = stability.run_ensemble(body, 3, SPIN, 1e-4, 16, keep=stability.Keep(save_every=0),
                                    **common)
    res = measured_omega_squared(stable)
    assert res.regime == REGIME_OSCILLATION
    assert abs(float(res.relative_error)) < 1e-5


# ---------------------------------------------------------------------------------------------
# The window a Dataset records, and the helpers of the tennis-racket analysis


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


def test_growth_line_has_the_given_slope_through_the_linear_phase():
    t = np.linspace(0.0, 3.0, 61)
    rate = 2.5
    amplitude = 1e-4 * np.exp(rate * t)
    intercept, (t0, t1) = growth_line(t, amplitude, rate, 1e-3, 1e-1)
    assert intercept == pytest.approx(np.log(1e-4), abs=1e-10)
    assert 1e-4 * np.exp(rate * t0) > 1e-3 and 1e-4 * np.exp(rate * t1) < 1e-1
    # Saturation after the window does not enter the line.
    saturated = np.minimum(amplitude, 0.5)
    assert growth_line(t, saturated, rate, 1e-3, 1e-1) == (intercept, (t0, t1))
    assert np.isnan(growth_line(t, amplitude, rate, 1e3, 1e4)[0])


def test_perpendicular_amplitude_and_sign_changes():
    t, w, t0, a_max = separatrix(3)
    ds = series_dataset(w, t, axis=2)
    amp = perpendicular_amplitude(ds.w, 2)
    assert amp.dims == ("member", "time") and amp.attrs["units"] == "rad s-1"
    np.testing.assert_allclose(amp.values, a_max / np.cosh(LAM * (t[None] - t0[:, None])),
                               rtol=1e-12)
    flips = sign_change_times(t, w[0, :, 1])
    np.testing.assert_allclose(flips, [t0[0]], atol=1e-4)


def test_richardson_bias_of_an_order_p_error():
    h, c, p = 0.1, 3.0, 4
    exact = 2.0
    coarse, fine = exact + c * h**p, exact + c * (h / 2) ** p
    assert richardson_bias(coarse, fine, p) == pytest.approx(c * h**p, rel=1e-9)
    np.testing.assert_array_equal(richardson_bias([1.0, np.nan], [0.5, 1.0], np.inf),
                                  [0.5, np.nan])


def test_exact_flip_intervals_and_moduli_of_every_start():
    body = stability.RigidBody(1.0, 2.0, 3.0)
    w0 = np.array([[1e-3, 1.0, 0.0], [1.0, 1e-3, 0.0]])
    exact, _ = exact_flip_intervals(body, 2, w0)
    every, _ = exact_flip_intervals(body, None, w0)
    assert exact[0] == every[0] == stability.flip_interval(body, w0[0])
    assert every[1] == stability.flip_interval(body, w0[1])
    kprime = complementary_moduli(body, w0)
    assert kprime.shape == (2,) and 0 < kprime[0] < 1e-2 and kprime[1] > 0.5


def test_analyse_ensemble_headline_is_what_the_accessor_gives():
    body = stability.RigidBody.preset("tennis_racket")
    ds = stability.run_ensemble(body, 2, 10.0, 1e-4, 32, h=2e-3, t_end=3.0, seed=3,
                                method="rk4", keep=stability.Keep(save_every=25),
                                options=stability.RunOptions(progress=False))
    out = analyse_ensemble(ds, body, 2, 10.0, 1e-4, low_factor=10.0, high_fraction=0.03)
    headline = out.attrs["growth_rate_fitted"]
    assert headline == float(out.stability.measured_growth_rate().growth_rate)
    assert out.attrs["growth_rate_fitted_members"] == 32
    assert abs(out.attrs["growth_rate_fitted"] / out.attrs["growth_rate_analytic"] - 1) < 1e-3
    t0, t1 = out.attrs["growth_fit_window"]
    assert 0 < t0 < t1 < 3.0 and np.isfinite(out.attrs["growth_fit_intercept"])
    for name in ("exact_flip_interval", "flip_interval_asymptote", "complementary_modulus"):
        assert out[name].dims == ("member",)
    assert out.perp_amplitude_median.dims == ("time",)
