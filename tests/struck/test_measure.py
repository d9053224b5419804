"""The strikes run and measured (stability.struck.measure): the centre of percussion and the
sweet zone found from the runs against the formulas; strikes off the body refused."""

import numpy as np
import pytest

import stability
from stability.struck.measure import measure_strikes
from stability.struck.model import INCH, baseball_bat, hand_velocity

BAT = baseball_bat()
TAU = 7e-4


def test_measured_centre_of_percussion_and_sweet_zone():
    """Held, the reaction is linear in the strike point: the zero and the sweet-zone edges
    found from the runs are the formula's to round-off. Free, the hands' point is at rest after
    a hit at the centre of percussion up to the body's turn during the contact, an error that
    falls as tau^2."""
    pivots = [0.1, 6 * INCH, 0.2]
    points = np.linspace(0.05, BAT.length, 41)
    ds = measure_strikes(BAT, pivots, points, contact_time=TAU,
                         options=stability.RunOptions(progress=False))
    q = ds.percussion_centre_formula.values
    np.testing.assert_allclose(ds.percussion_centre_measured.sel(hold="held"), q, atol=1e-12)
    np.testing.assert_allclose(ds.sweet_zone_measured, ds.sweet_zone_formula, atol=1e-9)
    np.testing.assert_allclose(ds.hand_velocity_across.sel(hold="held"), 0.0, atol=1e-9)
    errors = []
    for tau in (TAU, TAU / 2):
        ds = measure_strikes(BAT, pivots, points, contact_time=tau,
                             options=stability.RunOptions(progress=False))
        errors.append(np.abs(ds.percussion_centre_measured.sel(hold="free").values - q))
    assert errors[0].max() < 1e-4
    ratio = errors[0] / errors[1]
    assert np.all((3.5 < ratio) & (ratio < 4.5)), ratio
    np.testing.assert_allclose(ds.hand_velocity_across.sel(hold="free"),
                               hand_velocity(BAT, ds.pivot.values[:, None], points, 12.0),
                               atol=0.02)


def test_strikes_off_the_body_are_refused():
    with pytest.raises(ValueError, match="off the baseball bat"):
        measure_strikes(BAT, [0.15], [0.2, 0.9], options=stability.RunOptions(progress=False))
