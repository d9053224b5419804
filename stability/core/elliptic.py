"""Jacobi elliptic functions and elliptic integrals of the first kind, in Numba.

Every function takes the parameter ``m = k^2`` and, where it matters, its complement
``m1 = k'^2 = 1 - m`` as a separate input, so a caller that knows k'^2 without cancellation
(the exact solution of Euler's equations does) keeps that accuracy: near the separatrix of the
free rigid body, m1 is 1e-12 or smaller and ``1 - m`` would have no correct digit left. Nothing
here ever forms ``1 - m``.

- ``ellipk(m1)``: the complete integral K, from the arithmetic-geometric mean of 1 and
  k' = sqrt(m1): K = pi / (2 AGM(1, k')) (DLMF 19.8.5). Relative error ~1 ulp; K = inf at m1 = 0.
- ``carlson_rf(x, y, z)``: Carlson's symmetric integral R_F by the duplication algorithm
  (Carlson, Numer. Algorithms 10, 13 (1995); DLMF 19.36.i). Relative error a few ulp.
- ``ellipf(phi, m, m1)``: the incomplete integral F(phi|m) = sin(phi) R_F(cos^2 phi,
  1 - m sin^2 phi, 1) for |phi| <= pi/2 (DLMF 19.25.5), extended by F(phi + n pi) = F(phi) + 2nK;
  the middle argument is formed as cos^2 phi + m1 sin^2 phi when m > 1/2 (no cancellation).
- ``sncndn(u, m, m1)``: sn, cn, dn. The argument is reduced with the quarter period K
  (DLMF 22.4.iii, 22.17: period 4K in sn and cn, sn(u + 2K) = -sn u, cn(u + 2K) = -cn u,
  dn(u + 2K) = dn u, sn(2K - u) = sn u, cn(2K - u) = -cn u) to 0 <= u <= K; on K/2 < u <= K the
  complementary forms sn(K - v) = cn v / dn v, cn(K - v) = k' sn v / dn v, dn(K - v) = k' / dn v
  (DLMF 22.4.iii) bring it to 0 <= v <= K/2. There Bulirsch's descending Gauss transformation
  (Bulirsch, Numer. Math. 7, 78 (1965), procedure ``sncndn``; Press et al., Numerical Recipes,
  2nd ed., section 6.11) runs on k' alone. On [0, K/2] the final phase pi v / (2K) is at most
  pi/4 and every quantity of the backward recurrence is positive, so sn, cn and dn come out with
  a relative error of a few ulp, even at m1 = 1e-15 where cn and dn are ~1e-4 at K/2 and ~3e-8
  at K. The absolute error is a few ulp plus the argument's own rounding (ulp(u) times a
  derivative bounded by 1): measured against mpmath for m1 from 1 down to 1e-15 and
  |u| <= 10 K, it stays below eps (1 + |u|).

scipy's ``ellipj`` is not used: for m1 < 1e-9 it switches to an approximation that is valid
only below K and returns errors of order 1e6 past it (scipy documentation; checked in
``shared/notes/literature.md``, section 1.6). Here m1 may be anything in [0, 1]; m1 = 0 gives
sn = tanh, cn = dn = sech (DLMF 22.5.ii) and K = inf.

The kernels are ``njit(cache=True)`` scalar functions (no allocation, no exceptions; invalid
input gives NaN), safe to call from parallel loops. ``sncndn_many`` evaluates an array.
"""

import math

import numpy as np
from numba import njit

#: Stop the AGM when |a - b| <= AGM_TOL a; the next mean (a + b)/2 then differs from the limit by
#: (a - b)^2 / (16 a) <= 3.5e-18 a, below half an ulp (quadratic convergence, DLMF 19.8.1).
AGM_TOL = 2.0**-27
#: Hard cap on AGM steps; m1 down to 1e-300 needs ~16 (the loop halves log(a/b) until a ~ b).
AGM_MAX_STEPS = 40
#: Below this m1 (k' < 1e-16), sn = tanh u, cn = dn = sech u on 0 <= u <= K/2 to a relative
#: error <= k'/4 < 3e-17 (first-order terms of DLMF 22.10.ii are O(m1 sinh^2 u) <= O(k')).
TINY_M1 = 1e-32
#: Below this |u|, the Maclaurin series sn = u - (1 + m) u^3 / 6, cn = 1 - u^2 / 2,
#: dn = 1 - m u^2 / 2 (DLMF 22.10.i) is exact to rounding (next terms are O(u^4) < 1e-32).
SMALL_U = 2.0**-27
#: Carlson R_F duplication stops once 4^-n max|A0 - x_i| / |A_n| < (3 r)^(1/6), r = 2^-53:
#: the fifth-order series then has a relative truncation error below r (Carlson 1995, eq. 2.2).
RF_SCALE = (3.0 * 2.0**-53) ** (-1.0 / 6.0)
RF_MAX_STEPS = 60


