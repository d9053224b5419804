"""The exact torque-free solution and the flip interval (the ``exact`` method built on it is
tested in ``tests/free_body/test_methods.py``).

References used here, each independent of the code under test:
- scipy's DOP853 at rtol = atol = 1e-12 on Euler's equations written out in the test;
- mpmath at 40 digits evaluating Landau & Lifshitz's formulas (literature.md 1.1-1.3) with the
  initial phase from atan2 and mpmath's own F(phi|m), sn, cn, dn;
- the tanh/sech separatrix solution (literature.md 1.4) and the symmetric-top precession,
  written out in closed form.
"""

import math

import mpmath as mp
import numpy as np
import pytest
from scipy.integrate import solve_ivp

from stability import RigidBody, exact_omega, flip_interval, full_period
from stability.free_body.exact import (
    elliptic_frequency, elliptic_parameters, flip_interval_asymptote, regime,
)

EPS = np.finfo(float).eps


def euler_rhs(t, w, I):
    """Torque-free Euler equations, body frame, any axis order (ERRATA.md section 1)."""
    I1, I2, I3 = I
    return [
        (I2 - I3) * w[1] * w[2] / I1,
        (I3 - I1) * w[2] * w[0] / I2,
        (I1 - I2) * w[0] * w[1] / I3,
    ]


def dop853(I, w0, t):
    """DOP853 at rtol = atol = 1e-12, forwards and backwards from 0, at the times ``t``."""
    out = np.empty((len(t), 3))
    for direction in (1.0, -1.0):
        mask = t >= 0 if direction > 0 else t < 0
        if not mask.any():
            continue
        span = (0.0, direction * np.max(np.abs(t[mask])))
        sol = solve_ivp(
            euler_rhs, span, w0, method="DOP853", rtol=1e-12, atol=1e-12, args=(I,),
            t_eval=t[mask] if direction > 0 else None, dense_output=direction < 0,
        )
        out[mask] = sol.y.T if direction > 0 else sol.sol(t[mask]).T
    return out


def hyperbolic_invariant(I, w):
    """D2 = L^2 - 2 E I2 in the sorted frame (sign decides the regime), in exact rationals."""
    from fractions import Fraction

    order = np.argsort(I)
    I1, I2, I3 = (Fraction(float(I[k])) for k in order)
    w1, _, w3 = (Fraction(float(w[k])) for k in order)
    return I1 * (I1 - I2) * w1 * w1 + I3 * (I3 - I2) * w3 * w3


# ---------------------------------------------------------------------------------------------
# Against DOP853.


@pytest.mark.parametrize("seed", [0, 1, 2, 3])
def test_matches_dop853_on_random_bodies_both_regimes(seed):
    """Tolerance 1e-10 (|w0| = 1, |t| <= 20): DOP853's own global error at rtol = atol = 1e-12
    over ~20 radians of motion is ~1e-11 (measured: <= 1.1e-11), and the exact solution is good
    to ~1e-14 (mpmath test below), so the difference measures the integrator."""
    rng = np.random.default_rng(seed)
    I = rng.uniform(1.0, 3.0, 3)  # unsorted
    body = RigidBody(*I, physical=False)
    t = np.linspace(-20.0, 20.0, 41)
    seen = set()
    while seen != {"major", "minor"}:
        w0 = rng.normal(size=3)
        w0 /= np.linalg.norm(w0)
        kind = "major" if hyperbolic_invariant(I, w0) > 0 else "minor"
        if kind in seen:
            continue
        seen.add(kind)
        assert regime(body, w0) == kind
        np.testing.assert_allclose(exact_omega(body, w0, t), dop853(I, w0, t), rtol=0, atol=1e-10)


@pytest.mark.parametrize(
    "moments", [(2.0, 2.0, 3.0), (3.0, 1.0, 3.0), (1.0, 2.0, 2.0 * (1 + 1e-12))]
)
def test_symmetric_and_nearly_symmetric_bodies_match_dop853(moments):
    body = RigidBody(*moments, physical=False)
    w0 = np.array([0.6, -0.5, 0.7])
    t = np.linspace(-15.0, 15.0, 31)
    np.testing.assert_allclose(
        exact_omega(body, w0, t), dop853(np.array(moments), w0, t), rtol=0, atol=1e-10
    )


# ---------------------------------------------------------------------------------------------
# Against mpmath near the separatrix.


