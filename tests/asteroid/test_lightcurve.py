"""Synthetic light curves: their spectra show the frequencies theory predicts for each mode."""

import numpy as np
import pytest

from stability.asteroid.lightcurve import (
    brightness, ellipsoid_axes, ellipsoid_mesh, facets, lightcurve, main_frequencies,
)
from stability.asteroid.measure import lightcurve_peaks
from stability.asteroid.model import spin_state, state_of

SUN, OBSERVER = (1.0, 0.0, 0.3), (1.0, 0.2, 0.3)


@pytest.mark.parametrize("law", ["lommel-seeliger", "lambert"])
def test_apophis_light_curve_peaks_at_the_long_axis_frequency_2_over_p1(law):
    """Pravec et al. 2014: the strongest period of Apophis' light curve is P1/2 with
    P1 = (1/P_phi - 1/P_psi)^-1 = 30.56 h, the SAM's 2 (f_phi - f_psi)."""
    s = spin_state((0.61, 0.965, 1.0), 263.0, 27.38, "SAM")
    peaks, resolution = lightcurve_peaks(s, SUN, OBSERVER, samples=2048, count=1, law=law)
    assert abs(peaks[0] - main_frequencies(s)[0]) < 0.05 * resolution
    assert round(2.0 / peaks[0], 2) == 30.56


def test_oumuamua_lam_light_curve_shows_belton_2018_frequencies():
    """Belton et al., ApJL 856, L21 (2018), abstract: a LAM with the long axis precessing
    with P_phi = 8.67 h and rotating about it with P_psi = 54.48 h; the light curve's two
    fundamental frequencies 2.77 +- 0.11 and 6.42 +- 0.18 cycles/day, here 2 f_phi (the double
    minimum at 2.77 c/d, the strongest line) and 2 (f_phi + f_psi), among the four strongest.
    Shape: a uniform 6 : 1.2 : 1 cigar (the paper gives no moment ratios)."""
    a, b, c = 6.0, 1.2, 1.0
    moments = np.array([b * b + c * c, a * a + c * c, a * a + b * b]) / (a * a + b * b)
    s = spin_state(moments, 54.48, 8.67, "LAM")
    peaks, resolution = lightcurve_peaks(s, SUN, OBSERVER, samples=4096, count=4)
    predicted = main_frequencies(s)
    assert abs(peaks[0] - predicted[0]) < 0.05 * resolution  # the strongest: 2 f_phi
    found = [peaks[np.argmin(np.abs(peaks - f))] for f in predicted]  # among the 4 strongest
    assert np.abs(np.array(found) - predicted).max() < 0.05 * resolution
    per_day = 24.0 * np.array(found)
    assert abs(per_day[0] / 2.0 - 2.77) < 0.11 and abs(per_day[1] - 6.42) < 0.18


def test_a_principal_axis_rotator_has_one_line_at_twice_its_spin():
    """At E/E0 -> 1 the state is nearly a spin about the short axis: the strongest line is
    at twice the spin frequency L / (2 pi I3)."""
    s = state_of((0.5, 0.8, 1.0), (1e-3, 0.0, 1.0))
    assert s.mode == "SAM" and s.energy_ratio - 1.0 < 1e-6
    peaks, resolution = lightcurve_peaks(s, SUN, OBSERVER, samples=4096, count=1)
    spin = s.momentum / (2 * np.pi)  # I3 = 1
    assert abs(peaks[0] - main_frequencies(s)[0]) < 0.05 * resolution
    assert abs(peaks[0] / (2 * spin) - 1.0) < 1e-6


def test_a_sphere_is_as_bright_at_every_attitude_and_lambert_matches_its_integral():
    v, f = ellipsoid_mesh(1.0, 1.0, 1.0, 64)
    n, area = facets(v, f)
    s = np.tile([1.0, 0.0, 0.0], (5, 1))
    flux = brightness(n, area, s, s, "lambert")  # zero phase: integral of mu^2 = 2 pi / 3
    assert np.allclose(flux, 2 * np.pi / 3, rtol=2e-3)
    sp = spin_state((0.61, 0.965, 1.0), 263.0, 27.38, "SAM")
    curve = lightcurve(sp, np.linspace(0, 500, 50), SUN, OBSERVER, shape=(v, f))
    assert np.ptp(curve) < 2e-3 * curve.mean()


def test_ellipsoid_axes_give_back_the_moment_ratios():
    a, b, c = ellipsoid_axes((0.61, 0.965, 1.0))
    I = np.array([b * b + c * c, a * a + c * c, a * a + b * b])
    assert np.allclose(I / I[2], (0.61, 0.965, 1.0), rtol=1e-14)
