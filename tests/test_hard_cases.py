"""Hard cases for every registered method: each with its expected outcome, asserted.

- A start exactly on the separatrix (D2 = 0 to the last bit) follows the tanh/sech closed form
  through its single flip.
- Flip times for epsilon = 1e-2 ... 1e-12 against the exact 2K/nu. The first sign change of w2
  (at K/nu, reached from the start by exponential growth out of the saddle) is well conditioned
  at every epsilon; the later ones are not once the method's error in D2 = L^2 - 2 E I2 through
  one flip is comparable to D2 = -eps^2 (literature notes 1.5 and 2.2: dT/dD2 = -1/(nu D2)), and
  then no accuracy is demanded of them.
- epsilon = 0 on each principal axis, the intermediate one included: the spin stays put.
- Nearly symmetric (I2 - I1 = 1e-12 I3) and exactly symmetric bodies, and the sphere.
- Extreme shapes: a needle (I3 / I1 = 1e4) and a flat plate on the triangle edge I1 + I2 = I3.
- Fast spin (1e4 rad/s) over long horizons, with |L| and energy held to each method's bound
  (``INVARIANT_BOUNDS``, one row per method).
- A step far too large: flagged per member, never returned as numbers.

Accuracy bounds are stated in terms of the dimensionless step ``h * rate`` (rate: the fastest
angular rate of the motion) and the horizon ``rate * T``: a method of order p must reach a relative
error <= ``(h rate)^p (1 + rate T)`` (``order_bound``), which any sound implementation beats by
orders of magnitude and any wrong one (a sign, a lost term, a failed solve) misses by far.
"""

import math

import numpy as np
import pytest

import stability
from stability.util import conventions as cv
from stability.free_body.model import invariant_differences
from stability.free_body.propagate import propagate
from stability.free_body.exact import elliptic_frequency

ALL = list(stability.METHODS)
FINITE = [name for name, spec in stability.METHODS.items() if not spec.is_exact]

#: Relative round-off allowance of one evaluation of the exact solution or a few steps.
ROUNDOFF = 1e-13


# --------------------------------------------------------------------------------- references


def exact_w(body, w0, t):
    """The exact w at times ``t`` (n,) from ``w0`` (3,); shape (n, 3)."""
    t = np.atleast_1d(np.asarray(t, dtype=float))
    return stability.exact_omega(body, np.asarray(w0, float), t)


def flip_interval(body, w0):
    """2K/nu: the time between sign changes of the intermediate component (s)."""
    return stability.flip_interval(body, np.asarray(w0, float))


def separatrix_w(moments, w0, t):
    """The tanh/sech solution on the separatrix D2 = 0 (literature notes 1.4), sorted moments.

    w1 = s1 A sech u, w2 = W tanh u, w3 = s3 C sech u, u = u0 + s1 s3 lambda t,
    u0 = artanh(w2(0) / W), W = sqrt(2E / I2), lambda = W sqrt((I2 - I1)(I3 - I2) / (I1 I3)).
    """
    I1, I2, I3 = moments
    w0 = np.asarray(w0, float)
    two_e = float(np.sum(moments * w0 * w0))
    W = math.sqrt(two_e / I2)
    A = math.sqrt(two_e * (I3 - I2) / (I1 * (I3 - I1)))
    C = math.sqrt(two_e * (I2 - I1) / (I3 * (I3 - I1)))
    lam = W * math.sqrt((I2 - I1) * (I3 - I2) / (I1 * I3))
    s1, s3 = math.copysign(1.0, w0[0]), math.copysign(1.0, w0[2])
    u = math.atanh(w0[1] / W) + s1 * s3 * lam * np.asarray(t, float)
    sech = 1.0 / np.cosh(u)
    return np.column_stack([s1 * A * sech, W * np.tanh(u), s3 * C * sech]), lam


def order_bound(name, h_rate, rate_t):
    """Relative error a method of the registry must beat at step ``h_rate`` over ``rate_t``."""
    spec = stability.METHODS[name]
    truncation = 0.0 if spec.is_exact else h_rate**spec.order
    return (truncation + ROUNDOFF) * (1.0 + rate_t)