def mp_solution(I, w0, t):
    """Landau & Lifshitz in 40-digit arithmetic; I sorted ascending, all three distinct."""
    I1, I2, I3 = (mp.mpf(float(x)) for x in I)
    w1, w2, w3 = (mp.mpf(float(x)) for x in w0)
    D1 = I2 * (I2 - I1) * w2**2 + I3 * (I3 - I1) * w3**2
    D2 = I1 * (I1 - I2) * w1**2 + I3 * (I3 - I2) * w3**2
    D3 = I1 * (I3 - I1) * w1**2 + I2 * (I3 - I2) * w2**2
    a = mp.sqrt(D3 / (I1 * (I3 - I1)))
    if D2 > 0:  # literature.md 1.1
        s = mp.sign(w3)
        b = mp.sqrt(D3 / (I2 * (I3 - I2)))
        c = mp.sqrt(D1 / (I3 * (I3 - I1)))
        nu = mp.sqrt((I3 - I2) * D1 / (I1 * I2 * I3))
        m1 = (I3 - I1) * D2 / ((I3 - I2) * D1)
        phi0 = mp.atan2(s * w2 / b, w1 / a)
    else:  # literature.md 1.2
        s = mp.sign(w1)
        b = mp.sqrt(D1 / (I2 * (I2 - I1)))
        c = mp.sqrt(D1 / (I3 * (I3 - I1)))
        nu = mp.sqrt((I2 - I1) * D3 / (I1 * I2 * I3))
        m1 = (I3 - I1) * (-D2) / ((I2 - I1) * D3)
        phi0 = mp.atan2(s * w2 / b, w3 / c)
    m = 1 - m1
    u0 = mp.ellipf(phi0, m)  # continued past pi/2 by mpmath (F(phi + pi) = F(phi) + 2K)
    rows = []
    for ti in t:
        u = u0 + nu * mp.mpf(float(ti))
        sn, cn, dn = (mp.ellipfun(kind, u, m=m) for kind in ("sn", "cn", "dn"))
        if D2 > 0:
            rows.append([a * cn, s * b * sn, s * c * dn])
        else:
            rows.append([s * a * dn, s * b * sn, c * cn])
    return np.array(rows, dtype=float), float(m1), float(mp.ellipk(m) / nu)


def _near_separatrix_cases():
    rng = np.random.default_rng(11)
    I = np.array([0.7, 1.3, 1.9])
    e3 = 1e-3 / math.sqrt(3.0) * (1.0 + 2e-7)
    cases = [
        ((1.0, 2.0, 3.0), (1e-6, 1.0, 0.0), (0, 1, 2)),  # below, k'^2 = 1e-12
        ((1.0, 2.0, 3.0), (0.0, -1.0, 5e-7), (0, 1, 2)),  # above, k'^2 = 7.5e-13
        ((1.0, 2.0, 3.0), (1e-3, 1.0, e3), (0, 1, 2)),  # D2's terms cancel to 4e-7
        ((1.0, 2.0, 3.0), (-0.8e-3, 0.8, -0.8 * e3), (2, 0, 1)),  # the same, scaled, relabelled
    ]
    for _ in range(2):
        eps = 1e-7 * rng.normal(size=2)
        w0 = [eps[0], rng.choice([-1.0, 1.0]) * rng.uniform(0.5, 2.0), eps[1]]
        cases.append((tuple(I.tolist()), tuple(float(x) for x in w0), (1, 2, 0)))
    return cases


@pytest.mark.parametrize("I, w0, cycle", _near_separatrix_cases())
def test_matches_mpmath_near_separatrix_past_3K(I, w0, cycle):
    """k'^2 <= 1e-12, times up to +-6K/nu: error <= 1e-13 relative to |w0|."""
    with mp.workdps(40):
        ref, m1, quarter = mp_solution(I, w0, [0.0])
        assert m1 <= 1e-12
        t = quarter * np.concatenate([np.linspace(-6.0, 6.0, 41), [3.05, 3.5, 5.01]])
        ref, _, _ = mp_solution(I, w0, t)
    # The same motion with the axes relabelled cyclically (a proper rotation): unsorted input.
    perm = list(cycle)
    body = RigidBody(*np.array(I)[perm], physical=False)
    got = exact_omega(body, np.array(w0)[perm], t)
    err = np.max(np.abs(got - ref[:, perm])) / np.linalg.norm(w0)
    assert err <= 1e-13, err
    assert elliptic_parameters(body, np.array(w0)[perm])[1] == pytest.approx(m1, rel=1e-12)


