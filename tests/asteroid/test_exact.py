"""The exact relaxation of an axisymmetric tumbler (stability.asteroid.exact): it solves
equation (1) (its time derivative against the right-hand side), is evaluated to round-off in
every regime of its formulas (against mpmath), keeps |L| to round-off while the energy falls,
ends on the axis the physics says, and at alpha = 0 is the free symmetric top of
stability.exact_omega."""

import mpmath as mp
import numpy as np
import pytest

import stability
from stability.asteroid.exact import relaxed_momentum, symmetry_axis
from stability.asteroid.methods import relaxation_params, relaxation_rhs
from stability.asteroid.scene import energy

OBLATE = (1.0, 1.0, 2.0, 0.1)
PROLATE = (1.0, 2.0, 2.0, 0.1)
STARTS = np.array([[1.0, 1.2, 1.4], [-0.3, 0.8, -1.1], [0.9, -0.2, 0.05]])


def _rates(m, parameters):
    p = relaxation_params(parameters)
    return np.array([relaxation_rhs(*row, p) for row in m])


@pytest.mark.parametrize("parameters", [OBLATE, PROLATE, (1.0, 1.0, 2.0, 1e-9),
                                        (2.0, 3.0, 3.0, 0.02)])
@pytest.mark.parametrize("t", [0.0, 0.3, 2.0, 9.0])
def test_the_solution_solves_the_equations(parameters, t):
    """Its derivative by a central difference (h = 1e-5: an error of about 1e-11; the closed
    form holds for t < 0 too) is (1)'s right-hand side at the solution, to 1e-9 relative to
    |m| |w|."""
    h = 1e-5
    derivative = (relaxed_momentum(STARTS, parameters, t + h)
                  - relaxed_momentum(STARTS, parameters, t - h)) / (2 * h)
    rates = _rates(relaxed_momentum(STARTS, parameters, t), parameters)
    scale = np.max(np.abs(rates)) + np.max(np.abs(STARTS)) ** 2
    assert np.max(np.abs(derivative - rates)) <= 1e-9 * scale


def _high_precision(m0, parameters, t, digits=60):
    """The module docstring's closed form, evaluated by mpmath at ``digits`` digits; and the
    angle turned."""
    with mp.workdps(digits):
        i1, i2, i3, alpha = (mp.mpf(float(v)) for v in parameters)
        order, across, along = ((0, 1, 2), i1, i3) if i1 == i2 else ((1, 2, 0), i2, i1)
        x0, y0, z0 = (mp.mpf(float(m0[k])) for k in order)
        mu = 1 / along - 1 / across
        length2 = x0 ** 2 + y0 ** 2 + z0 ** 2
        kappa, c, t = -2 * alpha * mu * length2, (x0 ** 2 + y0 ** 2) / z0 ** 2, mp.mpf(t)
        z = mp.sign(z0) * mp.sqrt(length2) / mp.sqrt(1 + c * mp.exp(-kappa * t))
        shrink = mp.sqrt((1 + c) / (mp.exp(kappa * t) + c))
        turned = mp.sign(z0) * 2 * mp.sqrt(length2) / kappa * mp.log(
            (mp.exp(kappa * t / 2) + mp.sqrt(mp.exp(kappa * t) + c)) / (1 + mp.sqrt(1 + c)))
        angle = -mu * turned
        out = [0.0] * 3
        out[order[0]] = float(shrink * (x0 * mp.cos(angle) - y0 * mp.sin(angle)))
        out[order[1]] = float(shrink * (x0 * mp.sin(angle) + y0 * mp.cos(angle)))
        out[order[2]] = float(z)
        return np.array(out), float(abs(angle))