def run_w(name, body, w0, h, n_steps, save_every=0, **kwargs):
    """propagate() in w: returns (w_final (N, 3), saved w (N, S, 3), the Propagation)."""
    moments = body.moments
    run = propagate(name, moments, moments * np.atleast_2d(w0), h, n_steps,
                    save_every=save_every, progress=False, **kwargs)
    return run.m_final / moments, run.saved / moments, run


def relative(a, b):
    return np.linalg.norm(np.asarray(a) - np.asarray(b), axis=-1) / np.linalg.norm(b, axis=-1)


# --------------------------------------------------------------------------------- separatrix

#: A physical body whose separatrix has rational slope: I1 (I2 - I1) = I3 (I3 - I2) = 6, so
#: w0 = (e, w2, e) has D2 = I1 (I1 - I2) e^2 + I3 (I3 - I2) e^2 = -6 e^2 + 6 e^2 = 0 exactly in
#: floating point, whatever e and w2.
SEPARATRIX_BODY = stability.RigidBody(2.0, 5.0, 6.0)
E_SEP = 0.125  # exact in binary
#: (s1, s3): all four sign pairs; w2(0) = -s1 s3 so that the motion heads through w2 = 0.
SIGN_PAIRS = [(1, 1), (-1, -1), (1, -1), (-1, 1)]


def separatrix_start(s1, s3):
    return np.array([s1 * E_SEP, -s1 * s3 * 1.0, s3 * E_SEP])


@pytest.mark.parametrize("s1, s3", SIGN_PAIRS)
def test_separatrix_start_is_exactly_on_the_separatrix(s1, s3):
    """D2 = 0 to the last bit, and the exact solution is the tanh/sech closed form."""
    w0 = separatrix_start(s1, s3)
    assert invariant_differences(SEPARATRIX_BODY, w0).D2 == 0.0
    t = np.linspace(0.0, 12.0, 61)
    closed, _ = separatrix_w(SEPARATRIX_BODY.moments, w0, t)
    np.testing.assert_allclose(exact_w(SEPARATRIX_BODY, w0, t), closed, rtol=0, atol=1e-12)


@pytest.mark.parametrize("s1, s3", SIGN_PAIRS)
@pytest.mark.parametrize("name", ALL)
def test_separatrix_start_follows_the_closed_form_through_its_flip(name, s1, s3):
    """From an exact separatrix start, w2 goes from -W through 0 towards +W (or the mirror):
    exactly one flip at t = -u0 / (s1 s3 lambda), the whole path within the order bound."""
    body = SEPARATRIX_BODY
    w0 = separatrix_start(s1, s3)
    h, n = 0.005, 2400  # t = 12 s: the flip near 5 s, then most of the way to the saddle
    _, saved, run = run_w(name, body, w0, h, n, save_every=10)
    assert np.all(run.status == cv.STATUS_OK)
    t = h * 10 * np.arange(1, saved.shape[1] + 1)
    closed, lam = separatrix_w(body.moments, w0, t)
    rate = float(np.linalg.norm(w0))
    error = relative(saved[0], closed).max()
    assert error <= order_bound(name, h * rate, rate * t[-1]), f"{name}: {error:.2e}"
    flips = np.flatnonzero(np.signbit(saved[0, 1:, 1]) != np.signbit(saved[0, :-1, 1]))
    assert flips.size == 1
    t_flip = -math.atanh(w0[1] / math.sqrt(np.sum(body.moments * w0**2) / body.I2)) / (
        s1 * s3 * lam
    )
    assert t[flips[0]] <= t_flip <= t[flips[0] + 1]


# -------------------------------------------------------------------------- flip times vs eps

FLIP_BODY = stability.RigidBody(1.0, 2.0, 3.0)
EPSILONS = np.array([1e-2, 1e-3, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12])
#: Roundings of the state that a run may accumulate through one flip (a random walk over a few
#: thousand steps, with margin): the allowance on the one-rounding sensitivity of the interval.
ROUNDINGS = 1e3
#: A later flip is demanded to match 2K/nu where the change of D2 made by the run moves the
#: interval by less than this fraction of itself.
WELL_CONDITIONED = 0.05
#: Relative accuracy demanded of a flip time beyond the method's phase error: the crossing is
#: found by linear interpolation between steps (error O(h^3), w2'' = 0 at the crossing).
CROSSING_TOL = 1e-6


