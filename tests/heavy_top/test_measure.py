"""The heavy top's measurements (stability.heavy_top.measure): sleeping tops against the linear
theory, released gyroscopes against the exact motion."""

import numpy as np
import pytest

import stability
from stability.heavy_top.measure import measure_gyroscopes, measure_sleeping_tops
from stability.heavy_top.model import HeavyTop, critical_spin, sleeping_frequencies

#: The literature's worked example (notes 5.3): a 0.1 kg disk of radius 3 cm, 4 cm from the pivot.
DISK = HeavyTop.disk(0.1, 0.03, 0.04)


def test_sleeping_top_growth_matches_the_analytic_rate_on_both_sides():
    """Measured rates within 1e-4 of sqrt(4 A M g l - C^2 w3^2) / (2 A) below the threshold;
    bounded tilt (rate 0, amplification as the linear theory's |s+| + |s-| over |s+ - s-|)
    above it."""
    top = HeavyTop.disk(0.1, 0.03, 0.04)
    wc = critical_spin(top)
    spins = wc * np.array([0.0, 0.5, 0.9, 1.2, 2.0])
    ds = measure_sleeping_tops([top], spins, members=8,
                               options=stability.RunOptions(progress=False))
    below = spins < wc
    err = ds.relative_error.values[0, below]
    assert np.all(np.abs(err) < 1e-4), err
    assert np.all(ds.growth_rate_measured.values[0, ~below] == 0.0)
    slow, fast = sleeping_frequencies(top, spins[~below])
    bound = (slow + fast) / (fast - slow)  # |A| + |B| over the start, released with xi' = 0
    amp = ds.tilt_amplification.values[0, ~below]
    assert np.all(amp <= bound * (1 + 1e-3)) and np.all(amp > 0.9 * bound)
    assert ds.critical_spin.attrs["units"] == "rad s-1"


@pytest.fixture(scope="module")
def grid():
    spins = np.array([150.0, 400.0, 1200.0])
    return measure_gyroscopes(DISK, spins, np.radians([35.0, 90.0]), (-1.0, 0.0, 0.5),
                              options=stability.RunOptions(progress=False))


def test_runs_measure_precession_and_nutation_to_the_exact_motion(grid):
    """lp4 at step angle 0.02: rates within 2e-9, amplitude within 5e-7 of the exact values."""
    assert int((grid.status != 0).sum()) == 0
    assert float(np.abs(grid.precession_rate_error).max()) < 2e-9
    assert float(np.abs(grid.nutation_frequency_error).max()) < 2e-9
    assert float(np.abs(grid.nutation_amplitude_error).max()) < 5e-7
    paths = grid.path_theta - grid.path_theta_exact
    assert float(np.abs(paths).max()) < 1e-10
    assert float(np.abs(grid.path_phi - grid.path_phi_exact).max()) < 1e-3  # trapezoid phi


def test_fast_top_values_are_approached_as_one_over_spin_squared(grid):
    """exact / fast-top - 1 falls at least as w3^-2 (the next term of each expansion; w3^-4 for
    the precession at 90 degrees, where the term in cos(theta) vanishes): from 400 to 1200 rad/s
    it shrinks by (1/3)^2 or more (15% slack), to below 1e-2, for a top released at rest."""
    at_rest = grid.sel(release=0.0)
    for exact, fast in ((at_rest.precession_rate_exact, grid.precession_rate_gyroscopic),
                        (at_rest.nutation_frequency_exact, grid.nutation_frequency_gyroscopic),
                        (at_rest.nutation_amplitude_exact, at_rest.nutation_amplitude_gyroscopic)):
        offset = np.abs(exact / fast - 1.0)
        ratio = offset.sel(spin=1200.0) / offset.sel(spin=400.0)
        assert np.all(ratio < 1.15 * (400.0 / 1200.0) ** 2), ratio.values
        assert float(offset.sel(spin=1200.0).max()) < 1e-2


def test_paths_loop_cusp_and_wave(grid):
    """phi' changes sign on a looping path, stays >= 0 with a zero at the cusps, and > 0 on
    the wavy one; the cusped path starts at its highest point."""
    dphi = np.diff(grid.path_phi_exact.values, axis=1)
    loops, cusps, waves = dphi
    assert loops.min() < 0 < loops.max()
    assert cusps.min() >= -1e-12 and waves.min() > 0
    theta = grid.path_theta_exact.sel(release=0.0).values
    assert theta[0] == pytest.approx(theta.min(), abs=1e-12)