@njit(cache=True, error_model="numpy")
def agm(a, b):
    """Arithmetic-geometric mean of ``a, b >= 0`` (DLMF 19.8.1); 0 if either is 0.

    Parameters
    ----------
    a, b : float
        Non-negative numbers.

    Returns
    -------
    float
        AGM(a, b); 0 if either is 0, else NaN if either is negative or NaN.
    """
    if not (a > 0.0 and b > 0.0):
        return 0.0 if (a == 0.0 or b == 0.0) else math.nan
    for _ in range(AGM_MAX_STEPS):
        c = 0.5 * (a + b)
        if abs(a - b) <= AGM_TOL * a:
            return c
        b = math.sqrt(a * b)
        a = c
    return 0.5 * (a + b)


@njit(cache=True, error_model="numpy")
def ellipk(m1):
    """Complete elliptic integral of the first kind K from the complementary parameter.

    Parameters
    ----------
    m1 : float
        k'^2 = 1 - m, in [0, 1].

    Returns
    -------
    float
        K = pi / (2 AGM(1, sqrt(m1))) (DLMF 19.8.5); ``inf`` at m1 = 0, NaN outside [0, 1].
        Relative error ~1 ulp for every m1, because 1 - m is never formed.
    """
    if not (0.0 <= m1 <= 1.0):
        return math.nan
    if m1 == 0.0:
        return math.inf
    return 0.5 * math.pi / agm(1.0, math.sqrt(m1))


@njit(cache=True, error_model="numpy")
def carlson_rf(x, y, z):
    """Carlson's symmetric elliptic integral R_F(x, y, z), x, y, z >= 0, at most one zero.

    Duplication algorithm with the fifth-order series (Carlson, Numer. Algorithms 10, 13 (1995),
    algorithm 1; DLMF 19.36.1). Relative error a few ulp. Returns inf if two arguments are 0.

    Parameters
    ----------
    x, y, z : float
        Non-negative arguments, at most one of them 0.

    Returns
    -------
    float
        R_F(x, y, z); inf if two arguments are 0, NaN if any is negative or NaN.
    """
    if not (x >= 0.0 and y >= 0.0 and z >= 0.0):
        return math.nan
    if (x == 0.0 and y == 0.0) or (y == 0.0 and z == 0.0) or (x == 0.0 and z == 0.0):
        return math.inf
    a0 = (x + y + z) / 3.0
    q = RF_SCALE * max(abs(a0 - x), abs(a0 - y), abs(a0 - z))
    a = a0
    xn, yn, zn = x, y, z
    scale = 1.0  # 4^-n
    for _ in range(RF_MAX_STEPS):
        if q * scale < abs(a):
            break
        sx, sy, sz = math.sqrt(xn), math.sqrt(yn), math.sqrt(zn)
        lam = sx * (sy + sz) + sy * sz
        a = 0.25 * (a + lam)
        xn = 0.25 * (xn + lam)
        yn = 0.25 * (yn + lam)
        zn = 0.25 * (zn + lam)
        scale *= 0.25
    dx = (a0 - x) * scale / a
    dy = (a0 - y) * scale / a
    dz = -(dx + dy)
    e2 = dx * dy - dz * dz
    e3 = dx * dy * dz
    # Eq. (2.2), Carlson (1995): 1 - E2/10 + E3/14 + E2^2/24 - 3 E2 E3 / 44.
    series = 1.0 + e2 * (-0.1 + e2 / 24.0 - 3.0 * e3 / 44.0) + e3 / 14.0
    return series / math.sqrt(a)