def rounding_sensitivity(body, w0):
    """|T(D2 + u L^2) - T(D2)| / T: the interval's change when one rounding (u = 2^-53) of
    L^2 - 2 E I2 is added to D2, by moving w3 from 0 to sqrt(u L^2 / (I3 (I3 - I2)))."""
    I1, I2, I3 = body.moments
    w0 = np.asarray(w0, float)
    nudged = w0.copy()
    nudged[2] = math.sqrt(2.0**-53 * np.sum((body.moments * w0) ** 2) / (I3 * (I3 - I2)))
    t = flip_interval(body, w0)
    return abs(flip_interval(body, nudged) - t) / t


@pytest.fixture(scope="module")
def eps_starts():
    """Starts (eps, 1, 0): D2 = -eps^2 exactly, spin 1 rad/s about the intermediate axis; their
    exact flip intervals and the sensitivity of those to one rounding of D2."""
    w0 = np.zeros((EPSILONS.size, 3))
    w0[:, 0] = EPSILONS
    w0[:, 1] = 1.0
    intervals = np.array([flip_interval(FLIP_BODY, w) for w in w0])
    sensitivity = np.array([rounding_sensitivity(FLIP_BODY, w) for w in w0])
    return w0, intervals, sensitivity


def test_where_the_flip_interval_is_ill_conditioned(eps_starts):
    """For I = (1, 2, 3) and spin 1 rad/s: one rounding of D2 moves 2K/nu by ~1.5e-5 of itself
    at eps = 1e-6 but by ~3e-2 at eps = 1e-8 (dT/dD2 = -1/(nu D2), D2 = -eps^2): the interval is
    well conditioned for eps >= 1e-6 and ill-conditioned for eps <= 1e-8 (literature notes 1.5,
    where DOP853 runs scatter at eps = 1e-6 already)."""
    _, _, sensitivity = eps_starts
    well = ROUNDINGS * sensitivity < WELL_CONDITIONED
    np.testing.assert_array_equal(well, EPSILONS >= 1e-6)
    assert 1e-5 < sensitivity[EPSILONS == 1e-6][0] < 2e-5
    assert 2e-2 < sensitivity[EPSILONS == 1e-8][0] < 4e-2


