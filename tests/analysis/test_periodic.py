"""Measuring periodic signals (stability.analysis.periodic): crossings and turning points, means
over whole periods."""

import numpy as np
import pytest

from stability.analysis.periodic import extrema, level_crossings, mean_period, weighted_mean


def _signal(t, w=2.7):
    """x = cos(w t) + 0.3 cos(2 w t) and its derivative: minima -0.7167 at cos(wt) = -5/6."""
    return (np.cos(w * t) + 0.3 * np.cos(2 * w * t),
            -w * np.sin(w * t) - 0.6 * w * np.sin(2 * w * t))


def test_hermite_crossings_and_turning_points_converge_at_fourth_order():
    """Period, crossing levels and minima of a two-harmonic signal sampled 16, 32 and 64 times
    a period (not a whole number of samples a period): errors fall by more than 2^3 per halving
(fourth order, ~16 asymptotically) and reach 1e-6."""
    w = 2.7
    lowest = 0.6 * (5 / 6) ** 2 - 5 / 6 - 0.3  # x = 0.6 c^2 + c - 0.3, min at c = cos(w t) = -5/6
    errors = []
    for per_period in (16, 32, 64):
        t = np.arange(0.0, 20 * 2 * np.pi / w, 2 * np.pi / w / (per_period + 0.37)) + 0.123
        x, dx = _signal(t, w)
        up = level_crossings(t, x, dx, 0.1)
        down = level_crossings(t, x, dx, 0.1, direction=-1)
        _, lows = extrema(t, x, dx, "min")
        assert up.size == down.size == 20 and lows.size == 40  # two minima a period
        assert np.all(_signal(up, w)[1] > 0) and np.all(_signal(down, w)[1] < 0)
        errors.append([abs(mean_period(up) * w / (2 * np.pi) - 1.0),
                       np.abs(_signal(np.concatenate([up, down]), w)[0] - 0.1).max(),
                       np.abs(lows - lowest).max()])
    errors = np.array(errors)
    assert np.all(errors[:-1] / errors[1:] > 2**3), errors
    assert errors[-1].max() < 1e-6


def test_weighted_mean_converges_faster_than_the_plain_mean():
    """Over 40 periods the bump-weighted mean of a periodic signal is right to 1e-11 where the
    plain mean over a window of 40.5 periods is off by ~1e-3."""
    w = 2.7
    t = np.linspace(0.0, 40.5 * 2 * np.pi / w, 40 * 32)
    f = 1.5 + np.cos(w * t) ** 3 + 0.2 * np.sin(3 * w * t) + 0.5 / (1.2 + np.cos(w * t))
    exact = 1.5 + 0.5 / np.sqrt(1.2**2 - 1.0)
    assert abs(weighted_mean(f) - exact) < 1e-11
    assert abs(f.mean() - exact) > 1e-4


def test_extrema_refuses_an_unknown_kind():
    with pytest.raises(ValueError, match="kind must be 'min' or 'max'"):
        extrema([0.0, 1.0], [0.0, 1.0], [1.0, 1.0], "peak")
