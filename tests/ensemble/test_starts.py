"""The perturbed starts of an ensemble (stability.ensemble.starts): perpendicular with norm epsilon
spin, independent of the member count, from a seed sequence not consumed, along a fixed
direction checked where they are drawn."""

import math

import numpy as np
import pytest

from stability.ensemble.starts import RNG_CHUNK, perturbed_starts


@pytest.mark.parametrize("axis", [1, 2, 3])
def test_starts_are_perpendicular_with_norm_epsilon_spin(axis):
    spin, epsilon, n = 2.5, 1e-3, RNG_CHUNK + 500  # two RNG chunks
    w0 = perturbed_starts(axis, spin, epsilon, n, seed=7)
    a = axis - 1
    assert np.all(w0[:, a] == spin)  # the spin component is exact
    perp = np.delete(w0, a, axis=1)
    np.testing.assert_allclose(np.linalg.norm(perp, axis=1), epsilon * spin, rtol=4e-16)
    # Directions uniform on the circle: mean of the unit vectors ~ 0 within 5 / sqrt(n).
    unit = perp / (epsilon * spin)
    assert np.all(np.abs(unit.mean(axis=0)) < 5.0 / math.sqrt(n))
    assert np.unique(np.round(unit, 12), axis=0).shape[0] == n


def test_starts_do_not_depend_on_the_number_of_members():
    large = perturbed_starts(2, 1.0, 1e-2, 3 * RNG_CHUNK + 11, seed=3)
    for n in (1, 100, RNG_CHUNK, RNG_CHUNK + 1):
        np.testing.assert_array_equal(perturbed_starts(2, 1.0, 1e-2, n, seed=3), large[:n])


def test_seed_sequence_is_not_consumed():
    ss = np.random.SeedSequence(12345)
    first = perturbed_starts(1, 1.0, 0.1, 50, seed=ss)
    np.testing.assert_array_equal(perturbed_starts(1, 1.0, 0.1, 50, seed=ss), first)
    np.testing.assert_array_equal(perturbed_starts(1, 1.0, 0.1, 50, seed=12345), first)


def test_fixed_direction_is_normalised():
    w0 = perturbed_starts(1, 2.0, 0.05, 4, direction=[0.0, 3.0, 4.0])
    np.testing.assert_allclose(w0, np.tile([2.0, 0.06, 0.08], (4, 1)), rtol=1e-15)


@pytest.mark.parametrize("direction, message", [
    ([0.0, 1.0, 0.0], "not perpendicular to axis 2"),
    ([0.0, 0.0, 0.0], "nonzero"),
    ([[1.0, 0.0, 0.0]], r"direction must have shape \(3,\)"),
])
def test_a_fixed_direction_is_checked_where_the_starts_are_drawn(direction, message):
    with pytest.raises(ValueError, match=message):
        perturbed_starts(2, 1.0, 1e-3, 4, direction=direction)
