"""The implicit midpoint rule (stability.integrators.midpoint): its exact discrete growth rate."""

import numpy as np
import pytest

from stability.free_body.propagate import propagate

MOMENTS = np.array([1.0, 2.0, 3.0])


def test_midpoint_growth_rate_is_its_exact_discrete_rate():
    """Near the intermediate axis the midpoint rule grows at lambda_h = (2/h) artanh(h lambda/2).

    Start on the unstable eigenvector, 1e-10 off spin W = 1 rad/s about axis 2 of I = (1, 2, 3),
    so lambda = 1/sqrt(3) s^-1; at h = 0.4 s, lambda_h exceeds lambda by 4.5e-3 and the measured
    rate matches lambda_h to 1e-14 (bound 1e-9).
    """
    lam = 1.0 / np.sqrt(3.0)
    d1 = 1e-10
    d3 = MOMENTS[0] * lam / (MOMENTS[1] - MOMENTS[2]) * d1
    m0 = MOMENTS * np.array([[d1, 1.0, d3]])
    h = 0.4
    n = 40  # grows by e^{lambda t} ~ 1e4, still linear
    run = propagate("midpoint", MOMENTS, m0, h, n, save_every=1)
    w1 = run.saved[0, :, 0] / MOMENTS[0]
    rate = np.polyfit(h * np.arange(1, n + 1), np.log(w1), 1)[0]
    lam_h = (2.0 / h) * np.arctanh(h * lam / 2.0)
    assert rate / lam_h - 1.0 == pytest.approx(0.0, abs=1e-9)
    assert lam_h / lam - 1.0 == pytest.approx(4.48e-3, rel=1e-2)
