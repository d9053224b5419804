"""The Lie group variational integrator (stability.integrators.lgvi): the same map as DMV for the
free body."""

import numpy as np

from stability.free_body.propagate import propagate

MOMENTS = np.array([1.0, 2.0, 3.0])
W0 = np.array([0.3, 1.0, 0.9])
M0 = (MOMENTS * W0)[None, :]


def test_dmv_and_lgvi_are_the_same_map():
    """Same discrete Lagrangian for the free body: the m sequences agree to round-off."""
    dmv = propagate("dmv", MOMENTS, M0, 0.1, 100, save_every=10)
    lgvi = propagate("lgvi", MOMENTS, M0, 0.1, 100, save_every=10)
    np.testing.assert_allclose(lgvi.saved, dmv.saved, rtol=0, atol=1e-13)
