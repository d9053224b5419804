"""The damped scenes' declarations (stability.dissipation.scene): their energies fall at the
dissipated power with H kept, and their systems' moments."""

import numpy as np
import pytest

from stability.dissipation import model
from stability.dissipation.methods import (sphere_params, sphere_rhs, whip_params, whip_rates,
                                           whip_rhs)
from stability.dissipation.scene import sphere_energy, sphere_moments, whip_energy, whip_moments

from .test_model import TRIAXIAL, WHIPS


def energy_rate(energy, rhs, x, values, p, step=1e-6):
    """dE/dt = grad E . f by central differences."""
    grad = np.array([(energy(x + step * e, values) - energy(x - step * e, values)) / (2 * step)
                     for e in np.eye(x.size)])
    return grad @ np.array(rhs(*x, p))


def test_energy_falls_at_the_dissipated_power_and_h_is_kept_by_both_equations():
    rng = np.random.default_rng(1)
    p = sphere_params(TRIAXIAL)
    for _ in range(3):
        x = rng.standard_normal(6)
        u = x[3:] / TRIAXIAL[3] - x[:3] / TRIAXIAL[:3]
        assert energy_rate(sphere_energy, sphere_rhs, x, TRIAXIAL, p) == pytest.approx(
            -TRIAXIAL[4] * u @ u, rel=1e-7)
        f = np.array(sphere_rhs(*x, p))
        assert abs((x[:3] + x[3:]) @ (f[:3] + f[3:])) < 1e-13
    p = whip_params(WHIPS)
    for _ in range(3):
        x = rng.standard_normal(7) * [1, 1, 1, 0.1, 0.1, 0.1, 0.1]
        dz = np.array(whip_rates(*x, p)[3:])
        assert energy_rate(whip_energy, whip_rhs, x, WHIPS, p) == pytest.approx(
            -WHIPS[6] * dz @ dz, rel=1e-7)
        assert abs(x[:3] @ np.array(whip_rhs(*x, p))[:3]) < 1e-13


def test_energy_lost_to_the_flat_spin_and_the_systems_moments():
    assert np.allclose(sphere_moments(TRIAXIAL), [1.2, 2.2, 3.2])
    assert np.allclose(whip_moments(WHIPS), [1.025, 2.0125, 3.0125])
    assert model.energy_lost(2.0, 1.0, 4.0) == pytest.approx(0.5 * 4.0 * 0.75)
