"""Rolling with and without slipping (scene ``rolling_body``) against the formulas."""


import numpy as np
import pytest

from stability.engine import propagate_groups
from stability.rolling.methods import (
    HEAT, MODE, SWITCHES, T_ROLL, V, W, X, X_ROLL, track_row,
)
from stability.rolling.model import (
    G, SHAPES, launch_formulas, rolling_acceleration, rolls, slipping_acceleration,
    slipping_spin_rate, start_states,
)
from stability.registry import SCENES


SCENE = SCENES["rolling_body"]


def run(rows, x0, h, steps, save_every=0):
    rows = np.atleast_2d(rows)
    return propagate_groups(SCENE, "exact", x0, rows, np.ones(rows.shape[0], int), h, steps,
                            save_every=save_every, progress=False)


def test_released_on_an_incline_rolls_iff_tan_theta_within_mu_s_1_plus_mr2_over_i():
    """Random slopes, friction and shapes: the regime is the formula's, the acceleration is
    g sin / (1 + k) rolling, g (sin - mu_k cos) slipping, and the spin rate a / R or
    mu_k g cos / (k R), to round-off."""
    rng = np.random.default_rng(1)
    n = 400
    theta = rng.uniform(0.01, 1.4, n)
    mu_s = rng.uniform(0.02, 0.8, n)
    mu_k = mu_s * rng.uniform(0.3, 1.0, n)
    k = rng.uniform(0.2, 1.0, n)
    rows = np.array([track_row(*a, angles=(b,)) for a, b in
                     zip(zip(k, np.full(n, 0.07), mu_s, mu_k), theta)])
    T = 0.7
    out = run(rows, start_states(0.0, 0.0, rows), T, 1).x_final
    expect_roll = rolls(theta, mu_s, k)
    assert 50 < expect_roll.sum() < n - 50  # both regimes are tried
    assert np.array_equal(out[:, HEAT] == 0.0, expect_roll)
    a = np.where(expect_roll, rolling_acceleration(theta, k), slipping_acceleration(theta, mu_k))
    alpha = np.where(expect_roll, rolling_acceleration(theta, k) / 0.07,
                     slipping_spin_rate(theta, mu_k, k, 0.07))
    np.testing.assert_allclose(2 * out[:, X] / T**2, a, rtol=1e-13)
    np.testing.assert_allclose(out[:, W] / T, alpha, rtol=1e-13)
    # while slipping, the slip speed grows at g (sin - mu_k cos (1 + 1/k))
    u = out[:, V] - 0.07 * out[:, W]
    rate = G * (np.sin(theta) - mu_k * np.cos(theta) * (1 + 1 / k))
    np.testing.assert_allclose(u[~expect_roll] / T, rate[~expect_roll], rtol=1e-12)


@pytest.mark.parametrize("steps", [1, 7, 1000])
def test_launch_on_a_floor_rolls_from_the_formula_time_at_the_formula_speed(steps):
    """Any speed and spin (backspin, topspin beyond rolling): the switch time, place and final
    speed (5/7 v0 + 2/7 R w0 for a sphere), the heat M u0^2 k / (2 (1 + k)): to round-off, for
    any number of steps (the event is found inside the step)."""
    rng = np.random.default_rng(2)
    n, R = 300, 0.0286
    v0 = rng.uniform(0.2, 5.0, n)
    w0 = rng.uniform(-2.0, 3.0, n) * v0 / R
    mu_k = rng.uniform(0.05, 0.4, n)
    k = np.where(np.arange(n) % 2 == 0, SHAPES["sphere"], rng.uniform(0.2, 1.0, n))
    rows = np.array([track_row(kk, R, m, m, mass=0.17) for kk, m in zip(k, mu_k)])
    f = launch_formulas(v0, w0, k, R, mu_k, 0.17)
    T = 1.1 * f["t_roll"].max()
    out = run(rows, start_states(v0, w0, rows), T / steps, steps).x_final
    assert np.all(out[:, SWITCHES] == 1) and np.all(out[:, MODE] == 0)
    np.testing.assert_allclose(out[:, T_ROLL], f["t_roll"], rtol=4e-15 * max(steps, 8) ** 0.5,
                               atol=1e-15)
    np.testing.assert_allclose(out[:, X_ROLL], f["x_roll"], rtol=1e-13)
    # (v0 + k R w0) / (1 + k) cancels near 0: errors relative to the launch speeds
    np.testing.assert_allclose(out[:, V], f["v_final"], rtol=1e-13, atol=1e-14 * v0.max())
    sphere = k == SHAPES["sphere"]
    np.testing.assert_allclose(out[sphere, V], 5 / 7 * v0[sphere] + 2 / 7 * R * w0[sphere],
                               rtol=1e-13, atol=1e-14 * v0.max())
    np.testing.assert_allclose(out[:, HEAT], f["energy_lost"], rtol=1e-12)
    np.testing.assert_allclose(out[:, V], R * out[:, W], rtol=1e-13, atol=1e-14 * v0.max())
