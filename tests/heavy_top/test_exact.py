"""The exact heavy symmetric top (stability.heavy_top.exact) against references independent of it.

- scipy's DOP853 at rtol = 1e-12, atol = 1e-14 on the 6-dim equations m' = m x w + g x c,
  g' = g x w written out here, with phi' = (Lz - m3 u)/(A sin^2 theta) and the attitude
  R' = R hat(w) integrated alongside (the figure axis is R e3, phi its azimuth);
- nutation minima located by DOP853's event finder on u' = (g x w)_3;
- the fast-top expansions of literature.md section 5.3, and the numbers of its worked example;
- scipy's quad of phi' along the exact u(t), mpmath's R_J, and closed forms for the free
  symmetric top (mgl = 0), steady precession and the sleeping top.
"""

import functools
import itertools
import math

import mpmath as mp
import numpy as np
import pytest
from scipy.integrate import quad, solve_ivp

from stability.heavy_top import exact as exact_top
from stability.heavy_top.exact import (
    body_states, carlson_rj, cos_theta, figure_axis_path, mean_precession_rate, nutation_period,
    nutation_roots, precession_angle,
)
from stability.heavy_top.model import (
    HeavyTop, gyroscopic_nutation_amplitude, gyroscopic_nutation_frequency,
    gyroscopic_precession_rate, tilted_starts,
)

G = 9.81
#: The literature's worked example (notes 5.3): a 0.1 kg disk of radius 3 cm, 4 cm from the pivot.
DISK = HeavyTop.disk(0.1, 0.03, 0.04)


def gyroscope(theta0_deg, w3=314.16):
    """literature.md 5.3: disk M = 0.1 kg, r = 3 cm, l = 4 cm, released with w1 = w2 = 0."""
    M, r, l = 0.1, 0.03, 0.04
    C = M * r * r / 2.0
    A = M * r * r / 4.0 + M * l * l
    th = math.radians(theta0_deg)
    x0 = np.array([0.0, 0.0, C * w3, math.sin(th), 0.0, math.cos(th)])
    return x0, A, C, M * G * l


def tilted(theta, azimuth=0.0):
    """Body components of 'up' for a tilt ``theta`` of axis 3, in the direction ``azimuth``."""
    return [math.sin(theta) * math.sin(azimuth), math.sin(theta) * math.cos(azimuth),
            math.cos(theta)]


def _tops():
    x60, A, C, mgl = gyroscope(60.0)
    x90 = gyroscope(90.0)[0]
    return {
        # name: (x0, A, C, mgl, t_end)
        "gyroscope 60 deg": (x60, A, C, mgl, 0.5),
        "gyroscope 90 deg": (x90, A, C, mgl, 0.5),
        # slow spin and a sideways push: the figure axis draws loops (phi' changes sign)
        "loops": (np.array([0.3 * A, -0.5 * A, 20.0 * C, *tilted(1.0, 0.3)]), A, C, mgl, 1.0),
        # released at 30 deg, spinning too slowly to stay up: it falls past the horizontal
        "falls over": (np.array([0.0, 0.0, 30.0 * C, *tilted(math.radians(30.0))]),
                       A, C, mgl, 1.5),
        # 0.01 rad from upright, above the sleeping threshold (119 rad/s)
        "nearly sleeping": (np.array([0.0, 0.0, 300.0 * C, *tilted(0.01)]), A, C, mgl, 0.5),
        # mgl = 0: the free symmetric top, its axis tilted from the vertical and moving
        "free": (np.array([0.01, 0.004, 50.0 * C, 0.3, 0.4, math.sqrt(0.75)]), A, C, 0.0, 0.5),
    }


TOPS = _tops()