@pytest.mark.parametrize("name", ALL)
def test_flip_times_against_2K_over_nu(name, eps_starts):
    """First flip at K/nu for every epsilon; later flips every 2K/nu where well conditioned.

    The start (eps, 1, 0) is the turning point nearest +e2 (u0 = K), so w2 first changes sign
    at t = K/nu. That time is set by the growth out of the saddle, where the state's errors are
    relative to its small perpendicular part, and by the method's phase error (relative
    O(h^p)): it is demanded at every epsilon down to 1e-12.

    Each later flip passes the saddle again at a distance set by D2 = L^2 - 2 E I2, which the
    run has changed by dD2 (its roundings far from the saddle, ~1e-17 L^2 and more, see
    ``test_where_the_flip_interval_is_ill_conditioned``, plus the method's own truncation: about
    1e-11 for rkmk4 at h = 0.01, below round-off for rk4), so the interval moves by
    dD2 / (nu |D2|). dD2 is measured at the run's closest approach to the saddle after the first
    flip. Where the predicted shift is below ``WELL_CONDITIONED`` of the interval, the mean
    interval must match 2K/nu within three times it (plus the phase error); where it exceeds
    the interval itself, no accuracy is demanded, and the interval saturates instead: the run
    passes the saddle farther out than |D2| = eps^2 says, so it flips sooner than 2K/nu.
    """
    w0, intervals, _ = eps_starts
    spec = stability.METHODS[name]
    h, save_every = 0.01, 10
    n = int(round(2.6 * intervals.max() / h))  # at least three sign changes for every member
    _, saved, run = run_w(name, FLIP_BODY, w0, h, n, save_every=save_every, track_axis=1)
    assert np.all(run.status == cv.STATUS_OK)
    first = run.extras["first_axis_crossing"]
    count = run.extras["axis_crossings"]
    mean_interval = (run.extras["last_axis_crossing"] - first) / (count - 1)

    phase = 0.0 if spec.is_exact else (h * 1.0) ** spec.order
    np.testing.assert_allclose(first, intervals / 2, rtol=phase + CROSSING_TOL, atol=0)

    t = h * save_every * np.arange(1, saved.shape[1] + 1)
    amplitude = np.where(t > first[:, None], np.hypot(saved[..., 0], saved[..., 2]), np.inf)
    closest = np.argmin(amplitude, axis=1)
    d2_0 = invariant_differences(FLIP_BODY, w0).D2
    d2 = invariant_differences(FLIP_BODY, saved[np.arange(len(w0)), closest]).D2
    nu = np.array([elliptic_frequency(FLIP_BODY, w) for w in w0])
    shift = np.abs(d2 - d2_0) / (nu * np.abs(d2_0)) / intervals  # relative, predicted
    assert np.all(count >= 3)
    well = shift < WELL_CONDITIONED
    assert well[EPSILONS >= 1e-4].all(), f"{name}: predicted shifts {shift}"
    error = mean_interval / intervals - 1.0
    tol = phase + CROSSING_TOL + 3.0 * shift
    assert np.all(np.abs(error[well]) <= tol[well]), f"{name}: {error[well]} > {tol[well]}"
    ill = shift > 1.0
    assert ill[EPSILONS <= 1e-10].all(), f"{name}: predicted shifts {shift}"
    assert np.all(mean_interval[ill] < intervals[ill])


# ------------------------------------------------------------------------ spin about an axis


@pytest.mark.parametrize("axis", [1, 2, 3])
@pytest.mark.parametrize("name", ALL)
def test_spin_exactly_about_a_principal_axis_stays_put(name, axis):
    """epsilon = 0: w x Iw vanishes exactly, so every method keeps w to round-off.

    The intermediate axis is the sharp case: over t = 200 s a stray 1e-300 in a perpendicular
    component would grow by e^(lambda t) ~ 1e50 and show. Moments are given unsorted and the
    spin negative, so the canonical frame's signed permutation is exercised too.
    """
    body = stability.RigidBody(3.0, 1.0, 2.0)  # intermediate moment on body axis 3
    w0 = np.zeros(3)
    w0[axis - 1] = -2.0
    w_end, _, run = run_w(name, body, w0, 0.02, 10_000)
    assert np.all(run.status == cv.STATUS_OK)
    np.testing.assert_allclose(w_end[0], w0, rtol=0, atol=4 * np.spacing(2.0))


# ----------------------------------------------------------------------- (nearly) symmetric

SYMMETRIC_W0 = np.array([0.6, 0.8, 0.5])


@pytest.mark.parametrize("name", ALL)
def test_nearly_symmetric_body(name):
    """I2 - I1 = 1e-12 I3: no cancellation in the kernels, so the motion is the symmetric top's
    up to 1e-12 (w3 constant, (w1, w2) turning at (I3 - I1) w3 / I1), and each method stays
    within its order bound of the exact solution. The symmetric-top + residual splittings are
    exact up to the asymmetry there (their splitting error is proportional to I2 - I1)."""
    body = stability.RigidBody(1.0, 1.0 + 2e-12, 2.0)
    h, n = 0.02, 1000
    t_end = h * n
    w_end, saved, run = run_w(name, body, SYMMETRIC_W0, h, n, save_every=50)
    assert np.all(run.status == cv.STATUS_OK)
    reference = exact_w(body, SYMMETRIC_W0, [t_end])[0]
    rate = float(np.linalg.norm(SYMMETRIC_W0))
    error = relative(w_end[0], reference)
    assert error <= order_bound(name, h * rate, rate * t_end)
    assert np.abs(saved[0, :, 2] - SYMMETRIC_W0[2]).max() <= 1e-11 + rate * order_bound(
        name, h * rate, rate * t_end)
    spec = stability.METHODS[name]
    if spec.family == "Lie-Poisson splitting":
        assert error <= 1e-10


