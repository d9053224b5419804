"""Analytic invariants and linear stability (Omega^2 with the sign of ERRATA 2)."""

import itertools
import math
from fractions import Fraction

import numpy as np
import pytest

import stability
from stability.free_body.model import (
    angular_momentum, angular_momentum_norm, axis_stability, euler_rhs, euler_system, growth_rate,
    invariant_differences, kinetic_energy, omega_squared, oscillation_frequency,
)
from stability.util.conventions import perpendicular_axes
from stability.core.axes import intermediate_axis
from stability.core.body import RigidBody

BODY = RigidBody(1.0, 2.0, 3.0)


# ----------------------------------------------------------------------------- Omega^2


@pytest.mark.parametrize(
    "axis, per_spin_squared",
    [
        (1, (1 - 2) * (1 - 3) / (2 * 3)),  # +1/3: oscillation
        (2, (2 - 1) * (2 - 3) / (1 * 3)),  # -1/3: growth
        (3, (3 - 1) * (3 - 2) / (1 * 2)),  # +1: oscillation
    ],
)
@pytest.mark.parametrize("spin", [1.0, 2.5, -3.0])
def test_omega_squared_sign_and_magnitude_for_1_2_3(axis, per_spin_squared, spin):
    assert omega_squared(BODY, axis, spin) == pytest.approx(per_spin_squared * spin**2, rel=1e-15)


def test_growth_rate_and_frequency_for_1_2_3():
    assert growth_rate(BODY, 2, 2.0) == pytest.approx(2.0 / math.sqrt(3.0), rel=1e-15)
    assert oscillation_frequency(BODY, 2, 2.0) == 0.0
    assert growth_rate(BODY, 1, 2.0) == 0.0 and growth_rate(BODY, 3, 2.0) == 0.0
    assert oscillation_frequency(BODY, 1, 2.0) == pytest.approx(2.0 / math.sqrt(3.0), rel=1e-15)
    assert oscillation_frequency(BODY, 3, -2.0) == pytest.approx(2.0, rel=1e-15)
    # The textbook form of the rate, lambda = |W| sqrt((I2 - I1)(I3 - I2) / (I1 I3)).
    body = RigidBody(3.0, 5.0, 7.0)
    assert growth_rate(body, 2, 0.7) == pytest.approx(0.7 * math.sqrt(2 * 2 / (3 * 7)), rel=1e-15)
    # Symmetric top I1 = I2: the body-frame precession rate |I3 - I1| W / I1.
    top = RigidBody(2.0, 2.0, 3.5)
    assert oscillation_frequency(top, 3, 4.0) == pytest.approx(1.5 * 4.0 / 2.0, rel=1e-15)


@pytest.mark.parametrize("perm", list(itertools.permutations(range(3))))
def test_unsorted_moments_give_the_same_physics(perm):
    values = np.array([1.0, 2.0, 3.0])
    body = RigidBody(*values[list(perm)])
    words = {1.0: "stable", 2.0: "unstable", 3.0: "stable"}
    for label in (1, 2, 3):
        moment = body.moments[label - 1]
        sorted_label = int(moment)  # the label this moment has in the sorted body (1, 2, 3)
        assert omega_squared(body, label, 1.5) == omega_squared(BODY, sorted_label, 1.5)
        assert axis_stability(body, label) == words[moment]
    assert body.moments[intermediate_axis(body) - 1] == 2.0


def _euler_jacobian(I, w):
    """Jacobian of w' = ((I2 - I3) w2 w3 / I1, (I3 - I1) w3 w1 / I2, (I1 - I2) w1 w2 / I3)."""
    k = np.array([(I[1] - I[2]) / I[0], (I[2] - I[0]) / I[1], (I[0] - I[1]) / I[2]])
    return np.array([
        [0.0, k[0] * w[2], k[0] * w[1]],
        [k[1] * w[2], 0.0, k[1] * w[0]],
        [k[2] * w[1], k[2] * w[0], 0.0],
    ])


@pytest.mark.parametrize("seed", range(10))
def test_omega_squared_matches_the_eigenvalues_of_eulers_equations(seed):
    # Independent of the formula: linearise Euler's equations (ERRATA 1) about W e_a; the
    # eigenvalues are 0 and +-sqrt(-Omega^2).
    rng = np.random.default_rng(seed)
    I = rng.uniform(0.5, 2.0, 3)
    W = rng.uniform(-5.0, 5.0)
    body = RigidBody(*I, physical=False)
    for axis in (1, 2, 3):
        w = np.zeros(3)
        w[axis - 1] = W
        eig = np.linalg.eigvals(_euler_jacobian(I, w))
        assert growth_rate(body, axis, W) == pytest.approx(np.max(eig.real), rel=1e-12, abs=1e-12)
        assert oscillation_frequency(body, axis, W) == pytest.approx(np.max(eig.imag), rel=1e-12,
                                                                     abs=1e-12)