def top_rhs(t, y, A, C, mgl, with_phi=True):
    """m' = m x w + g x c, g' = g x w, phi' = (Lz - m3 u)/(A (1 - u^2)), R' = R hat(w).

    ``with_phi=False`` leaves phi out (0/0 where the axis passes through the vertical).
    """
    m1, m2, m3, g1, g2, g3 = y[:6]
    w1, w2, w3 = m1 / A, m2 / A, m3 / C
    phi_dot = (m1 * g1 + m2 * g2) / (A * (1.0 - g3 * g3)) if with_phi else 0.0
    R = y[7:16].reshape(3, 3)
    w_hat = np.array([[0.0, -w3, w2], [w3, 0.0, -w1], [-w2, w1, 0.0]])
    return np.concatenate([
        [m2 * w3 - m3 * w2 + g2 * mgl, m3 * w1 - m1 * w3 - g1 * mgl, m1 * w2 - m2 * w1,
         g2 * w3 - g3 * w2, g3 * w1 - g1 * w3, g1 * w2 - g2 * w1, phi_dot],
        (R @ w_hat).ravel(),
    ])


def initial_attitude(g):
    """Body-to-space R with R^T e_z = g and R e3 at azimuth phi = 0: R = Rx(theta) Rz(psi)."""
    theta = math.acos(g[2])
    psi = math.atan2(g[0], g[1])
    cx, sx, cz, sz = math.cos(theta), math.sin(theta), math.cos(psi), math.sin(psi)
    Rx = np.array([[1.0, 0.0, 0.0], [0.0, cx, -sx], [0.0, sx, cx]])
    Rz = np.array([[cz, -sz, 0.0], [sz, cz, 0.0], [0.0, 0.0, 1.0]])
    return Rx @ Rz


def u_rate(t, y, A, C, mgl, with_phi):
    """u' = (g x w)_3; rising through 0 at each minimum of u."""
    return y[3] * y[1] / A - y[4] * y[0] / A


u_rate.direction = 1.0


def dop853_run(x0, A, C, mgl, t_end, with_phi=True):
    """DOP853 from ``x0`` with R(0) = initial_attitude, dense output, the minima of u."""
    y0 = np.concatenate([x0, [0.0], initial_attitude(x0[3:]).ravel()])
    return solve_ivp(top_rhs, (0.0, t_end), y0, method="DOP853", rtol=1e-12, atol=1e-14,
                     args=(A, C, mgl, with_phi), dense_output=True, events=u_rate)


@functools.cache
def dop853(name):
    """DOP853 run of ``TOPS[name]``."""
    return dop853_run(*TOPS[name])


@pytest.mark.parametrize("name", list(TOPS))
def test_motion_matches_dop853(name):
    x0, A, C, mgl, t_end = TOPS[name]
    sol = dop853(name)
    t = np.linspace(0.0, t_end, 301)
    y = sol.sol(t)
    u = cos_theta(t, x0, A, C, mgl)
    phi = precession_angle(t, x0, A, C, mgl)
    axis = figure_axis_path(t, x0, A, C, mgl)
    assert u.shape == phi.shape == t.shape and axis.shape == t.shape + (3,)
    assert abs(u[0] - x0[5]) < 4e-16 and phi[0] == 0.0
    assert np.max(np.abs(u - y[5])) < 1e-9
    assert np.max(np.abs(phi - y[6])) < 1e-8
    figure_axis = y[7:16].reshape(3, 3, -1)[:, 2, :].T  # R e3
    assert np.max(np.abs(axis - figure_axis)) < 1e-8
    u1, u2, _ = nutation_roots(x0, A, C, mgl)
    assert u1 - 1e-12 <= y[5].min() and y[5].max() <= u2 + 1e-12
    assert_body_states_match(t, x0, A, C, mgl, y)


def assert_body_states_match(t, x0, A, C, mgl, y):
    """body_states (m, g) against the integrated y[:6]: g to 1e-9, m to 1e-9 of its size."""
    x = body_states(t, x0, A, C, mgl)
    assert x.shape == t.shape + (6,) and np.max(np.abs(x[0] - x0)) < 1e-15
    error = np.abs(x - y[:6].T)
    assert np.max(error[:, :3]) < 1e-9 * np.max(np.abs(y[:3])), np.max(error[:, :3])
    assert np.max(error[:, 3:]) < 1e-9, np.max(error[:, 3:])


