"""Jacobi elliptic functions and elliptic integrals against mpmath at 40 digits.

The test arguments are exact doubles, so mpmath evaluates the functions at the very same u,
with m = 1 - m1 formed exactly in 40-digit arithmetic. Errors are absolute (sn, cn, dn lie in
[-1, 1]); the tolerance allows for the argument's own rounding: reduction modulo the quarter
period K costs ~ulp(u) in the reduced argument, and the functions' derivatives are bounded by 1.
"""

import math

import mpmath as mp
import numpy as np
import pytest

from stability.core.elliptic import carlson_rf, ellipf, ellipk, sncndn, sncndn_many

EPS = np.finfo(float).eps
#: Complementary parameters m1 = k'^2 from m = 0 to m = 1 - 1e-15.
M1_VALUES = [1.0, 1.0 - 1e-10, 0.9, 0.5, 0.1, 1e-3, 1e-6, 1e-9, 1e-12, 1e-15]


def _pair(m1):
    """(m, m1) as doubles with m + m1 = 1 exactly in real arithmetic, and mpmath's m."""
    if m1 >= 0.5:  # m small: take m as given, m1 = 1 - m is then exact
        m = 1.0 - m1
        m1 = 1.0 - m
        return m, m1, mp.mpf(m)
    m = 1.0 - m1  # rounded; the test's reference uses the exact complement of m1
    return m, m1, 1 - mp.mpf(m1)


@pytest.fixture(autouse=True)
def _digits():
    with mp.workdps(40):
        yield


@pytest.mark.parametrize("m1", M1_VALUES)
def test_sncndn_matches_mpmath_up_to_ten_quarter_periods(m1):
    m, m1, m_mp = _pair(m1)
    K = ellipk(m1)
    rng = np.random.default_rng(int(-math.log10(m1 + 1e-300) * 7) + 3)
    u = np.concatenate(
        [
            rng.uniform(-10.0 * K, 10.0 * K, 40),
            [0.0, 1e-12, 0.5 * K, K, 1.5 * K, 2.0 * K, 3.0 * K, 4.0 * K, 9.99 * K, -3.0 * K],
            K * (1.0 + rng.uniform(-1e-3, 1e-3, 6)),  # near the zero of cn, where dn ~ k'
        ]
    )
    got = sncndn_many(u, m, m1)
    worst = 0.0
    for ui, row in zip(u, got):
        ref = [float(mp.ellipfun(kind, mp.mpf(ui), m=m_mp)) for kind in ("sn", "cn", "dn")]
        # ~ulp(u) from the reduction, a few ulp from the evaluation.
        tol = 8.0 * EPS * (1.0 + abs(ui))
        err = max(abs(row[i] - ref[i]) for i in range(3))
        worst = max(worst, err / (1.0 + abs(ui)))
        assert err <= tol, (ui, row, ref)
        # dn keeps its relative accuracy where it is as small as k' (|d ln dn / du| <= 1).
        assert abs(row[2] - ref[2]) <= tol * ref[2]
    assert worst < 4.0 * EPS  # typical: ~1 ulp per unit of |u|


@pytest.mark.parametrize("m1", [1e-10, 1e-12, 1e-15])
def test_no_loss_past_k_near_m_equal_one(m1):
    """scipy's ellipj returns O(1e6) garbage here (u = 3K, m1 < 1e-9); we keep full accuracy."""
    m, m1, m_mp = _pair(m1)
    K = ellipk(m1)
    for factor in (1.2, 2.5, 3.0, 3.7, 7.3):
        u = factor * K
        sn, cn, dn = sncndn(u, m, m1)
        for kind, value in zip(("sn", "cn", "dn"), (sn, cn, dn)):
            ref = float(mp.ellipfun(kind, mp.mpf(u), m=m_mp))
            assert abs(value - ref) <= 4.0 * EPS * u


