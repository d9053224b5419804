"""The distributions of a dispersion (stability.uncertainty.distributions): their maps are
the inverse CDFs."""

import numpy as np
from scipy import stats

from stability.uncertainty.distributions import distribution


def test_the_maps_are_the_inverse_cdfs():
    u = np.linspace(0.01, 0.99, 7)
    cases = [({"distribution": "normal", "sigma": 2.0}, stats.norm(3.0, 2.0)),
             ({"distribution": "truncated-normal", "sigma": 2.0, "lower": 2.0, "upper": 6.0},
              stats.truncnorm(-0.5, 1.5, 3.0, 2.0)),
             ({"distribution": "log-uniform", "decades": 2.0}, stats.loguniform(0.3, 30.0)),
             ({"distribution": "uniform", "relative": 0.1}, stats.uniform(2.7, 0.6))]
    for spec, ref in cases:
        assert np.allclose(distribution("x", spec, 3.0).ppf(u), ref.ppf(u), rtol=1e-12), spec
