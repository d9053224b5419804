"""What the damped runs measure (stability.dissipation.measure): the nutation amplitude a rigid
motion keeps where the angle swings; the Explorer with a spherical damper or whips, run past the
flat spin, meets the linear theory and the energy formula."""

import numpy as np
import pytest

import stability
from stability.dissipation import model
from stability.dissipation.measure import SPHERE, WHIPS, Whips, run_damped

EXPLORER = model.EXPLORER_1


@pytest.fixture(scope="module")
def runs():
    """The Explorer body with a heavy spherical damper (lp2, lp4, dmv) and with whips (rk4),
    two starting angles each, run past the flat spin and measured."""
    I, W = EXPLORER.moments, EXPLORER.spin
    star = model.energy_sink_optimum(I[0], I[1], 1e-2, W)
    values = np.array([*I, 1e-2, star])
    angles = np.radians([0.01, 1.0])
    out = {m: run_damped(SPHERE, m, [values], angles, spin=W, samples=800,
                         options=stability.RunOptions(progress=False))
           for m in ("lp2", "lp4", "dmv")}
    whips = Whips(0.4, 0.5, frequency_ratio=0.3, damping_ratio=0.5).values(I, W)
    out["whips"] = run_damped(WHIPS, "rk4", [whips], angles, spin=W, step_angle=0.06, tail=25.0,
                              samples=800, options=stability.RunOptions(progress=False))
    return out


@pytest.mark.parametrize("name", ["lp2", "lp4", "dmv", "whips"])
def test_fitted_growth_rate_is_the_linear_eigenvalue_within_1e3(runs, name):
    r = runs[name]
    error = r["growth_rate_error"][0]
    assert np.isfinite(error[0]) and abs(error[0]) <= 1e-3, error
    assert np.isnan(error[1])  # started beyond the linear regime: no fit
    assert np.all(r["status"] == 0)


@pytest.mark.parametrize("name", ["lp2", "lp4", "dmv"])
def test_the_flat_spin_is_the_major_axis_with_the_energy_of_the_formula(runs, name):
    r = runs[name]
    assert np.all(np.abs(r["end_angle"] - 90.0) < 0.1)
    assert np.all(r["angular_momentum_drift"] <= 1e-12)
    assert np.all(np.abs(r["end_energy_error"]) < 1e-5)
    # Lost: the formula less the start's tilt, |H|^2 / 2 sin^2(theta0) (1/A_1 - 1/A_2).
    assert np.allclose(r["energy_lost_error"][0], -np.sin(np.radians([0.01, 1.0])) ** 2,
                       rtol=2e-2, atol=1e-5)
    assert np.all(np.abs(r["decay_rate_error"]) < 1e-3)
    assert np.all(r["flat_time"] > 0)


def test_whips_reach_the_flat_spin_too(runs):
    r = runs["whips"]
    assert np.all(np.abs(r["end_angle"] - 90.0) < 1.0) and np.all(r["flat_time"] > 0)
    assert np.all(np.abs(r["energy_lost_error"]) < 1e-2)
    assert np.all(r["energy_rise"] < 1e-9)


def test_the_nutation_amplitude_is_kept_by_a_rigid_motion_where_the_angle_swings():
    """On unequal transverse moments the angle of H from the spin axis swings twice a nutation;
    the amplitude the rates are fitted to does not, and on equal ones it is the angle's sine."""
    import stability
    from stability.dissipation.measure import nutation_amplitude, nutation_angle

    I = np.array([120.0, 135.0, 150.0])
    w0 = np.array([2.0, 0.01, 0.0])
    H = np.array([I * stability.exact_omega(stability.RigidBody(*I), w0, t)
                  for t in np.linspace(0.0, 30.0, 200)])
    angle = nutation_angle(H, 0)
    amplitude = nutation_amplitude(H, I, 0)
    assert angle.max() / angle.min() > 1.3
    assert np.ptp(amplitude) < 1e-9 * amplitude.max()
    symmetric = np.array([[2.0, 0.01, 0.02]])
    assert nutation_amplitude(symmetric, [1.0, 2.0, 2.0], 0)[0] == pytest.approx(
        np.sin(nutation_angle(symmetric, 0)[0]), rel=1e-12)