@pytest.mark.parametrize("m1", M1_VALUES + [0.0])
def test_identities(m1):
    if m1 > 0.0:
        m, m1, _ = _pair(m1)
        K = ellipk(m1)
    else:
        m, K = 1.0, 20.0
    u = np.linspace(-10.0 * K, 10.0 * K, 2001)
    sn, cn, dn = sncndn_many(u, m, m1).T
    np.testing.assert_allclose(sn * sn + cn * cn, 1.0, rtol=0, atol=8 * EPS)
    np.testing.assert_allclose(dn * dn + m * sn * sn, 1.0, rtol=0, atol=8 * EPS)
    # The same identity in the form that keeps dn's relative accuracy: dn^2 = cn^2 + m1 sn^2.
    np.testing.assert_allclose(dn * dn, cn * cn + m1 * sn * sn, rtol=8 * EPS, atol=0)
    assert np.all(dn > 0.0)


def test_limits_m_zero_and_one():
    u = np.linspace(-7.0, 7.0, 101)
    trig = sncndn_many(u, 0.0, 1.0)
    np.testing.assert_allclose(trig[:, 0], np.sin(u), rtol=0, atol=2 * EPS)
    np.testing.assert_allclose(trig[:, 1], np.cos(u), rtol=0, atol=2 * EPS)
    np.testing.assert_array_equal(trig[:, 2], 1.0)
    hyp = sncndn_many(u, 1.0, 0.0)
    np.testing.assert_allclose(hyp[:, 0], np.tanh(u), rtol=2 * EPS)
    np.testing.assert_allclose(hyp[:, 1], 1.0 / np.cosh(u), rtol=2 * EPS)
    np.testing.assert_array_equal(hyp[:, 1], hyp[:, 2])
    assert ellipk(0.0) == math.inf
    assert ellipk(1.0) == pytest.approx(math.pi / 2, rel=EPS)


@pytest.mark.parametrize("m1", M1_VALUES + [1e-30, 1e-100])
def test_complete_integral_from_complement(m1):
    with mp.workdps(120):  # enough digits to hold 1 - 1e-100
        ref = mp.ellipk(1 - mp.mpf(m1))
        assert abs(ellipk(m1) - ref) <= 2 * EPS * ref


@pytest.mark.parametrize("m1", M1_VALUES)
def test_incomplete_integral(m1):
    m, m1, m_mp = _pair(m1)
    K = ellipk(m1)
    for phi in np.linspace(-7.0, 7.0, 29):
        ref = mp.ellipf(mp.mpf(phi), m_mp)
        got = ellipf(phi, m, m1)
        # Near phi = (n + 1/2) pi and m -> 1 F is ill-conditioned in phi: dF/dphi <= 1/k'.
        assert abs(got - ref) <= 4 * EPS * (abs(ref) + abs(phi) / math.sqrt(m1))
        # Inverse check: sn(F(phi)) = sin(phi) where that is well conditioned.
        if m1 > 1e-6:
            assert sncndn(got, m, m1)[0] == pytest.approx(math.sin(phi), abs=1e-14 * (1 + K))


def test_carlson_rf():
    rng = np.random.default_rng(7)
    for _ in range(40):
        x, y, z = rng.uniform(0, 3, 3) ** 3
        ref = mp.elliprf(mp.mpf(x), mp.mpf(y), mp.mpf(z))
        assert abs(carlson_rf(x, y, z) - ref) <= 4 * EPS * ref
    assert carlson_rf(0.0, 1.0, 1.0) == pytest.approx(math.pi / 2, rel=2 * EPS)
    assert carlson_rf(0.0, 0.0, 1.0) == math.inf
    assert math.isnan(carlson_rf(-1.0, 1.0, 1.0))


def test_bad_input():
    assert all(math.isnan(x) for x in sncndn(1.0, 0.5, 1.5))
    assert all(math.isnan(x) for x in sncndn(math.nan, 0.5, 0.5))
    with pytest.raises(ValueError, match="m1 must be 1 - m"):
        sncndn_many([1.0], 0.5, 0.25)
    with pytest.raises(ValueError, match="0 <= m <= 1"):
        sncndn_many([1.0], 1.5)
