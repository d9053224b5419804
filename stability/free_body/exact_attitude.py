"""The exact attitude of the torque-free rigid body: Euler angles about L by exact quadrature.

Frames as in :mod:`stability.free_body.attitude`: R(q) maps body to space and ``R' = R hat(w)``, so
the spatial angular momentum L = R m is fixed. Take z-x-z Euler angles with space Z along L and
body z along the axis of the *smallest* moment (canonical axis 1, a racket's handle), body x, y
along canonical axes 2, 3 (Landau & Lifshitz, *Mechanics*, section 35, with the axes renamed):

    R(t) = A Rz(phi) Rx(theta) Rz(psi) P,    P b = (b2, b3, b1)  (canonical body components)

A is fixed by R(0) with phi(0) = 0. theta and psi are read off m(t) itself,

    m1 = |L| cos(theta),   m2 = |L| sin(theta) sin(psi),   m3 = |L| sin(theta) cos(psi),

with m(t) from the exact elliptic solution (:mod:`stability.free_body.exact`), and the precession
angle is the quadrature of

    phi' = |L| (m2^2 / I2 + m3^2 / I3) / (m2^2 + m3^2)      (a weighted mean of |L|/I2, |L|/I3)

(Landau & Lifshitz section 37 writes the same integral as a third-kind elliptic integral).
phi' is analytic and periodic with the period P = 2K / nu of m2^2 and m3^2, so its Fourier
coefficients, from the trapezoid rule over one period, converge geometrically; the number of
nodes is doubled until the highest quarter of the spectrum is at round-off (below 1e-15 of c0,
or no longer falling), the coefficients below 1e-16 of c0 are dropped, and

    phi(t) = c0 t + sum_{k != 0} c_k (exp(i k W t) - 1) / (i k W),   W = 2 pi / P,

is then exact to round-off at any t (the oscillating part is evaluated at t mod P). Near the
separatrix the spectrum is wider (about 20 ln(4/k') nodes per unit of nu P), and on it (k' = 0)
the motion is not periodic: such members are refused.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..core.quaternions import (
    IDENTITY, canonical_quaternion, quaternion_conjugate, quaternion_multiply,
)
from ..core.body import RigidBody, canonical_frame, to_canonical
from ..util.checks import real_array, vectors3
from .exact import MAJOR, MINOR, PRECESS1, PRECESS3, Q_K, Q_KIND, Q_RATE, STEADY, motion
from .exact import omega_many

#: Quaternion of P: body components (canonical) to the Euler-angle body frame (x, y, z) =
#: (axis 2, axis 3, axis 1), a cyclic (proper) permutation.
_P = np.array([0.5, -0.5, -0.5, -0.5])

#: Largest number of quadrature nodes per period before a member is refused.
MAX_NODES = 2**16


@dataclass(frozen=True)
class FreeMotion:
    """One member's exact torque-free motion, canonical frame (I1 <= I2 <= I3).

    The fields are the constructor's parameters and the instance's attributes; build one with
    :func:`free_motion`.

    Parameters
    ----------
    moments : ndarray, shape (3,)
        Principal moments, ascending, kg m^2.
    w0 : ndarray, shape (3,)
        Angular velocity at t = 0, rad/s.
    kind : int
        ``stability.free_body.exact`` motion kind (MAJOR, MINOR, PRECESS1, PRECESS3 or STEADY).
    period : float
        Period of m(t) in s (4K / nu; 2 pi / |rate| for a symmetric body; inf at rest).
    momentum : float
        |L| in kg m^2/s.
    energy : float
        Kinetic energy in J.
    phi_mean : float
        Mean precession rate c0 in rad/s.
    phi_coeffs : ndarray of complex
        c_1 ... c_{n/2 - 1} of phi' over its period ``period / 2``.
    """

    moments: np.ndarray
    w0: np.ndarray
    kind: int
    period: float
    momentum: float
    energy: float
    phi_mean: float
    phi_coeffs: np.ndarray

    def m(self, t) -> np.ndarray:
        """Body angular momentum m(t) (canonical), shape (n, 3), kg m^2/s."""
        t = np.ascontiguousarray(np.atleast_1d(np.asarray(t, dtype=float)))
        out = np.empty((t.size, 3))
        omega_many(*self.moments, *self.w0, t, out)
        return out * self.moments

    def phi(self, t) -> np.ndarray:
        """Precession angle phi(t) of the handle about L in rad, phi(0) = 0; shape of ``t``."""
        t = np.asarray(t, dtype=float)
        phi = self.phi_mean * t
        if self.phi_coeffs.size:
            half = 0.5 * self.period  # the period of phi'
            tau = np.mod(t, half).reshape(-1)
            omega = 2.0 * math.pi / half * np.arange(1, self.phi_coeffs.size + 1)
            weights = self.phi_coeffs / (1j * omega)
            wave = np.empty(tau.size)
            step = max(1, 2**20 // omega.size)  # at most ~16 MB of complex terms at a time
            for lo in range(0, tau.size, step):
                terms = weights * np.expm1(1j * omega * tau[lo:lo + step, None])
                wave[lo:lo + step] = 2.0 * terms.real.sum(axis=-1)
            phi = phi + wave.reshape(t.shape)
        return phi

    def phi_rate(self, t) -> np.ndarray:
        """phi'(t) in rad/s from m(t), shape (n,)."""
        return precession_rate(self.m(t), self.moments)