@pytest.mark.parametrize("m0,parameters,t", [
    ((1.0, 1.2, 1.4), OBLATE, 3.0),
    ((0.9, -0.2, 0.05), PROLATE, 40.0),  # kappa t = -3.4, near the minor axis
    ((1.0, 1e-9, 1e-9), PROLATE, 2000.0),  # kappa t = -200 from 1e-9 of the axis
    ((1.0, 1.0, 1e-5), (1.0, 1.0, 2.0, 1e-6), 3e6),  # slow damping near the equator
    ((1.0, 1e-6, 1e-7), (1.0, 2.0, 2.0, 1e-6), 3e7),  # the angle turned: 1.5e7 rad
    ((1.0, 0.5, -0.3), (1.0, 1.0, 2.0, 1e-14), 100.0),  # kappa t = 1.3e-13: the series
    ((1.0, 0.5, 0.3), OBLATE, 1e4),  # kappa t = 1350: e^(kappa t) overflows
])
def test_the_closed_form_is_evaluated_to_round_off(m0, parameters, t):
    """Against mpmath's 60-digit evaluation of the same closed form: within 2e-14 of |L|, and
    of a few roundings of the angle turned (the conditioning of cos and sin of 1.5e7 rad)."""
    reference, angle = _high_precision(m0, parameters, t)
    got = relaxed_momentum(np.array([m0]), parameters, t)[0]
    length = np.linalg.norm(m0)
    assert np.max(np.abs(got - reference)) <= (2e-14 + 4e-16 * angle) * length


@pytest.mark.parametrize("parameters,axis", [(OBLATE, 2), (PROLATE, 0)])
def test_angular_momentum_is_kept_while_the_energy_falls_to_the_end_state(parameters, axis):
    """|m| to 1e-15 relative (a few ulp) at every time; the energy falls at every step of the
    time grid; at t = 1e4 the oblate body spins about its axis (m3 = +-L) and the prolate one
    across its axis (m1 = 0, the energy L^2 / (2 I2), the lowest there is)."""
    times = np.linspace(0.0, 60.0, 241)
    length = np.linalg.norm(STARTS, axis=1)
    energies = []
    for t in times:
        m = relaxed_momentum(STARTS, parameters, t)
        assert np.max(np.abs(np.linalg.norm(m, axis=1) / length - 1.0)) <= 1e-15
        energies.append(energy(m, parameters))
    assert np.all(np.diff(np.array(energies), axis=0) < 0.0)
    end = relaxed_momentum(STARTS, parameters, 1e4)
    if axis == 2:
        np.testing.assert_allclose(np.abs(end[:, 2]), length, rtol=1e-15)
    else:
        assert np.max(np.abs(end[:, 0])) <= 1e-15
        np.testing.assert_allclose(energy(end, parameters) * 2.0 * parameters[1], length ** 2,
                                   rtol=1e-15)


def test_without_dissipation_it_is_the_free_symmetric_top():
    """alpha = 0: stability.exact_omega's motion of the same symmetric body, to 1e-13."""
    for parameters in ((1.0, 1.0, 2.0, 0.0), (1.0, 2.0, 2.0, 0.0)):
        moments = np.array(parameters[:3])
        body = stability.RigidBody(*moments, physical=False)
        for t in (0.5, 3.0):
            free = [stability.exact_omega(body, w0, np.array([t]))[0] for w0 in STARTS / moments]
            np.testing.assert_allclose(relaxed_momentum(STARTS, parameters, t),
                                       np.array(free) * moments, rtol=0, atol=1e-13)


def test_principal_spins_stay_and_triaxial_bodies_have_no_closed_form():
    spins = np.array([[0.0, 0.0, 2.0], [1.5, 0.0, 0.0], [0.0, -1.0, 0.0]])
    np.testing.assert_array_equal(relaxed_momentum(spins, OBLATE, 5.0), spins)
    assert relaxed_momentum(spins, (1.0, 1.5, 2.2, 0.1), 5.0) is None
    assert relaxed_momentum(spins, (1.0, 1.0, 1.0, 0.1), 5.0) is None
    assert [symmetry_axis(m) for m in ((1, 1, 2), (1, 2, 2), (1, 2, 3), (2, 2, 2))] == [
        2, 0, None, None]