def test_the_tops_are_what_they_claim():
    """Loops: phi' changes sign; 'falls over': u1 < 0; 'nearly sleeping': |u - 1| < 1e-4."""
    phi_dot = np.diff(dop853("loops").sol(np.linspace(0.0, 1.0, 2001))[6])
    assert phi_dot.min() < 0.0 < phi_dot.max()
    assert nutation_roots(*TOPS["falls over"][:4])[0] < -0.5
    assert nutation_roots(*TOPS["nearly sleeping"][:4])[0] > 1.0 - 1e-4


@pytest.mark.parametrize("name", list(TOPS))
def test_period_and_mean_precession_match_dop853_minima(name):
    x0, A, C, mgl, _ = TOPS[name]
    sol = dop853(name)
    minima = sol.t_events[0]
    assert len(minima) >= 3
    period = nutation_period(x0, A, C, mgl)
    assert np.max(np.abs(np.diff(minima) / period - 1.0)) < 1e-9
    # cos_theta has its minimum u1 there
    assert np.max(np.abs(cos_theta(minima, x0, A, C, mgl)
                         - nutation_roots(x0, A, C, mgl)[0])) < 1e-10
    phi = sol.sol(minima)[6]
    mean_dop = np.diff(phi) / np.diff(minima)
    rate = mean_precession_rate(x0, A, C, mgl)
    assert np.max(np.abs(mean_dop - rate)) < 1e-9 * abs(rate) + 1e-12


@pytest.mark.parametrize("name", ["gyroscope 60 deg", "loops", "falls over", "free"])
def test_precession_integrals_match_quadrature(name):
    """phi(t) and the mean rate against quad / trapezoid of eq. (2) along the exact u(t)."""
    x0, A, C, mgl, _ = TOPS[name]
    a, b = x0[2] / A, (x0[:3] @ x0[3:]) / A

    def phi_dot(t):
        u = cos_theta(t, x0, A, C, mgl)
        return (b - a * u) / (1.0 - u * u)

    period = nutation_period(x0, A, C, mgl)
    ends = np.array([0.37, 1.0, 2.61]) * period
    phi = precession_angle(ends, x0, A, C, mgl)
    scale = np.abs(phi).max()
    for t_end, value in zip(ends, phi):
        # quad on each half period (phi' is smooth there), summed
        edges = np.append(np.arange(0.0, t_end, 0.5 * period), t_end)
        ref = sum(quad(phi_dot, lo, hi, epsabs=0.0, epsrel=2e-14, limit=200)[0]
                  for lo, hi in itertools.pairwise(edges))
        assert abs(value - ref) < 1e-12 * scale
    # the trapezoid rule over a period converges exponentially for a smooth periodic phi'
    t = np.linspace(0.0, period, 2049)[:-1]
    trapezoid = np.mean(phi_dot(t))
    rate = mean_precession_rate(x0, A, C, mgl)
    assert abs(rate - trapezoid) < 1e-13 * np.max(np.abs(phi_dot(t)))
    # whole periods add the mean rate times the period, to round-off
    many = precession_angle(np.array([0.3, 1000.3]) * period, x0, A, C, mgl)
    assert abs((many[1] - many[0]) / (1000.0 * period * rate) - 1.0) < 1e-12


