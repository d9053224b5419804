"""What the dissipation studies share (stability.dissipation.studies.common): a key of a number
> 0 refuses 0, and the worst error is the largest magnitude over the finite values."""

import math

import pytest

from stability.dissipation.studies.common import positive_key, worst


def test_a_positive_key_is_a_float_above_zero_with_its_unit():
    key = positive_key("mass", 0.02, "mass of a pair of tips", "kg")
    assert (key.name, key.kind, key.default, key.doc, key.unit) == (
        "mass", "float", 0.02, "mass of a pair of tips", "kg")
    assert key.minimum == 0.0 and key.exclusive_minimum


@pytest.mark.parametrize("values, expected", [
    ([1e-4, -3e-4, float("nan"), 2e-4], 3e-4),
    ([float("nan"), float("inf")], math.nan),
    ([], math.nan),
])
def test_the_worst_is_the_largest_magnitude_of_the_finite_values(values, expected):
    got = worst(values)
    assert got == expected or (math.isnan(got) and math.isnan(expected))