# ---------------------------------------------------------------------------------------------
# Closed forms: separatrix, symmetric top, sphere, axes.

#: I = (3, 4, 6), |w1| = 2, |w3| = 1: I1 (I2 - I1) w1^2 = 12 = I3 (I3 - I2) w3^2, so D2 = 0 exactly.
SEP_I = (3.0, 4.0, 6.0)


def separatrix_closed_form(w0, t):
    """literature.md 1.4, sorted frame I = (3, 4, 6)."""
    I1, I2, I3 = SEP_I
    two_e = I1 * w0[0] ** 2 + I2 * w0[1] ** 2 + I3 * w0[2] ** 2
    W = math.sqrt(two_e / I2)
    A = math.sqrt(two_e * (I3 - I2) / (I1 * (I3 - I1)))
    C = math.sqrt(two_e * (I2 - I1) / (I3 * (I3 - I1)))
    lam = W * math.sqrt((I2 - I1) * (I3 - I2) / (I1 * I3))
    s1, s3 = math.copysign(1.0, w0[0]), math.copysign(1.0, w0[2])
    u = math.atanh(w0[1] / W) + s1 * s3 * lam * t
    return np.stack([s1 * A / np.cosh(u), W * np.tanh(u), s3 * C / np.cosh(u)], axis=-1), lam, W


@pytest.mark.parametrize("s1", [1.0, -1.0])
@pytest.mark.parametrize("s2", [1.0, -1.0])
@pytest.mark.parametrize("s3", [1.0, -1.0])
def test_separatrix_against_tanh_sech(s1, s2, s3):
    w0 = np.array([2.0 * s1, 5.0 * s2, 1.0 * s3])
    t = np.linspace(-8.0, 8.0, 33)
    ref, lam, W = separatrix_closed_form(w0, t)
    for perm in ([0, 1, 2], [2, 0, 1]):  # sorted, and cyclically relabelled
        body = RigidBody(*np.array(SEP_I)[perm])
        got = exact_omega(body, w0[perm], t)
        np.testing.assert_allclose(got, ref[:, perm], rtol=0, atol=2e-14 * W)
        assert regime(body, w0[perm]) == "separatrix"
        assert flip_interval(body, w0[perm]) == math.inf
        assert full_period(body, w0[perm]) == math.inf
        assert elliptic_frequency(body, w0[perm]) == pytest.approx(lam, rel=4 * EPS)
    # One flip only: w2 tends to -W as t -> -inf and to +W as t -> +inf when s1 s3 > 0.
    far = exact_omega(RigidBody(*SEP_I), w0, [-200.0 / lam, 200.0 / lam])
    np.testing.assert_allclose(far[:, 1], [-s1 * s3 * W, s1 * s3 * W], rtol=4 * EPS)


def test_symmetric_top_precesses_uniformly():
    """I1 = I2: w3 constant, (w1, w2) turns at Omega = (I3 - I1) w3 / I1 (literature.md 2.3)."""
    I1, I3 = 2.0, 3.0
    w0 = np.array([0.6, -0.5, 0.7])
    t = np.linspace(-30.0, 30.0, 61)
    omega = (I3 - I1) * w0[2] / I1
    z = (w0[0] + 1j * w0[1]) * np.exp(1j * omega * t)
    got = exact_omega(RigidBody(I1, I1, I3), w0, t)
    # sin and cos of Omega t are good to ~ulp(Omega t) (|Omega t| <= 10.5 here).
    np.testing.assert_allclose(got[:, 0], z.real, rtol=0, atol=1e-14)
    np.testing.assert_allclose(got[:, 1], z.imag, rtol=0, atol=1e-14)
    np.testing.assert_array_equal(got[:, 2], w0[2])
    body = RigidBody(I1, I1, I3)
    assert regime(body, w0) == "symmetric"
    assert flip_interval(body, w0) == pytest.approx(math.pi / abs(omega), rel=4 * EPS)
    assert full_period(body, w0) == pytest.approx(2 * math.pi / abs(omega), rel=4 * EPS)
    # Spin in the equal-moment plane is steady.
    assert flip_interval(body, [0.6, -0.5, 0.0]) == math.inf
    np.testing.assert_array_equal(exact_omega(body, [0.6, -0.5, 0.0], t), [[0.6, -0.5, 0.0]] * 61)