def symmetric_top(w0, moments, t):
    """I1 = I2: w3 constant, w1 + i w2 turning at +(I3 - I1) w3 / I1 (ERRATA 3)."""
    rate = (moments[2] - moments[0]) * w0[2] / moments[0]
    z = (w0[0] + 1j * w0[1]) * np.exp(1j * rate * np.asarray(t))
    return np.column_stack([z.real, z.imag, np.full(np.size(t), w0[2])]), rate


@pytest.mark.parametrize("name", ALL)
def test_symmetric_body_precesses_uniformly(name):
    """I1 = I2: w3 constant, uniform precession of (w1, w2) at (I3 - I1) w3 / I1.

    w3 is constant to round-off for the methods whose update of m3 carries the factor
    I1 - I2 = 0 (Runge-Kutta, the splittings, the Moser-Veselov and midpoint maps, the exact
    flow); a Lie-group method (rkmk4) rotates m about an axis that is only O(h^p) close to w
    and keeps w3 to its truncation error."""
    body = stability.RigidBody(1.0, 1.0, 1.5)
    h, n = 0.02, 1000
    _, saved, run = run_w(name, body, SYMMETRIC_W0, h, n, save_every=50)
    assert np.all(run.status == cv.STATUS_OK)
    t = h * 50 * np.arange(1, saved.shape[1] + 1)
    expected, rate = symmetric_top(SYMMETRIC_W0, body.moments, t)
    spin = float(np.linalg.norm(SYMMETRIC_W0))
    bound = order_bound(name, h * spin, spin * t[-1])
    assert np.abs(saved[0, :, 2] / SYMMETRIC_W0[2] - 1.0).max() <= bound
    error = relative(saved[0], expected).max()
    assert error <= bound


@pytest.mark.parametrize("name", ALL)
def test_sphere_keeps_w_constant(name):
    """I1 = I2 = I3: w x Iw = 0, so w stays where it started: exactly for the methods whose
    increments carry the differences of the moments, to a random walk of roundings (2000
    steps: ~1e-15) for a Lie-group method that rotates m about itself (rkmk4)."""
    body = stability.RigidBody(2.0, 2.0, 2.0)
    w_end, _, run = run_w(name, body, SYMMETRIC_W0, 0.05, 2000)
    assert np.all(run.status == cv.STATUS_OK)
    np.testing.assert_allclose(w_end[0], SYMMETRIC_W0, rtol=0, atol=1e-14)


# ------------------------------------------------------------------------------ extreme shapes

#: name: (body, start, step): a needle spinning fast about its long axis and slowly tumbling
#: (I3 / I1 = 1e4, every energy term comparable), and a flat plate (I1 + I2 = I3 exactly:
#: J3 = (I1 + I2 - I3) / 2 = 0 in the Moser-Veselov form) tumbling near its intermediate axis.
SHAPES = {
    "needle": (stability.RigidBody(1e-4, 0.99995, 1.0), np.array([50.0, 0.4, 0.3]), 2e-4),
    "flat plate": (stability.RigidBody(0.25, 0.75, 1.0), np.array([0.3, 1.0, 0.4]), 0.01),
}


@pytest.mark.parametrize("shape", list(SHAPES))
@pytest.mark.parametrize("name", ALL)
def test_extreme_shapes(name, shape):
    """Every method runs the extreme shapes without failure, within its order bound."""
    body, w0, h = SHAPES[shape]
    n = 2000
    w_end, _, run = run_w(name, body, w0, h, n)
    assert np.all(run.status == cv.STATUS_OK)
    reference = exact_w(body, w0, [h * n])[0]
    rate = float(np.max(np.abs(w0)))
    error = relative(w_end[0], reference)
    assert error <= order_bound(name, h * rate, rate * h * n), f"{name}, {shape}: {error:.2e}"


# ------------------------------------------------------------------ fast spin, long horizons

