"""Long-run invariant errors: the envelope, its log-log slope, and the behaviour in words."""

import numpy as np

import stability
from stability.free_body.work_precision.drift import drift_kind, envelope, log_slope, long_horizon


def test_envelope_is_the_running_maximum_of_the_size():
    np.testing.assert_array_equal(envelope([1.0, -3.0, 2.0, np.nan, 4.0]),
                                  [1.0, 3.0, 3.0, 3.0, 4.0])
    assert envelope([]).size == 0


def test_envelope_and_slope_classify_drift():
    t = np.linspace(1.0, 1e4, 10_000)
    assert drift_kind(log_slope(t, 1e-5 * np.sin(t))) == "bounded"
    assert drift_kind(log_slope(t, 1e-9 * t)) == "linear drift"
    rng = np.random.default_rng(0)
    walk = np.cumsum(rng.standard_normal(t.size))  # ~ sqrt(t)
    assert drift_kind(log_slope(t, 1e-10 * walk), 1e-8) == "random walk"
    kind = drift_kind(log_slope(t, 1e-16 * walk), 1e-14)
    assert kind.startswith("round-off, grows like t^0.")
    assert drift_kind(log_slope(t, 1e-16 * np.sin(t)), 1e-16) == "round-off, bounded"
    assert drift_kind(np.nan) == "n/a"


def test_long_horizon_keeps_rms_errors_at_the_sampled_times():
    body = stability.RigidBody(1.0, 2.0, 3.0)
    w0 = np.array([[0.3, 1.0, 0.9], [0.31, 1.0, 0.9]])
    t, energy, momentum, wall = long_horizon("lp2", body, w0, 0.1, 1000, 10)
    np.testing.assert_allclose(t, 10.0 * np.arange(1, 11))
    assert energy.shape == momentum.shape == (10,) and wall >= 0
    assert np.max(np.abs(momentum)) < 1e-14  # lp2 keeps |L|
    assert 0 < np.max(np.abs(energy)) < 1e-2
