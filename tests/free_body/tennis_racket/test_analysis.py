"""The tennis-racket study's analysis of an ensemble
(stability.free_body.tennis_racket.analysis): its headline is what the accessor gives."""

import numpy as np

import stability
from stability.free_body.tennis_racket.analysis import analyse_ensemble


def test_analyse_ensemble_headline_is_what_the_accessor_gives():
    body = stability.RigidBody.preset("tennis_racket")
    ds = stability.run_ensemble(body, 2, 10.0, 1e-4, 32, h=2e-3, t_end=3.0, seed=3,
                                method="rk4", keep=stability.Keep(save_every=25),
                                options=stability.RunOptions(progress=False))
    out = analyse_ensemble(ds, body, 2, 10.0, 1e-4, low_factor=10.0, high_fraction=0.03)
    headline = out.attrs["growth_rate_fitted"]
    assert headline == float(out.stability.measured_growth_rate().growth_rate)
    assert out.attrs["growth_rate_fitted_members"] == 32
    assert abs(out.attrs["growth_rate_fitted"] / out.attrs["growth_rate_analytic"] - 1) < 1e-3
    t0, t1 = out.attrs["growth_fit_window"]
    assert 0 < t0 < t1 < 3.0 and np.isfinite(out.attrs["growth_fit_intercept"])
    for name in ("exact_flip_interval", "flip_interval_asymptote", "complementary_modulus"):
        assert out[name].dims == ("member",)
    assert out.perp_amplitude_median.dims == ("time",)
