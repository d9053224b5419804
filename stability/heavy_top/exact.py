"""The exact motion of the symmetric heavy top (Lagrange top): tilt, nutation and precession.

A symmetric top (I1 = I2 = A about the pivot, I3 = C) spins on a fixed pivot in uniform gravity,
its centre of mass on the body axis +e3 at distance l. A state is x = (m, g): m the body
angular momentum about the pivot, w = (m1/A, m2/A, m3/C), and g the body components of the unit
vector pointing up. The equations of motion ``m' = m x w + g x c``, c = (0, 0, M g l), and
``g' = g x w`` conserve E = m.w/2 + M g l g3, m3 and Lz = m.g. With u = cos(theta) = g3 they reduce
to one quadrature (Goldstein, *Classical Mechanics*, 3rd ed., section 5.7; Landau & Lifshitz,
*Mechanics*, section 35, problems 1 and 2):

    u'^2 = f(u) = (alpha - beta u)(1 - u^2) - (b - a u)^2,                      (1)
    alpha = 2 (E - m3^2 / (2 C)) / A,  beta = 2 M g l / A,  a = m3 / A,  b = Lz / A,
    phi' = (b - a u) / (1 - u^2),  psi' = m3 / C - phi' u,                       (2)

phi being the azimuth of the symmetry axis about the vertical (z-x-z Euler angles). f is a
cubic with roots u1 <= u0 <= u2 in [-1, 1] and u3 >= 1, and

    u(t) = u1 + (u2 - u1) sn^2(r0 + s t | m),  m = (u2 - u1)/(u3 - u1),  s = sqrt(beta (u3 - u1))/2,
                                                                                 (3)
(substitute (3) into (1): u'^2 = beta (u - u1)(u2 - u)(u3 - u) becomes sn'^2 = cn^2 dn^2), so the
nutation period is 2 K(m) / s. The precession (2) splits into (b - a)/(2 (1 - u)) +
(b + a)/(2 (1 + u)), and each part integrates in closed form to Legendre's third integral,
evaluated with Carlson's R_J (DLMF 19.25.14, 19.36.i): phi(t) - phi(0) needs no quadrature.
The spin angle likewise: phi' u = a + (b - a)/(2 (1 - u)) - (b + a)/(2 (1 + u)), so
psi(t) - psi(0) is (m3/C - a) t less phi's integral with its second term's sign turned; with
psi the state (m, g) itself follows in the body frame (:func:`body_states`).

Everything is computed about the initial point, without cancellation: with v = u - u0, the cubic
is f = beta v^3 + c2 v^2 + c1 v + c0 with coefficients read off the state,

    c0 = (g1 w2 - g2 w1)^2 = u'(0)^2,  c1 = 2 a Q - 2 P u0 - beta S,                     (4)
    c2 = 2 beta u0 - P - a^2,  P = w1^2 + w2^2 = alpha - beta u0,  S = g1^2 + g2^2 = 1 - u0^2,
    Q = w1 g1 + w2 g2 = b - a u0,

(derived from (1); checked numerically), so the turning-point distances u0 - u1 and u2 - u0 keep
full relative accuracy however small they are, a top released at a turning point
(u'(0) = 0) has u0 as an exact root, and m1 = 1 - m = (u3 - u2)/(u3 - u1) is formed directly. The
largest root is found as y3 = beta (u3 - u0) by Newton's method from Fujiwara's bound (monotone
for a cubic with real roots), which stays finite as beta -> 0; the two others follow from the
deflated quadratic (deflated from the constant term, the stable direction for removing the
largest root) and a Newton polish on f. At M g l = 0 (the free symmetric top) the same formulas
give m = 0, sn = sin, u3 = +inf and s = sqrt(w1^2 + w2^2 + a^2)/2 = L/(2A): no separate branch.

Degenerate starts, where u0 is a double root (u1 = u2 = u0; c0 = c1 = 0): steady precession, a
top spinning exactly upright (g = e3, w1 = w2 = 0: the sleeping top), or a top at rest. u stays
u0, phi' = Q/S (a/2 when upright, the limit of (2) along b = a) and the nutation period is the
small-oscillation limit pi/s, s = sqrt(-c2)/2, or inf where -c2 <= 0 (an upright top spinning
below the sleeping threshold C^2 w3^2 > 4 A M g l, where u3 < 1).

Through the vertical: where u2 = 1 (b = a; an upright top kicked sideways) or u1 = -1
(b = -a; a non-spinning top swinging as a planar pendulum) the axis passes through the pole, the
matching term of (2) is 0/0, and phi jumps by pi at each passage (the limit of near passages,
signed as b - a, resp. b + a; +pi when that is 0). The figure axis stays continuous. Near such a
passage 1 - u2 (or 1 + u1) is polished as the small root of f written about u = +-1, so a
passage 5e-10 from the pole keeps phi to round-off; what remains is the conditioning of
b -+ a = (b - a u0) -+ a (1 -+ u0) itself, a relative error eps |b - a u0| / |b -+ a|, which is
the effect of rounding the state. A start exactly upright or hanging (g = +-e3) has no
azimuth: phi(0) = 0 then names the direction in which the axis leaves the pole.

Accuracy (tests/heavy_top/test_exact.py): against DOP853 at rtol = 1e-12 on the 6-dim equations it
shows DOP853's own error (cos(theta) <= 3e-12, phi <= 3e-10 over 5-10 nutation periods, the
figure axis <= 3e-12 against the integrated attitude); against mpmath at 40-50 digits, the
roots, the period and the mean precession rate to a few 1e-16 relative and phi(t) to a few
1e-15 rad, passages near the pole included. Cost: a few microseconds per member to set up,
then O(1) per output time (one sncndn and at most two R_J), independent of t.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..util.checks import positive_float, real_array, real_number
from ..core.elliptic import carlson_rf, ellipk, sncndn_k

#: Slots of a member's parameter row (see :func:`_setup`).
(Q_U0, Q_V1, Q_V2, Q_Y3, Q_BETA, Q_RATE, Q_M, Q_M1, Q_K, Q_R0, Q_OMU1, Q_OMU2, Q_OPU1,
 Q_OPU2, Q_BMA, Q_BPA, Q_GK, Q_G0, Q_OMEGA, Q_JTOP, Q_JBOT) = range(21)
N_PARAMS = 21

#: Newton iterations allowed for the largest root; from Fujiwara's bound the iteration gains a
#: factor >= 3/2 per step while far (monotone for real roots) and then converges quadratically.
NEWTON_MAX_STEPS = 200
#: Carlson R_J duplication stops once 4^-n max|A0 - x_i| / |A_n| < (r/4)^(1/6), r = 2^-53:
#: the fifth-order series then has a relative truncation error below r (Carlson 1995, R_J).
RJ_SCALE = (0.25 * 2.0**-53) ** (-1.0 / 6.0)
RJ_MAX_STEPS = 60
#: |g| may differ from 1 by this much (a state from an integrator); it is then normalised.
G_UNIT_TOL = 1e-6


@njit(cache=True, error_model="numpy")
def _rc1(e, y):
    """R_C(1, y) for y = 1 + e > 0, both given (DLMF 19.2.19, 19.2.20).

    atan(sqrt e)/sqrt e for e > 0; for e < 0, atanh(r)/r with r = sqrt(-e), written as
    log((1 + r)/sqrt(y))/r when r > 1/2 so that y -> 0 loses nothing (1 - r = y/(1 + r)).
    """
    if e > 0.0:
        r = math.sqrt(e)
        return math.atan(r) / r
    if e < 0.0:
        r = math.sqrt(-e)
        if r <= 0.5:
            return math.atanh(r) / r
        return math.log((1.0 + r) / math.sqrt(y)) / r
    return 1.0


@njit(cache=True, error_model="numpy")
def carlson_rj(x, y, z, p):
    """Carlson's symmetric elliptic integral of the third kind R_J(x, y, z, p).

    Parameters
    ----------
    x, y, z : float
        >= 0, at most one of them 0.
    p : float
        > 0.

    Returns
    -------
    float
        R_J by the duplication algorithm with the fifth-order series (Carlson, Numer.
        Algorithms 10, 13 (1995), algorithm for R_J; DLMF 19.36.i), the R_C terms in closed form
        with 1 + e_n = 2 sqrt(p_n) (p_n + lambda_n) / d_n formed without cancellation (the
        textbook 1 + delta 4^-3n / d_n^2 loses digits as p -> 0). Relative error a few ulp
        (checked against mpmath for arguments over 18 decades). NaN for invalid input.
    """
    if not (x >= 0.0 and y >= 0.0 and z >= 0.0 and p > 0.0):
        return math.nan
    if (x == 0.0 and y == 0.0) or (y == 0.0 and z == 0.0) or (x == 0.0 and z == 0.0):
        return math.inf
    a0 = (x + y + z + 2.0 * p) / 5.0
    delta = (p - x) * (p - y) * (p - z)
    q = RJ_SCALE * max(abs(a0 - x), abs(a0 - y), abs(a0 - z), abs(a0 - p))
    a = a0
    xn, yn, zn, pn = x, y, z, p
    scale = 1.0  # 4^-n
    total = 0.0
    for _ in range(RJ_MAX_STEPS):
        if q * scale < abs(a):
            break
        sx, sy, sz, sp = math.sqrt(xn), math.sqrt(yn), math.sqrt(zn), math.sqrt(pn)
        lam = sx * (sy + sz) + sy * sz
        d = (sp + sx) * (sp + sy) * (sp + sz)
        e = scale * scale * scale * delta / (d * d)  # 4^-3n delta / d_n^2
        # 1 + e = 2 sqrt(p_n) (p_n + lambda_n) / d_n: the odd terms of d_n^2 + 4^-3n delta
        # cancel exactly, so 1 + e keeps full accuracy when p << x, y, z (e -> -1).
        y1 = 2.0 * sp * (pn + lam) / d
        total += scale * _rc1(e, y1) / d
        a = 0.25 * (a + lam)
        xn = 0.25 * (xn + lam)
        yn = 0.25 * (yn + lam)
        zn = 0.25 * (zn + lam)
        pn = 0.25 * (pn + lam)
        scale *= 0.25
    dx = (a0 - x) * scale / a
    dy = (a0 - y) * scale / a
    dz = (a0 - z) * scale / a
    dp = -0.5 * (dx + dy + dz)
    xyz = dx * dy * dz
    e2 = dx * dy + dx * dz + dy * dz - 3.0 * dp * dp
    e3 = xyz + 2.0 * e2 * dp + 4.0 * dp * dp * dp
    e4 = (2.0 * xyz + e2 * dp + 3.0 * dp * dp * dp) * dp
    e5 = xyz * dp * dp
    # Fifth-order series of R_J, Carlson (1995); DLMF 19.36.i.
    series = (1.0 - 3.0 * e2 / 14.0 + e3 / 6.0 + 9.0 * e2 * e2 / 88.0 - 3.0 * e4 / 22.0
              - 9.0 * e2 * e3 / 52.0 + 3.0 * e5 / 26.0)
    return scale * series / (a * math.sqrt(a)) + 6.0 * total


@njit(cache=True, error_model="numpy")
def _largest_root(c0, c1, c2, beta):
    """y3 = beta v3, the largest root of y^3 + c2 y^2 + beta c1 y + beta^2 c0 (beta^2 f(u0 + y/beta)).

    Newton from Fujiwara's bound 2 max(|c2|, |beta c1|^(1/2), |beta^2 c0 / 2|^(1/3)) (Fujiwara,
    Tohoku Math. J. 10, 167 (1916)); for a cubic with three real roots the iterates decrease
    monotonically to the largest root.
    """
    b1 = beta * c1
    b0 = beta * beta * c0
    y = 2.0 * max(abs(c2), math.sqrt(abs(b1)), (0.5 * abs(b0)) ** (1.0 / 3.0))
    if y == 0.0:
        return 0.0
    for _ in range(NEWTON_MAX_STEPS):
        qv = ((y + c2) * y + b1) * y + b0
        dq = (3.0 * y + 2.0 * c2) * y + b1
        if qv <= 0.0 or dq <= 0.0:
            break
        dy = qv / dq
        y -= dy
        if dy <= 2.2e-16 * abs(y):
            break
    return y


@njit(cache=True, error_model="numpy")
def _polish(v, c0, c1, c2, c3):
    """Up to three Newton steps on c0 + c1 v + c2 v^2 + c3 v^3, kept while |value| drops."""
    fv = ((c3 * v + c2) * v + c1) * v + c0
    for _ in range(3):
        df = (3.0 * c3 * v + 2.0 * c2) * v + c1
        if df == 0.0 or fv == 0.0:
            break
        w = v - fv / df
        fw = ((c3 * w + c2) * w + c1) * w + c0
        if not abs(fw) < abs(fv):
            break
        v, fv = w, fw
    return v


@njit(cache=True, error_model="numpy")
def _third_kind(r, sn, cn, dn, d21, lo, hi_at, sign):
    """lo times the integral over [0, r] of d sigma / (lo - sign d21 sn^2), |r| <= K.

    With n = sign d21 / lo this is Legendre's Pi(n; am r | m) = r + (n/3) sn^3 R_J(cn^2, dn^2,
    1, 1 - n sn^2) (DLMF 19.25.14). ``hi_at`` is lo - sign d21 sn^2 > 0 itself, formed without
    cancellation by the caller.
    """
    s3 = sn * sn * sn
    if s3 == 0.0:
        return r
    return r + sign * (d21 / (3.0 * lo)) * s3 * carlson_rj(cn * cn, dn * dn, 1.0, hi_at / lo)


@njit(cache=True, error_model="numpy")
def _precession_integral(r, sn, cn, dn, q):
    """G(r): the integral of phi' d sigma over [0, r], |r| <= K, for one member's row ``q``.

    phi' = (b - a)/(2 (1 - u)) + (b + a)/(2 (1 + u)) (eq. (2) in partial fractions), with
    1 - u = (1 - u2) + (u2 - u1) cn^2 and 1 + u = (1 + u1) + (u2 - u1) sn^2 (eq. (3)). A term
    whose denominator reaches 0 (u2 = 1, so b = a; or u1 = -1, b = -a: the axis passes through
    the vertical) is left out: its limit is a jump of phi by pi at each passage.
    """
    d21 = q[Q_V2] - q[Q_V1]
    g = 0.0
    if q[Q_BMA] != 0.0 and q[Q_OMU2] > 0.0:  # u2 = 1: jumps, see _unwrapped
        omu = q[Q_OMU2] + d21 * cn * cn
        g += (0.5 * q[Q_BMA] / q[Q_OMU1]) * _third_kind(
            r, sn, cn, dn, d21, q[Q_OMU1], omu, 1.0)
    if q[Q_BPA] != 0.0 and q[Q_OPU1] > 0.0:
        opu = q[Q_OPU1] + d21 * sn * sn
        g += (0.5 * q[Q_BPA] / q[Q_OPU1]) * _third_kind(
            r, sn, cn, dn, d21, q[Q_OPU1], opu, -1.0)
    return g


@njit(cache=True, error_model="numpy")
def _phase(row, t):
    """Half periods n and the reduced phase r in [-K, K] of r0 + s t, with sn, cn, dn of r."""
    K = row[Q_K]
    sigma = row[Q_R0] + row[Q_RATE] * t
    n = math.floor((sigma + K) / (2.0 * K))
    r = min(max(sigma - 2.0 * K * n, -K), K)
    sn, cn, dn = sncndn_k(r, row[Q_M], row[Q_M1], K)
    return n, r, sn, cn, dn


@njit(cache=True, error_model="numpy")
def _unwrapped(row, t):
    """s (phi(t) + const): whole half periods, G(r), and pi per passage through the vertical.

    Passages through u2 = 1 happen at r0 + s t = (2k + 1) K, through u1 = -1 at 2 k K; phi jumps
    there by pi, with the sign of b - a (or b + a), the limit of a near passage.
    """
    n, r, sn, cn, dn = _phase(row, t)
    n_bottom = n if r >= 0.0 else n - 1.0
    g = 2.0 * n * row[Q_GK] + _precession_integral(r, sn, cn, dn, row)
    if row[Q_JTOP] != 0.0 or row[Q_JBOT] != 0.0:
        g += row[Q_RATE] * (row[Q_JTOP] * n + row[Q_JBOT] * n_bottom)
    return g


@njit(cache=True, error_model="numpy")
def _setup(x, A, C, mgl, out):
    """Parameter row of each member (slots ``Q_*``) from its state ``x`` (N, 6), |g| = 1."""
    beta = 2.0 * mgl / A  # eq. (1)
    for j in range(x.shape[0]):
        w1 = x[j, 0] / A
        w2 = x[j, 1] / A
        a = x[j, 2] / A
        g1, g2, u0 = x[j, 3], x[j, 4], x[j, 5]
        # Eq. (4): the cubic about u0, coefficients from the state.
        P = w1 * w1 + w2 * w2
        S = g1 * g1 + g2 * g2
        Q = w1 * g1 + w2 * g2
        ud = g1 * w2 - g2 * w1
        c0 = ud * ud
        c1 = 2.0 * a * Q - 2.0 * P * u0 - beta * S
        c2 = 2.0 * beta * u0 - P - a * a
        hp = S / (1.0 + u0) if u0 > 0.0 else 1.0 - u0  # 1 - u0 without cancellation
        hm = S / (1.0 - u0) if u0 < 0.0 else 1.0 + u0  # 1 + u0
        row = out[j]
        row[:] = 0.0
        row[Q_U0] = u0
        row[Q_BETA] = beta
        row[Q_BMA] = Q - a * hp  # b - a = (b - a u0) - a (1 - u0)
        row[Q_BPA] = Q + a * hm  # b + a
        v1 = 0.0
        v2 = 0.0
        if c0 == 0.0 and c1 == 0.0:  # u0 a double root: f = v^2 (beta v + c2)
            y3 = -c2
        else:
            y3 = _largest_root(c0, c1, c2, beta)
            if y3 > 0.0:
                # Backward deflation: f = (y3 - beta v)(e2 v^2 + e1 v + e0), e2 ~ -1.
                e0 = c0 / y3
                e1 = (c1 + beta * e0) / y3
                e2 = (c2 + beta * e1) / y3
                disc = max(e1 * e1 - 4.0 * e2 * e0, 0.0)
                qq = -0.5 * (e1 + math.copysign(math.sqrt(disc), e1))
                if qq != 0.0 and e2 != 0.0:
                    ra = qq / e2
                    rb = e0 / qq
                    v1 = _polish(min(ra, rb), c0, c1, c2, beta)
                    v2 = _polish(max(ra, rb), c0, c1, c2, beta)
                v1 = min(max(v1, -hm), 0.0)
                v2 = max(min(v2, hp), 0.0)
        row[Q_V1] = v1
        row[Q_V2] = v2
        row[Q_Y3] = y3
        row[Q_OMU1] = hp - v1
        row[Q_OMU2] = max(hp - v2, 0.0)
        row[Q_OPU1] = max(hm + v1, 0.0)
        row[Q_OPU2] = hm + v2
        bma, bpa = row[Q_BMA], row[Q_BPA]
        if 0.0 < row[Q_OMU2] < 0.5 * hp:
            # u2 near the pole, 1 - u2 = hp - v2 has cancelled: polish it as the small root of
            # f(1 - w) = -(b - a)^2 + 2 (Pm - a (b - a)) w + (2 beta - Pm - a^2) w^2 - beta w^3,
            # Pm = alpha - beta = P - beta (1 - u0) (eq. (1) about u = 1).
            pm = P - beta * hp
            row[Q_OMU2] = max(_polish(row[Q_OMU2], -bma * bma, 2.0 * (pm - a * bma),
                                      2.0 * beta - pm - a * a, -beta), 0.0)
        if 0.0 < row[Q_OPU1] < 0.5 * hm:
            # likewise 1 + u1 = z: f(z - 1) = -(b + a)^2 + 2 (Pp + a (b + a)) z
            # - (Pp + 2 beta + a^2) z^2 + beta z^3, Pp = alpha + beta = P + beta (1 + u0).
            pp = P + beta * hm
            row[Q_OPU1] = max(_polish(row[Q_OPU1], -bpa * bpa, 2.0 * (pp + a * bpa),
                                      -(pp + 2.0 * beta + a * a), beta), 0.0)
        d21 = v2 - v1
        if d21 == 0.0 or not y3 > 0.0:  # u stays u0
            row[Q_V1] = 0.0
            row[Q_V2] = 0.0
            row[Q_RATE] = 0.5 * math.sqrt(y3) if y3 > 0.0 else 0.0
            row[Q_M] = 0.0
            row[Q_M1] = 1.0
            row[Q_K] = 0.5 * math.pi
            row[Q_OMEGA] = Q / S if S > 0.0 else 0.5 * a
            continue
        b31 = y3 - beta * v1  # beta (u3 - u1) > 0
        b32 = max(y3 - beta * v2, 0.0)  # beta (u3 - u2)
        m1 = b32 / b31
        K = ellipk(m1)
        row[Q_M] = beta * d21 / b31
        row[Q_M1] = m1
        row[Q_K] = K
        row[Q_RATE] = 0.5 * math.sqrt(b31)  # eq. (3)
        # Initial phase r0 in [-K, K]: sn^2 = (u0 - u1)/(u2 - u1), cn^2 = (u2 - u0)/(u2 - u1),
        # dn^2 = (u3 - u0)/(u3 - u1); sign(sn) = sign u'(0); F = sn R_F(cn^2, dn^2, 1).
        sn2 = -v1 / d21
        cn2 = v2 / d21
        dn2 = y3 / b31
        sn0 = math.sqrt(sn2)
        if ud < 0.0:
            sn0 = -sn0
        r0 = sn0 * carlson_rf(cn2, dn2, 1.0) if sn0 != 0.0 else 0.0
        row[Q_R0] = r0
        if row[Q_OMU2] == 0.0:  # u2 = 1: through the upward vertical once per period
            row[Q_JTOP] = math.copysign(math.pi, row[Q_BMA])
        if row[Q_OPU1] == 0.0:  # u1 = -1: through the downward vertical
            row[Q_JBOT] = math.copysign(math.pi, row[Q_BPA])
        # Half-period integral G(K): sn = 1, cn = 0, dn^2 = m1.
        row[Q_GK] = _precession_integral(K, 1.0, 0.0, math.sqrt(m1), row)
        # G at t = 0 evaluated exactly as _path does, so that phi(0) = 0 exactly.
        row[Q_G0] = _unwrapped(row, 0.0)
        row[Q_OMEGA] = row[Q_GK] / K + (row[Q_JTOP] + row[Q_JBOT]) * row[Q_RATE] / (2.0 * K)


@njit(cache=True, error_model="numpy")
def _path(q, t, want_phi, u_out, sin_out, phi_out):
    """cos(theta), sin(theta) and phi(t) - phi(0) of each member (rows ``q``) at times ``t``."""
    for j in range(q.shape[0]):
        row = q[j]
        v1, v2 = row[Q_V1], row[Q_V2]
        d21 = v2 - v1
        for i in range(t.shape[0]):
            if d21 == 0.0:
                u_out[j, i] = row[Q_U0]
                sin_out[j, i] = math.sqrt(row[Q_OMU2] * row[Q_OPU1])
                phi_out[j, i] = row[Q_OMEGA] * t[i] if want_phi else 0.0
                continue
            _, _, sn, cn, _ = _phase(row, t[i])
            sn2 = sn * sn
            cn2 = cn * cn
            u_out[j, i] = row[Q_U0] + (v1 * cn2 + v2 * sn2)  # eq. (3)
            sin_out[j, i] = math.sqrt((row[Q_OMU2] + d21 * cn2) * (row[Q_OPU1] + d21 * sn2))
            if want_phi:
                phi_out[j, i] = (_unwrapped(row, t[i]) - row[Q_G0]) / row[Q_RATE]


def _members(x0, A, C, mgl):
    """Validated parameter rows (N, N_PARAMS) and whether ``x0`` was a single state."""
    A = positive_float("A", A, "kg m2")
    C = positive_float("C", C, "kg m2")
    mgl = real_number("mgl", mgl, "N m")
    if not (math.isfinite(mgl) and mgl >= 0.0):
        raise ValueError(f"mgl must be finite and >= 0 (N m), got {mgl!r}")
    x = real_array("x0", x0)
    if x.ndim not in (1, 2) or x.shape[-1] != 6:
        raise ValueError(
            f"x0 must have shape (6,) or (N, 6) (m1, m2, m3, g1, g2, g3), got shape {x.shape}")
    if not np.all(np.isfinite(x)):
        raise ValueError("x0 must be finite")
    single = x.ndim == 1
    x = np.ascontiguousarray(np.atleast_2d(x))
    norm = np.sqrt(np.sum(x[:, 3:] ** 2, axis=1))
    if np.any(np.abs(norm - 1.0) > G_UNIT_TOL):
        bad = int(np.argmax(np.abs(norm - 1.0)))
        raise ValueError(
            f"g = x0[..., 3:6] must be a unit vector (body components of 'up'); member {bad} "
            f"has |g| = {norm[bad]!r}")
    x[:, 3:] /= norm[:, None]
    q = np.empty((x.shape[0], N_PARAMS))
    _setup(x, A, C, mgl, q)
    return q, single


def _times(t):
    t_arr = real_array("t", t, "s")
    if t_arr.ndim > 1:
        raise ValueError(f"t must be a number or have shape (T,), got shape {t_arr.shape}")
    if not np.all(np.isfinite(t_arr)):
        raise ValueError("t must be finite (times in s)")
    return np.ascontiguousarray(np.atleast_1d(t_arr)), t_arr.ndim == 0


def _evaluate(t, x0, A, C, mgl, want_phi):
    q, single = _members(x0, A, C, mgl)
    times, scalar_t = _times(t)
    shape = (q.shape[0], times.shape[0])
    u, sin_theta, phi = np.empty(shape), np.empty(shape), np.empty(shape)
    _path(q, times, want_phi, u, sin_theta, phi)
    index = (0 if single else slice(None), 0 if scalar_t else slice(None))
    return u[index], sin_theta[index], phi[index]


def _per_member(values, single):
    return float(values[0]) if single else values


def nutation_roots(x0, A, C, mgl):
    """Roots u1 <= u2 <= u3 of the cubic f(u) of eq. (1), the turning points of cos(theta).

    Parameters
    ----------
    x0 : array_like, shape (N, 6) or (6,)
        States (m1, m2, m3, g1, g2, g3): body angular momentum about the pivot (kg m2 s-1) and
        the body components of the unit vector pointing up (|g| = 1 to 1e-6; normalised).
    A, C : float
        Moments of inertia about a transverse axis through the pivot and about the symmetry
        axis (kg m2).
    mgl : float
        M g l >= 0 (N m), the centre of mass at distance l along +e3 from the pivot.

    Returns
    -------
    u1, u2, u3 : ndarray, shape (N,) (floats for a single state)
        -1 <= u1 <= g3 <= u2 <= 1 and u3 >= 1 (eq. (1)). u0 - u1 and u2 - u0 are
        computed directly (eq. (4)) with full relative accuracy; a top released at a turning
        point (u'(0) = 0) returns g3 exactly as a root. ``u3 = inf`` for mgl = 0 (the free
        symmetric top: f is then quadratic). u1 = u2 = g3 for a double root (steady precession,
        a top spinning exactly upright, rest); then u3 = g3 - c2 / beta is the third root, below
        1 for an upright top spinning under the sleeping threshold C^2 w3^2 < 4 A M g l.
    """
    q, single = _members(x0, A, C, mgl)
    u0, beta = q[:, Q_U0], q[:, Q_BETA]
    u1 = np.clip(u0 + q[:, Q_V1], -1.0, 1.0)
    u2 = np.clip(u0 + q[:, Q_V2], -1.0, 1.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        u3 = np.where(beta > 0.0, u0 + q[:, Q_Y3] / np.where(beta > 0.0, beta, 1.0), np.inf)
    return tuple(_per_member(r, single) for r in (u1, u2, u3))


def cos_theta(t, x0, A, C, mgl):
    """Exact cos(theta(t)) = g3(t), the cosine of the tilt of the symmetry axis from the vertical.

    Parameters
    ----------
    t : float or array_like, shape (T,)
        Times in s (any real values).
    x0, A, C, mgl
        States at t = 0 and the top, as in :func:`nutation_roots`.

    Returns
    -------
    ndarray, shape (N, T)
        u(t) = u1 + (u2 - u1) sn^2(r0 + s t | m) (eq. (3)), the phase r0 fixed
        by u(0) = g3 and the sign of u'(0) = (g x w)_3. The member axis is dropped for a single
        state, the time axis for a scalar ``t``. Absolute error a few ulp plus the phase's
        rounding, eps s |t| (u2 - u1).
    """
    return _evaluate(t, x0, A, C, mgl, False)[0]


def nutation_period(x0, A, C, mgl):
    """Exact nutation period: the time between successive minima of cos(theta).

    Parameters
    ----------
    x0, A, C, mgl
        As in :func:`nutation_roots`.

    Returns
    -------
    ndarray, shape (N,) (a float for a single state)
        T = 2 K(m) / s = 4 K(m) / sqrt(beta (u3 - u1)) in s (eq. (3)), K from k'^2 = m1 directly;
        2 pi A / L for mgl = 0. For a double root (steady precession, upright spin) the
        small-oscillation limit pi / s, s = sqrt(-c2)/2; ``inf`` where there is no oscillation
        (an upright top below the sleeping threshold, rest).
    """
    q, single = _members(x0, A, C, mgl)
    rate = q[:, Q_RATE]
    with np.errstate(divide="ignore"):
        period = np.where(rate > 0.0, 2.0 * q[:, Q_K] / np.where(rate > 0.0, rate, 1.0), np.inf)
    return _per_member(period, single)


def mean_precession_rate(x0, A, C, mgl):
    """Mean of phi' over one nutation period: the average precession rate of the figure axis.

    Parameters
    ----------
    x0, A, C, mgl
        As in :func:`nutation_roots`.

    Returns
    -------
    ndarray, shape (N,) (a float for a single state)
        In rad/s: G(K)/K with G(K) = sum over the partial fractions of eq. (2),
        (b -+ a)/(2 (1 -+ u1)) (K +- n/3 R_J(0, k'^2, 1, 1 -+ n)), n = (u2 - u1)/(1 -+ u1)
        (complete third integral, DLMF 19.25.14 at phi = pi/2), plus pi per period for each
        passage through the vertical. No quadrature: the error is that of R_J and K, a few ulp
        of each term (where phi' changes sign, the loops, the terms partly cancel and the
        error is a few ulp of their sum of magnitudes). Measured: <= 3e-15 relative against
        mpmath at 40 digits and against the trapezoid rule over a period (which converges
        exponentially for this smooth periodic phi'). Q/S for steady precession, a/2 = m3/(2A)
        (the limit) for an upright top.
    """
    q, single = _members(x0, A, C, mgl)
    return _per_member(q[:, Q_OMEGA].copy(), single)


def precession_angle(t, x0, A, C, mgl):
    """Exact phi(t) - phi(0): the angle the figure axis has turned about the vertical.

    Parameters
    ----------
    t : float or array_like, shape (T,)
        Times in s.
    x0, A, C, mgl
        As in :func:`nutation_roots`.

    Returns
    -------
    ndarray, shape (N, T)
        In rad, continuous (not wrapped): the integral of eq. (2) from 0 to t, as whole half
        periods times 2 G(K) plus the incomplete third integrals at both ends
        (Pi(n; am r | m) = r + n/3 sn^3 R_J(cn^2, dn^2, 1, 1 - n sn^2), DLMF 19.25.14), in
        closed form, plus a jump of pi at each passage through the vertical (module
        docstring). Error a few ulp of the terms plus the phase's rounding eps s |t|: within a
        few 1e-15 rad of mpmath at 40-50 digits (passages 5e-10 from the pole included), and
        1000 periods on, the increment is 1000 T times the mean rate to 2e-16 relative. The
        member axis is dropped for a single state, the time axis for a scalar ``t``.
    """
    return _evaluate(t, x0, A, C, mgl, True)[2]


def figure_axis_path(t, x0, A, C, mgl):
    """Exact unit vector along the symmetry axis in space coordinates (the figure axis path).

    Parameters
    ----------
    t : float or array_like, shape (T,)
        Times in s.
    x0, A, C, mgl
        As in :func:`nutation_roots`.

    Returns
    -------
    ndarray, shape (N, T, 3)
        (sin theta sin phi, -sin theta cos phi, cos theta) (z-x-z Euler angles, Goldstein
        section 4.4: the third column of the rotation), z up, with phi(0) = 0: the axis starts in
        the y-z plane at (0, -sin theta0, cos theta0). sin theta = sqrt((1 - u)(1 + u)) with both
        factors formed without cancellation; continuous through passages of the pole (module
        docstring). Draws the looping, cusped or wavy curves of a gyroscope.
    """
    u, sin_theta, phi = _evaluate(t, x0, A, C, mgl, True)
    return np.stack((sin_theta * np.sin(phi), -sin_theta * np.cos(phi), u), axis=-1)


@njit(cache=True, error_model="numpy")
def _spin_row(row):
    """The row whose precession integral is the spin's: psi - psi(0) = (m3/C - a) t - that.

    psi' = m3/C - phi' u (eq. (2)) and phi' u = a + (b - a)/(2 (1 - u)) - (b + a)/(2 (1 + u))
    (partial fractions): the row of phi with the sign of its (b + a) term turned, jumps at the
    downward vertical included; whole half periods and the value at t = 0 are evaluated anew.
    A double root (u = u0) keeps its constant rate: Q u0 / S - a with S = 1 - u0^2.
    """
    out = row.copy()
    out[Q_BPA] = -row[Q_BPA]
    out[Q_JBOT] = -row[Q_JBOT]
    if row[Q_V2] - row[Q_V1] == 0.0:
        s = row[Q_OMU2] * row[Q_OPU1]
        bma, bpa = row[Q_BMA], row[Q_BPA]
        # (b - a)/(2 (1 - u0)) - (b + a)/(2 (1 + u0)); nothing turns about an upright top
        out[Q_OMEGA] = 0.5 * (bma * row[Q_OPU1] - bpa * row[Q_OMU2]) / s if s > 0.0 else 0.0
        return out
    out[Q_GK] = _precession_integral(row[Q_K], 1.0, 0.0, math.sqrt(row[Q_M1]), out)
    out[Q_G0] = _unwrapped(out, 0.0)
    return out


@njit(cache=True, error_model="numpy")
def _body_path(q, x0, t, A, C, out):
    """States (m, g) in the body frame of each member (rows ``q``, starts ``x0``) at ``t``."""
    for j in range(q.shape[0]):
        row = q[j]
        a = x0[j, 2] / A
        spin = _spin_row(row)
        psi0 = math.atan2(x0[j, 3], x0[j, 4])
        q0 = (x0[j, 0] * x0[j, 3] + x0[j, 1] * x0[j, 4]) / A  # b - a u0
        v1, v2 = row[Q_V1], row[Q_V2]
        d21 = v2 - v1
        for i in range(t.shape[0]):
            if d21 == 0.0:
                dv = 0.0
                sin_theta = math.sqrt(row[Q_OMU2] * row[Q_OPU1])
                turned = spin[Q_OMEGA] * t[i]
                u_rate = 0.0
            else:
                _, _, sn, cn, dn = _phase(row, t[i])
                dv = v1 * cn * cn + v2 * sn * sn  # u - u0, eq. (3)
                sin_theta = math.sqrt((row[Q_OMU2] + d21 * cn * cn)
                                      * (row[Q_OPU1] + d21 * sn * sn))
                turned = (_unwrapped(spin, t[i]) - spin[Q_G0]) / spin[Q_RATE]
                u_rate = 2.0 * d21 * sn * cn * dn * row[Q_RATE]
            psi = psi0 + (x0[j, 2] / C - a) * t[i] - turned
            sp, cp = math.sin(psi), math.cos(psi)
            # Across the axis w = phi' sin(theta) (sin psi, cos psi) + theta' (cos psi, -sin psi)
            # with phi' sin^2(theta) = b - a u and theta' sin(theta) = -u'.
            if sin_theta > 0.0:
                along = (q0 - a * dv) / sin_theta
                tilt = -u_rate / sin_theta
            else:
                along = 0.0
                tilt = 0.0
            out[j, i, 0] = A * (along * sp + tilt * cp)
            out[j, i, 1] = A * (along * cp - tilt * sp)
            out[j, i, 2] = x0[j, 2]
            out[j, i, 3] = sin_theta * sp
            out[j, i, 4] = sin_theta * cp
            out[j, i, 5] = row[Q_U0] + dv


def body_states(t, x0, A, C, mgl):
    """Exact states (m, g) in the body frame: the heavy top scene's own state at times ``t``.

    Parameters
    ----------
    t : float or array_like, shape (T,)
        Times in s.
    x0, A, C, mgl
        As in :func:`nutation_roots` (``g`` is normalised).

    Returns
    -------
    ndarray, shape (N, T, 6)
        ``(m1, m2, m3, g1, g2, g3)``: with z-x-z Euler angles, g = (sin theta sin psi,
        sin theta cos psi, cos theta) and the body angular velocity across the axis
        w = phi' sin theta (sin psi, cos psi) + theta' (cos psi, -sin psi), m = (A w1, A w2, m3).
        The spin angle psi - psi(0) = (m3/C - m3/A) t minus the precession integral with the
        sign of its (b + a) term turned (psi' = m3/C - phi' u, eq. (2), in partial fractions),
        in closed form as phi's. Across the axis the components are divided by sin theta: a
        top passing within a small angle e of the vertical loses digits as 1/e, and at a time
        exactly on the pole they are set to 0. The member axis is dropped for a single state,
        the time axis for a scalar ``t``.
    """
    q, single = _members(x0, A, C, mgl)
    x = np.atleast_2d(np.asarray(x0, dtype=float))
    x = np.concatenate([x[:, :3], x[:, 3:] / np.linalg.norm(x[:, 3:], axis=1)[:, None]], axis=1)
    times, scalar_t = _times(t)
    out = np.empty((q.shape[0], times.shape[0], 6))
    _body_path(q, np.ascontiguousarray(x), times, float(A), float(C), out)
    index = (0 if single else slice(None), 0 if scalar_t else slice(None))
    return out[index]
