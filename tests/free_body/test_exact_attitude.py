"""The exact attitude of the free body (stability.free_body.exact_attitude): against DOP853 in any
axis order, and the motions it refuses."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import stability
from stability.core.quaternions import attitude_error, quaternion_multiply
from stability.free_body.exact_attitude import exact_attitude, free_motion

from ..helpers import random_members


def dop853_attitude(moments, w0, q0, t):
    def rhs(_, y):
        w = y[:3] / moments
        return np.r_[np.cross(y[:3], w), 0.5 * quaternion_multiply(y[3:], np.r_[0.0, w])]

    sol = solve_ivp(rhs, (0.0, t[-1]), np.r_[moments * w0, q0], method="DOP853", rtol=1e-13,
                    atol=1e-13, t_eval=t)
    return sol.y[3:].T


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_exact_attitude_matches_dop853_in_any_axis_order(seed):
    rng = np.random.default_rng(seed)
    moments, w0 = random_members(1, seed)
    order = rng.permutation(3)  # the body's own axis order, not the canonical one
    body = stability.RigidBody(*moments[0][order])
    q0 = rng.normal(size=4)
    q0 /= np.linalg.norm(q0)
    t = np.linspace(0.0, 25.0, 11)
    q = exact_attitude(body, w0[0][order], t, q0)
    reference = dop853_attitude(body.moments, w0[0][order], q0, t)
    assert np.max(attitude_error(q, reference)) < 5e-11  # DOP853's own error
    assert attitude_error(q[:1], q0[None])[0] < 1e-15


def test_separatrix_and_handle_spin_are_refused_with_a_reason():
    with pytest.raises(ValueError, match="separatrix"):
        free_motion(np.array([1.0, 2.0, 3.0]), np.array([0.0, 1.0, 0.0]))
    with pytest.raises(ValueError, match="handle"):
        free_motion(np.array([1.0, 2.0, 3.0]), np.array([1.0, 0.0, 0.0]))
