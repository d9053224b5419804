"""Status you can trust: a member is ok only if its numbers are, for every registered method.

Each method declares ``max_step_angle`` (the largest step angle h max|w| at which its results
are trustworthy, measured as the spec's docstring says); ``run_ensemble`` labels members beyond
it ``step_too_large`` and refuses a run where every member would be.
"""

import math

import numpy as np
import pytest

import stability
from stability.util import conventions as cv
from stability.free_body.spin_ensembles import run_ensemble
from stability.free_body.timescales import max_angular_speed
from stability.free_body.exact import exact_omega_of_starts

BODY = stability.RigidBody(1.0, 2.0, 3.0)
#: A start near the intermediate axis (it flips) and a generic one.
STARTS = np.array([[0.01, 1.0, 0.02], [0.3, 1.0, 0.9]])


@pytest.mark.parametrize("name", sorted(stability.METHODS))
def test_every_method_declares_a_step_bound(name):
    bound = stability.METHODS[name].max_step_angle
    assert bound is not None and 0.0 < bound < math.inf
    assert stability.METHODS[name].describe()["max_step_angle"] == bound


@pytest.mark.parametrize("name", sorted(stability.METHODS))
def test_absurd_step_is_never_ok_and_a_good_step_is(name):
    bound = stability.METHODS[name].max_step_angle
    speed = max_angular_speed(BODY.moments, STARTS)
    h = 0.25 * bound / speed.max()  # the slow members are well inside the bound
    n = 80
    # The same starts 2000 times faster (the lp2 case: ~2000 rad per step), and 1.5
    # times the bound.
    fast = np.vstack([STARTS * 2000.0 * 4.0 / bound, STARTS * 1.5 * 4.0])
    ds = run_ensemble(BODY, 2, starts=np.vstack([STARTS, fast]), h=h, t_end=n * h,
                      method=name, keep=stability.Keep(save_every=n),
                      options=stability.RunOptions(progress=False))
    status = ds.status.values
    assert np.all(status[:2] == cv.STATUS_OK), status
    assert np.all(status[2:] != cv.STATUS_OK), status
    assert np.isnan(ds.w.values[2:, -1]).all()
    # ok means right: the good members against the exact solution.
    exact = exact_omega_of_starts(BODY, STARTS, n * h)
    error = np.linalg.norm(ds.w.values[:2, -1] - exact, axis=1) / np.linalg.norm(exact, axis=1)
    assert error.max() < 0.05, error


def test_a_run_with_every_member_beyond_the_bound_is_refused():
    racket = stability.RigidBody.preset("tennis_racket")
    with pytest.raises(ValueError, match=r"h = 0.002 s is too large for lp2 .* choose h <= "):
        run_ensemble(racket, 2, 1e6, 1e-4, 10, h=2e-3, t_end=0.2, method="lp2")


def test_step_bound_is_recorded_in_the_dataset():
    ds = run_ensemble(BODY, 2, 1.0, 1e-3, 4, h=0.1, t_end=1.0, method="lp2",
                      options=stability.RunOptions(progress=False))
    assert ds.attrs["method_max_step_angle"] == stability.METHODS["lp2"].max_step_angle
    assert "step_too_large" in ds.status.attrs["comment"]


@pytest.mark.parametrize("w0", [[0.01, 1.0, 0.02], [0.3, 1.0, 0.9], [1.0, 0.1, 0.05],
                                [0.05, 0.1, 1.0], [1.0, 1.0, 1.0]])
def test_max_angular_speed_is_the_largest_speed_of_the_exact_motion(w0):
    t = np.linspace(0.0, 200.0, 20001)
    w = stability.exact_omega(BODY, w0, t)
    reached = np.linalg.norm(w, axis=1).max()
    bound = max_angular_speed(BODY.moments, [w0])[0]
    assert reached <= bound * (1 + 1e-12)
    assert reached >= bound * (1 - 1e-3)


@pytest.mark.parametrize("moments, spin", [(1e-200, 1.0), (1e200, 1.0), (1.0, 1e200),
                                           (1e-160, 1e160)])
def test_max_angular_speed_is_the_same_at_any_scale(moments, spin):
    """The motion is the same for moments scaled alike and scales with the start, so the
    bound is too: no square of a tiny moment or a huge spin turns it into inf or nan."""
    w0 = np.array([[0.3, 1.0, 0.9], [0.01, 1.0, 0.02]])
    reference = max_angular_speed(BODY.moments, w0)
    scaled = max_angular_speed(BODY.moments * moments, w0 * spin)
    np.testing.assert_allclose(scaled, reference * spin, rtol=1e-14)
