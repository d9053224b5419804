"""The compositions lp4, lp6, lp8 of lp2 (stability.integrators.composition): their weights meet the
order conditions."""

import math

import numpy as np
import pytest

from stability.integrators.composition import KAHAN_LI6, KAHAN_LI8, SUZUKI4


@pytest.mark.parametrize(
    "weights, order", [(SUZUKI4, 4), (KAHAN_LI6, 6), (KAHAN_LI8, 8)], ids=["lp4", "lp6", "lp8"]
)
def test_composition_weights_are_consistent(weights, order):
    """Palindromic, sum to 1, and sum g^k = 0 for the odd k in 3 .. order - 1."""
    g = np.array(weights)
    np.testing.assert_array_equal(g, g[::-1])
    assert math.fsum(g) == pytest.approx(1.0, abs=1e-15)
    for k in range(3, order, 2):
        assert abs(np.sum(g**k)) < 1e-14, f"sum g^{k} = {np.sum(g**k)}"
