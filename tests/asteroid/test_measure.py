"""Periods measured off a long exact-attitude run equal the closed forms; the ensemble."""

import numpy as np
import pytest

from stability.asteroid.measure import draw_members, measure_tumblers, measured_periods
from stability.asteroid.model import spin_states, state_of


@pytest.mark.parametrize("state", [
    *spin_states((0.61, 0.965, 1.0), 263.0, 27.38),  # Apophis: a SAM and a LAM state
    state_of((1.0, 2.0, 2.6), (0.3, 0.2, 1.0)),
    state_of((1.0, 2.0, 2.6), (1.0, 0.4, 0.2)),
], ids=["apophis-sam", "apophis-lam", "sam", "lam"])
def test_periods_from_fifty_turns_of_the_exact_attitude_equal_the_closed_forms(state):
    p_psi, p_phi = measured_periods(state, periods=50)
    assert abs(p_psi / state.period_psi - 1.0) < 1e-10
    assert abs(p_phi / state.period_phi - 1.0) < 1e-10


def test_ensemble_keeps_the_nominal_member_and_refuses_none_silently():
    draws = draw_members((0.61, 0.965), (0.03, 0.004), (263.0, 27.38), (2.0, 0.023), 6, 1)
    draws[3, :2] = (0.99, 0.98)  # out of order: no state, NaN and fitted = 0
    ds = measure_tumblers(draws, "SAM", (1, 0, 0.3), (1, 0.2, 0.3), samples=1024)
    assert ds.fitted.values.tolist() == [1, 1, 1, 0, 1, 1]
    assert np.isnan(ds.energy_ratio.values[3])
    assert round(float(ds.energy_ratio[0]), 3) == 1.024
    ok = ds.fitted.values == 1
    rel = ds.frequency_measured.values[ok] / ds.frequency_predicted.values[ok] - 1.0
    assert np.abs(rel).max() < 1e-4
