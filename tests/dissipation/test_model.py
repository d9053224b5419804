"""The damped bodies' closed forms: equations, energy balance, linear theory, energy sink."""

import numpy as np
import pytest

from stability.dissipation import model
from stability.dissipation.methods import (sphere_params, sphere_rhs, whip_params, whip_rhs)

TRIAXIAL = np.array([1.0, 2.0, 3.0, 0.2, 0.1])  # I1, I2, I3, J, c
WHIPS = np.array([1.0, 2.0, 3.0, 0.05, 0.5, 3.0, 0.2])  # I1, I2, I3, mu, b, k, c
EXPLORER = model.EXPLORER_1


def numerical_jacobian(rhs, x, p, step=1e-6):
    """Central differences of ``rhs(*x, p)``."""
    out = np.empty((x.size, x.size))
    for j in range(x.size):
        up, down = x.copy(), x.copy()
        up[j] += step
        down[j] -= step
        out[:, j] = (np.array(rhs(*up, p)) - np.array(rhs(*down, p))) / (2 * step)
    return out


@pytest.mark.parametrize("axis", [0, 1, 2])
def test_sphere_jacobian_in_closed_form_is_the_kernels(axis):
    x = model.sphere_steady_spin(TRIAXIAL, axis, 1.3)
    exact = model.sphere_jacobian(TRIAXIAL, axis, 1.3)
    assert np.abs(numerical_jacobian(sphere_rhs, x, sphere_params(TRIAXIAL)) - exact).max() \
        < 1e-8 * np.abs(exact).max()
    assert np.allclose(sphere_rhs(*x, sphere_params(TRIAXIAL)), 0.0, atol=1e-15)  # steady


def test_the_major_axis_rule_minor_grows_slowly_middle_fast_major_decays():
    minor, middle, major = (model.growth_rate(model.sphere_eigenvalues(TRIAXIAL, a, 1.3))
                            for a in range(3))
    assert 0.0 < minor < 0.1 * middle and major < 0.0
    assert model.sphere_eigenvalues(TRIAXIAL, 1, 1.3)[0].imag == 0.0  # middle: a real root
    # The rigid body alone (c = 0): the minor and major axes are neutral, the middle is not.
    rigid = np.array([*TRIAXIAL[:4], 0.0])
    assert abs(model.growth_rate(model.sphere_eigenvalues(rigid, 0, 1.3))) < 1e-12
    assert abs(model.growth_rate(model.sphere_eigenvalues(rigid, 2, 1.3))) < 1e-12
    assert model.growth_rate(model.sphere_eigenvalues(rigid, 1, 1.3)) > 0.5


def test_axisymmetric_quadratic_gives_the_jacobians_eigenvalues():
    I = EXPLORER.moments
    for J, c in ((1e-4, 6e-5), (1e-2, 3e-3), (0.5, 20.0)):
        values = np.array([*I, J, c])
        closed = model.axisymmetric_eigenvalues(I[0], I[1], J, c, EXPLORER.spin)
        numeric = model.sphere_eigenvalues(values, 0, EXPLORER.spin)
        assert np.allclose(np.sort_complex(closed), np.sort_complex(numeric), rtol=1e-9,
                           atol=1e-12)


def test_a_weak_damper_grows_the_minor_axis_nutation_at_first_order_and_the_sink_agrees():
    """l = -i nu + c (I_t - I_s) / (I_t I_s) + O(c^2); the energy sink is exact at that order."""
    I_s, I_t, W = 1.0, 3.0, 2.0
    for c in (1e-4, 1e-5):
        rate = model.growth_rate(model.axisymmetric_eigenvalues(I_s, I_t, 0.3, c, W))
        first = c * (I_t - I_s) / (I_t * I_s)
        assert rate == pytest.approx(first, rel=50 * c)
        assert model.energy_sink_rate(I_s, I_t, 0.3, c, W) == pytest.approx(first, rel=50 * c)
    # About the major (symmetry) axis of an oblate body the same term is a decay.
    assert model.growth_rate(model.axisymmetric_eigenvalues(3.0, 1.0, 0.3, 1e-4, W)) < 0.0


