"""Montgomery's angle and the twist (stability.free_body.twisting_racket.geometric_phase): each
against an independent route."""

import numpy as np
import pytest

import stability
from stability.free_body.attitude import propagate_attitudes
from stability.core.quaternions import attitude_error
from stability.free_body.exact_attitude import exact_attitude, free_motion
from stability.free_body.twisting_racket.geometric_phase import exact_angles, run_angles, wrap
from stability.free_body.twisting_racket.measure import tossed_members

from ...helpers import random_members


def test_montgomery_and_twist_hold_for_random_bodies_from_runs_and_exactly():
    moments, w0 = random_members(12, 7)
    motions = [free_motion(I, w) for I, w in zip(moments, w0)]
    kinds = {fm.kind for fm in motions}
    assert kinds == {1, 2}  # both sides of the separatrix
    period = np.array([fm.period for fm in motions])
    exact = exact_angles(motions, period)
    # the formula 2 E T / |L| - S against phi(T) of the exact attitude
    assert np.max(np.abs(wrap(exact["montgomery"] - exact["montgomery_formula"]))) < 1e-11
    # with +S the formula would be wrong: S is not a multiple of 2 pi
    assert np.max(np.abs(wrap(exact["dynamic_phase"] + exact["solid_angle"]
                              - exact["montgomery"]))) > 0.1
    n = 1000
    runs = propagate_attitudes("lp8", moments, moments * w0, np.tile([1.0, 0, 0, 0], (12, 1)),
                               period / n, 2 * n, save_every=5,
                               options=stability.RunOptions(progress=False))
    ran = run_angles(runs, period, exact["flip_time"])
    assert np.max(np.abs(wrap(ran["montgomery"] - exact["montgomery_formula"]))) < 1e-8
    flip, half = exact["flip_time"], exact["half_window"]
    fits = (flip - half >= 0.0) & (flip + half <= 2 * period)  # the window inside the run
    assert fits.sum() >= 8 and np.array_equal(np.isfinite(ran["twist"]), fits)
    assert np.max(np.abs(ran["twist"] - exact["twist"])[fits]) < 1e-8
    # the window is what it says: m2 = 0 at its centre, phi advances by exactly 2 pi
    for fm, f, d in zip(motions, exact["flip_time"], exact["half_window"]):
        m = fm.m([f])[0]
        assert abs(m[1]) < 1e-14 * fm.momentum
        assert abs(fm.phi(f + d) - fm.phi(f - d) - 2 * np.pi) < 1e-12


def test_exact_precession_angle_matches_the_attitude_of_a_run():
    moments, w0 = random_members(4, 3)
    motions = [free_motion(I, w) for I, w in zip(moments, w0)]
    period = np.array([fm.period for fm in motions])
    runs = propagate_attitudes("lp8", moments, moments * w0, np.tile([1.0, 0, 0, 0], (4, 1)),
                               period / 800, 800, save_every=100,
                               options=stability.RunOptions(progress=False))
    for j, fm in enumerate(motions):  # R(t) R(0)^T of the run, against the exact attitude
        t = runs.times[j]
        q = exact_attitude(stability.RigidBody(*moments[j], physical=False), w0[j], t)
        assert np.max(attitude_error(runs.saved[j, :, 3:], q)) < 1e-9


def test_the_racket_twists_by_nearly_a_half_turn():
    body = stability.RigidBody.preset("tennis_racket")
    moments, w0, _ = tossed_members(body.moments, 6, 10.0, (1e-5, 1e-4), 0.0, seed=2)
    motions = [free_motion(I, w) for I, w in zip(moments, w0)]
    exact = exact_angles(motions, [fm.period for fm in motions])
    defect = np.pi - np.abs(exact["twist"])
    assert np.all((defect > 0.15) & (defect < 0.3))  # close to, not exactly, pi
    assert np.ptp(defect) < 1e-3  # near the separatrix it depends on the moments alone


