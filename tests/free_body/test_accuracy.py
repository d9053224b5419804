"""References to score runs against: exact final states, the floor, the DOP853 attitude, errors."""

import numpy as np
import pytest

import stability
from stability.ensemble.starts import perturbed_starts
from stability.free_body.accuracy import (
    METRICS, attitude_reference, conditioning_floor, error_statistics, exact_final_w,
    final_errors,
)

BODY = stability.RigidBody(1.0, 2.0, 3.0)


def test_error_statistics_over_the_finite_values_in_metric_order():
    values = np.r_[np.arange(1.0, 101.0), np.nan, np.inf]
    stats = error_statistics(values)
    assert METRICS == ("max", "p99", "median")
    np.testing.assert_allclose(stats, [100.0, np.percentile(np.arange(1.0, 101.0), 99), 50.5])
    assert np.all(np.isnan(error_statistics([np.nan])))


def test_exact_final_w_is_the_exact_solution_of_each_start():
    w0 = perturbed_starts(2, 1.0, 1e-2, 4, seed=1)
    w_ref = exact_final_w(BODY, w0, 7.5)
    assert w_ref.shape == (4, 3)
    for w, start in zip(w_ref, w0):
        np.testing.assert_array_equal(w, stability.exact_omega(BODY, start, 7.5))


def test_final_errors_vanish_for_the_exact_end_state():
    w0 = perturbed_starts(2, 1.0, 1e-2, 6, seed=2)
    w_ref = exact_final_w(BODY, w0, 10.0)
    errors = final_errors(BODY.moments, w0, w_ref, w_ref)
    assert np.all(errors["w"] == 0.0)
    assert np.max(errors["energy"]) < 1e-13 and np.max(errors["momentum"]) < 1e-13
    nudged = final_errors(BODY.moments, w0, w_ref * (1 + 1e-6), w_ref)
    np.testing.assert_allclose(nudged["w"], 1e-6, rtol=1e-6)
    np.testing.assert_allclose(nudged["energy"], 2e-6, rtol=1e-5)
    np.testing.assert_allclose(nudged["momentum"], 1e-6, rtol=1e-5)


def test_conditioning_floor_is_larger_near_the_separatrix():
    floors = {}
    for axis in (2, 3):
        w0 = perturbed_starts(axis, 1.0, 1e-2, 32, seed=1)
        w_ref = exact_final_w(BODY, w0, 30.0)
        floors[axis] = conditioning_floor(BODY, w0, 30.0, w_ref, seed=1)
        assert floors[axis].shape == (32,) and np.all(floors[axis] >= 0)
    assert np.max(floors[3]) < 1e-13 < np.max(floors[2])


@pytest.mark.parametrize("axis", [1, 3])
def test_attitude_reference_of_a_steady_spin_is_a_rotation_about_its_axis(axis):
    spin, t_end = 0.7, 4.0
    w0 = np.zeros((2, 3))
    w0[:, axis - 1] = spin
    q, w_error = attitude_reference(BODY, w0, t_end)
    expected = np.zeros(4)
    expected[0], expected[axis] = np.cos(spin * t_end / 2), np.sin(spin * t_end / 2)
    np.testing.assert_allclose(q, np.tile(expected, (2, 1)), atol=1e-12)
    assert np.all(w_error < 1e-14)
