"""The rolling ensembles run and measured (stability.rolling.measure) against the formulas."""

import numpy as np

import stability
from stability.rolling.measure import measure_incline, measure_launches


def test_incline_map_has_no_cell_on_the_wrong_side_and_the_launches_match():
    ds = measure_incline(["sphere", "hoop"], np.radians(np.linspace(3, 60, 12)),
                         np.linspace(0.05, 0.5, 10), members=3,
                         options=stability.RunOptions(progress=False))
    assert int(ds.wrong_side.sum()) == 0
    assert np.array_equal(ds.slipped.values, 1 - ds.rolls_formula.values)
    assert 0 < float(ds.slip_fraction.mean()) < 1
    dl = measure_launches(radius=0.1085, mass=7.26, k=0.4, mu_k=0.2, speeds=(6, 9),
                          spin_ratios=(-0.3, 0.3), members=50,
                          options=stability.RunOptions(progress=False))
    for key in ("t_roll", "x_roll", "v_final"):
        np.testing.assert_allclose(dl[key], dl[key + "_formula"], rtol=1e-13)
    np.testing.assert_allclose(dl.heat, dl.energy_lost_formula, rtol=1e-12)
    np.testing.assert_allclose(dl.energy_lost, dl.energy_lost_formula, rtol=1e-8)