@pytest.mark.parametrize("theta0", [60.0, 90.0])
def test_fast_top_asymptotics(theta0):
    """Released fast top (literature.md 5.3), eps = 2 A M g l / (C w3)^2 -> 0 as w3 doubles.

    Amplitude u2 - u1 = eps sin^2(theta0) (1 + 2 cos(theta0) eps + O(eps^2)) (expanding the
    exact u0 - u1 = eps sin^2(theta1)); mean precession M g l/(C w3) (1 + cos(theta0) eps/2
    + O(eps^2)), the correction of the slow steady-precession root; nutation frequency
    C w3 / A (1 + O(eps)). Tolerances: 3 eps (leading order) and 3 eps^2 (corrected); the
    corrected errors must fall ~16-fold when w3 doubles.
    """
    errors = []
    for w3 in (314.16, 628.32):
        x0, A, C, mgl = gyroscope(theta0, w3)
        eps = 2.0 * A * mgl / (C * w3) ** 2
        u0 = math.cos(math.radians(theta0))
        s2 = 1.0 - u0 * u0
        u1, u2, u3 = nutation_roots(x0, A, C, mgl)
        assert u2 == u0 and u3 > 1.0  # released at its upper turning point
        lead_amp = eps * s2
        assert abs((u2 - u1) / lead_amp - 1.0) < 3.0 * eps
        amp_err = abs((u2 - u1) / (lead_amp * (1.0 + 2.0 * u0 * eps)) - 1.0)
        assert amp_err < 3.0 * eps**2
        bare = mgl / (C * w3)
        rate = mean_precession_rate(x0, A, C, mgl)
        assert abs(rate / bare - 1.0) < 3.0 * eps
        rate_err = abs(rate / (bare * (1.0 + A * mgl * u0 / (C * w3) ** 2)) - 1.0)
        assert rate_err < 3.0 * eps**2
        omega_n = 2.0 * math.pi / nutation_period(x0, A, C, mgl)
        assert abs(omega_n / (C * w3 / A) - 1.0) < 3.0 * eps
        errors.append((amp_err, rate_err))
    (amp0, rate0), (amp1, rate1) = errors
    assert 8.0 < amp0 / amp1 < 32.0 and 8.0 < rate0 / rate1 < 32.0


def test_literature_worked_example():
    """literature.md 5.3, worked example (disk M = 0.1 kg, r = 3 cm, l = 4 cm, spin 50 rev/s),
    to the digits the notes give."""
    x90, A, C, mgl = gyroscope(90.0, w3=100.0 * math.pi)
    w3 = x90[2] / C
    assert round(mgl / (C * w3), 2) == 2.78  # Omega = M g l / (I3 w3)
    assert round(C * w3 / A, 1) == 77.5  # omega_n ~ I3 w3 / I1
    u1 = nutation_roots(x90, A, C, mgl)[0]
    assert round(math.degrees(math.acos(u1)) - 90.0, 1) == 4.1  # Delta theta from horizontal
    # the exact mean precession of this release is within 0.5 % of M g l / (I3 w3)
    assert abs(mean_precession_rate(x90, A, C, mgl) / (mgl / (C * w3)) - 1.0) < 5e-3
    # slow steady precession at 60 deg: A cos(th) W^2 - C w3 W + M g l = 0
    th = math.radians(60.0)
    slow = (C * w3 - math.sqrt((C * w3) ** 2 - 4.0 * A * mgl * math.cos(th))) / (
        2.0 * A * math.cos(th))
    assert round(slow, 4) == 2.8273
    assert round(mgl / (C * w3) * (1.0 + A * mgl * math.cos(th) / (C * w3) ** 2), 4) == 2.8254
    assert round(mgl / (C * w3), 4) == 2.7757
    # started on it (w = W g + psi' e3, w3 fixed), the exact top precesses steadily at W
    g = np.array(tilted(th))
    x0 = np.array([A * slow * g[0], A * slow * g[1], C * w3, *g])
    u1, u2, _ = nutation_roots(x0, A, C, mgl)
    assert u2 - u1 < 1e-6
    assert abs(mean_precession_rate(x0, A, C, mgl) / slow - 1.0) < 1e-9
    t = np.linspace(0.0, 1.0, 11)
    np.testing.assert_allclose(precession_angle(t, x0, A, C, mgl), slow * t, rtol=1e-9)
    # sleeping top threshold: C^2 w3^2 > 4 A M g l
    assert round(math.sqrt(4.0 * A * mgl) / C) == 119


