"""The dual-spin maps run and measured (stability.dissipation.measure_gyrostat): the rates
measured over a map meet the eigenvalues to 1e-3, and the verdicts are the eigenvalues'."""

import numpy as np

import stability
from stability.dissipation.measure_gyrostat import measure_dual_spin
from stability.dissipation.model_gyrostat import DualSpinBody


def test_measured_rates_are_the_eigenvalues_within_1e3_for_every_placement():
    """A 3 x 3 map of each placement, two starts per cell: every member whose linear regime
    spans an e-fold is fitted within 1e-3 of the eigenvalue (a few 1e-5 at worst), and every
    cell's measured verdict is the eigenvalues'."""
    body = DualSpinBody(100.0, 25.0, 5.0, 1.0, 1.0, 0.3)
    ds = measure_dual_spin(body, [0.6, 1.0, 1.4], [-1.0, 1.0, 3.0], np.radians([1e-3, 2e-3]),
                           fit_top=1e-3, samples=300, options=stability.RunOptions(progress=False))
    error = ds.rate_error.values
    assert np.isfinite(error).sum() >= 0.9 * error.size
    assert np.nanmax(np.abs(error)) < 1e-4
    assert np.all(ds.verdict_measured.values == ds.verdict_linear.values)
    assert np.all(ds.status.values == 0)
    assert ds.angular_momentum_drift.max() < 1e-10 and ds.energy_rise.max() < 1e-15
