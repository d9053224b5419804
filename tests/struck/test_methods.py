"""The struck body's kernels (stability.struck.methods): a held strike converges at order four to
the exact motion."""

import numpy as np

from stability.struck.methods import held_exact
from stability.struck.model import INCH

from .test_model import BAT, TAU, run, strike


def test_held_strike_converges_at_order_four_to_the_exact_motion():
    st = strike(BAT, 6 * INCH, 0.7, 1.0)
    errors = []
    for n in (8, 16, 32):
        x = run([st], 2 * n, n).x_final[0]
        errors.append(np.abs(x - held_exact(np.array([2 * TAU]), st)[0]).max())
    orders = np.log2(np.array(errors[:-1]) / errors[1:])
    assert np.all(np.abs(orders - 4.0) < 0.2), orders