def test_free_symmetric_top():
    """mgl = 0: the axis circles L at L/A (Landau & Lifshitz section 33)."""
    x0, A, C, _, _ = TOPS["free"]
    L = np.linalg.norm(x0[:3])
    assert nutation_roots(x0, A, C, 0.0)[2] == math.inf
    assert nutation_period(x0, A, C, 0.0) == pytest.approx(2.0 * math.pi * A / L, rel=1e-14)
    # L vertical (m parallel to g): theta is constant and phi' = L / A
    g = np.array(tilted(0.7, 1.1))
    vertical = np.concatenate([L * g, g])
    u = cos_theta(np.linspace(0.0, 3.0, 7), vertical, A, C, 0.0)
    np.testing.assert_allclose(u, g[2], rtol=0.0, atol=1e-15)
    assert mean_precession_rate(vertical, A, C, 0.0) == pytest.approx(L / A, rel=1e-14)


def test_body_states_of_a_steady_spin_turn_the_vertical_at_the_spin_rate():
    """Free symmetric top with L vertical, chosen so that u0 is an exact double root (the
    constant-rate branch): g turns in the body about e3 at psi' = m3/C - phi' u0."""
    A, C = 1.0, 0.5
    x0 = np.array([0.0, 0.6, 0.8, 0.0, 0.6, 0.8])  # m = |L| g, |g| = 1 exactly
    t = np.linspace(0.0, 3.0, 31)
    y = dop853_run(x0, A, C, 0.0, 3.0, with_phi=False).sol(t)
    assert np.ptp(y[3]) > 0.5  # g turns in the body
    assert_body_states_match(t, x0, A, C, 0.0, y)


def test_sleeping_top():
    """Exactly upright, spinning: u stays 1, no NaN; the period is the limit of a tilted top."""
    _, A, C, mgl = gyroscope(0.0)
    t = np.linspace(0.0, 2.0, 5)
    for w3, stable in ((300.0, True), (100.0, False)):  # threshold 119 rad/s
        x0 = np.array([0.0, 0.0, C * w3, 0.0, 0.0, 1.0])
        assert np.all(cos_theta(t, x0, A, C, mgl) == 1.0)
        assert np.all(body_states(t, x0, A, C, mgl) == x0)
        axis = figure_axis_path(t, x0, A, C, mgl)
        assert np.all(axis == [0.0, 0.0, 1.0])
        assert np.all(np.isfinite(precession_angle(t, x0, A, C, mgl)))
        u1, u2, u3 = nutation_roots(x0, A, C, mgl)
        assert u1 == u2 == 1.0 and (u3 > 1.0) == stable
        period = nutation_period(x0, A, C, mgl)
        if stable:
            tilted_top = np.array([0.0, 0.0, C * w3, *tilted(1e-5)])
            assert period == pytest.approx(nutation_period(tilted_top, A, C, mgl), rel=1e-8)
        else:
            assert period == math.inf


def _passages():
    _, A, C, mgl = gyroscope(0.0)
    up, down = np.array(tilted(0.3)), np.array(tilted(2.5))
    m3_fast, m3_slow = 300.0 * C, 20.0 * C
    return {
        # Lz - m3 = m2 g2 - m3 (1 - g3) = 1 % of m2 g2: the axis passes 3e-3 rad from upright
        "near the upward vertical": np.array(
            [0.0, 1.01 * m3_fast * (1.0 - up[2]) / up[1], m3_fast, *up]),
        # Lz + m3 = 1 % of m2 g2: 1e-3 rad from hanging straight down
        "near the downward vertical": np.array(
            [0.0, -1.01 * m3_slow * (1.0 + down[2]) / down[1], m3_slow, *down]),
        # upright and kicked (b = a exactly): through the vertical once per nutation period.
        # No azimuth at the start: phi(0) = 0 names the way the axis leaves, here -y in the
        # frame of initial_attitude (e3' = w x e3 = (0, -w1, 0)), so w1 > 0.
        "through the upward vertical": np.array([5.0 * A, 0.0, m3_fast, 0.0, 0.0, 1.0]),
        # no spin (a = b = 0): a planar pendulum, through the bottom, and over the top
        "pendulum": np.array([3.0 * A, 0.0, 0.0, *tilted(0.5)]),
        "pendulum over the top": np.array([30.0 * A, 0.0, 0.0, *tilted(0.5)]),
    }, A, C, mgl


