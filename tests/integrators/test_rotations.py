"""The rotation helpers of the step kernels (stability.integrators.rotations) against SciPy's
matrix exponential and rotations and NumPy's solver: Cramer's rule, the exponential's
coefficients across the small-angle switch, Rodrigues' increment, the quaternion of a rotation
and its increment, and the Cayley map, each to a stated multiple of the machine epsilon."""

import mpmath
import numpy as np
from scipy.linalg import expm
from scipy.spatial.transform import Rotation

from stability.integrators.rotations import (
    SMALL_ANGLE, cayley_increment, cayley_quaternion, cross, exp_coefficients,
    quaternion_increment, rotate_increment, solve3,
)

RNG = np.random.default_rng(5)
EPS = np.finfo(float).eps


def hat(k):
    return np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])


def hamilton(a, b):
    a0, a1, a2, a3 = a
    b0, b1, b2, b3 = b
    return np.array([a0 * b0 - a1 * b1 - a2 * b2 - a3 * b3, a0 * b1 + a1 * b0 + a2 * b3 - a3 * b2,
                     a0 * b2 - a1 * b3 + a2 * b0 + a3 * b1, a0 * b3 + a1 * b2 - a2 * b1 + a3 * b0])


def test_cross_and_cramers_rule():
    for _ in range(50):
        a, b = RNG.standard_normal(3), RNG.standard_normal(3)
        np.testing.assert_allclose(cross(*a, *b), np.cross(a, b), rtol=0, atol=8 * EPS)
        m, r = RNG.standard_normal((3, 3)) + 3 * np.eye(3), RNG.standard_normal(3)
        x = np.array(solve3(*m.ravel(), *r))
        np.testing.assert_allclose(x, np.linalg.solve(m, r), rtol=1e-13, atol=1e-14)
    singular = np.ones((3, 3))
    assert not np.all(np.isfinite(solve3(*singular.ravel(), 1.0, 2.0, 3.0)))  # no exception


def test_the_exponential_rotates_as_expm_on_both_sides_of_the_small_angle_switch():
    for theta in (0.0, 1e-12, 0.999 * SMALL_ANGLE, 1.001 * SMALL_ANGLE, 1e-4, 0.3, 2.0, 3.1):
        axis = RNG.standard_normal(3)
        k = theta * axis / np.linalg.norm(axis)
        v = RNG.standard_normal(3)
        a, b, cm1, d = exp_coefficients(theta)
        with mpmath.workdps(40):  # the precision here, whatever another module set
            t = mpmath.mpf(theta)
            exact = ((mpmath.sin(t) / t, (1 - mpmath.cos(t)) / t ** 2, mpmath.cos(t / 2) - 1,
                      mpmath.sin(t / 2) / t) if theta else (1, 0.5, 0, 0.5))
            exact = [float(x) for x in exact]
        # a and b to 4 eps (near theta = pi, a = sin(theta) / theta is formed from cos(theta/2)
        # and loses relative, not absolute, accuracy); c and d to 4 eps of themselves, so a
        # tiny angle's quaternion keeps its relative accuracy
        for got, want, floor in zip((a, b, cm1, d), exact, (1.0, 1.0, 0.0, 0.0)):
            assert abs(got - want) <= 4 * EPS * max(abs(want), floor), (
                theta, got, want)
        increment = np.array(rotate_increment(*k, *v, a, b))
        # (the matrix reference cancels: it is good to the rounding of v only)
        np.testing.assert_allclose(increment, expm(hat(k)) @ v - v, rtol=0,
                                   atol=8 * EPS * np.linalg.norm(v))
        # the unit quaternion of exp(hat k) is (1 + c, d k): SciPy's rotation vector agrees
        q = np.array([1.0 + cm1, *(d * k)])
        scipy_q = Rotation.from_rotvec(k).as_quat(scalar_first=True)
        np.testing.assert_allclose(q, scipy_q * np.sign(scipy_q[0]), rtol=0, atol=4 * EPS)


def test_the_quaternion_increment_is_the_hamilton_product_less_q():
    for _ in range(50):
        q = RNG.standard_normal(4)
        q /= np.linalg.norm(q)
        r = Rotation.from_rotvec(RNG.standard_normal(3)).as_quat(scalar_first=True)
        e = np.array(quaternion_increment(*q, r[0] - 1.0, *r[1:]))
        np.testing.assert_allclose(e, hamilton(q, r) - q, rtol=0, atol=8 * EPS)


def test_the_cayley_map_is_a_rotation_by_twice_atan_f():
    for scale in (1e-9, 1e-3, 0.5, 3.0):
        f = scale * RNG.standard_normal(3)
        r0m1, *rv = cayley_quaternion(*f)
        r = np.array([1.0 + r0m1, *rv])
        assert abs(np.linalg.norm(r) - 1.0) <= 2 * EPS
        angle = 2 * np.arctan(np.linalg.norm(f))
        want = Rotation.from_rotvec(angle * f / np.linalg.norm(f)).as_quat(scalar_first=True)
        np.testing.assert_allclose(r, want, rtol=0, atol=4 * EPS)
        # its increment of m is F^T m - m with F the Cayley matrix, without cancellation
        m = RNG.standard_normal(3)
        big_f = (np.eye(3) + hat(f)) @ np.linalg.inv(np.eye(3) - hat(f))
        # (the matrix reference cancels: it is good to the rounding of m only)
        np.testing.assert_allclose(cayley_increment(*m, *f), big_f.T @ m - m, rtol=0,
                                   atol=8 * EPS * np.linalg.norm(m))
