"""The fits behind the figures (stability.analysis.fits): the growth line and Richardson's bias."""

import numpy as np
import pytest

from stability.analysis.fits import growth_line, richardson_bias


def test_growth_line_has_the_given_slope_through_the_linear_phase():
    t = np.linspace(0.0, 3.0, 61)
    rate = 2.5
    amplitude = 1e-4 * np.exp(rate * t)
    intercept, (t0, t1) = growth_line(t, amplitude, rate, 1e-3, 1e-1)
    assert intercept == pytest.approx(np.log(1e-4), abs=1e-10)
    assert 1e-4 * np.exp(rate * t0) > 1e-3 and 1e-4 * np.exp(rate * t1) < 1e-1
    # Saturation after the window does not enter the line.
    saturated = np.minimum(amplitude, 0.5)
    assert growth_line(t, saturated, rate, 1e-3, 1e-1) == (intercept, (t0, t1))
    assert np.isnan(growth_line(t, amplitude, rate, 1e3, 1e4)[0])


def test_richardson_bias_of_an_order_p_error():
    h, c, p = 0.1, 3.0, 4
    exact = 2.0
    coarse, fine = exact + c * h**p, exact + c * (h / 2) ** p
    assert richardson_bias(coarse, fine, p) == pytest.approx(c * h**p, rel=1e-9)
    np.testing.assert_array_equal(richardson_bias([1.0, np.nan], [0.5, 1.0], np.inf),
                                  [0.5, np.nan])