PASSAGES, _A, _C, _MGL = _passages()


@pytest.mark.parametrize("name", list(PASSAGES))
def test_passages_near_and_through_the_vertical(name):
    """phi' is a spike (or phi jumps by pi) there; the figure axis stays smooth."""
    x0 = PASSAGES[name]
    t_end = 0.3
    sol = dop853_run(x0, _A, _C, _MGL, t_end, with_phi=False)
    t = np.linspace(0.0, t_end, 301)
    y = sol.sol(t)
    assert np.max(np.abs(cos_theta(t, x0, _A, _C, _MGL) - y[5])) < 1e-9
    figure_axis = y[7:16].reshape(3, 3, -1)[:, 2, :].T
    assert np.max(np.abs(figure_axis_path(t, x0, _A, _C, _MGL) - figure_axis)) < 1e-9
    assert_body_states_match(t, x0, _A, _C, _MGL, y)
    u1, u2, _ = nutation_roots(x0, _A, _C, _MGL)
    assert (u2 == 1.0) == (name in ("through the upward vertical", "pendulum over the top"))
    assert (u1 == -1.0) == name.startswith("pendulum")
    assert 0.0 < 1.0 - u2 < 1e-4 or 0.0 < 1.0 + u1 < 1e-4 or "near" not in name


def test_time_reversal():
    """Backwards in time from x0 = forwards from (-m, g): u(-t) and phi(-t) agree."""
    t = np.linspace(0.0, 0.7, 8)
    for name in ("loops", "falls over", "gyroscope 60 deg"):
        x0, A, C, mgl, _ = TOPS[name]
        back = np.concatenate([-x0[:3], x0[3:]])
        np.testing.assert_allclose(cos_theta(-t, x0, A, C, mgl), cos_theta(t, back, A, C, mgl),
                                   rtol=0.0, atol=1e-14)
        np.testing.assert_allclose(precession_angle(-t, x0, A, C, mgl),
                                   precession_angle(t, back, A, C, mgl), rtol=0.0, atol=1e-13)


def test_many_members_and_shapes():
    names = list(TOPS)[:5]  # same A, C, mgl
    _, A, C, mgl, _ = TOPS[names[0]]
    x = np.array([TOPS[n][0] for n in names])
    t = np.linspace(0.0, 0.3, 4)
    u = cos_theta(t, x, A, C, mgl)
    assert u.shape == (5, 4) and figure_axis_path(t, x, A, C, mgl).shape == (5, 4, 3)
    assert nutation_period(x, A, C, mgl).shape == (5,)
    for j, name in enumerate(names):
        np.testing.assert_array_equal(u[j], cos_theta(t, TOPS[name][0], A, C, mgl))
        assert precession_angle(0.3, TOPS[name][0], A, C, mgl) == precession_angle(
            t, x, A, C, mgl)[j, -1]
    with pytest.raises(ValueError, match="unit vector"):
        cos_theta(t, [0.0, 0.0, 1.0, 0.0, 0.0, 2.0], A, C, mgl)
    with pytest.raises(ValueError, match="shape"):
        nutation_period(np.zeros((2, 5)), A, C, mgl)
    with pytest.raises(ValueError, match="mgl"):
        nutation_period(x, A, C, -1.0)