#: Invariant bounds over the long fast-spin run: relative |L| error and relative energy error
#: at the end, for I = (1, 2, 3), |w| = 1e4 rad/s, h |w| = 0.05, one row per method, set a few
#: times above the measured values (in brackets). Steps: 1e7 for the cheap explicit methods,
#: fewer for costly ones. Poisson splittings keep |L| to round-off and their energy error
#: bounded at O((h |w|)^p) (lp6 and lp8 are at round-off already); rk4 and rkmk4 drift
#: linearly; the methods that keep E and |L| do so to round-off. A method missing here gets a
#: row from its declared properties (``invariant_bounds``).
INVARIANT_BOUNDS = {
    #  name         steps        |L| bound  energy bound    measured |L|, energy
    "rk4": (10_000_000, 1e-4, 3e-4),  # 4.4e-5, 1.2e-4 (linear drift)
    "lp2": (10_000_000, 1e-14, 1e-4),  # 7.8e-16, 2.0e-5 (bounded)
    "lp4": (1_000_000, 1e-14, 1e-9),  # 2.2e-16, 1.1e-10
    "lp6": (1_000_000, 1e-14, 1e-13),  # 1.1e-15, 1.2e-14
    "lp8": (300_000, 1e-14, 1e-13),  # 0, 4.4e-16
    "dmv": (1_000_000, 1e-14, 1e-14),  # 1.1e-16, 6.7e-16
    "dmv4": (1_000_000, 1e-13, 1e-13),  # 4.2e-15, 1.1e-14
    "lgvi": (1_000_000, 1e-14, 1e-14),  # 1.1e-16, 2.6e-15
    "midpoint": (1_000_000, 1e-14, 1e-14),  # 4.4e-16, 1.1e-15
    "rkmk4": (1_000_000, 1e-14, 3e-4),  # 4.4e-16, 1.9e-4 (linear drift)
    "exact": (1_000_000, 1e-13, 1e-13),  # 1.1e-15, 8.9e-15
}


def invariant_bounds(name):
    """(steps, |L| bound, energy bound) from the table, or from the method's declarations."""
    if name in INVARIANT_BOUNDS:
        return INVARIANT_BOUNDS[name]
    spec = stability.METHODS[name]
    steps = 1_000_000
    roundoff = 1e-13
    truncation = 0.05**spec.order if not spec.is_exact else 0.0
    drift = truncation * 0.05 * steps  # linear in the number of steps
    bound_l = roundoff if spec.preserves_casimir else drift + roundoff
    if spec.preserves_energy:
        bound_e = roundoff
    elif spec.poisson:
        bound_e = truncation + roundoff
    else:
        bound_e = drift + roundoff
    return steps, bound_l, bound_e


@pytest.mark.parametrize("name", ALL)
def test_fast_spin_long_horizon_keeps_invariants(name):
    """|w| = 1e4 rad/s with h |w| = 0.05 (nothing in the kernels may assume |w| ~ 1): |L| and
    energy stay within the method's bound from INVARIANT_BOUNDS after its steps."""
    steps, bound_l, bound_e = invariant_bounds(name)
    body = stability.RigidBody(1.0, 2.0, 3.0)
    spin = 1e4
    w0 = spin * np.array([0.3, 1.0, 0.9]) / np.linalg.norm([0.3, 1.0, 0.9])
    w_end, _, run = run_w(name, body, w0, 0.05 / spin, steps)
    assert np.all(run.status == cv.STATUS_OK)
    m0, m1 = body.moments * w0, body.moments * w_end[0]
    error_l = abs(np.linalg.norm(m1) / np.linalg.norm(m0) - 1.0)
    error_e = abs(np.dot(m1, w_end[0]) / np.dot(m0, w0) - 1.0)
    assert error_l <= bound_l, f"{name}: |L| error {error_l:.2e} > {bound_l:.0e}"
    assert error_e <= bound_e, f"{name}: energy error {error_e:.2e} > {bound_e:.0e}"


# --------------------------------------------------------------------------- step too large


