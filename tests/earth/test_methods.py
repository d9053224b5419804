"""The Earth's methods (stability.earth.methods): the perturbers' geometry, the full model's order
against DOP853, the free oblate Earth exact for any step."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation

from stability.earth import precession as eq
from stability.earth.methods import perturber
from stability.engine import propagate_groups
from stability.registry import SCENES

FULL = SCENES["lunisolar_earth"]


def orbit_direction(t, elements):
    """The perturber's direction and G M / r^3, written out here with SciPy's rotations."""
    k, e, n, m0, w0, wdot, inc, node0, nodedot = elements
    mean = m0 + n * t
    ecc = mean
    for _ in range(50):
        ecc = mean + e * math.sin(ecc)  # fixed point, slow but sure
    f = 2.0 * math.atan2(math.sqrt(1 + e) * math.sin(ecc / 2), math.sqrt(1 - e) * math.cos(ecc / 2))
    r = Rotation.from_euler("ZXZ", [node0 + nodedot * t, inc, w0 + wdot * t + f])
    return r.apply([1.0, 0.0, 0.0]), k / (1.0 - e * math.cos(ecc)) ** 3


def rhs(t, y, earth):
    """m' = m x w + sum 3 G M / r^3 s x I s, q' = q (0, w) / 2 in plain NumPy and SciPy."""
    A, C = earth[:2]
    inertia = np.array([A, A, C])
    m, q = y[:3], y[3:7]
    w = m / inertia
    body = Rotation.from_quat([q[1], q[2], q[3], q[0]])  # SciPy: scalar last
    torque = np.zeros(3)
    for elements in (earth[2:11], earth[11:20]):
        direction, strength = orbit_direction(y[7], elements)
        s = body.inv().apply(direction)
        torque += 3.0 * strength * np.cross(s, inertia * s)
    q0, qv = q[0], q[1:]
    dq = 0.5 * np.concatenate([[-qv @ w], q0 * w + np.cross(qv, w)])
    return np.concatenate([np.cross(m, w) + torque, dq, [1.0]])


def test_perturber_geometry_matches_scipy_rotations_and_kepler():
    """The kernels' ellipse (Kepler by Newton, argument of latitude, node and inclination) is
    the z-x-z rotation of the orbit's direction, to 1e-14; the Sun at J2000 stands at the true
    longitude 280.38 degrees (Meeus, ch. 25)."""
    for elements in (eq.orbit_elements("sun"), eq.orbit_elements("moon")):
        for t in (0.0, 3.1e6, 4.7e8, -2.2e9):
            x, y, z, strength = perturber(t, elements, 0)
            direction, expected = orbit_direction(t, elements)
            assert np.allclose([x, y, z], direction, atol=1e-13)
            assert strength == pytest.approx(expected, rel=1e-13)
    x, y, _, _ = perturber(0.0, eq.orbit_elements("sun"), 0)
    assert math.degrees(math.atan2(y, x)) % 360 == pytest.approx(280.38, abs=0.01)


@pytest.mark.parametrize("name, order", [("lp2", 2), ("lp4", 4)])
def test_full_model_converges_at_its_order_against_dop853(name, order):
    """Scaled example Earths (both torques on, orbits of periods 10 to 60 s, spin 1 rad/s),
    t = 6 s: the error in (m, q) against DOP853 falls as h^order."""
    x0, earths = FULL.example(4, seed=1)
    earth = earths[0]
    t_end = 6.0
    ref = np.array([solve_ivp(rhs, (0.0, t_end), x, method="DOP853", rtol=1e-13, atol=1e-14,
                              args=(earth,)).y[:, -1] for x in x0])
    spec = FULL.method(name)
    errors = []
    for steps in (60, 120, 240):
        h = t_end / steps
        out = propagate_groups(FULL, spec, x0, spec.params(earth, h)[None, :], [4], h, steps,
                               progress=False)
        errors.append(np.abs(out.x_final[:, :7] - ref[:, :7]).max())
        assert np.allclose(out.x_final[:, 7], t_end, rtol=1e-14)
        assert np.allclose(out.x_final[:, 2], x0[:, 2], rtol=1e-15)  # m3: no axial torque
        assert np.allclose(np.linalg.norm(out.x_final[:, 3:7], axis=1), 1.0, atol=1e-14)
    slopes = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all(np.abs(slopes - order) < 0.25), (errors, slopes)


def test_free_oblate_earth_is_exact_for_any_step():
    """Torques off: the drift is the exact free flow, so one step of 6 s and 600 steps agree to
    round-off."""
    x0, earths = FULL.example(3, seed=2)
    earth = earths[1].copy()
    earth[2], earth[11] = 0.0, 0.0
    spec = FULL.method("lp2")
    ends = [propagate_groups(FULL, spec, x0, spec.params(earth, 6.0 / n)[None, :], [3],
                             6.0 / n, n, progress=False).x_final for n in (1, 600)]
    assert np.abs(ends[0] - ends[1]).max() < 1e-12
