"""The compiled growth-rate fit gives each member the rate and regime of the NumPy estimator
(stability.analysis.growth_fit against stability.analysis.estimates.member_rates)."""

import numpy as np
import pytest

import stability
from stability.analysis.estimates import member_rates
from stability.analysis.growth_fit import series_growth_rates
from stability.analysis.members import members
from stability.analysis.regimes import classify
from stability.util import conventions as cv

#: Rounding only: the compiled sums run in sample order, NumPy's pairwise.
RATE_RTOL = 1e-13


def _ensemble(axis, epsilon, method="rk4", preset="tennis_racket"):
    body = stability.RigidBody.preset(preset)
    return stability.run_ensemble(body, axis, 10.0, epsilon, 300, h=2e-3, t_end=6.0, seed=5,
                                  keep=stability.Keep(save_every=25), method=method,
                                  options=stability.RunOptions(progress=False))


@pytest.mark.parametrize("axis, epsilon, method, regime", [
    (2, 1e-4, "rk4", cv.REGIME_EXPONENTIAL),   # the flip: growth, then saturation
    (2, 1e-7, "lp2", cv.REGIME_EXPONENTIAL),
    (1, 1e-3, "rk4", cv.REGIME_OSCILLATION),   # about a stable axis
    (3, 1e-2, "lp2", cv.REGIME_OSCILLATION),
])
def test_rates_and_regimes_are_the_numpy_estimators(axis, epsilon, method, regime):
    ds = _ensemble(axis, epsilon, method)
    mem = members(ds)
    expected_regime, *_ = classify(mem)
    expected = member_rates(mem, expected_regime, 10.0, 0.03)
    ok = (ds.status == cv.STATUS_OK).values
    rates, regimes, amp = series_growth_rates(ds.time.values, ds.w.values, axis, 10.0, 10.0,
                                              0.03, valid=ok)
    np.testing.assert_array_equal(regimes, expected_regime)
    assert np.all(regimes == regime)
    np.testing.assert_array_equal(np.isnan(rates), np.isnan(expected))
    np.testing.assert_allclose(rates, expected, rtol=RATE_RTOL, atol=0)
    b, c = cv.perpendicular_axes(axis)
    np.testing.assert_array_equal(amp, np.hypot(ds.w.values[..., b - 1], ds.w.values[..., c - 1]))


def test_members_left_out_and_broken_series():
    """A member whose status is not ok, or whose series holds a NaN, is undetermined, has no
    rate, and its amplitudes are NaN only where it is left out by its status."""
    ds = _ensemble(2, 1e-4)
    w = ds.w.values.copy()
    w[3, 40, 0] = np.nan
    valid = np.ones(w.shape[0], dtype=bool)
    valid[7] = False
    rates, regimes, amp = series_growth_rates(ds.time.values, w, 2, 10.0, 10.0, 0.03,
                                              valid=valid)
    for j in (3, 7):
        assert regimes[j] == cv.REGIME_UNDETERMINED and np.isnan(rates[j])
    assert np.all(np.isnan(amp[7])) and np.isfinite(amp[3, 39])
    assert np.all(np.isfinite(rates[[0, 1, 2, 4]]))


def test_a_window_too_short_gives_no_rate():
    """Three samples at least (MIN_POINTS): a window ending just above the start has none."""
    ds = _ensemble(2, 1e-4)
    rates, regimes, _ = series_growth_rates(ds.time.values, ds.w.values, 2, 10.0, 1.0001,
                                            1.00011e-4, valid=None)
    assert np.all(regimes == cv.REGIME_EXPONENTIAL) and np.all(np.isnan(rates))


def test_amplitudes_counted_in_the_fit_are_their_log_histogram():
    """With ``edges`` the amplitudes are counted in the fit's pass, never kept: the counts
    are log_histogram's of the amplitudes the fit gives without it, and the rates and regimes
    unchanged, from the body-frame series and from the loop's canonical momenta alike."""
    from stability.analysis.growth_fit import canonical_growth_rates
    from stability.core.body import canonical_frame, from_canonical, to_canonical
    from stability.ensemble.combine import log_edges, log_histogram

    ds = _ensemble(2, 1e-4)
    t, w = ds.time.values, ds.w.transpose(cv.MEMBER, cv.TIME, cv.AXIS).values
    valid = np.ones(w.shape[0], dtype=bool)
    valid[[2, 9]] = False
    edges = log_edges(1e-5, 50.0)
    rates, regimes, amp = series_growth_rates(t, w, 2, 10.0, 10.0, 0.03, valid=valid)
    expected = log_histogram(amp, edges)
    assert expected.sum() == (w.shape[0] - 2) * t.size  # every valid sample counted
    got = series_growth_rates(t, w, 2, 10.0, 10.0, 0.03, valid=valid, edges=edges)
    np.testing.assert_array_equal(got[0], rates)
    np.testing.assert_array_equal(got[1], regimes)
    np.testing.assert_array_equal(got[2], expected)

    moments = stability.RigidBody.preset("tennis_racket").moments
    frame = canonical_frame(moments)
    m = np.stack([to_canonical(w[i, 1:] * moments, *frame) for i in range(w.shape[0])])
    read = w.copy()  # the series the kernel reads the momenta as
    read[:, 1:] = np.stack([from_canonical(m[i], *frame) for i in range(w.shape[0])]) / moments
    rates, regimes, amp = series_growth_rates(t, read, 2, 10.0, 10.0, 0.03, valid=valid)
    got = canonical_growth_rates(t, w[:, 0], m, frame, moments, 2, 10.0, 10.0, 0.03,
                                 valid=valid, edges=edges)
    np.testing.assert_array_equal(got[0], rates)
    np.testing.assert_array_equal(got[1], regimes)
    np.testing.assert_array_equal(got[2], log_histogram(amp, edges))
