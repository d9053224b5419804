"""Designs of the unit cube (stability.uncertainty.designs): in [0, 1)^d; a Latin hypercube
puts one point in each of its N strata of every dimension; N = 2^k scrambled Sobol' points put
one in each of the N dyadic intervals of every dimension; a random design's rows do not depend
on how many members are drawn; a bad design is one line."""

import numpy as np
import pytest

from stability.uncertainty.designs import DESIGNS, RNG_BLOCK, unit_design


@pytest.mark.parametrize("design", DESIGNS)
def test_every_design_lies_in_the_unit_cube_and_repeats_with_its_seed(design):
    points = unit_design(design, 256, 5, seed=3)
    assert points.shape == (256, 5) and np.all((points >= 0) & (points < 1))
    assert np.array_equal(points, unit_design(design, 256, 5, seed=3))
    assert not np.array_equal(points, unit_design(design, 256, 5, seed=4))


def test_a_latin_hypercube_has_one_point_per_stratum_of_each_dimension():
    n = 200
    strata = np.floor(unit_design("lhs", n, 4, seed=1) * n).astype(int)
    for column in strata.T:
        assert np.array_equal(np.sort(column), np.arange(n))


def test_sobol_points_fill_every_dyadic_interval_of_each_dimension_once():
    n = 2 ** 9
    cells = np.floor(unit_design("sobol", n, 6, seed=2) * n).astype(int)
    for column in cells.T:
        assert np.array_equal(np.sort(column), np.arange(n))


def test_a_random_designs_rows_are_the_first_rows_of_any_larger_one():
    small = unit_design("random", 10, 3, seed=5)
    large = unit_design("random", RNG_BLOCK + 10, 3, seed=5)
    assert np.array_equal(small, large[:10])
    # the second block is drawn from its own stream: not a repeat of the first
    assert not np.array_equal(large[:10], large[RNG_BLOCK:RNG_BLOCK + 10])


@pytest.mark.parametrize("args, message", [
    (("halton", 8, 2, 0), "design must be one of random, sobol, lhs"),
    (("lhs", 0, 2, 0), "members must be >= 1"),
    (("lhs", 8, 2, -1), "seed must be >= 0"),
])
def test_bad_designs_are_one_line(args, message):
    with pytest.raises(ValueError, match=message) as info:
        unit_design(*args)
    assert "\n" not in str(info.value)
