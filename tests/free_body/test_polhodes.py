"""Polhodes lie on the |L| sphere and on an energy level; the separatrix is D2 = 0."""

import numpy as np

import stability
from stability.free_body.model import invariant_differences, kinetic_energy
from stability.free_body.polhodes import polhodes, separatrix_circles

BODY = stability.RigidBody.preset("tennis_racket")


def test_separatrix_is_on_d2_zero_and_the_unit_sphere():
    for m in separatrix_circles(BODY):
        np.testing.assert_allclose(np.linalg.norm(m, axis=1), 1.0, atol=1e-15)
        d1, d2, d3 = invariant_differences(BODY, m / BODY.moments)
        assert np.max(np.abs(d2) / d1) < 1e-13


def test_polhodes_circle_the_stable_axes_at_constant_energy():
    families = polhodes(BODY, levels=(0.3, 0.9), samples=100)
    order = np.argsort(BODY.moments)
    assert [centre for centre, _ in families] == [order[0], order[2]]
    for centre, curves in families:
        assert len(curves) == 4  # each level and its mirror image
        for m in curves:
            np.testing.assert_allclose(np.linalg.norm(m, axis=1), 1.0, atol=1e-14)
            energy = kinetic_energy(BODY, m / BODY.moments)
            np.testing.assert_allclose(energy, energy[0], rtol=1e-12)
            # The centre's component keeps its sign: the orbit circles that axis.
            assert np.all(np.sign(m[:, centre]) == np.sign(m[0, centre]))


def test_a_symmetric_body_has_no_orbit_at_its_equal_axes():
    body = stability.RigidBody(1.0, 1.0, 1.5)
    (_, small), (_, large) = polhodes(body, levels=(0.5,), samples=50)
    assert small == [] and len(large) == 2  # spin in the equal-moment plane is steady
