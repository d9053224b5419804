"""The explicit Lie-Poisson splitting lp2 (stability.integrators.lie_poisson): its energy
error stays bounded."""

import numpy as np

from stability.free_body.propagate import propagate

from ..helpers import invariants

W0 = np.array([0.3, 1.0, 0.9])


def test_lp2_energy_error_is_bounded():
    """Poisson map: the energy error oscillates at O(h^2) with no secular growth."""
    moments = np.array([1.0, 2.0, 3.0])
    m0 = (moments * W0)[None, :]
    run = propagate("lp2", moments, m0, 0.1, 200_000, save_every=100)  # t = 2e4
    _, dE = invariants(moments, np.concatenate([m0, run.saved[0]]))
    early = np.abs(dE[: dE.size // 100]).max()  # t <= 200
    late = np.abs(dE[dE.size // 2 :]).max()  # 1e4 <= t <= 2e4
    assert 1e-6 < early < 1e-3  # O(h^2) at h = 0.1
    assert late < 2.0 * early
