"""The flip interval against the perturbation: starts, the exact curve, the measured sweep."""

import math

import numpy as np

import stability
from stability.free_body.tennis_racket.flipsweep import (
    exact_flip_curve, flip_sweep, flip_sweep_starts,
)

MOMENTS = (0.25, 0.75, 1.0)


def test_starts_spin_about_axis_2_nudged_along_axis_1():
    w0 = flip_sweep_starts([1e-2, 1e-4], 2.0)
    np.testing.assert_array_equal(w0, [[2e-2, 2.0, 0.0], [2e-4, 2.0, 0.0]])


def test_exact_curve_is_the_exact_flip_interval_and_follows_the_log_law():
    eps = np.array([1e-3, 1e-5, 1e-7])
    exact, asymptote = exact_flip_curve(MOMENTS, eps, 1.0)
    body = stability.RigidBody(*MOMENTS)
    for e, value in zip(eps, exact):
        assert value == stability.flip_interval(body, [e, 1.0, 0.0])
    lam = float(stability.growth_rate(body, 2, 1.0))
    np.testing.assert_allclose(np.diff(asymptote), 2 / lam * math.log(100.0), rtol=1e-6)
    np.testing.assert_allclose(exact, asymptote, rtol=1e-4)


def test_sweep_measures_the_exact_interval():
    sweep = flip_sweep(np.array([MOMENTS]), [1e-2, 1e-4], 1.0, ["rk4"], [0.05])
    assert sweep["measured"].shape == (1, 1, 2)
    np.testing.assert_allclose(sweep["measured"][0], sweep["exact"], rtol=1e-4)
    assert sweep["growth_rate"][0] == float(stability.growth_rate(MOMENTS, 2, 1.0))
