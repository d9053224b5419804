"""A step and a horizon chosen from the physics (stability.free_body.timescales), for
run_ensemble and integrate where they are not given."""

import numpy as np
import pytest

import stability
from stability.free_body.spin_ensembles import run_ensemble
from stability.free_body.timescales import max_angular_speed

BODY = stability.RigidBody(1.0, 2.0, 3.0, name="I=(1,2,3)")


def test_one_line_start_chooses_step_and_horizon_from_the_physics():
    """run_ensemble(body, axis, spin): step angle 0.02 rad, four flip intervals, 100 members
    at epsilon 1e-3; the rules are in the Dataset, and an explicit step or horizon stays."""
    from stability.free_body.exact import flip_interval
    from stability.free_body.timescales import DEFAULT_FLIPS, DEFAULT_STEP_ANGLE, nominal_start

    ds = run_ensemble(BODY, axis=2, spin=1.0, options=stability.RunOptions(progress=False),
                      keep=stability.Keep(save_every=0))
    h, t_end = ds.attrs["h"], ds.attrs["t_end"]
    w0 = nominal_start(2, 1.0, 1e-3)
    assert h * float(max_angular_speed(BODY.moments, w0[None])[0]) == pytest.approx(
        DEFAULT_STEP_ANGLE, rel=1e-12)
    interval = flip_interval(BODY, w0)
    assert DEFAULT_FLIPS * interval <= t_end < DEFAULT_FLIPS * interval + h
    assert ds.sizes["member"] == 100 and ds.attrs["epsilon"] == 1e-3
    assert "0.02 rad" in ds.attrs["h_rule"] and "4 flip intervals" in ds.attrs["t_end_rule"]
    # the rule says the interval, the four of them and the horizon they round up to
    assert (f"4 x {interval:.6g} s = {4 * interval:.6g} s, rounded up to whole saved steps: "
            f"{t_end:.6g} s") in ds.attrs["t_end_rule"]
    flips = ds.flip_count.values[ds.status.values == 0]
    assert flips.size == 100 and 3 <= np.median(flips) <= 5  # about one a flip interval
    stable = run_ensemble(BODY, axis=3, spin=1.0, h=0.05,
                          options=stability.RunOptions(progress=False),
                          keep=stability.Keep(save_every=0))
    assert stable.attrs["h"] == 0.05 and "h_rule" not in stable.attrs
    assert np.all(stable.flip_count.values == 0)
    assert stable.attrs["t_end"] == pytest.approx(
        DEFAULT_FLIPS * flip_interval(BODY, nominal_start(3, 1.0, 1e-3)), abs=0.05)
    # a horizon given without a step: the default step, shortened so that the horizon is a
    # whole number of saved steps (it was refused as not a whole number of steps)
    fitted = run_ensemble(BODY, axis=2, spin=1.0, t_end=7.0, keep=stability.Keep(save_every=3),
                          options=stability.RunOptions(progress=False))
    steps = round(7.0 / fitted.attrs["h"])
    assert steps % 3 == 0 and steps * fitted.attrs["h"] == pytest.approx(7.0, rel=1e-14)
    assert 1.0 <= h / fitted.attrs["h"] < 1.0 + 3 * h / 7.0  # no longer than the default
    assert fitted.sizes["time"] == steps // 3 + 1
    assert f"shortened to t_end / {steps}" in fitted.attrs["h_rule"]


def test_integrate_chooses_step_and_horizon_from_the_physics_where_not_given():
    """integrate(body, w0): the step angle 0.02 rad and four flip intervals, as run_ensemble
    chooses them; the trajectory ends on the exact motion; a given horizon keeps its value."""
    from stability.free_body.exact import flip_interval
    from stability.free_body.timescales import DEFAULT_FLIPS, DEFAULT_STEP_ANGLE

    w0 = np.array([1e-3, 1.0, 1e-3])
    ds = stability.integrate(BODY, w0)
    h, t_end = ds.attrs["h"], float(ds.time[-1])
    speed = float(max_angular_speed(BODY.moments, w0[None])[0])
    assert h * speed == pytest.approx(DEFAULT_STEP_ANGLE, rel=1e-12)
    assert DEFAULT_FLIPS * flip_interval(BODY, w0) <= t_end < DEFAULT_FLIPS * flip_interval(
        BODY, w0) + h
    assert "0.02 rad" in ds.attrs["h_rule"] and "4 flip intervals" in ds.attrs["t_end_rule"]
    # rk4 at 0.02 rad a step over four flips: the end state on the exact one to 1e-6
    np.testing.assert_allclose(ds.w.values[-1], stability.exact_omega(BODY, w0, t_end),
                               atol=1e-6 * speed)
    given = stability.integrate(BODY, w0, 5.0, save_every=4)
    assert float(given.time[-1]) == pytest.approx(5.0, rel=1e-14)
    assert given.attrs["h"] <= h and "t_end_rule" not in given.attrs
    assert round(5.0 / given.attrs["h"]) % 4 == 0