@pytest.mark.parametrize("name", ALL)
def test_step_far_too_large_is_flagged_not_returned(name):
    """h |w| = 50: no method may return such a step as a plausible number.

    - Explicit methods that do not keep |L| blow up: every member is flagged non-finite, and
      its numbers are masked (``run_ensemble``: every float variable NaN; ``integrate``: NaN
      after the failure), never returned as the overflowed values.
    - Explicit methods that keep |L| (rotations) stay finite with |L| exact, but their energy is
      scrambled: a member whose energy error exceeds the divergence tolerance is flagged
      diverged (nearly all of them), the rest step_too_large, all masked: none is ok.
    - ``run_ensemble`` labels ok no member at such a step, whatever the method (an extra slow
      member, inside every method's bound, keeps the run from being refused and stays ok).
    - Implicit methods either report non-convergence (status 3) or, where the solve converged,
      return a step that keeps what they declare to keep (E and |L| to the solver tolerance).
    - The exact flow is exact at any step.
    """
    spec = stability.METHODS[name]
    body = stability.RigidBody(1.0, 2.0, 3.0)
    rng = np.random.default_rng(5)
    w0 = rng.standard_normal((64, 3))
    h = 50.0 / np.linalg.norm(w0, axis=1).max()
    n = 40
    w_end, _, run = run_w(name, body, w0, h, n)
    m0, m1 = body.moments * w0, body.moments * w_end
    error_l = np.abs(np.linalg.norm(m1, axis=1) / np.linalg.norm(m0, axis=1) - 1.0)
    error_e = np.abs(np.sum(m1 * w_end, axis=1) / np.sum(m0 * w0, axis=1) - 1.0)
    ok = run.status == cv.STATUS_OK
    slow = w0[:1] * 0.1 / (h * np.linalg.norm(body.moments * w0[0]))  # h max|w| < 0.1 rad
    ds = stability.run_ensemble(body, 2, starts=np.vstack([w0, slow]), h=h, t_end=n * h,
                                method=name, keep=stability.Keep(save_every=n),
                                options=stability.RunOptions(progress=False))
    assert ds.status.values[-1] == cv.STATUS_OK
    ds = ds.isel(member=slice(0, -1))
    flagged = ds.status.values != cv.STATUS_OK
    assert flagged.all()
    for var in ("w", "energy_error", "angular_momentum_error", "max_perp_amplitude"):
        assert np.isnan(ds[var].values[flagged]).all(), var
    if spec.is_exact:
        assert ok.all()  # exact states, but events between steps 50 rad apart are not resolved
        assert np.all(ds.status.values == cv.STATUS_STEP_TOO_LARGE)
        reference = np.array([exact_w(body, w, [n * h])[0] for w in w0])
        assert relative(w_end, reference).max() <= 1e-10
    elif spec.implicit:
        assert set(np.unique(run.status)) <= {cv.STATUS_OK, cv.STATUS_NOT_CONVERGED}
        assert np.all(error_l[ok] <= 1e-12)
        if spec.preserves_energy:
            assert np.all(error_e[ok] <= 1e-12)
        assert np.all(ds.status.values[ok] == cv.STATUS_STEP_TOO_LARGE)
        assert np.all(ds.status.values[~ok] == cv.STATUS_NOT_CONVERGED)
    elif spec.preserves_casimir:
        assert ok.all() and np.all(np.isfinite(w_end))
        assert error_l.max() <= 1e-13
        tolerance = 1e-2  # run_ensemble's default divergence tolerance
        diverged = ds.status.values == cv.STATUS_DIVERGED
        np.testing.assert_array_equal(diverged, error_e > tolerance)
        assert np.all(ds.status.values[~diverged] == cv.STATUS_STEP_TOO_LARGE)
        assert diverged.mean() > 0.9
    else:
        assert np.all(run.status == cv.STATUS_NONFINITE)
        assert np.all(ds.status.values == cv.STATUS_NONFINITE)
        one = stability.integrate(body, w0[0], n * h, h, method=name)
        assert one.attrs["status"] == "non_finite"
        assert np.isnan(one.w.values[-1]).all()
        assert np.all(np.isfinite(one.w.values) | np.isnan(one.w.values))