@pytest.mark.parametrize("moments", [(1.0, 1.0, 2.0), (1.0, 2.0, 2.0), (2.0, 1.0, 2.0)])
def test_equal_moment_axes_are_exactly_neutral(moments):
    body = RigidBody(*moments)
    for axis in (1, 2, 3):
        equal = moments.count(moments[axis - 1]) == 2
        if equal:
            assert omega_squared(body, axis, 3.0) == 0.0  # exactly, not ~1e-17
            assert growth_rate(body, axis, 3.0) == 0.0
            assert oscillation_frequency(body, axis, 3.0) == 0.0
            assert axis_stability(body, axis) == "neutral"
        else:  # the symmetry axis: (I3 - I)^2 W^2 / I^2 > 0
            other = moments[axis % 3]
            expected = (moments[axis - 1] - other) ** 2 / other**2 * 9.0
            assert omega_squared(body, axis, 3.0) == pytest.approx(expected, rel=1e-15)
            assert axis_stability(body, axis) == "stable"
    sphere = RigidBody(2.0, 2.0, 2.0)
    assert [axis_stability(sphere, a) for a in (1, 2, 3)] == ["neutral"] * 3


def test_nearly_equal_moments_keep_full_relative_accuracy():
    # I1 and I2 differ by 1e-12: the differences are taken directly, so Omega^2 is exact to
    # a few ulps (a form such as I1 I2 - I1^2 would lose 12 digits).
    I = (1.0, 1.0 + 1e-12, 2.0)
    body = RigidBody(*I)
    exact = [Fraction(x) for x in I]
    for axis in (1, 2, 3):
        a, b, c = exact[axis - 1], exact[axis % 3], exact[(axis + 1) % 3]
        expected = float((a - b) * (a - c) / (b * c) * Fraction(7.0) ** 2)
        assert omega_squared(body, axis, 7.0) == pytest.approx(expected, rel=4e-16)


def test_vectorized_over_moments_and_spins():
    moments = np.array([[1.0, 2.0, 3.0], [3.0, 5.0, 7.0], [1.0, 1.0, 2.0], [2.0, 3.0, 1.0]])
    spins = np.array([1.0, 2.0, 3.0, 4.0])
    got = omega_squared(moments, 2, spins)
    assert got.shape == (4,)
    for row, spin, value in zip(moments, spins, got):
        assert value == omega_squared(RigidBody(*row, physical=False), 2, spin)
    grid = omega_squared(BODY, 2, np.linspace(0, 1, 12).reshape(3, 4))
    assert grid.shape == (3, 4)
    np.testing.assert_array_equal(
        axis_stability(moments, 1), ["stable", "stable", "neutral", "unstable"]
    )
    np.testing.assert_array_equal(intermediate_axis(moments), [2, 2, 2, 1])
    assert isinstance(axis_stability(BODY, 2), str)


def test_top_level_exports():
    assert stability.omega_squared is omega_squared
    assert stability.growth_rate is growth_rate
    assert stability.oscillation_frequency is oscillation_frequency
    assert stability.axis_stability is axis_stability


# -------------------------------------------------------------------------------- invariants


def test_energy_and_angular_momentum_by_hand():
    w = [0.3, 1.0, 0.9]
    # E = (1 * 0.09 + 2 * 1 + 3 * 0.81) / 2 = 2.26 J; m = (0.3, 2, 2.7); L^2 = 11.38.
    assert kinetic_energy(BODY, w) == pytest.approx(2.26, rel=1e-15)
    np.testing.assert_allclose(angular_momentum(BODY, w), [0.3, 2.0, 2.7], rtol=1e-15)
    assert angular_momentum_norm(BODY, w) == pytest.approx(math.sqrt(11.38), rel=1e-15)


def test_invariants_are_vectorized():
    rng = np.random.default_rng(1)
    w = rng.standard_normal((5, 4, 3))
    E, L = kinetic_energy(BODY, w), angular_momentum_norm(BODY, w)
    assert E.shape == L.shape == (5, 4)
    assert angular_momentum(BODY, w).shape == (5, 4, 3)
    np.testing.assert_allclose(E[2, 3], 0.5 * np.dot(BODY.moments, w[2, 3] ** 2), rtol=1e-15)
    np.testing.assert_allclose(L[2, 3], np.linalg.norm(BODY.moments * w[2, 3]), rtol=1e-15)
    D = invariant_differences(BODY, w)
    assert D.D2.shape == (5, 4)
    # NaN members stay NaN (masked), no error.
    w[0, 0, 0] = np.nan
    assert np.isnan(kinetic_energy(BODY, w)[0, 0]) and np.isfinite(kinetic_energy(BODY, w)[0, 1])