def precession_rate(m, moments) -> np.ndarray:
    """phi' = |L| (m2^2/I2 + m3^2/I3) / (m2^2 + m3^2) for canonical m (..., 3), rad/s.

    Parameters
    ----------
    m : array_like, shape (..., 3)
        Body angular momenta, canonical frame, kg m^2/s; m2 and m3 not both 0.
    moments : array_like, shape (3,) or (..., 3)
        Principal moments, ascending, kg m^2.

    Returns
    -------
    ndarray, shape (...)
        The precession rate phi' of the smallest-moment axis about L, rad/s.
    """
    m = np.asarray(m, dtype=float)
    I = np.asarray(moments, dtype=float)
    across = m[..., 1] ** 2 + m[..., 2] ** 2
    weighted = m[..., 1] ** 2 / I[..., 1] + m[..., 2] ** 2 / I[..., 2]
    return np.linalg.norm(m, axis=-1) * weighted / across


def free_motion(moments, w0) -> FreeMotion:
    """The exact motion of one member from its canonical moments and start (rad/s).

    Parameters
    ----------
    moments : array_like, shape (3,)
        Principal moments, ascending (canonical frame), kg m^2.
    w0 : array_like, shape (3,)
        Angular velocity at t = 0, canonical frame, rad/s.

    Returns
    -------
    FreeMotion
        The motion, with the Fourier series of phi' (empty where phi' is constant).

    Raises
    ------
    ValueError
        For w0 = 0; on the separatrix (L^2 = 2 E I2 exactly, or k'^2 below the double range), where
        the motion is not periodic, or for a start along the handle (phi undefined).
    """
    I = np.asarray(moments, dtype=float)
    w = np.asarray(w0, dtype=float)
    q = motion(*I, *w)
    kind, rate = int(q[Q_KIND]), float(q[Q_RATE])
    m0 = I * w
    momentum = float(np.linalg.norm(m0))
    energy = 0.5 * float(np.dot(m0, w))
    if momentum == 0.0:
        raise ValueError("w0 = 0: a body at rest has no attitude motion to follow")
    if m0[1] == 0.0 and m0[2] == 0.0:
        raise ValueError(
            "the start spins exactly about the smallest-moment axis (the handle): the "
            "precession angle about L is undefined; tilt the start off that axis"
        )
    if kind in (MAJOR, MINOR):
        period = 4.0 * float(q[Q_K]) / rate
    elif kind in (PRECESS1, PRECESS3):
        period = 2.0 * math.pi / abs(rate) if rate != 0.0 else math.inf
    elif kind == STEADY:
        period = math.inf
    else:
        raise ValueError(
            "the start lies on the separatrix (L^2 = 2 E I2): its motion is not periodic, so "
            "it has no period and no exact attitude series here; perturb it off the separatrix"
        )
    if not math.isfinite(period):  # phi' constant: steady spin or a sphere
        rate0 = float(precession_rate(m0, I))
        return FreeMotion(I, w, kind, math.inf, momentum, energy, rate0, np.zeros(0, complex))
    half = 0.5 * period
    n, previous = 32, math.inf
    while True:
        t = np.arange(n) * (half / n)
        out = np.empty((n, 3))
        omega_many(*I, *w, t, out)
        c = np.fft.rfft(precession_rate(out * I, I)) / n
        scale = abs(c[0].real)
        tail = np.abs(c[n // 4:]).max()
        if tail <= 1e-15 * scale or (n >= 128 and tail >= 0.5 * previous) or n >= MAX_NODES:
            break  # converged, or the tail no longer falls: it is round-off
        n, previous = 2 * n, tail
    if tail > 1e-13 * scale:
        raise ValueError(
            f"the precession rate needs more than {MAX_NODES} quadrature nodes per period "
            "(the start is within round-off of the separatrix)"
        )
    keep = np.flatnonzero(np.abs(c[1:n // 2]) > 1e-16 * scale)  # round-off dropped
    coeffs = c[1:2 + keep[-1]] if keep.size else np.zeros(0, complex)
    return FreeMotion(I, w, kind, period, momentum, energy, float(c[0].real),
                      np.ascontiguousarray(coeffs))


def euler_quaternion(phi, theta, psi) -> np.ndarray:
    """Quaternion of Rz(phi) Rx(theta) Rz(psi), shape (..., 4).

    Parameters
    ----------
    phi, theta, psi : float or array_like, shape (...)
        z-x-z Euler angles in rad; they broadcast.

    Returns
    -------
    ndarray, shape (..., 4)
        Unit quaternions, scalar first.
    """
    a, b, c = (0.5 * np.asarray(x, dtype=float) for x in (phi, theta, psi))
    ca, sa, cb, sb = np.cos(a), np.sin(a), np.cos(b), np.sin(b)
    cc, sc = np.cos(c), np.sin(c)
    return np.stack([ca * cb * cc - sa * cb * sc, ca * sb * cc + sa * sb * sc,
                     sa * sb * cc - ca * sb * sc, ca * cb * sc + sa * cb * cc], axis=-1)


def nutation_spin(m):
    """theta and psi (rad) of canonical body angular momenta m (..., 3): L along space Z.

    Parameters
    ----------
    m : array_like, shape (..., 3)
        Body angular momenta, canonical frame, kg m^2/s (only the direction matters).

    Returns
    -------
    theta : ndarray, shape (...)
        Nutation angle in rad, in [0, pi]: the angle between L and the smallest-moment axis.
    psi : ndarray, shape (...)
        Spin angle in rad, in [-pi, pi], ``atan2(m2, m3)``.
    """
    m = np.asarray(m, dtype=float)
    theta = np.arctan2(np.hypot(m[..., 1], m[..., 2]), m[..., 0])
    return theta, spin_angle(m)


def spin_angle(m):
    """The spin angle psi = atan2(m2, m3): the body's turn about its smallest-moment axis.

    Parameters
    ----------
    m : array_like, shape (..., 3)
        Body angular momenta, canonical frame, kg m^2/s (only the direction matters).

    Returns
    -------
    ndarray, shape (...)
        psi in rad, in [-pi, pi].
    """
    m = np.asarray(m, dtype=float)
    return np.arctan2(m[..., 1], m[..., 2])


def l_frame(m0, q0) -> np.ndarray:
    """Quaternion of A: the space frame with Z along L and phi = 0 at the start, shape (..., 4).

    ``m0`` (..., 3) canonical body angular momenta and ``q0`` (..., 4) canonical attitudes at
    t = 0; A = R(q0) P^T (Rx(theta0) Rz(psi0))^T.

    Parameters
    ----------
    m0 : array_like, shape (..., 3)
        Body angular momenta at t = 0, canonical frame, kg m^2/s.
    q0 : array_like, shape (..., 4)
        Canonical-frame attitudes at t = 0, unit quaternions, scalar first.

    Returns
    -------
    ndarray, shape (..., 4)
        The quaternions of A, scalar first.
    """
    theta0, psi0 = nutation_spin(m0)
    g0 = euler_quaternion(np.zeros_like(theta0), theta0, psi0)
    return quaternion_multiply(quaternion_multiply(q0, quaternion_conjugate(_P)),
                               quaternion_conjugate(g0))


def canonical_attitude(fm: FreeMotion, t, q0_canonical) -> np.ndarray:
    """Exact canonical-frame attitude quaternions at times ``t`` (n,) from ``q0``; (n, 4).

    Parameters
    ----------
    fm : FreeMotion
        The member's motion (:func:`free_motion`).
    t : array_like, shape (n,)
        Times in s.
    q0_canonical : array_like, shape (4,)
        Canonical-frame attitude at t = 0, unit quaternion, scalar first.

    Returns
    -------
    ndarray, shape (n, 4)
        Quaternions q(t), scalar first (sign not fixed).
    """
    a = l_frame(fm.m(0.0)[0], q0_canonical)
    theta, psi = nutation_spin(fm.m(t))
    g = euler_quaternion(fm.phi(t), theta, psi)
    return quaternion_multiply(quaternion_multiply(a, g), _P)


def exact_attitude(body: RigidBody, w0, t, q0=None) -> np.ndarray:
    """Exact body-to-space attitude of the torque-free body at times ``t``.

    Parameters
    ----------
    body : RigidBody
        Moments in any order (three distinct ones, or a symmetric body).
    w0 : array_like, shape (3,)
        Angular velocity at t = 0 along the body's axes, rad/s.
    t : array_like, shape (n,)
        Times in s.
    q0 : array_like, shape (4,), optional
        Attitude at t = 0, unit quaternion scalar first; default the identity.

    Returns
    -------
    ndarray, shape (n, 4)
        Unit quaternions q(t) (R(q) body to space), sign chosen with q0 >= 0.

    Notes
    -----
    See the module docstring; accurate to a few ulp times the number of turns.
    """
    if not isinstance(body, RigidBody):
        raise ValueError(f"body must be a stability.RigidBody, got {type(body).__name__}")
    w0 = vectors3("w0", w0, "rad/s")
    if w0.ndim != 1:
        raise ValueError(f"w0 must have shape (3,), got {w0.shape}")
    t = np.atleast_1d(real_array("t", t, "s"))
    q0 = IDENTITY if q0 is None else real_array("q0", q0)
    if q0.shape != (4,) or not abs(np.linalg.norm(q0) - 1.0) <= 1e-9:
        raise ValueError(f"q0 must be a unit quaternion of shape (4,), scalar first, got {q0!r}")
    return exact_attitudes(body.moments[None, :], w0[None, :], t, q0[None, :])[0]


def exact_attitudes(moments, w0, t, q0) -> np.ndarray:
    """:func:`exact_attitude` of N members, each of its own body; shape (N, n, 4).

    ``moments`` (N, 3) (or (1, 3) for all) in any order, ``w0`` (N, 3) rad/s along the
    bodies' axes, ``t`` (n,) s, ``q0`` (N, 4). A member on the separatrix (no period: a steady
    spin about the middle axis, or within round-off of one) or spinning exactly about its
    smallest-moment axis (where phi is undefined) gets NaN.

    Parameters
    ----------
    moments : array_like, shape (N, 3) or (1, 3)
        Principal moments of each member in kg m^2, any order; one row for all members.
    w0 : array_like, shape (N, 3)
        Angular velocities at t = 0 along the bodies' axes, rad/s.
    t : array_like, shape (n,)
        Times in s.
    q0 : array_like, shape (N, 4) or (4,)
        Attitudes at t = 0, unit quaternions, scalar first; broadcast over the members.

    Returns
    -------
    ndarray, shape (N, n, 4)
        Unit quaternions q(t) (R(q) body to space) with q0 >= 0, NaN for the members above.

    Raises
    ------
    ValueError
        For a member with w0 = 0.
    """
    moments = np.atleast_2d(np.asarray(moments, dtype=float))
    w0 = np.atleast_2d(np.asarray(w0, dtype=float))
    q0 = np.broadcast_to(np.asarray(q0, dtype=float), (w0.shape[0], 4))
    out = np.empty((w0.shape[0], np.size(t), 4))
    for j in range(w0.shape[0]):
        I = moments[j] if moments.shape[0] > 1 else moments[0]
        perm, signs = canonical_frame(I)
        c = canonical_quaternion(I)
        try:
            fm = free_motion(I[perm], to_canonical(w0[j], perm, signs))
        except ValueError:
            if not np.any(w0[j]):
                raise
            out[j] = np.nan
            continue
        qc = canonical_attitude(fm, t, quaternion_multiply(q0[j], quaternion_conjugate(c)))
        q = quaternion_multiply(qc, c)
        q /= np.linalg.norm(q, axis=-1, keepdims=True)
        out[j] = np.where(q[:, :1] < 0.0, -q, q)
    return out
