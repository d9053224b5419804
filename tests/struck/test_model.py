"""The struck bat or racket (scene ``struck_body``): the centre of percussion from the runs."""


import numpy as np
import pytest

from stability.core.body import Part
from stability.engine import propagate_groups
from stability.registry import SCENES
from stability.struck.methods import J_ACROSS, X, strike_params
from stability.struck.model import (
    INCH, baseball_bat, centre_of_percussion, reaction_impulse, tennis_racket,
)


SCENE = SCENES["struck_body"]
BAT = baseball_bat()
TAU = 7e-4


def strike(body, pivot, s, held, impulse=12.0, tau=TAU):
    return np.array([body.mass, body.centre - pivot, body.inertia, s - pivot, impulse, tau,
                     held])


def run(strikes, steps, n_per_contact, tau=TAU, save_every=0):
    x0 = np.zeros((len(strikes), SCENE.width))
    x0[:, X] = [st[1] for st in strikes]
    params = np.array([strike_params(st) for st in strikes])
    return propagate_groups(SCENE, "rk4", x0, params, np.ones(len(strikes), int),
                            tau / n_per_contact, steps, save_every=save_every, progress=False)


def test_frustum_gives_the_cone_and_cylinder_closed_forms():
    cone = Part.frustum(3.0, 0.2, 0.0, 0.6)  # solid cone: 3/10 M r^2, 3/20 M r^2 + 3/80 M h^2
    np.testing.assert_allclose(np.diag(cone.inertia),
                               [3 / 20 * 3 * 0.04 + 3 / 80 * 3 * 0.36] * 2 + [0.3 * 3 * 0.04],
                               rtol=1e-14)
    np.testing.assert_allclose(cone.position, [0, 0, 0.15], atol=1e-15)  # h / 4 from the base
    rod = Part.frustum(2.0, 0.1, 0.1, 0.5, base=(1, 0, 0), axis=(1, 0, 0))
    assert rod.inertia[1, 1] == pytest.approx(2.0 * (3 * 0.01 + 0.25) / 12, rel=1e-14)
    np.testing.assert_allclose(rod.position, [1.25, 0, 0])
    with pytest.raises(ValueError, match="not both 0"):
        Part.frustum(1.0, 0.0, 0.0, 1.0)


def test_the_bat_is_a_real_bat():
    """33 in, 30 oz; balance point and moment about the 6-inch pivot in the measured ranges."""
    assert BAT.length == pytest.approx(33 * INCH)
    assert BAT.mass == pytest.approx(0.850)
    assert 21 * INCH < BAT.centre < 24 * INCH
    assert 0.146 <= BAT.moment_about(6 * INCH) <= 0.183
    cop = centre_of_percussion(BAT, 6 * INCH)
    assert 5 * INCH < BAT.length - cop < 8 * INCH  # 5-7 in from the end is where players feel it
    racket = tennis_racket()
    assert racket.mass == pytest.approx(0.302) and 0.3 < racket.centre < 0.38


def test_reaction_across_the_hands_is_the_impulse_formula_and_vanishes_at_the_cop():
    pivot = 6 * INCH
    q = centre_of_percussion(BAT, pivot)
    points = np.array([0.3, 0.5, q, 0.75, 0.83])
    out = run([strike(BAT, pivot, s, 1.0) for s in points], 64, 64).x_final
    np.testing.assert_allclose(out[:, J_ACROSS], reaction_impulse(BAT, pivot, points, 12.0),
                               rtol=1e-8, atol=1e-12)
    assert abs(out[2, J_ACROSS]) < 1e-13 * 12.0


def test_free_body_after_the_contact_keeps_its_angular_momentum():
    sts = [strike(BAT, 6 * INCH, 0.7, 0.0), strike(BAT, 6 * INCH, 0.7, 1.0)]
    out = run(sts, 256, 32, save_every=32)
    for i, st in enumerate(sts):
        L = SCENE.invariants["angular_momentum"](out.saved[i, 1:], st)  # after the contact
        assert np.ptp(L) < 1e-9 * abs(L[0])


def test_a_pivot_at_the_centre_has_no_centre_of_percussion():
    with pytest.raises(ValueError, match="no centre of percussion"):
        centre_of_percussion(BAT, BAT.centre)

