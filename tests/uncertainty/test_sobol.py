"""Sobol' indices (stability.uncertainty.sobol) against closed forms (Ishigami)."""

import math

import numpy as np
import pytest

from stability.uncertainty.dispersions import dispersions
from stability.uncertainty.schema import SOBOL_INDICES
from stability.uncertainty.sobol import sobol_design, sobol_indices

A, B = 7.0, 0.1
PI = math.pi


def ishigami_indices(a, b):
    """S1, S2, S3, ST1, ST2, ST3 of Y = sin x1 + a sin^2 x2 + b x3^4 sin x1, x_i ~ U(-pi, pi)
    (Ishigami & Homma 1990; Sobol' & Levitan 1999): V1 = (1 + b pi^4 / 5)^2 / 2,
    V2 = a^2 / 8, V13 = 8 b^2 pi^8 / 225, V = V1 + V2 + V13."""
    v1 = 0.5 * (1.0 + b * PI**4 / 5.0) ** 2
    v2 = a * a / 8.0
    v13 = 8.0 * b * b * PI**8 / 225.0
    v = v1 + v2 + v13
    return np.array([v1 / v, v2 / v, 0.0]), np.array([(v1 + v13) / v, v2 / v, v13 / v])


def test_the_closed_forms_are_the_published_values():
    first, total = ishigami_indices(A, B)
    assert np.allclose(first, [0.3139, 0.4424, 0.0], atol=1e-4)
    assert np.allclose(total, [0.5576, 0.4424, 0.2437], atol=1e-4)


ISHIGAMI = dispersions({f"x{i}": {"distribution": "uniform", "lower": -PI, "upper": PI}
                        for i in (1, 2, 3)}, {"x1": 0.0, "x2": 0.0, "x3": 0.0})


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_the_indices_of_the_ishigami_function_within_0_02(seed):
    design = sobol_design(ISHIGAMI, 2**14, seed)
    x = ISHIGAMI.draw(design.unit)
    y = np.sin(x["x1"]) + A * np.sin(x["x2"]) ** 2 + B * x["x3"] ** 4 * np.sin(x["x1"])
    ds = sobol_indices(design, {"y": (y, "1", "Ishigami function")}, seed=seed)
    first, total = ishigami_indices(A, B)
    error = max(np.abs(ds.first_order.values[0] - first).max(),
                np.abs(ds.total.values[0] - total).max())
    print(f"seed {seed}: max |index - closed form| = {error:.4f}")
    assert error < 0.02
    assert np.all(ds.first_order_conf.values > 0) and np.all(ds.total_conf.values < 0.05)
    assert SOBOL_INDICES.problems(ds) == []


def test_an_output_of_another_length_or_not_finite_is_refused():
    design = sobol_design(ISHIGAMI, 8, 0)
    with pytest.raises(ValueError, match="one value per design point"):
        sobol_indices(design, {"y": (np.zeros(3), "1", "y")})
    y = np.zeros(design.unit.shape[0])
    y[2] = np.nan
    with pytest.raises(ValueError, match="not finite at 1 design points"):
        sobol_indices(design, {"y": (y, "1", "y")})
    with pytest.raises(ValueError, match="power of 2"):
        sobol_design(ISHIGAMI, 12, 0)

