"""The member loop: chunking, threads, interruption, failure flags and in-loop tracking."""

import os
import signal
import threading

import numba
import numpy as np
import pytest

from stability.util.conventions import STATUS_NONFINITE, STATUS_OK
from stability.free_body.propagate import CHECK_EVERY, propagate
from stability.engine.driver import untrusted

MOMENTS = np.array([1.0, 2.0, 3.0])


def starts(n, seed=0):
    rng = np.random.default_rng(seed)
    w = np.column_stack([1e-3 * rng.standard_normal(n), np.ones(n), 1e-3 * rng.standard_normal(n)])
    return MOMENTS * w


@pytest.mark.parametrize("method", ["rk4", "lp4"])
def test_result_is_bitwise_independent_of_chunks_and_threads(method):
    m0 = starts(300)
    one_call = propagate(method, MOMENTS, m0, 0.01, 400, save_every=50, chunk_steps=400)
    chunked = propagate(method, MOMENTS, m0, 0.01, 400, save_every=50, chunk_steps=100)
    previous = numba.get_num_threads()
    try:
        numba.set_num_threads(1)
        serial = propagate(method, MOMENTS, m0, 0.01, 400, save_every=50, chunk_steps=150)
    finally:
        numba.set_num_threads(previous)
    for other in (chunked, serial):
        np.testing.assert_array_equal(other.m_final, one_call.m_final)
        np.testing.assert_array_equal(other.saved, one_call.saved)


def test_member_results_do_not_depend_on_the_other_members():
    m0 = starts(130)
    together = propagate("lp2", MOMENTS, m0, 0.01, 200)
    alone = propagate("lp2", MOMENTS, m0[77:78], 0.01, 200)
    np.testing.assert_array_equal(alone.m_final[0], together.m_final[77])


def test_unsorted_moments_give_the_same_physics():
    """Relabelling the axes by a proper rotation (cyclic shift) relabels the trajectory."""
    m0 = starts(5)
    run = propagate("rk4", MOMENTS, m0, 0.01, 300)
    shift = [1, 2, 0]  # body axes (2, 3, 1): an even permutation, a rotation
    shifted = propagate("rk4", MOMENTS[shift], m0[:, shift], 0.01, 300)
    np.testing.assert_allclose(shifted.m_final, run.m_final[:, shift], rtol=0, atol=1e-14)


def test_non_finite_members_are_flagged_with_the_step():
    m0 = np.vstack([starts(2), [[1e200, 1e200, 1e200]]])
    run = propagate("rk4", MOMENTS, m0, 0.1, 50, save_every=10)
    assert list(run.status) == [STATUS_OK, STATUS_OK, STATUS_NONFINITE]
    assert 1 <= run.fail_step[2] <= CHECK_EVERY and run.fail_step[0] == -1
    mask = untrusted(np.arange(0, 51, 10), run.fail_step)
    assert not mask[:2].any() and mask[2, 1:].all()
    assert np.all(np.isfinite(run.saved[:2]))


def test_interrupt_stops_after_the_chunk_in_flight():
    """Ctrl-C ends the run between chunks; asked for its partial result, the state is exactly
    that of ``steps_done`` steps."""
    m0 = starts(2000)
    timer = threading.Timer(0.5, os.kill, (os.getpid(), signal.SIGINT))
    timer.start()
    try:
        run = propagate("lp2", MOMENTS, m0, 1e-3, 10_000_000, chunk_steps=2000, partial=True)
    finally:
        timer.cancel()
    assert run.interrupted
    assert 0 < run.steps_done < 10_000_000 and run.steps_done % 2000 == 0
    again = propagate("lp2", MOMENTS, m0, 1e-3, run.steps_done, chunk_steps=2000)
    np.testing.assert_array_equal(again.m_final, run.m_final)


