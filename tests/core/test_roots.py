"""The bracketed Newton solver (stability.core.roots)."""

import numpy as np

from stability.core.roots import bracketed_newton


def test_bracketed_newton_reaches_round_off_and_flags_bad_brackets():
    target = np.array([0.3, 0.7, -0.5])
    roots = bracketed_newton(lambda x: (np.cos(x) - target, -np.sin(x)),
                             np.zeros(3), np.full(3, 3.0))
    np.testing.assert_allclose(roots, np.arccos(target), rtol=2e-15)
    bad = bracketed_newton(lambda x: (x * x + 1.0, 2 * x), np.array([-1.0]), np.array([1.0]))
    assert np.isnan(bad[0])
