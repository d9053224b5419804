"""The shape triangle: the grid with exact edges, Omega^2 over it, run lengths, levels, edges."""

import numpy as np
import pytest

import stability
from stability.util.conventions import REGIME_ALGEBRAIC, REGIME_NEUTRAL
from stability.free_body.stability_map.shapes import (
    EDGE_CASES, EDGE_EQUAL_12, EDGE_EQUAL_23, EDGE_FLAT, amplitude_levels, analytic_omega_squared,
    edge_series, horizons, shape_grid,
)


@pytest.mark.parametrize("n", [1, 2, 5, 32])
def test_grid_covers_the_allowed_triangle_with_exact_edges(n):
    moments, edges = shape_grid(n)
    assert moments.shape == ((n + 1) * (n + 2) // 2 - 1, 3)
    I1, I2, I3 = moments.T
    assert np.all(I3 == 1.0) and np.all(I1 > 0)
    assert np.all(I1 <= I2) and np.all(I2 <= I3)
    assert np.all(I1 + I2 >= 1.0 - 1e-15)
    # Edge flags are exact: equal moments are the same float, so Omega^2 is exactly 0 there.
    equal12 = (edges & EDGE_EQUAL_12) > 0
    equal23 = (edges & EDGE_EQUAL_23) > 0
    flat = (edges & EDGE_FLAT) > 0
    np.testing.assert_array_equal(equal12, I1 == I2)
    np.testing.assert_array_equal(equal23, I2 == I3)
    np.testing.assert_array_equal(flat, np.abs(I1 + I2 - 1.0) < 1e-15)
    assert np.sum(equal12 & equal23) == 1  # the sphere
    for I in moments[equal12 | equal23]:
        zero = [a for a in (1, 2, 3) if np.sum(I == I[a - 1]) > 1]
        for a in zero:
            assert float(stability.omega_squared(I, a, 1.0)) == 0.0


def test_horizon_depends_on_the_size_of_omega_squared_only():
    omega2 = np.array([[0.25, -0.25, 0.0]])
    t = horizons(omega2, horizon=80.0, t_max=2500.0, t_neutral=800.0)
    np.testing.assert_allclose(t, [[160.0, 160.0, 800.0]])
    assert horizons(np.array([1e-8]), 80.0, 2500.0, 800.0)[0] == 2500.0
    levels = amplitude_levels(2.0, 1e-7, 8)
    assert levels[0] <= 1.5e-7 * 2.0 < levels[1] and levels[-1] == pytest.approx(2.0)
    np.testing.assert_allclose(np.diff(np.log10(levels)), 1 / 8)


def test_analytic_omega_squared_is_that_of_each_body():
    moments, _ = shape_grid(4)
    omega2 = analytic_omega_squared(moments, 2.0)
    assert omega2.shape == (moments.shape[0], 3)
    for I, row in zip(moments, omega2):
        body = stability.RigidBody(*I, physical=False)
        expected = [float(stability.omega_squared(body, a, 2.0)) for a in (1, 2, 3)]
        np.testing.assert_array_equal(row, expected)


def test_edge_series_drift_linearly_without_flips():
    edge = edge_series(1.0, 1e-3, 60.0, "rk4", 0.1)
    assert edge["names"] == [name for name, _, _ in EDGE_CASES]
    assert edge["w"].shape == (len(EDGE_CASES), edge["time"].size, 3)
    assert np.all(edge["flips"] == 0) and np.all(edge["distinct_change"] == 0.0)
    for c, (name, _, _) in enumerate(EDGE_CASES):
        if name == "sphere":
            assert edge["slope_predicted"][c] == 0.0 and edge["regime"][c] == REGIME_NEUTRAL
        else:
            assert edge["regime"][c] == REGIME_ALGEBRAIC
            assert edge["slope_measured"][c] == pytest.approx(edge["slope_predicted"][c],
                                                              rel=1e-3)
