"""The tossed ensemble of the twisting-racket study (stability.free_body.twisting_racket.measure,
tossed_members): the nudge log-uniform within its range and across the middle axis, the first
half of the members the body itself, the second half scattered but as flat as the body. The
twist each member measures is checked in test_geometric_phase.py."""

import numpy as np

from stability.free_body.twisting_racket.measure import tossed_members

RACKET = np.array([0.0144, 0.0013, 0.0157])  # kg m2, any order


def test_the_tossed_members_spin_about_the_middle_axis_nudged_within_the_range():
    moments, w0, epsilon = tossed_members(RACKET, 400, 12.0, (1e-3, 1e-1), 0.2, seed=4)
    assert moments.shape == (400, 3) and w0.shape == (400, 3)
    assert np.all((epsilon >= 1e-3) & (epsilon <= 1e-1))
    # log-uniform: about as many members in each decade
    decades = np.histogram(np.log10(epsilon), bins=[-3, -2, -1])[0]
    assert abs(decades[0] - decades[1]) < 0.2 * 400
    assert np.all(w0[:, 1] == 12.0)
    np.testing.assert_allclose(np.hypot(w0[:, 0], w0[:, 2]), epsilon * 12.0, rtol=1e-15)
    again = tossed_members(RACKET, 400, 12.0, (1e-3, 1e-1), 0.2, seed=4)
    assert all(np.array_equal(a, b) for a, b in zip((moments, w0, epsilon), again))


def test_half_the_members_are_the_body_and_half_are_scattered_as_flat_as_it():
    moments, _, _ = tossed_members(RACKET, 100, 12.0, (1e-2, 1e-2), 0.3, seed=1)
    body = np.sort(RACKET)
    assert np.all(moments[:50] == body)
    scattered = moments[50:]
    assert np.all(np.diff(scattered, axis=1) > 0)  # distinct, ascending: a middle axis
    assert not np.any(np.all(scattered == body, axis=1))
    flatness = body[2] / (body[0] + body[1])
    np.testing.assert_allclose(scattered[:, 2] / scattered[:, :2].sum(axis=1), flatness,
                               rtol=1e-14)