def test_run_continued_between_saved_steps_is_continuous_and_lands_on_the_steps():
    moments, w0 = random_members(2, 5)
    runs = propagate_attitudes("rk4", moments, moments * w0, np.tile([1.0, 0, 0, 0], (2, 1)),
                               [0.01, 0.013], 40, save_every=8,
                               options=stability.RunOptions(progress=False))
    k = np.array([3, 5])  # a saved state, reached by continuing from the one before it
    t = runs.h * 8 * k
    np.testing.assert_allclose(runs.state_at(t - runs.h * 8 * 1e-12), runs.saved[[0, 1], k],
                               rtol=0, atol=1e-11)
    for j in range(1, 8):  # across a whole step of h inside a saved interval: no jump
        t = runs.h * (8 * 2 + j)
        gap = runs.state_at(t + 1e-13) - runs.state_at(t - 1e-13)
        assert np.max(np.abs(gap)) < 1e-11


def test_attitude_run_bad_input_says_what_is_wrong():
    moments, w0 = random_members(2, 5)
    q0 = np.tile([1.0, 0, 0, 0], (2, 1))
    for kwargs, message in ((dict(save_every=0), "save_every"), (dict(h=[0.01, -1.0]), "h"),
                            (dict(q0=q0[0]), "shapes")):
        args = dict(method="lp2", moments=moments, m0=moments * w0, q0=q0, h=[0.01, 0.01],
                    n_steps=10, save_every=1)
        with pytest.raises(ValueError, match=message):
            propagate_attitudes(**{**args, **kwargs}, options=stability.RunOptions(progress=False))
    runs = propagate_attitudes("lp2", moments, moments * w0, q0, 0.01, 10,
                               options=stability.RunOptions(progress=False))
    with pytest.raises(ValueError, match="period T at a saved step"):
        run_angles(runs, [1.0, 1.0], [0.5, 0.5])


def test_ensemble_carries_the_attitude_with_its_exact_error():
    body = stability.RigidBody.preset("tennis_racket")
    kwargs = dict(axis=2, spin=10.0, epsilon=1e-3, members=8, h=0.002, t_end=2.0,
                  method="lp4", options=stability.RunOptions(progress=False))
    ds = stability.run_ensemble(body, keep=stability.Keep(save_every=50, attitude=True),
                                **kwargs)
    plain = stability.run_ensemble(body, keep=stability.Keep(save_every=50), **kwargs)
    assert ds.w.equals(plain.w) and ds.flip_count.equals(plain.flip_count)
    assert ds.q.dims == ("member", "time", "quaternion_component")
    assert float(ds.attitude_error.max()) < 1e-6  # lp4 at h |w| = 0.02
    assert float(abs(ds.q_norm_error).max()) < 1e-13
    fine = stability.run_ensemble(body, keep=stability.Keep(save_every=100, attitude=True),
                                  **dict(kwargs, h=0.001))
    ratio = float(ds.attitude_error[:, -1].median() / fine.attitude_error[:, -1].median())
    assert 12.0 < ratio < 20.0  # order 4
    for name in ("q", "q_norm_error", "attitude_error"):
        assert ds[name].attrs["units"] and ds[name].attrs["long_name"]


@pytest.mark.parametrize("kwargs, message", [
    (dict(method="exact"), "cannot carry the attitude"),
    (dict(keep=dict(save_every=0, attitude=True)), "the attitude is kept with the time series"),
    (dict(keep=dict(attitude="yes")), "attitude must be True or False, got 'yes'"),
])
def test_ensemble_attitude_bad_input(kwargs, message):
    body = stability.RigidBody(1.0, 2.0, 3.0)
    base = dict(axis=2, spin=1.0, epsilon=1e-3, members=4, h=0.01, t_end=1.0,
                keep=dict(attitude=True))
    call = {**base, **kwargs}
    with pytest.raises(ValueError, match=message):
        stability.run_ensemble(body, **{**call, "keep": stability.Keep(**call["keep"])})