def test_invariant_differences_equal_their_definitions():
    rng = np.random.default_rng(2)
    w = rng.standard_normal((100, 3))
    L2 = angular_momentum_norm(BODY, w) ** 2
    twoE = 2 * kinetic_energy(BODY, w)
    D1, D2, D3 = invariant_differences(BODY, w)
    np.testing.assert_allclose(D1, L2 - twoE * 1.0, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(D2, L2 - twoE * 2.0, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(D3, twoE * 3.0 - L2, rtol=1e-12, atol=1e-12)
    assert np.all(D1 >= 0) and np.all(D3 >= 0)
    # D2 > 0: circling axis 3 (largest); < 0: circling axis 1 (smallest).
    assert invariant_differences(BODY, [0.0, 0.1, 1.0]).D2 > 0
    assert invariant_differences(BODY, [1.0, 0.1, 0.0]).D2 < 0


def test_d2_has_full_accuracy_next_to_the_separatrix():
    eps = 1e-9
    w = [eps, 1.0, 0.0]  # I1 (I1 - I2) eps^2 = -1e-18; L^2 - 2E I2 would give round-off ~1e-16
    assert invariant_differences(BODY, w).D2 == pytest.approx(-(eps**2), rel=1e-15)
    # Unsorted moments: D's are defined with the body's own intermediate moment.
    body = RigidBody(3.0, 1.0, 2.0)
    D_sorted = invariant_differences(BODY, [0.3, 1.0, 0.9])
    D_unsorted = invariant_differences(body, [0.9, 0.3, 1.0])
    np.testing.assert_array_equal(D_sorted, D_unsorted)


# ----------------------------------------------------------------------------------- errors


@pytest.mark.parametrize("axis", [0, 4, -1, 2.0, "2", True, None])
def test_bad_axis(axis):
    with pytest.raises(ValueError, match="axis must be 1, 2 or 3"):
        omega_squared(BODY, axis, 1.0)
    with pytest.raises(ValueError, match="axis must be 1, 2 or 3"):
        axis_stability(BODY, axis)


@pytest.mark.parametrize(
    "spin, match",
    [
        (math.nan, "spin must be finite"),
        (math.inf, "spin must be finite"),
        ([1.0, -math.inf], "spin must be finite"),
        ("fast", "spin must be real numbers in rad/s, got strings"),
    ],
)
@pytest.mark.parametrize("func", [omega_squared, growth_rate, oscillation_frequency])
def test_bad_spin(func, spin, match):
    with pytest.raises(ValueError, match=match):
        func(BODY, 2, spin)


@pytest.mark.parametrize(
    "body, match",
    [
        ([1.0, 2.0], r"shape \(\.\.\., 3\)"),
        (5.0, r"shape \(\.\.\., 3\)"),
        ([0.0, 1.0, 2.0], "finite and > 0"),
        ([1.0, math.nan, 2.0], "finite and > 0"),
        ([[1.0, 2.0, 3.0], [1.0, -2.0, 3.0]], "finite and > 0"),
        ("body", r"body \(principal moments, or a stability.RigidBody\) must be real numbers"),
    ],
)
def test_bad_moments(body, match):
    with pytest.raises(ValueError, match=match):
        omega_squared(body, 1, 1.0)
    with pytest.raises(ValueError, match=match):
        kinetic_energy(body, [1.0, 0.0, 0.0])


@pytest.mark.parametrize("w", [[1.0, 2.0], 3.0, np.zeros((3, 2))])
def test_bad_w_shape(w):
    with pytest.raises(ValueError, match=r"w must have shape \(\.\.\., 3\)"):
        kinetic_energy(BODY, w)


# ------------------------------------------------------------------- axes and Euler's equations


def test_perpendicular_axes():
    assert [perpendicular_axes(a) for a in (1, 2, 3)] == [(2, 3), (1, 3), (1, 2)]


def test_euler_rhs_is_m_cross_w_and_the_scipy_system_stacks_it():
    rng = np.random.default_rng(4)
    moments = np.array([1.0, 2.5, 3.0])
    w = rng.standard_normal((5, 3))
    np.testing.assert_allclose(euler_rhs(moments, w) * moments, np.cross(moments * w, w),
                               rtol=1e-13, atol=1e-15)
    assert euler_rhs(moments, w[0]).shape == (3,)
    stacked = euler_system(RigidBody(*moments), 5)(0.0, np.ascontiguousarray(w.T).ravel())
    np.testing.assert_array_equal(stacked, euler_rhs(moments, w).T.ravel())