def test_carlson_rj_matches_mpmath():
    rng = np.random.default_rng(5)
    mp.mp.dps = 30
    worst = 0.0
    for _ in range(300):
        x, y, z = rng.uniform(0.0, 2.0, 3) * 10.0 ** rng.uniform(-8.0, 1.0, 3)
        p = rng.uniform(0.0, 2.0) * 10.0 ** rng.uniform(-10.0, 3.0)
        ref = mp.elliprj(x, y, z, p)
        worst = max(worst, abs(float((carlson_rj(x, y, z, p) - ref) / ref)))
    complete = carlson_rj(0.0, 0.5, 1.0, 1e-9)
    worst = max(worst, abs(float((complete - mp.elliprj(0.0, 0.5, 1.0, 1e-9))
                                 / mp.elliprj(0.0, 0.5, 1.0, 1e-9))))
    assert worst < 2e-15


def test_the_worked_example_of_the_notes():
    """Disk top at w3 = 314 rad/s released at rest horizontally (the notes: W = 2.78 rad/s,
    w_n = 77.5 rad/s, 4.1 degrees), against references written out here.

    Released at rest at u = cos(theta) = 0, the energy and p_phi give
    u'^2 = f(u) = beta u (u - u2)(u - u3) with beta = 2 M g l / A, a = C w3 / A and u2, u3 the
    roots of beta u^2 - a^2 u - beta (Goldstein, section 5.7): u2 is the lowest point, the
    period is twice the integral of du / sqrt(f) from u2 to 0 and phi' = -a u / (1 - u^2),
    integrated by quadrature with the 1 / sqrt end-point weights. The fast-top values are
    M g l / (C w3), C w3 / A and 2 A M g l / (C w3)^2.
    """
    from scipy.integrate import quad

    w3 = 314.0
    x0 = tilted_starts(w3, np.pi / 2, 1, top=DISK)
    A, _, C = DISK.pivot_moments
    mgl = DISK.mgl
    a, beta = C * w3 / A, 2.0 * mgl / A
    u2, u3 = sorted(np.roots([beta, -a * a, -beta]).real)
    weight = {"weight": "alg", "wvar": (-0.5, -0.5), "epsabs": 0.0, "epsrel": 1e-13}

    def half_period_integral(g):  # integral of g(u) du / sqrt(f(u)) from u2 to 0
        return quad(lambda u: g(u) / np.sqrt(beta * (u3 - u)), u2, 0.0, **weight)[0]

    period = 2.0 * half_period_integral(lambda u: 1.0)
    precession = 2.0 * half_period_integral(lambda u: -a * u / (1.0 - u * u)) / period
    amplitude = np.degrees(np.arccos(u2) - np.pi / 2)
    assert exact_top.mean_precession_rate(x0, A, C, mgl)[0] == pytest.approx(precession,
                                                                              rel=1e-10)
    assert exact_top.nutation_period(x0, A, C, mgl)[0] == pytest.approx(period, rel=1e-10)
    u1_code, u2_code, _ = exact_top.nutation_roots(x0, A, C, mgl)
    assert np.degrees(np.arccos(u1_code) - np.arccos(u2_code))[0] == pytest.approx(
        amplitude, rel=1e-10)
    assert gyroscopic_precession_rate(DISK, w3) == pytest.approx(mgl / (C * w3), rel=1e-14)
    assert gyroscopic_nutation_frequency(DISK, w3) == pytest.approx(a, rel=1e-14)
    assert gyroscopic_nutation_amplitude(DISK, w3, np.pi / 2) == pytest.approx(
        2.0 * A * mgl / (C * w3) ** 2, rel=1e-14)
    # the notes' figures, at the notes' precision
    assert precession == pytest.approx(2.78, abs=0.015)
    assert 2.0 * np.pi / period == pytest.approx(77.5, abs=0.25)
    assert amplitude == pytest.approx(4.1, abs=0.05)