@njit(cache=True, error_model="numpy")
def ellipf(phi, m, m1):
    """Incomplete elliptic integral of the first kind F(phi | m), any real ``phi``.

    Parameters
    ----------
    phi : float
        Amplitude in rad.
    m, m1 : float
        Parameter m = k^2 in [0, 1] and its complement m1 = 1 - m, computed by the caller
        without cancellation.

    Returns
    -------
    float
        F(phi|m) = sin(phi) R_F(cos^2 phi, 1 - m sin^2 phi, 1) on |phi| <= pi/2 (DLMF 19.25.5),
        continued by F(phi + n pi) = F(phi) + 2 n K (DLMF 19.2.10). The middle argument is
        cos^2 phi + m1 sin^2 phi for m > 1/2, so F keeps full relative accuracy as m -> 1.
        ``inf`` where F diverges (m1 = 0, |phi| >= pi/2).
    """
    n = math.floor(phi / math.pi + 0.5)
    psi = phi - n * math.pi
    s = math.sin(psi)
    c = math.cos(psi)
    d2 = 1.0 - m * s * s if m <= 0.5 else c * c + m1 * s * s
    f = s * carlson_rf(c * c, d2, 1.0)
    if n != 0.0:
        f += 2.0 * n * ellipk(m1)
    return f


@njit(cache=True, error_model="numpy")
def _agm_level(kc, j):
    """(a_j, b_j) of the AGM started at (1, kc), recomputed exactly as in the forward pass."""
    a = 1.0
    b = kc
    for _ in range(j):
        c = 0.5 * (a + b)
        b = math.sqrt(a * b)
        a = c
    return a, b


@njit(cache=True, error_model="numpy")
def _sncndn_direct(u, m, m1):
    """sn, cn, dn for 0 <= u <= K/2 (all three in [0, 1], relative error a few ulp).

    Bulirsch's ``sncndn`` (Numer. Math. 7, 78 (1965); Numerical Recipes 2nd ed. section 6.11):
    descending Gauss transformation driven by k' = sqrt(m1). The AGM pairs (a_j, b_j) are
    recomputed in the backward pass instead of stored, so the kernel allocates nothing (cost
    O(n^2) square roots for n AGM steps; n <= 14 for m1 >= 1e-32).
    """
    if u < SMALL_U:
        u2 = u * u
        return u * (1.0 - (1.0 + m) * u2 / 6.0), 1.0 - 0.5 * u2, 1.0 - 0.5 * m * u2
    if m1 < TINY_M1:
        sech = 1.0 / math.cosh(u)
        return math.tanh(u), sech, sech
    kc = math.sqrt(m1)
    a = 1.0
    b = kc
    n = 0
    c = 0.5 * (a + b)
    while n < AGM_MAX_STEPS:
        c = 0.5 * (a + b)
        if abs(a - b) <= AGM_TOL * a:
            break
        b = math.sqrt(a * b)
        a = c
        n += 1
    phase = c * u  # = pi u / (2K) <= pi/4
    r = math.cos(phase) / math.sin(phase)
    cc = c * r
    dn = 1.0
    for j in range(n, -1, -1):
        aj, bj = _agm_level(kc, j)
        r *= cc
        cc *= dn
        dn = (bj + r) / (aj + r)
        r = cc / aj
    sn = 1.0 / math.sqrt(cc * cc + 1.0)
    return sn, cc * sn, dn


