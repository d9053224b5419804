"""The exact relaxation of an axisymmetric tumbler (stability.asteroid.exact): it solves
equation (1) (its time derivative against the right-hand side, on both sides of the branch
at kappa t = 1 and far past it), keeps |L| to round-off while the energy falls, ends on the
axis the physics says, and at alpha = 0 is the free symmetric top of stability.exact_omega."""

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
    """Its derivative by a central difference (h = 1e-5, error ~1e-10) is (1)'s right-hand
    side at the solution, to 1e-8 relative to |m| |w|."""
    h = 1e-5
    at = relaxed_momentum(STARTS, parameters, t + h)
    before = relaxed_momentum(STARTS, parameters, max(t - h, 0.0))
    span = 2 * h if t > 0 else h
    derivative = (at - before) / span if t > 0 else (at - relaxed_momentum(STARTS, parameters,
                                                                          0.0)) / h
    rates = _rates(relaxed_momentum(STARTS, parameters, t), parameters)
    scale = np.max(np.abs(rates)) + np.max(np.abs(STARTS)) ** 2
    tolerance = 1e-8 if t > 0 else 1e-4  # one-sided at t = 0: an error ~h
    assert np.max(np.abs(derivative - rates)) <= tolerance * scale


def test_the_two_forms_of_the_turned_angle_meet_at_kappa_t_equal_to_one():
    """The closed form switches formula at kappa t = 1 (for overflow): the states just below
    and just above agree to 1e-13, as the solution's own change over that time does."""
    m = STARTS[:1]
    p = np.array(OBLATE)
    kappa = 2.0 * p[3] * (1.0 / p[0] - 1.0 / p[2]) * float(np.sum(m * m))
    t = 1.0 / kappa
    below, above = relaxed_momentum(m, p, t * (1 - 1e-15)), relaxed_momentum(m, p, t * (1 + 1e-15))
    assert np.max(np.abs(below - above)) <= 1e-13


@pytest.mark.parametrize("parameters,axis", [(OBLATE, 2), (PROLATE, 0)])
def test_angular_momentum_is_kept_while_the_energy_falls_to_the_end_state(parameters, axis):
    """|m| to 1e-15 relative (a few ulp) at every time; the energy falls at every step of the time grid;
    at t = 1e4 the oblate body spins about its axis (m3 = +-L) and the prolate one
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