def test_sphere_keeps_w():
    body = RigidBody(2.0, 2.0, 2.0)
    w0 = [0.3, -1.2, 0.4]
    np.testing.assert_array_equal(exact_omega(body, w0, [-5.0, 0.0, 1e3]), [w0] * 3)
    assert regime(body, w0) == "sphere"
    assert flip_interval(body, w0) == math.inf and full_period(body, w0) == math.inf


@pytest.mark.parametrize("axis", [0, 1, 2])
@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_start_on_a_principal_axis_is_steady(axis, sign):
    body = RigidBody(2.0, 3.0, 1.0)  # intermediate moment on axis 1, largest on axis 2
    w0 = np.zeros(3)
    w0[axis] = 1.7 * sign
    t = np.array([-50.0, -1.0, 0.5, 3.0, 1e4])
    np.testing.assert_array_equal(exact_omega(body, w0, t), np.tile(w0, (5, 1)))
    expected = {0: "separatrix", 1: "major", 2: "minor"}[axis]
    assert regime(body, w0) == expected
    if axis == 0:
        assert flip_interval(body, w0) == math.inf
    else:  # the limit of nearby motions: half the period of small oscillations
        I = body.moments
        j, k = [x for x in range(3) if x != axis]
        omega = abs(w0[axis]) * math.sqrt((I[axis] - I[j]) * (I[axis] - I[k]) / (I[j] * I[k]))
        assert flip_interval(body, w0) == pytest.approx(math.pi / omega, rel=8 * EPS)


def test_time_zero_returns_w0_exactly():
    rng = np.random.default_rng(5)
    bodies = [RigidBody(1.0, 2.0, 3.0), RigidBody(3.0, 1.5, 2.0), RigidBody(2.0, 2.0, 3.0),
              RigidBody(*SEP_I), RigidBody(1.0, 1.0, 1.0)]
    starts = [rng.normal(size=3), [2.0, -5.0, 1.0], [1e-7, 1.0, 0.0]]
    for body in bodies:
        for w0 in starts:
            got = exact_omega(body, w0, [0.0, 1.0, 0.0])
            np.testing.assert_array_equal(got[0], w0)
            np.testing.assert_array_equal(got[2], w0)
            assert exact_omega(body, w0, 0.0).shape == (3,)


def test_scale_and_time_reversal():
    """w(t; c w0) = c w(c t; w0), and running back from w(t) for time t returns w0."""
    body = RigidBody(1.0, 1.7, 2.2)
    w0 = np.array([0.4, 0.9, -0.3])
    t = np.linspace(0.0, 12.0, 13)
    base = exact_omega(body, w0, t)
    for c in (2.0**-600, 3.0, 2.0**400):
        np.testing.assert_allclose(exact_omega(body, c * w0, t / c), c * base, rtol=1e-13, atol=0)
    for ti, wi in zip(t[1:], base[1:]):
        np.testing.assert_allclose(exact_omega(body, wi, -ti), w0, rtol=0, atol=1e-14)


# ---------------------------------------------------------------------------------------------
# Flip interval and period.


def crossing_spacing(I, w0, component, n_crossings, t_end):
    sol = solve_ivp(
        euler_rhs, (0.0, t_end), w0, method="DOP853", rtol=1e-12, atol=1e-12, args=(I,),
        events=lambda t, w, I: w[component],
    )
    times = sol.t_events[0]
    assert len(times) >= n_crossings
    return np.diff(times)


@pytest.mark.parametrize("eps, published", [(1e-2, 20.754610), (1e-3, None), (1e-4, 36.707819)])
def test_flip_interval_against_zero_crossings(eps, published):
    """I = (1, 2, 3), start (eps, 1, 0): literature.md 1.5 gives 2K/nu = 20.754610, 36.707819."""
    body = RigidBody(1.0, 2.0, 3.0)
    w0 = np.array([eps, 1.0, 0.0])
    T = flip_interval(body, w0)
    if published is not None:
        assert T == pytest.approx(published, abs=6e-7)
    assert full_period(body, w0) == 2.0 * T
    spacing = crossing_spacing(np.array([1.0, 2.0, 3.0]), w0, 1, 3, 3.6 * T)
    # The flip time is ill-conditioned in the start: dT/d(eps) = -(2/lambda)/eps, so DOP853's
    # ~1e-12 errors move it by ~(2/lambda) 1e-12/eps (measured relative spacing errors: 2.5e-12,
    # 4.2e-11, 4.5e-9 at eps = 1e-2, 1e-3, 1e-4).
    np.testing.assert_allclose(spacing, T, rtol=2e-12 / eps)
    # The asymptote (2 / lambda) ln(4 / k') is off by O(k'^2).
    m1 = elliptic_parameters(body, w0)[1]
    assert abs(flip_interval_asymptote(body, w0) / T - 1.0) < m1


