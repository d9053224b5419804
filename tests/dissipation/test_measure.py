"""What the damped runs measure (stability.dissipation.measure): the nutation amplitude a rigid
motion keeps where the angle swings."""

import numpy as np
import pytest


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