def test_interrupt_raises_unless_the_partial_result_is_asked_for():
    """By default a stopped run raises KeyboardInterrupt after its chunk in flight, so no
    caller can take a partial run for a whole one."""
    timer = threading.Timer(0.5, os.kill, (os.getpid(), signal.SIGINT))
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):  # run to its end, it would return (minutes)
            propagate("lp2", MOMENTS, starts(2000), 1e-3, 10_000_000, chunk_steps=2000)
    finally:
        timer.cancel()


@pytest.mark.parametrize(
    "eps, flip_interval",
    [(1e-2, 20.754610), (1e-4, 36.707819)],  # 2K/nu, literature notes section 1.5
)
def test_tracked_flip_interval_matches_the_exact_one(eps, flip_interval):
    m0 = MOMENTS * np.array([[eps, 1.0, 0.0]])
    run = propagate("rk4", MOMENTS, m0, 0.005, 40_000, track_axis=1)  # t = 200
    e = run.extras
    count = e["axis_crossings"][0]
    assert count >= 4
    measured = (e["last_axis_crossing"][0] - e["first_axis_crossing"][0]) / (count - 1)
    assert measured == pytest.approx(flip_interval, rel=2e-6)
    assert e["perp_crossings"][0] == 0  # w1 keeps its sign in this regime


@pytest.mark.parametrize("h", [0.01, 0.1])
def test_tracked_passage_times_give_the_growth_rate(h):
    """ln(level) against passage time has slope lambda = sqrt((I2-I1)(I3-I2)/(I1 I3)) = 1/sqrt(3).

    Passage times interpolate ln(amplitude) within a step, so what is left is RK4's own rate
    bias -(h lambda)^4 / 120 (literature notes 4.1): -9.3e-8 at h = 0.1.
    """
    lam = 1.0 / np.sqrt(3.0)
    d1 = 1e-9
    d3 = MOMENTS[0] * lam / ((MOMENTS[1] - MOMENTS[2]) * 1.0) * d1  # unstable eigenvector
    m0 = MOMENTS * np.array([[d1, 1.0, d3]])
    levels = np.geomspace(1e-7, 1e-4, 16)
    run = propagate("rk4", MOMENTS, m0, h, round(40 / h), track_axis=1, levels=levels)
    t = run.extras["passage_time"][0]
    assert np.all(np.isfinite(t)) and np.all(np.diff(t) > 0)
    slope = np.polyfit(t, np.log(levels), 1)[0]
    bias = -((h * lam) ** 4) / 120
    assert slope / lam - 1 == pytest.approx(bias, abs=1e-8)


def test_tracked_oscillation_about_the_largest_axis():
    """Small oscillation about axis 3: perpendicular crossings at Omega = 1 rad/s (I = 1, 2, 3)."""
    m0 = MOMENTS * np.array([[1e-4, 0.0, 1.0]])
    run = propagate("rk4", MOMENTS, m0, 0.005, 20_000, track_axis=2)  # t = 100
    e = run.extras
    n = e["perp_crossings"][0]
    omega = np.pi * (n - 1) / (e["last_perp_crossing"][0] - e["first_perp_crossing"][0])
    assert omega == pytest.approx(1.0, rel=1e-6)
    assert e["axis_crossings"][0] == 0
    assert e["max_perp_amplitude"][0] == pytest.approx(1e-4, rel=1e-3)


def test_one_compiled_signature_serves_every_kind_of_run():
    """Saving, tracking and chunking must not trigger a second compilation (timed loops)."""
    from stability.engine import compiled_loop
    from stability.registry import SCENES

    m0 = starts(70)
    propagate("rk4", MOMENTS, m0, 0.01, 100, save_every=10, chunk_steps=30)
    propagate("rk4", MOMENTS, m0, 0.01, 100, track_axis=1, levels=[1e-3, 1e-2])
    propagate("rk4", MOMENTS, m0, 0.01, 100)
    scene = SCENES["free_body"]
    assert len(compiled_loop(scene, scene.method("rk4")).signatures) == 1
