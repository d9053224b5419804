"""The members of an ensemble (stability.analysis.members): crossings, the perpendicular amplitude,
and the members marked bad left out of every fit."""

import numpy as np

from stability.analysis.estimates import measured_growth_rate
from stability.analysis.members import perpendicular_amplitude, sign_change_times, zero_crossings

from ..helpers import LAM, separatrix, series_dataset


def test_zero_crossings_interpolates_and_counts():
    t = np.linspace(0.0, 10.0, 1001)
    x = np.sin(np.array([[1.0], [2.0]]) * t[None, :] + 0.1)
    count, first, last = zero_crossings(t, x)
    np.testing.assert_array_equal(count, [3, 6])
    np.testing.assert_allclose(first, [np.pi - 0.1, (np.pi - 0.1) / 2], atol=1e-6)
    np.testing.assert_allclose(last, [3 * np.pi - 0.1, (6 * np.pi - 0.1) / 2], atol=1e-6)


def test_members_marked_bad_are_left_out():
    t, w, _, _ = separatrix(8)
    w[3, 100:, :] = np.nan
    ds = series_dataset(w, t, axis=2)
    ds["status"] = ("member", np.array([0, 0, 0, 1, 0, 0, 0, 0], dtype=np.int8))
    fit = measured_growth_rate(ds)
    assert int(fit.n_fitted) == 7 and np.isnan(fit.member_growth_rate.values[3])
    assert abs(float(fit.growth_rate) / LAM - 1) < 1e-5


def test_perpendicular_amplitude_and_sign_changes():
    t, w, t0, a_max = separatrix(3)
    ds = series_dataset(w, t, axis=2)
    amp = perpendicular_amplitude(ds.w, 2)
    assert amp.dims == ("member", "time") and amp.attrs["units"] == "rad s-1"
    np.testing.assert_allclose(amp.values, a_max / np.cosh(LAM * (t[None] - t0[:, None])),
                               rtol=1e-12)
    flips = sign_change_times(t, w[0, :, 1])
    np.testing.assert_allclose(flips, [t0[0]], atol=1e-4)
