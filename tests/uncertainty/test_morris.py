"""Morris screening (stability.uncertainty.morris): the elementary effects of a linear function."""

import numpy as np

from stability.uncertainty.dispersions import dispersions
from stability.uncertainty.morris import morris_design, morris_indices
from stability.uncertainty.schema import MORRIS_SCREENING


def test_morris_elementary_effects_of_a_linear_function_are_its_slopes():
    """Y = sum c_i x_i: every elementary effect is c_i (upper - lower) in unit steps, so mu* is
    that and sigma is 0."""
    c = np.array([3.0, -1.0, 0.5])
    disp = dispersions({f"x{i}": {"distribution": "uniform", "lower": 0.0, "upper": 2.0}
                        for i in range(3)}, {f"x{i}": 1.0 for i in range(3)})
    design = morris_design(disp, 40, seed=3)
    x = disp.draw(design.unit)
    y = sum(c[i] * x[f"x{i}"] for i in range(3))
    ds = morris_indices(design, {"y": (y, "1", "a linear function")})
    sd = np.std(y)
    assert np.allclose(ds.mu_star.values[0] * sd, np.abs(c) * 2.0, rtol=1e-9)
    assert np.allclose(ds.sigma.values[0] * sd, 0.0, atol=1e-9)
    assert MORRIS_SCREENING.problems(ds) == []
