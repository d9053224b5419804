"""Timed sweeps: the step ladder, the starts of the long run, one method and DOP853 swept."""

import numpy as np
import pytest

import stability
from stability.free_body.propagate import propagate
from stability.free_body.accuracy import exact_final_w
from stability.free_body.work_precision.sweeps import (
    jittered_starts, step_grid, sweep_method, sweep_point, sweep_scipy, timed_propagate,
)

BODY = stability.RigidBody(1.0, 2.0, 3.0)
W0 = np.array([[0.01, 1.0, 0.0], [0.0, 1.0, 0.01], [1.0, 0.01, 0.0]])


def test_step_grid_runs_from_h_max_to_h_min():
    counts = step_grid(50.0, 0.5, 1e-3, 2)
    assert counts[0] == 100 and np.all(np.diff(counts) > 0)
    h = 50.0 / counts
    assert h[-1] >= 1e-3 and h[-1] / 2**0.5 < 1e-3 * 1.01
    np.testing.assert_allclose(h[:-1] / h[1:], 2**0.5, rtol=0.02)
    np.testing.assert_array_equal(step_grid(1.0, 2.0, 1.5, 1), [1])


def test_jittered_starts_keep_the_first_member_and_move_the_rest_a_little():
    w0 = np.array([0.3, 1.0, 0.9])
    starts = jittered_starts(w0, 5, seed=3)
    np.testing.assert_array_equal(starts[0], w0)
    offset = np.linalg.norm(starts[1:] - w0, axis=1) / np.linalg.norm(w0)
    assert np.all(offset > 0) and np.all(offset < 1e-2)
    np.testing.assert_array_equal(jittered_starts(w0, 5, seed=3), starts)


def test_sweep_point_without_errors_is_nan():
    point = sweep_point(h=0.1, steps=10, wall=2.0, members=4)
    assert point["member_step_time"] == pytest.approx(0.05)
    for key in ("w_error", "energy_error", "momentum_error", "attitude_error"):
        assert point[key].shape == (3,) and np.all(np.isnan(point[key]))


def test_timed_propagate_returns_the_run_and_a_positive_time():
    m0 = BODY.moments * W0
    run, wall = timed_propagate(stability.method_spec("rk4"), BODY.moments, m0, 0.1, 20)
    again = propagate("rk4", BODY.moments, m0, 0.1, 20, progress=False)
    np.testing.assert_array_equal(run.m_final, again.m_final)
    assert 0 <= wall <= run.wall_time


def test_sweep_method_errors_fall_with_h_and_the_exact_flow_takes_one_step():
    w_ref = exact_final_w(BODY, W0, 5.0)
    points = sweep_method(stability.method_spec("rk4"), BODY, W0, w_ref, 5.0,
                          step_grid(5.0, 0.5, 0.05, 1), budget=10.0, stop_error=1e-14)
    errors = [p["w_error"][0] for p in points]
    assert len(points) == 4 and np.all(np.diff(errors) < 0)
    assert all(p["failed"] == 0 and p["evaluations"] == 4 * p["steps"] for p in points)
    (exact,) = sweep_method(stability.method_spec("exact"), BODY, W0, w_ref, 5.0,
                            step_grid(5.0, 0.5, 0.05, 1), budget=10.0, stop_error=1e-14)
    assert exact["steps"] == 1 and exact["w_error"][0] < 1e-13


def test_sweep_scipy_tighter_tolerance_smaller_error():
    w_ref = exact_final_w(BODY, W0, 5.0)
    loose, tight = sweep_scipy(BODY, W0, w_ref, 5.0, [1e-4, 1e-10], scale=1.0)
    assert tight["evaluations"] > loose["evaluations"]
    assert tight["w_error"][0] < loose["w_error"][0] < 1e-2
    assert np.isnan(loose["h"]) and loose["rtol"] == 1e-4
