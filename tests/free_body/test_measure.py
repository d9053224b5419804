"""Omega^2 and the flips measured on free-body ensembles (stability.free_body.measure), against
the linear theory and the exact flip interval."""

import numpy as np
import pytest

import stability
from stability.free_body.measure import (complementary_moduli, exact_flip_intervals,
                                         flip_statistics, measured_omega_squared)
from stability.util.conventions import REGIME_EXPONENTIAL, REGIME_OSCILLATION

from ..helpers import LAM, SPIN, separatrix, series_dataset


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


def test_exact_flip_intervals_and_moduli_of_every_start():
    body = stability.RigidBody(1.0, 2.0, 3.0)
    w0 = np.array([[1e-3, 1.0, 0.0], [1.0, 1e-3, 0.0]])
    exact, _ = exact_flip_intervals(body, 2, w0)
    every, _ = exact_flip_intervals(body, None, w0)
    assert exact[0] == every[0] == stability.flip_interval(body, w0[0])
    assert every[1] == stability.flip_interval(body, w0[1])
    kprime = complementary_moduli(body, w0)
    assert kprime.shape == (2,) and 0 < kprime[0] < 1e-2 and kprime[1] > 0.5