def test_flip_interval_unsorted_body_counts_the_intermediate_axis():
    body = RigidBody(3.0, 1.0, 2.0)  # intermediate moment on axis 3, smallest on axis 2
    w0 = np.array([0.0, 1e-3, 1.0])
    T = flip_interval(body, w0)
    assert T == pytest.approx(flip_interval(RigidBody(1.0, 2.0, 3.0), [1e-3, 1.0, 0.0]), rel=1e-14)
    spacing = crossing_spacing(body.moments, w0, 2, 3, 3.6 * T)
    np.testing.assert_allclose(spacing, T, rtol=2e-9)


# ---------------------------------------------------------------------------------------------
# The ``exact`` method.


# ---------------------------------------------------------------------------------------------
# Bad input.


def test_bad_input_is_rejected_clearly():
    body = RigidBody(1.0, 2.0, 3.0)
    with pytest.raises(ValueError, match="RigidBody"):
        exact_omega((1.0, 2.0, 3.0), [1.0, 0.0, 0.0], [1.0])
    with pytest.raises(ValueError, match="shape"):
        exact_omega(body, [1.0, 0.0], [1.0])
    with pytest.raises(ValueError, match=r"shape \(3,\)"):
        exact_omega(body, [[1.0, 0.0, 0.0]], [1.0])
    with pytest.raises(ValueError, match="finite"):
        exact_omega(body, [1.0, math.nan, 0.0], [1.0])
    with pytest.raises(ValueError, match="t must be finite"):
        exact_omega(body, [1.0, 0.0, 0.0], [1.0, math.inf])
    with pytest.raises(ValueError, match=r"t must be a number or have shape \(n,\)"):
        exact_omega(body, [1.0, 0.0, 0.0], [[1.0]])
    with pytest.raises(ValueError, match="t must be"):
        exact_omega(body, [1.0, 0.0, 0.0], "soon")
    with pytest.raises(ValueError, match="RigidBody"):
        flip_interval("racket", [1.0, 0.0, 0.0])


@pytest.mark.parametrize("moments", [(1.0, 2.0, 3.0), (3.0, 1.0, 2.0), (1.0, 1.0, 2.0),
                                     (1.0, 2.0, 2.0), (2.0, 2.0, 2.0)])
def test_flip_intervals_of_many_starts_are_bitwise_the_one_start_functions(moments):
    """The compiled loop over starts gives exactly what flip_interval,
    flip_interval_asymptote and elliptic_parameters give one start at a time, in every regime
    (both sides of the separatrix, on it, symmetric bodies, the sphere)."""
    from stability.free_body.exact import (
        elliptic_parameters, flip_interval_asymptote, flip_intervals,
    )

    body = RigidBody(*moments, physical=False)
    rng = np.random.default_rng(5)
    w0 = rng.standard_normal((40, 3))
    w0[0] = (0.0, 1.0, 0.0)  # on an axis: steady, or the separatrix for the middle one
    w0[1] = (1e-9, 1.0, 0.0)
    exact, asymptote, kprime = flip_intervals(body, w0)
    for j, w in enumerate(w0):
        interval = flip_interval(body, w)
        assert exact[j] == interval or (np.isnan(interval) and np.isnan(exact[j]))
        a = flip_interval_asymptote(body, w)
        assert asymptote[j] == a or (np.isnan(a) and np.isnan(asymptote[j]))
        k2 = elliptic_parameters(body, w)[1]
        assert kprime[j] == math.sqrt(k2) or (np.isnan(k2) and np.isnan(kprime[j]))


@pytest.mark.parametrize("moments", [(1.0, 2.0, 3.0), (3.0, 1.0, 2.0), (1.0, 1.0, 2.0),
                                     (2.0, 2.0, 2.0)])
def test_exact_omega_of_many_starts_is_bitwise_exact_omega_of_each(moments):
    from stability.free_body.exact import exact_omega_of_starts

    body = RigidBody(*moments, physical=False)
    w0 = np.random.default_rng(8).standard_normal((30, 3))
    w0[0] = (0.0, 1.0, 0.0)
    many = exact_omega_of_starts(body, w0, 7.3)
    for j, w in enumerate(w0):
        assert np.array_equal(many[j], exact_omega(body, w, 7.3))