def test_explorer_optimum_damping_by_the_eigenvalues_and_by_the_energy_sink():
    I = EXPLORER.moments
    best = model.optimum_damping(I[0], I[1], 1e-4, EXPLORER.spin)
    star = model.energy_sink_optimum(I[0], I[1], 1e-4, EXPLORER.spin)
    assert best == pytest.approx(star, rel=2e-2)
    rate = model.growth_rate(model.axisymmetric_eigenvalues(I[0], I[1], 1e-4, best,
                                                            EXPLORER.spin))
    for other in (0.9 * best, 1.1 * best):
        assert model.growth_rate(model.axisymmetric_eigenvalues(
            I[0], I[1], 1e-4, other, EXPLORER.spin)) < rate
    assert model.energy_sink_rate(I[0], I[1], 1e-4, star, EXPLORER.spin) == pytest.approx(
        rate, rel=3e-3)


def test_explorer_moments_are_a_uniform_cylinders():
    I = EXPLORER.moments
    assert I[0] == pytest.approx(0.5 * 13.97 * 0.076**2)
    assert I[1] == I[2] == pytest.approx(13.97 * (3 * 0.076**2 + 2.03**2) / 12)
    assert EXPLORER.spin == pytest.approx(78.5398, rel=1e-5)


@pytest.mark.parametrize("axis", [0, 1, 2])
def test_whip_jacobian_by_complex_step_is_the_kernels(axis):
    x = model.whip_steady_spin(WHIPS, axis, 1.3)
    exact = model.whip_jacobian(WHIPS, axis, 1.3)
    assert np.allclose(whip_rhs(*x, whip_params(WHIPS)), 0.0, atol=1e-15)  # steady
    assert np.abs(numerical_jacobian(whip_rhs, x, whip_params(WHIPS)) - exact).max() \
        < 1e-7 * np.abs(exact).max()


def test_whips_turn_a_minor_axis_spin_over_and_damp_the_major_axis():
    assert model.growth_rate(model.whip_eigenvalues(WHIPS, 0, 1.3)) > 0.0
    assert model.growth_rate(model.whip_eigenvalues(WHIPS, 1, 1.3)) > 0.0  # middle
    assert model.growth_rate(model.whip_eigenvalues(WHIPS, 2, 1.3)) < 0.0


@pytest.mark.parametrize("make, values, message", [
    (sphere_params, [1.0, 2.0, 3.0, 0.2], "5 numbers"),
    (sphere_params, [1.0, 2.0, 3.0, 0.0, 0.1], "J must be positive"),
    (sphere_params, [1.0, 2.0, 3.0, 0.2, -0.1], "c >= 0"),
    (whip_params, [1.0, 2.0, 3.0, 0.05, 0.5, 3.0], "7 numbers"),
    (whip_params, [1.0, 2.0, 3.0, 0.05, 0.5, np.nan, 0.2], "all finite"),
])
def test_bad_parameter_sets_are_refused_in_one_line(make, values, message):
    with pytest.raises(ValueError, match=message):
        make(values)


def test_a_spinner_of_measured_moments_puts_its_spin_axis_first_and_refuses_another():
    body = model.Spinner.about([150.0, 120.0, 135.0], "smallest", 2.0)
    assert body.moments == (120.0, 150.0, 135.0) and body.spin == 2.0
    with pytest.raises(ValueError, match="must be the smallest"):
        model.Spinner.about([150.0, 120.0, 135.0], 1, 2.0)


def test_the_general_linear_theory_is_the_symmetric_one_on_a_symmetric_shell():
    """best_damping and nutation_growth_rate take any moments; on Explorer they are the closed
    form's, and the equivalent transverse moment is I_t itself."""
    I, W, J = EXPLORER.moments, EXPLORER.spin, 1e-4
    assert model.equivalent_transverse_moment(I) == pytest.approx(I[1], rel=1e-12)
    assert model.best_damping(I, J, W) == model.optimum_damping(I[0], I[1], J, W)
    c = model.energy_sink_optimum(I[0], I[1], J, W)
    assert model.nutation_growth_rate(I, J, c, W) == pytest.approx(model.growth_rate(
        model.axisymmetric_eigenvalues(I[0], I[1], J, c, W)), rel=1e-9)
    # on unequal transverse moments: the best damping is the eigenvalues' largest growth
    I = [120.0, 135.0, 150.0]
    best = model.best_damping(I, 1.0, 2.0)
    rates = [model.nutation_growth_rate(I, 1.0, f * best, 2.0) for f in (0.9, 1.0, 1.1)]
    assert rates[1] > max(rates[0], rates[2]) and best == pytest.approx(1.704, rel=1e-3)
    assert float(model.flat_spin_time(rates[1], np.radians(1.0))) / 60 == pytest.approx(
        87.5, rel=1e-2)

