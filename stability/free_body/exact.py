"""The exact torque-free motion of a rigid body: body angular velocity from Jacobi functions.

Euler's equations ``I1 w1' = (I2 - I3) w2 w3`` (and cyclic) conserve the kinetic energy E and
L^2 = |I w|^2. In the canonical frame (I1 <= I2 <= I3, axis 2 intermediate) three
cancellation-free combinations of them decide the motion (literature.md section 1;
Landau & Lifshitz, *Mechanics*, section 37):

    D1 = L^2 - 2 E I1 = I2 (I2 - I1) w2^2 + I3 (I3 - I1) w3^2   >= 0
    D3 = 2 E I3 - L^2 = I1 (I3 - I1) w1^2 + I2 (I3 - I2) w2^2   >= 0
    D2 = L^2 - 2 E I2 = I1 (I1 - I2) w1^2 + I3 (I3 - I2) w3^2   (either sign)

- D2 > 0 ("major"): w circles the largest-moment axis 3, w3 keeps its sign s3:
  w = (a cn u, s3 b sn u, s3 c dn u), u = u0 + nu t, with a^2 = D3 / (I1 (I3 - I1)),
  b^2 = D3 / (I2 (I3 - I2)), c^2 = D1 / (I3 (I3 - I1)), nu^2 = (I3 - I2) D1 / (I1 I2 I3),
  m = k^2 = (I2 - I1) D3 / ((I3 - I2) D1), k'^2 = (I3 - I1) D2 / ((I3 - I2) D1).
- D2 < 0 ("minor"): w circles the smallest-moment axis 1, w1 keeps its sign s1:
  w = (s1 a dn u, s1 b sn u, c cn u), a^2 = D3 / (I1 (I3 - I1)), b^2 = D1 / (I2 (I2 - I1)),
  c^2 = D1 / (I3 (I3 - I1)), nu^2 = (I2 - I1) D3 / (I1 I2 I3), m = (I3 - I2) D1 / ((I2 - I1) D3),
  k'^2 = (I3 - I1) (-D2) / ((I2 - I1) D3).
- D2 = 0 (separatrix, one flip between -W e2 and +W e2; literature.md section 1.4):
  w = (s1 A sech u, W tanh u, s3 C sech u), u = u0 + s1 s3 lambda t, with independent signs
  s1, s3, A^2 = D3 / (I1 (I3 - I1)), C^2 = D1 / (I3 (I3 - I1)), W^2 = 2E / I2 and the growth rate
  lambda = W sqrt((I2 - I1)(I3 - I2) / (I1 I3)).
- Two equal moments: the component along the distinct axis is constant and the other two
  rotate uniformly (literature.md section 2.3); a sphere keeps w constant.

No initial phase u0 is ever formed: sn^2 u0 and cn^2 u0 are read off the state as ratios of
positive terms, and w(t) follows from Jacobi's addition theorem at u0 + nu t (DLMF 22.8), with
the products of amplitudes folded into Euler's own coefficients (see :func:`increment`). So
near the separatrix, where u0 = F(phi0|m) is ill-conditioned in phi0, nothing is lost, and for
short times the increment w(t) - w(0) comes out with a relative error of a few ulp, which is
what makes the ``exact`` method as accurate after 2000 steps as one evaluation. D2, whose two
terms cancel near the separatrix, is summed in double-double arithmetic (Dekker, Numer. Math.
18, 224 (1971)), so k'^2 keeps full relative accuracy for the given double inputs. The elliptic
functions are :mod:`stability.core.elliptic` (argument reduction that keeps k'^2 = 1e-15 at full
accuracy).

Accuracy (tests/free_body/test_exact.py): against mpmath at 40 digits near the separatrix (k'^2 <=
1e-12, times up to 6K/nu), <= 1.5e-14 relative to |w0|; against DOP853 at rtol = atol = 1e-12, the
integrator's own error (<= 9e-12 over |t| <= 20). Cost: O(1) per output time, independent of t: ~1
microsecond to set up, a fraction of that per time.

Sign conventions were checked against direct integration; the Celledoni et al. (2008) preprint
has a sign error in nu for its case (i) and forces s1 = s3 on the separatrix (Leroy, "On an
article by Celledoni et al.", Principia documentation), both avoided here.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..core.body import RigidBody, from_canonical, to_canonical
from ..util.checks import real_array, real_number, vectors3
from ..core.compensated import dd_add, dd_mul, two_prod, two_sum
from ..core.elliptic import ellipk, sncndn_k

#: Kinds of motion (canonical frame).
STEADY = 0  #: sphere, or w = 0: w constant
MAJOR = 1  #: D2 > 0: w circles axis 3 (largest moment); includes steady spin about axis 3
MINOR = 2  #: D2 < 0: w circles axis 1 (smallest moment); includes steady spin about axis 1
SEPARATRIX = 3  #: D2 = 0 with I1 < I2 < I3; includes steady spin about axis 2
PRECESS3 = 4  #: I1 = I2 < I3: w3 constant, (w1, w2) rotate at (I3 - I1) w3 / I1
PRECESS1 = 5  #: I1 < I2 = I3: w1 constant, (w2, w3) rotate at -(I2 - I1) w1 / I2

REGIME_NAMES = {
    STEADY: "sphere",
    MAJOR: "major",
    MINOR: "minor",
    SEPARATRIX: "separatrix",
    PRECESS3: "symmetric",
    PRECESS1: "symmetric",
}

#: Slots of the tuple returned by :func:`motion`.
Q_KIND, Q_RATE, Q_M, Q_M1, Q_K = 0, 1, 2, 3, 4

#: Components below 2^-500 of the largest are set to zero: their squares would underflow in D.
_FLUSH = 2.0**-500


@njit(cache=True, error_model="numpy")
def _hyperbolic_invariant(I1, I2, I3, w1, w2, w3):
    """D2 = I1 (I1 - I2) w1^2 + I3 (I3 - I2) w3^2 in double-double, rounded once."""
    dh, dl = two_sum(I1, -I2)
    ch, cl = dd_mul(dh, dl, I1, 0.0)
    sh, sl = two_prod(w1, w1)
    t1h, t1l = dd_mul(ch, cl, sh, sl)
    dh, dl = two_sum(I3, -I2)
    ch, cl = dd_mul(dh, dl, I3, 0.0)
    sh, sl = two_prod(w3, w3)
    t3h, t3l = dd_mul(ch, cl, sh, sl)
    h, lo = dd_add(t1h, t1l, t3h, t3l)
    return h + lo


@njit(cache=True, error_model="numpy")
def invariants(I1, I2, I3, w1, w2, w3):
    """The cancellation-free invariants (D1, D2, D3) of a state, canonical frame (module doc).

    Parameters
    ----------
    I1, I2, I3 : float
        Principal moments, I1 <= I2 <= I3 (kg m^2).
    w1, w2, w3 : float
        Body angular velocity, canonical frame (rad/s).

    Returns
    -------
    D1, D2, D3 : float
        ``L^2 - 2 E I1 >= 0``, ``L^2 - 2 E I2`` (summed in double-double, rounded once) and
        ``2 E I3 - L^2 >= 0``, in kg^2 m^4 s^-2.
    """
    D1 = I2 * (I2 - I1) * w2 * w2 + I3 * (I3 - I1) * w3 * w3
    D3 = I1 * (I3 - I1) * w1 * w1 + I2 * (I3 - I2) * w2 * w2
    return D1, _hyperbolic_invariant(I1, I2, I3, w1, w2, w3), D3


@njit(cache=True, error_model="numpy")
def motion(I1, I2, I3, w1, w2, w3):
    """Parameters of the exact motion through the state w at t = 0 (canonical frame).

    Parameters
    ----------
    I1, I2, I3 : float
        Principal moments, I1 <= I2 <= I3 (kg m^2).
    w1, w2, w3 : float
        Body angular velocity at t = 0 (rad/s).

    Returns
    -------
    tuple
        ``(kind, rate, m, m1, K, p0, p1, c1, c2, c3)``: the kind of motion (``MAJOR``,
        ``MINOR``, ``SEPARATRIX``, ``PRECESS3``, ``PRECESS1``, ``STEADY``); the phase rate
        (nu, s1 s3 lambda, or the precession rate, rad/s); the parameter m = k^2, its
        complement k'^2 and K(k). Then, for ``MAJOR``/``MINOR``: sn^2 u0, cn^2 u0 and the
        Euler coefficients (I3 - I2)/I1, (I3 - I1)/I2, (I2 - I1)/I3; for ``SEPARATRIX``: u0,
        unused, and the signed amplitudes s1 A, W, s3 C. Feed it to :func:`increment`.

    Notes
    -----
    Works on w scaled by a power of two (exact) so that no square over- or underflows;
    components below 2^-500 of the largest are treated as zero. Never raises, never allocates.
    """
    nan = math.nan
    inf = math.inf
    big = max(abs(w1), abs(w2), abs(w3))
    if big == 0.0 or I1 == I3:
        return STEADY, 0.0, nan, nan, nan, nan, nan, nan, nan, nan
    if I1 == I2:  # w3 constant, (w1, w2) rotate: literature.md 2.3
        return PRECESS3, (I3 - I1) * w3 / I1, 0.0, 1.0, 0.5 * math.pi, nan, nan, nan, nan, nan
    if I2 == I3:
        return PRECESS1, -(I2 - I1) * w1 / I2, 0.0, 1.0, 0.5 * math.pi, nan, nan, nan, nan, nan
    # Exact rescaling by powers of two: rates and amplitudes scale with w, nothing else changes.
    e_w = math.frexp(big)[1]
    sw = math.ldexp(1.0, -e_w)
    x1 = w1 * sw if abs(w1) >= _FLUSH * big else 0.0
    x2 = w2 * sw if abs(w2) >= _FLUSH * big else 0.0
    x3 = w3 * sw if abs(w3) >= _FLUSH * big else 0.0
    si = math.ldexp(1.0, -math.frexp(I3)[1])
    J1, J2, J3 = I1 * si, I2 * si, I3 * si
    D1, D2, D3 = invariants(J1, J2, J3, x1, x2, x3)
    up = math.ldexp(1.0, e_w)
    e1 = (I3 - I2) / I1
    e2 = (I3 - I1) / I2
    e3 = (I2 - I1) / I3

    if D2 > 0.0:  # literature.md 1.1; D1 > 0 here
        m1 = min((J3 - J1) * D2 / ((J3 - J2) * D1), 1.0)
        if m1 > 0.0:
            m = min((J2 - J1) * D3 / ((J3 - J2) * D1), 1.0)
            nu = math.sqrt((J3 - J2) * D1 / (J1 * J2 * J3)) * up
            if D3 == 0.0:  # steady spin about axis 3
                s0sq, c0sq = 0.0, 1.0
            else:
                s0sq = J2 * (J3 - J2) * x2 * x2 / D3  # sn^2 u0 = (w2 / b)^2
                c0sq = J1 * (J3 - J1) * x1 * x1 / D3  # cn^2 u0 = (w1 / a)^2
            return MAJOR, nu, m, m1, ellipk(m1), s0sq, c0sq, e1, e2, e3
    elif D2 < 0.0:  # literature.md 1.2; D3 > 0 here
        m1 = min((J3 - J1) * (-D2) / ((J2 - J1) * D3), 1.0)
        if m1 > 0.0:
            m = min((J3 - J2) * D1 / ((J2 - J1) * D3), 1.0)
            nu = math.sqrt((J2 - J1) * D3 / (J1 * J2 * J3)) * up
            if D1 == 0.0:  # steady spin about axis 1
                s0sq, c0sq = 0.0, 1.0
            else:
                s0sq = J2 * (J2 - J1) * x2 * x2 / D1  # sn^2 u0 = (w2 / b)^2
                c0sq = J3 * (J3 - J1) * x3 * x3 / D1  # cn^2 u0 = (w3 / c)^2
            return MINOR, nu, m, m1, ellipk(m1), s0sq, c0sq, e1, e2, e3

    # Separatrix (D2 = 0, or k'^2 below the smallest double): literature.md section 1.4.
    s1 = 1.0 if x1 >= 0.0 else -1.0
    s3 = 1.0 if x3 >= 0.0 else -1.0
    W = math.sqrt((D1 + D3) / (J2 * (J3 - J1)))  # sqrt(2E / I2): D1 + D3 = 2E (I3 - I1)
    lam = W * math.sqrt((J2 - J1) * (J3 - J2) / (J1 * J3))
    A = math.sqrt(D3 / (J1 * (J3 - J1)))
    C = math.sqrt(D1 / (J3 * (J3 - J1)))
    if x1 == 0.0 and x3 == 0.0:  # steady spin about axis 2
        u0 = inf if x2 > 0.0 else -inf
    elif x1 != 0.0:  # sinh u0 = tanh u0 / sech u0 = (w2 / W) / (|w1| / A)
        u0 = math.asinh(x2 * math.sqrt(D3 * J2 / (J1 * (D1 + D3))) / abs(x1))
    else:  # the same with |w3| / C
        u0 = math.asinh(x2 * math.sqrt(D1 * J2 / (J3 * (D1 + D3))) / abs(x3))
    return SEPARATRIX, s1 * s3 * lam * up, 1.0, 0.0, inf, u0, nan, s1 * A * up, W * up, s3 * C * up


@njit(cache=True, error_model="numpy")
def increment(q, w1, w2, w3, t):
    """w(t) - w(0) for the motion ``q = motion(I1, I2, I3, w1, w2, w3)`` through (w1, w2, w3).

    Computed as a difference that never cancels: for small t it has a relative error of a few
    ulp, so a step of the ``exact`` method keeps the compensated sum as accurate as its input;
    for any t the absolute error is a few ulp of |w|. Exactly 0 at t = 0.

    Parameters
    ----------
    q : tuple
        The motion, as :func:`motion` returns it for the same state.
    w1, w2, w3 : float
        Body angular velocity at t = 0, canonical frame (rad/s).
    t : float
        Time in s (any real value; negative runs the motion backwards).

    Returns
    -------
    d1, d2, d3 : float
        ``w(t) - w(0)``, canonical frame (rad/s).

    Notes
    -----
    Jacobi's addition theorem (DLMF 22.8.1-22.8.3) at u0 + v, v = nu t, with sn^2 u0 and cn^2 u0
    read off the state, so u0 is never formed. Dividing out the amplitudes turns the products of
    two components into Euler's own coefficients: in regime "major" (cn, sn, dn along axes
    1, 2, 3), with S, C, D = sn v, cn v, dn v, tau = S / nu and
    Delta = 1 - m sn^2 u0 S^2 = cn^2 u0 + sn^2 u0 D^2 (no cancellation),

        w1' = (w1 C - (I3 - I2)/I1 w2 w3 tau D) / Delta
        w2' = (w2 C D + (I3 - I1)/I2 w1 w3 tau) / Delta
        w3' = (w3 D - (I2 - I1)/I3 w1 w2 tau C) / Delta

    and in regime "minor" (dn, sn, cn) C and D trade places in the first and third lines. While
    Delta >= 1/2 (every step short of a quarter period) the increments are formed directly,
    with 1 - C = S^2 / (1 + C) (C >= 0), 1 - D = m S^2 / (1 + D) and 1 - Delta = m sn^2 u0 S^2;
    as t -> 0 they reduce to t times Euler's equations. For longer times w' is formed first
    (its terms are products, so it keeps an absolute error of a few ulp even where Delta ~ k'^2).
    """
    kind, rate, m, m1, K, p0, p1, c1, c2, c3 = q
    if t == 0.0 or kind == STEADY:
        return 0.0, 0.0, 0.0
    if kind == MAJOR or kind == MINOR:
        S, C, D = sncndn_k(rate * t, m, m1, K)
        tau = S / rate  # ~ t for short steps; multiplied in first, so w^2 never over/underflows
        S2 = S * S
        msq = m * p0 * S2  # 1 - Delta
        den = p1 + p0 * (D * D)  # Delta
        if kind == MAJOR:
            P1, Q1, P3, Q3 = C, D, D, C
        else:
            P1, Q1, P3, Q3 = D, C, C, D
        if msq > 0.5:  # far step: the new state directly, then the difference
            n1 = (w1 * P1 - c1 * (w2 * tau) * w3 * Q1) / den
            n2 = (w2 * C * D + c2 * (w1 * tau) * w3) / den
            n3 = (w3 * P3 - c3 * (w1 * tau) * w2 * Q3) / den
            return n1 - w1, n2 - w2, n3 - w3
        # Near step (Delta >= 1/2): P - Delta from 1 - C and 1 - D without cancellation.
        omc = S2 / (1.0 + C) if C >= 0.0 else 1.0 - C  # 1 - cn v
        omd = m * S2 / (1.0 + D)  # 1 - dn v
        q1 = msq - (omc if kind == MAJOR else omd)  # P1 - Delta
        q3 = msq - (omd if kind == MAJOR else omc)  # P3 - Delta
        d1 = (w1 * q1 - c1 * (w2 * tau) * w3 * Q1) / den
        d2 = (w2 * (msq - omc * D - omd) + c2 * (w1 * tau) * w3) / den
        d3 = (w3 * q3 - c3 * (w1 * tau) * w2 * Q3) / den
        return d1, d2, d3
    if kind == SEPARATRIX:
        u0 = p0
        if u0 - u0 != 0.0:  # steady spin about axis 2
            return 0.0, 0.0, 0.0
        v = rate * t
        u = u0 + v
        if abs(v) <= 1.0 and abs(u0) <= 20.0:
            # tanh u - tanh u0 = sinh v / (cosh u cosh u0);
            # sech u - sech u0 = -2 sinh(u0 + v/2) sinh(v/2) / (cosh u cosh u0).
            ch = math.cosh(u) * math.cosh(u0)
            dtanh = math.sinh(v) / ch
            dsech = -2.0 * math.sinh(u0 + 0.5 * v) * math.sinh(0.5 * v) / ch
        else:
            dtanh = math.tanh(u) - math.tanh(u0)
            dsech = 1.0 / math.cosh(u) - 1.0 / math.cosh(u0)
        return c1 * dsech, c2 * dtanh, c3 * dsech
    # Uniform precession by theta = rate t; cos(theta) - 1 = -2 sin^2(theta / 2).
    theta = rate * t
    sn = math.sin(theta)
    half = math.sin(0.5 * theta)
    cm1 = -2.0 * half * half
    if kind == PRECESS3:
        return w1 * cm1 - w2 * sn, w2 * cm1 + w1 * sn, 0.0
    return 0.0, w2 * cm1 - w3 * sn, w3 * cm1 + w2 * sn


@njit(cache=True, error_model="numpy")
def omega_at(q, w1, w2, w3, t):
    """w(t) for the motion ``q = motion(I1, I2, I3, w1, w2, w3)``; exactly (w1, w2, w3) at t = 0.

    Parameters
    ----------
    q : tuple
        The motion, as :func:`motion` returns it for the same state.
    w1, w2, w3 : float
        Body angular velocity at t = 0, canonical frame (rad/s).
    t : float
        Time in s (any real value; negative runs the motion backwards).

    Returns
    -------
    w1, w2, w3 : float
        w(t), canonical frame (rad/s).
    """
    d1, d2, d3 = increment(q, w1, w2, w3, t)
    return w1 + d1, w2 + d2, w3 + d3


@njit(cache=True, error_model="numpy")
def flow(I1, I2, I3, w1, w2, w3, t):
    """Exact flow of Euler's equations: w(t) from w(0) = (w1, w2, w3), canonical frame.

    Parameters
    ----------
    I1, I2, I3 : float
        Principal moments, I1 <= I2 <= I3 (kg m^2).
    w1, w2, w3 : float
        Body angular velocity at t = 0, canonical frame (rad/s).
    t : float
        Time in s.

    Returns
    -------
    w1, w2, w3 : float
        w(t), canonical frame (rad/s).
    """
    return omega_at(motion(I1, I2, I3, w1, w2, w3), w1, w2, w3, t)


@njit(cache=True, error_model="numpy")
def flow_increment(I1, I2, I3, w1, w2, w3, t):
    """w(t) - w(0) of the exact flow from (w1, w2, w3), canonical frame (see :func:`increment`).

    Parameters
    ----------
    I1, I2, I3 : float
        Principal moments, I1 <= I2 <= I3 (kg m^2).
    w1, w2, w3 : float
        Body angular velocity at t = 0, canonical frame (rad/s).
    t : float
        Time in s.

    Returns
    -------
    d1, d2, d3 : float
        ``w(t) - w(0)``, canonical frame (rad/s).
    """
    return increment(motion(I1, I2, I3, w1, w2, w3), w1, w2, w3, t)


@njit(cache=True, error_model="numpy")
def omega_many(I1, I2, I3, w1, w2, w3, t, out):
    """w at many times of one exact motion, canonical frame, written into ``out``.

    The compiled loop behind :func:`exact_omega` and the exact attitude
    (:mod:`stability.free_body.exact_attitude`): :func:`motion` once, then :func:`omega_at` per
    time.

    Parameters
    ----------
    I1, I2, I3 : float
        Principal moments, I1 <= I2 <= I3 (kg m^2).
    w1, w2, w3 : float
        Body angular velocity at t = 0, canonical frame (rad/s).
    t : ndarray, shape (n,)
        Times in s.
    out : ndarray, shape (n, 3)
        Receives w at each time, canonical frame (rad/s).
    """
    q = motion(I1, I2, I3, w1, w2, w3)
    for i in range(t.shape[0]):
        out[i, 0], out[i, 1], out[i, 2] = omega_at(q, w1, w2, w3, t[i])


# ---------------------------------------------------------------------------------------------
# Python layer: validation and the user's axis order.


@njit(cache=True, error_model="numpy")
def _final_many(I1, I2, I3, w, t, out):
    """w(t) of each canonical start ``w`` (N, 3) at one time t: :func:`omega_many` per start."""
    for j in range(w.shape[0]):
        q = motion(I1, I2, I3, w[j, 0], w[j, 1], w[j, 2])
        out[j, 0], out[j, 1], out[j, 2] = omega_at(q, w[j, 0], w[j, 1], w[j, 2], t)


def exact_omega_of_starts(body: RigidBody, w0, t) -> np.ndarray:
    """:func:`exact_omega` at one time ``t`` for many starts ``w0`` (N, 3); shape (N, 3).

    One compiled loop over the starts, bitwise what :func:`exact_omega` gives for each.

    Parameters
    ----------
    body : RigidBody
        Moments in any order.
    w0 : array_like, shape (N, 3)
        Angular velocities at t = 0 along the body's axes 1, 2, 3 (rad/s); one start of
        shape (3,) is taken as (1, 3).
    t : float
        Time in s, finite.

    Returns
    -------
    ndarray, shape (N, 3)
        w(t) of each start in rad/s, body axes in the caller's order.

    Raises
    ------
    ValueError
        If ``body`` is not a RigidBody, ``w0`` is not of shape (N, 3) or ``t`` is not finite.
    """
    if not isinstance(body, RigidBody):
        raise ValueError(f"body must be a stability.RigidBody, got {type(body).__name__}")
    w0 = np.atleast_2d(vectors3("w0", w0, "rad/s"))
    t = real_number("t", t, "s")
    if not math.isfinite(t):
        raise ValueError(f"t must be a finite time in s, got {t!r}")
    perm, signs = body.canonical_frame()
    I1, I2, I3 = (float(x) for x in body.moments[perm])
    out = np.empty((w0.shape[0], 3))
    _final_many(I1, I2, I3, np.ascontiguousarray(to_canonical(w0, perm, signs)), t, out)
    return from_canonical(out, perm, signs)


def _canonical_state(body, w0):
    if not isinstance(body, RigidBody):
        raise ValueError(f"body must be a stability.RigidBody, got {type(body).__name__}")
    w0 = vectors3("w0", w0, "rad/s")
    if w0.ndim != 1:
        raise ValueError(
            f"w0 must have shape (3,) (one initial angular velocity), got shape {w0.shape}"
        )
    perm, signs = body.canonical_frame()
    moments = body.moments[perm]
    return moments, to_canonical(w0, perm, signs), perm, signs


def exact_omega(body: RigidBody, w0, t) -> np.ndarray:
    """Exact body-frame angular velocity of the torque-free body at times ``t``.

    Parameters
    ----------
    body : RigidBody
        Moments in any order.
    w0 : array_like, shape (3,)
        Angular velocity at t = 0 along the body's axes 1, 2, 3 (rad/s).
    t : float or array_like, shape (n,)
        Times in s; any real values (negative times run the motion backwards).

    Returns
    -------
    ndarray, shape (n, 3) (or (3,) for a scalar ``t``)
        w(t) in rad/s, body axes in the caller's order. ``w0`` itself (bit for bit) where t = 0.

    Notes
    -----
    Landau & Lifshitz section 37 with cancellation-free invariants; see the module docstring for
    the formulas, the regimes and the accuracy. Cost O(1) per time after a set-up of a few
    microseconds, independent of t. Use it as the reference trajectory for integrators.
    """
    moments, w, perm, signs = _canonical_state(body, w0)
    t_arr = real_array("t", t, "s")
    scalar = t_arr.ndim == 0
    t_arr = np.ascontiguousarray(np.atleast_1d(t_arr))
    if t_arr.ndim != 1:
        raise ValueError(f"t must be a number or have shape (n,), got shape {t_arr.shape}")
    if not np.all(np.isfinite(t_arr)):
        raise ValueError("t must be finite (times in s)")
    out = np.empty((t_arr.shape[0], 3))
    omega_many(*moments, *w, t_arr, out)
    result = from_canonical(out, perm, signs)
    return result[0] if scalar else result


def _summary(body, w0):
    moments, w, _, _ = _canonical_state(body, w0)
    q = motion(*moments, *w)
    return moments, w, q


def regime(body: RigidBody, w0) -> str:
    """Kind of torque-free motion that starts at ``w0``.

    Parameters
    ----------
    body : RigidBody
        Moments in any order.
    w0 : array_like, shape (3,)
        Angular velocity at t = 0 along the body's axes 1, 2, 3 (rad/s).

    Returns
    -------
    str
        ``"major"`` (L^2 > 2 E I2: w circles the axis of the largest moment; steady spin about
        it included), ``"minor"`` (L^2 < 2 E I2: w circles the smallest-moment axis),
        ``"separatrix"`` (L^2 = 2 E I2 for three distinct moments: one flip, or steady spin
        about the intermediate axis), ``"symmetric"`` (two equal moments: uniform precession
        about the distinct axis), ``"sphere"``, or ``"rest"`` for w0 = 0.
    """
    _, w, q = _summary(body, w0)
    if not np.any(w):
        return "rest"
    return REGIME_NAMES[int(q[Q_KIND])]


def elliptic_parameters(body: RigidBody, w0) -> tuple[float, float]:
    """The parameter m = k^2 of the Jacobi functions and its complement k'^2 = 1 - m.

    k'^2 is computed as (I3 - I1) |D2| / ((I3 - I2) D1) (or with (I2 - I1) D3 below the
    separatrix), D2 summed in double-double, so it keeps full relative accuracy near the
    separatrix where 1 - k^2 would be all rounding error. Returns (1, 0) on the separatrix,
    (0, 1) for symmetric bodies, and (nan, nan) for a sphere.

    Parameters
    ----------
    body : RigidBody
        Moments in any order.
    w0 : array_like, shape (3,)
        Angular velocity at t = 0 along the body's axes 1, 2, 3 (rad/s).

    Returns
    -------
    m, m1 : float
        k^2 and k'^2 (dimensionless).
    """
    q = _summary(body, w0)[2]
    return float(q[Q_M]), float(q[Q_M1])


def elliptic_frequency(body: RigidBody, w0) -> float:
    """Rate nu (rad/s) of the Jacobi argument u = u0 + nu t.

    On the separatrix, the rate lambda of the tanh/sech solution (the linear growth rate about
    the intermediate axis at spin W = sqrt(2E / I2)); for a symmetric body, |(I3 - I1) w3 / I1|
    (I1 = I2) or |(I2 - I1) w1 / I2| (I2 = I3), the precession rate; 0 for a sphere.

    Parameters
    ----------
    body : RigidBody
        Moments in any order.
    w0 : array_like, shape (3,)
        Angular velocity at t = 0 along the body's axes 1, 2, 3 (rad/s).

    Returns
    -------
    float
        The rate in rad/s, >= 0.
    """
    return abs(float(_summary(body, w0)[2][Q_RATE]))


def flip_interval(body: RigidBody, w0) -> float:
    """Time between consecutive sign changes of the intermediate-axis component of w: 2K / nu.

    In both regimes the component of w along the axis of the *intermediate* moment goes as
    sn(u0 + nu t) and changes sign every 2K/nu (literature.md section 1.5); so does the
    component along the smallest-moment axis (regime "major") or the largest-moment axis
    (regime "minor"), while the component along the circled axis keeps its sign. One tennis
    racket flip (+e2 -> -e2) takes 2K/nu; the motion repeats after :func:`full_period` =
    4K/nu, which contains two flips.

    Parameters
    ----------
    body : RigidBody
        Moments in any order.
    w0 : array_like, shape (3,)
        Angular velocity along the body's axes, rad/s.

    Returns
    -------
    float
        2K/nu in s. ``inf`` on the separatrix (a single flip; also for steady spin about the
        intermediate axis) and for a sphere. For steady spin about the smallest or largest axis
        the value is the limit of nearby motions, pi / Omega (half the small-oscillation
        period). For a symmetric body (two equal moments) it is pi / |precession rate|: the time
        between sign changes of each component in the equal-moment plane (``inf`` when w lies
        in that plane, a steady spin; for spin about the distinct axis, the limit again).
    """
    _, _, q = _summary(body, w0)
    kind, rate, K = int(q[Q_KIND]), abs(float(q[Q_RATE])), float(q[Q_K])
    if kind in (STEADY, SEPARATRIX) or rate == 0.0:
        return math.inf
    return 2.0 * K / rate


@njit(cache=True, error_model="numpy")
def _flip_many(I1, I2, I3, w, out):
    """2K/nu, its asymptote (2/lambda) ln(4/k') and k' for each canonical start ``w`` (N, 3).

    The arithmetic of :func:`flip_interval`, :func:`flip_interval_asymptote` and
    :func:`elliptic_parameters`, member by member.
    """
    for j in range(w.shape[0]):
        w1, w2, w3 = w[j, 0], w[j, 1], w[j, 2]
        q = motion(I1, I2, I3, w1, w2, w3)
        kind, rate, m1, K = int(q[Q_KIND]), abs(q[Q_RATE]), q[Q_M1], q[Q_K]
        out[j, 0] = math.inf if (kind == STEADY or kind == SEPARATRIX or rate == 0.0) else (
            2.0 * K / rate)
        if kind == SEPARATRIX:
            out[j, 1] = math.inf
        elif kind == MAJOR or kind == MINOR:
            energy2 = (I1 * w1) * w1 + (I2 * w2) * w2 + (I3 * w3) * w3
            lam = math.sqrt(energy2 / I2) * math.sqrt((I2 - I1) * (I3 - I2) / (I1 * I3))
            out[j, 1] = (2.0 / lam) * math.log(4.0 / math.sqrt(m1))
        else:
            out[j, 1] = math.nan
        out[j, 2] = math.sqrt(m1)


def flip_intervals(body: RigidBody, w0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`flip_interval`, :func:`flip_interval_asymptote` and k' for many starts at once.

    Parameters
    ----------
    body : RigidBody
    w0 : array_like, shape (N, 3)
        Starts, body frame, rad/s.

    Returns
    -------
    exact, asymptote, kprime : ndarray, shape (N,)
        2K/nu (s), (2/lambda) ln(4/k') (s) and the complementary modulus k' of each start,
        bitwise what the one-start functions give (compiled loop over the starts).
    """
    if not isinstance(body, RigidBody):
        raise ValueError(f"body must be a stability.RigidBody, got {type(body).__name__}")
    w0 = vectors3("w0", w0, "rad/s")
    w0 = np.atleast_2d(w0)
    perm, signs = body.canonical_frame()
    I1, I2, I3 = (float(x) for x in body.moments[perm])
    out = np.empty((w0.shape[0], 3))
    _flip_many(I1, I2, I3, np.ascontiguousarray(to_canonical(w0, perm, signs)), out)
    return out[:, 0], out[:, 1], out[:, 2]


def full_period(body: RigidBody, w0) -> float:
    """Period of w(t): 4K / nu = 2 x :func:`flip_interval` (two flips, +e2 -> -e2 -> +e2).

    Many texts call this "the Dzhanibekov period"; the time of one flip is
    :func:`flip_interval`. ``inf`` on the separatrix and for a sphere; 2 pi / |precession rate|
    for a symmetric body (``inf`` for steady spin in its equal-moment plane).

    Parameters
    ----------
    body : RigidBody
        Moments in any order.
    w0 : array_like, shape (3,)
        Angular velocity along the body's axes, rad/s.

    Returns
    -------
    float
        4K/nu in s.
    """
    return 2.0 * flip_interval(body, w0)


def flip_interval_asymptote(body: RigidBody, w0) -> float:
    """Leading-order flip interval near the separatrix: (2 / lambda) ln(4 / k').

    From K = ln(4/k') + O(k'^2 ln k') (Abramowitz & Stegun 17.3.26; DLMF 19.12.1) and
    nu -> lambda as k' -> 0 (literature.md section 1.5), with lambda = W sqrt((I2 - I1)(I3 - I2)
    / (I1 I3)) at W = sqrt(2E / I2), axes sorted, and the exact k'^2 of the state. Its relative
    error is O(k'^2): for I = (1, 2, 3) and w0 = (1e-2, 1, 0) (k'^2 = 1e-4) it gives 20.754696
    against 2K/nu = 20.754610 (4e-6). (The 20.755042 of literature.md 1.5 is the same formula
    with the leading-order k' = eps and W = 1.) ``inf`` on the separatrix, like
    :func:`flip_interval`.

    Parameters
    ----------
    body : RigidBody
        Moments in any order.
    w0 : array_like, shape (3,)
        Angular velocity at t = 0 along the body's axes 1, 2, 3 (rad/s).

    Returns
    -------
    float
        Time in s; ``nan`` for a body with two equal moments.
    """
    moments, w, q = _summary(body, w0)
    kind, m1 = int(q[Q_KIND]), float(q[Q_M1])
    if kind not in (MAJOR, MINOR, SEPARATRIX):
        return math.nan
    if kind == SEPARATRIX:
        return math.inf
    I1, I2, I3 = moments
    energy2 = float(np.sum(moments * w * w))  # 2E
    lam = math.sqrt(energy2 / I2) * math.sqrt((I2 - I1) * (I3 - I2) / (I1 * I3))
    return (2.0 / lam) * math.log(4.0 / math.sqrt(m1))
