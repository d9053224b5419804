"""Scalar helpers for the rotation-based step kernels: 3x3 solves, rotation exponentials, and
quaternion increments.

All functions take and return plain floats (no arrays, no allocation). The short ones are
``njit(forceinline=True, error_model="numpy")`` (LLVM inlines them into the kernels that call
them), the long ``carried_rotation`` ``njit(inline="always")`` (:mod:`stability.engine.loop`,
"Inlining").
Quaternions are scalar first, ``q = (q0, q1, q2, q3)``, Hamilton product; ``R(q)`` is the
rotation matrix of a unit ``q`` and ``R(a b) = R(a) R(b)``. An attitude update ``Q <- Q F``
(right multiplication by the body-frame rotation of one step) is ``q <- q r`` with ``r`` the
unit quaternion of ``F``; the kernels return the *increment* ``q r - q = q (r - 1)``, with
``r - 1`` formed without cancellation, so the member loop can add it with compensated summation
like the increment of m.
"""

import math

from numba import njit

from ..core.trig import sin_cosm1

#: Below this rotation angle (rad) the exponential's coefficients use their Taylor series
#: (next term ~ theta^4 / 120 < 1e-34), which also covers theta = 0 without a 0/0.
SMALL_ANGLE = 1e-8


@njit(forceinline=True, error_model="numpy")
def cross(a1, a2, a3, b1, b2, b3):
    """The vector product a x b."""
    return a2 * b3 - a3 * b2, a3 * b1 - a1 * b3, a1 * b2 - a2 * b1


@njit(forceinline=True, error_model="numpy")
def solve3(a11, a12, a13, a21, a22, a23, a31, a32, a33, r1, r2, r3):
    """Solve the 3x3 system A x = r by Cramer's rule (cofactors); no pivoting, no allocation.

    A singular A gives inf or NaN components (never an exception), which callers treat as a
    failed solve.
    """
    c11 = a22 * a33 - a23 * a32
    c12 = a23 * a31 - a21 * a33
    c13 = a21 * a32 - a22 * a31
    det = a11 * c11 + a12 * c12 + a13 * c13
    inv = 1.0 / det
    x1 = (r1 * c11 + a12 * (a23 * r3 - r2 * a33) + a13 * (r2 * a32 - a22 * r3)) * inv
    x2 = (a11 * (r2 * a33 - a23 * r3) + r1 * c12 + a13 * (a21 * r3 - r2 * a31)) * inv
    x3 = (a11 * (a22 * r3 - r2 * a32) + a12 * (r2 * a31 - a21 * r3) + r1 * c13) * inv
    return x1, x2, x3


@njit(forceinline=True, error_model="numpy")
def exp_coefficients(theta):
    """Coefficients of the rotation exponential for the angle ``theta = |k| >= 0``.

    Returns ``(sin(theta)/theta, (1 - cos(theta))/theta^2, cos(theta/2) - 1, sin(theta/2)/theta)``,
    so that ``exp(hat k) v = v + a (k x v) + b k x (k x v)`` (Rodrigues) and the unit quaternion
    of ``exp(hat k)`` is ``(1 + c, d k)``. One ``sin_cosm1`` call at theta/2 (vectorizable); the
    full-angle values follow from the half-angle identities sin t = 2 s c, 1 - cos t = 2 s^2.
    """
    s, cm1 = sin_cosm1(0.5 * theta)
    small = theta < SMALL_ANGLE
    t = theta if not small else 1.0
    t2 = theta * theta
    a = 2.0 * s * (1.0 + cm1) / t if not small else 1.0 - t2 / 6.0
    b = 2.0 * s * s / (t * t) if not small else 0.5 - t2 / 24.0
    d = s / t if not small else 0.5 - t2 / 48.0
    return a, b, cm1, d


@njit(forceinline=True, error_model="numpy")
def rotate_increment(k1, k2, k3, v1, v2, v3, a, b):
    """``exp(hat k) v - v = a (k x v) + b k x (k x v)``, a and b from ``exp_coefficients``."""
    # written out rather than two cross() calls: fewer inlinings, shorter compilation
    u1 = k2 * v3 - k3 * v2  # k x v
    u2 = k3 * v1 - k1 * v3
    u3 = k1 * v2 - k2 * v1
    w1 = k2 * u3 - k3 * u2  # k x (k x v)
    w2 = k3 * u1 - k1 * u3
    w3 = k1 * u2 - k2 * u1
    return a * u1 + b * w1, a * u2 + b * w2, a * u3 + b * w3


@njit(forceinline=True, error_model="numpy")
def quaternion_increment(q0, q1, q2, q3, r0m1, r1, r2, r3):
    """``q r - q = q (r - 1)`` for ``r = (1 + r0m1, r1, r2, r3)`` (Hamilton product)."""
    e0 = q0 * r0m1 - q1 * r1 - q2 * r2 - q3 * r3
    e1 = q0 * r1 + q1 * r0m1 + q2 * r3 - q3 * r2
    e2 = q0 * r2 - q1 * r3 + q2 * r0m1 + q3 * r1
    e3 = q0 * r3 + q1 * r2 - q2 * r1 + q3 * r0m1
    return e0, e1, e2, e3