@njit(cache=True, error_model="numpy")
def sncndn_k(u, m, m1, K):
    """sn, cn, dn of ``u`` for parameter ``m`` with complement ``m1`` and K = ``ellipk(m1)``.

    The same as :func:`sncndn` for callers that evaluate many arguments at one parameter and
    have K already (it must be ``ellipk(m1)`` exactly, so the reduction matches the phase).

    Parameters
    ----------
    u : float
        Argument (any real).
    m, m1 : float
        Parameter m = k^2 in [0, 1] and its complement m1 = k'^2 = 1 - m, as in :func:`sncndn`.
    K : float
        The quarter period ``ellipk(m1)``.

    Returns
    -------
    sn, cn, dn : float
        As :func:`sncndn` returns them; NaN for m1 outside [0, 1] or non-finite u.
    """
    if not (0.0 <= m1 <= 1.0) or u - u != 0.0:
        return math.nan, math.nan, math.nan
    if m1 == 0.0:  # m = 1: DLMF 22.5.ii
        sech = 1.0 / math.cosh(u)
        return math.tanh(u), sech, sech
    sign_s = 1.0
    sign_c = 1.0
    x = u
    if x < 0.0:  # sn odd, cn and dn even
        x = -x
        sign_s = -1.0
    four_k = 4.0 * K
    if x >= four_k:  # period 4K
        x -= math.floor(x / four_k) * four_k
        x = min(max(x, 0.0), four_k)
    two_k = 2.0 * K
    if x >= two_k:  # sn(x + 2K) = -sn x, cn(x + 2K) = -cn x, dn(x + 2K) = dn x
        x -= two_k
        sign_s = -sign_s
        sign_c = -sign_c
    if x > K:  # sn(2K - x) = sn x, cn(2K - x) = -cn x, dn(2K - x) = dn x
        x = two_k - x
        sign_c = -sign_c
    if x <= 0.5 * K:
        s, c, d = _sncndn_direct(x, m, m1)
    else:  # x = K - v: sn = cn v / dn v, cn = k' sn v / dn v, dn = k' / dn v
        kc = math.sqrt(m1)
        sv, cv, dv = _sncndn_direct(K - x, m, m1)
        s = cv / dv
        c = kc * sv / dv
        d = kc / dv
    return sign_s * s, sign_c * c, d


@njit(cache=True, error_model="numpy")
def sncndn(u, m, m1):
    """Jacobi elliptic functions sn(u|m), cn(u|m), dn(u|m).

    Parameters
    ----------
    u : float
        Argument (any real).
    m, m1 : float
        Parameter m = k^2 in [0, 1] and its complement m1 = k'^2 = 1 - m, computed by the caller
        without cancellation. m1 drives the computation (quarter period, reduction,
        transformation); m enters only the series for |u| < 2^-27.

    Returns
    -------
    sn, cn, dn : float
        Relative error a few ulp after argument reduction; the reduction adds an absolute
        error of about ulp(u) (the argument's own rounding), so |u| <= 10 K stays within
        ~20 ulp(K). NaN for m1 outside [0, 1] or non-finite u.

    Notes
    -----
    Argument reduction by the quarter period and the complementary forms near K (DLMF 22.4.iii),
    then Bulirsch's descending Gauss transformation on [0, K/2] (see the module docstring).
    """
    return sncndn_k(u, m, m1, ellipk(m1))


@njit(cache=True, error_model="numpy")
def _sncndn_loop(u, m, m1, out):
    K = ellipk(m1)
    for i in range(u.shape[0]):
        out[i, 0], out[i, 1], out[i, 2] = sncndn_k(u[i], m, m1, K)


def sncndn_many(u, m, m1=None):
    """sn, cn, dn at an array of arguments (Python convenience over :func:`sncndn`).

    Parameters
    ----------
    u : array_like, shape (n,)
        Arguments.
    m : float
        Parameter m = k^2 in [0, 1].
    m1 : float, optional
        Complement 1 - m; pass it whenever it is known more accurately than ``1 - m``.

    Returns
    -------
    ndarray, shape (n, 3)
        Columns sn, cn, dn.
    """
    m = float(m)
    m1 = 1.0 - m if m1 is None else float(m1)
    if not (0.0 <= m <= 1.0 and 0.0 <= m1 <= 1.0):
        raise ValueError(f"need 0 <= m <= 1 and 0 <= m1 <= 1, got m = {m}, m1 = {m1}")
    if abs(m + m1 - 1.0) > 4.0 * np.finfo(float).eps:
        raise ValueError(
            f"m1 must be 1 - m; got m = {m}, m1 = {m1} (m + m1 - 1 = {m + m1 - 1.0:.3g})"
        )
    u = np.ascontiguousarray(np.atleast_1d(np.asarray(u, dtype=float)))
    if u.ndim != 1:
        raise ValueError(f"u must have shape (n,), got {u.shape}")
    out = np.empty((u.shape[0], 3))
    _sncndn_loop(u, m, m1, out)
    return out
