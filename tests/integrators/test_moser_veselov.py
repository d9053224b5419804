"""Discrete Moser-Veselov and its order-4 variant (stability.integrators.moser_veselov)."""

import numpy as np
import pytest

MOMENTS = np.array([1.0, 2.0, 3.0])


def test_dmv4_coefficients_follow_hairer_vilmart():
    """The order-4 constants of the modified inertia (literature notes 3.2) for I = (1, 2, 3)."""
    from stability.integrators.moser_veselov import (
        P_D1,
        P_D2,
        P_S1,
        P_S2,
        modified_inertia_params,
    )

    p = modified_inertia_params(MOMENTS)
    assert p[P_S1] == pytest.approx(6.0 / 36.0)  # (I1 + I2 + I3) / (6 I1 I2 I3)
    assert p[P_S2] == pytest.approx(-(1.0 + 0.5 + 1.0 / 3.0) / 3.0)
    assert p[P_D1] == pytest.approx(-1.0 / 18.0)
    assert p[P_D2] == p[P_S1]