@njit(forceinline=True, error_model="numpy")
def cayley_quaternion(f1, f2, f3):
    """``r - 1`` for the unit quaternion ``r = (1, f) / sqrt(1 + |f|^2)``.

    ``r`` is the quaternion of the Cayley rotation ``(Id + hat f)(Id - hat f)^-1``, a rotation
    about f by the angle 2 atan|f|; the scalar part ``1/sqrt(1 + |f|^2) - 1`` is written as
    ``-|f|^2 / (sqrt(1 + |f|^2) (1 + sqrt(1 + |f|^2)))`` so small f loses nothing.
    """
    f2n = f1 * f1 + f2 * f2 + f3 * f3
    root = math.sqrt(1.0 + f2n)
    inv = 1.0 / root
    return -f2n * inv / (1.0 + root), f1 * inv, f2 * inv, f3 * inv


@njit(forceinline=True, error_model="numpy")
def cayley_attitude_increment(d1, d2, d3, q0, q1, q2, q3, f1, f2, f3, it):
    """Increments of m and of ``q <- q (1, f) / sqrt(1 + |f|^2)`` (the Cayley rotation of f).

    ``q r - q`` with ``r - 1`` from :func:`cayley_quaternion`, passed with ``(d1, d2, d3)``
    and ``it`` through :func:`unless_failed_attitude`: the attitude steps of the Cayley methods.
    """
    r0, r1, r2, r3 = cayley_quaternion(f1, f2, f3)
    e0, e1, e2, e3 = quaternion_increment(q0, q1, q2, q3, r0, r1, r2, r3)
    return unless_failed_attitude(d1, d2, d3, e0, e1, e2, e3, it)


@njit(forceinline=True, error_model="numpy")
def cayley_increment(m1, m2, m3, f1, f2, f3):
    """``F^T m - m`` for the Cayley rotation F of ``f``, formed without cancellation.

    With ``F = Id + 2 (hat f + hat f^2) / (1 + |f|^2)``:
    ``F^T m - m = 2 (m x f + f x (f x m)) / (1 + |f|^2)``.
    """
    u1, u2, u3 = cross(m1, m2, m3, f1, f2, f3)  # m x f
    v1, v2, v3 = cross(f1, f2, f3, -u1, -u2, -u3)  # f x (f x m)
    scale = 2.0 / (1.0 + f1 * f1 + f2 * f2 + f3 * f3)
    return scale * (u1 + v1), scale * (u2 + v2), scale * (u3 + v3)


@njit(inline="always", error_model="numpy")
def carried_rotation(m1, m2, m3, g1, g2, g3, first, theta, t_casimir, inv2):
    """Free flow of a top that carries a vector g along: the increments of m and g.

    Both m and g turn about body axis 1 (``first``) or 3 by the angle ``-theta`` (the flow of
    ``c_k m_k^2 / 2``, ``theta = t c_k m_k``); then g turns about the new m by
    ``-phi = -t_casimir |m| inv2`` (the flow of the Casimir part ``|m|^2 / (2 I2)``, which
    leaves m fixed; Rodrigues with cos - 1)::

        g <- g + (cos phi - 1)(g - n (n . g)) + sin phi (g x n),   n = m / |m|.

    The vector g is the heavy top's vertical, or a damper's angular momentum, which the free
    rotation carries as it carries m. Increments are formed with cos - 1 (``sin_cosm1``), so
    small angles lose nothing; zero angles give increments of exactly zero.
    """
    sn, cm1 = sin_cosm1(theta)
    # (u, v) are the components across the axis: (2, 3) about axis 1, (1, 2) about axis 3.
    mu = m2 if first else m1
    mv = m3 if first else m2
    gu = g2 if first else g1
    gv = g3 if first else g2
    dmu = cm1 * mu + sn * mv
    dmv = cm1 * mv - sn * mu
    dgu = cm1 * gu + sn * gv
    dgv = cm1 * gv - sn * gu
    r1 = 0.0 if first else dmu
    r2 = dmu if first else dmv
    r3 = dmv if first else 0.0
    q1 = g1 + (0.0 if first else dgu)
    q2 = g2 + (dgu if first else dgv)
    q3 = g3 + (dgv if first else 0.0)
    n1, n2, n3 = m1 + r1, m2 + r2, m3 + r3  # m after the axis rotation
    norm = math.sqrt(n1 * n1 + n2 * n2 + n3 * n3)
    phi = t_casimir * norm * inv2
    sp, cp = sin_cosm1(phi)
    inv = 1.0 / norm if norm > 0.0 else 0.0
    u1, u2, u3 = n1 * inv, n2 * inv, n3 * inv
    along = u1 * q1 + u2 * q2 + u3 * q3
    e1 = cp * (q1 - u1 * along) + sp * (q2 * u3 - q3 * u2)
    e2 = cp * (q2 - u2 * along) + sp * (q3 * u1 - q1 * u3)
    e3 = cp * (q3 - u3 * along) + sp * (q1 * u2 - q2 * u1)
    return r1, r2, r3, (q1 - g1) + e1, (q2 - g2) + e2, (q3 - g3) + e3


@njit(forceinline=True, error_model="numpy")
def unless_failed(d1, d2, d3, it):
    """``(d1, d2, d3, it)``, with a zero increment when the solve failed (``it <= 0``)."""
    ok = it > 0
    return (d1 if ok else 0.0), (d2 if ok else 0.0), (d3 if ok else 0.0), it


@njit(forceinline=True, error_model="numpy")
def unless_failed_attitude(d1, d2, d3, e0, e1, e2, e3, it):
    """Increments of m and q, both zero when the solve failed (``it <= 0``)."""
    ok = it > 0
    return (
        (d1 if ok else 0.0), (d2 if ok else 0.0), (d3 if ok else 0.0),
        (e0 if ok else 0.0), (e1 if ok else 0.0), (e2 if ok else 0.0), (e3 if ok else 0.0),
        it,
    )
