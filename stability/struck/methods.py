"""A long body struck across its axis, held at a pivot (the hands) or free: planar motion.

The body lies along its unit axis e = (cos phi, sin phi) from the pivot P (the hands, at the
origin at the start); n = (-sin phi, cos phi) is across it. Its centre of mass is at distance d
from P along e, its moment of inertia about the centre is I_cm (I_P = I_cm + M d^2 about P).
The ball pushes across the body at distance s from P with the half-sine contact force

    F(t) = (pi J / (2 tau)) sin(pi t / tau)  for 0 <= t <= tau, 0 after,       (1)

of impulse J over the contact time tau [Cross, Am. J. Phys. 67, 692 (1999): a ball stays on a
bat or racket for about a millisecond]. Held (the hands a hinge at P), the body turns about P
and the hands supply the reaction R = M a_cm - F n:

    I_P w' = s F,   a_cm = d (w' n - w^2 e),
    R . n = (M d s / I_P - 1) F,   R . e = -M d w^2;                           (2)

free, I_cm w' = (s - d) F and M a_cm = F n. The state is the centre of mass (x, y), phi, its
velocity (vx, vy), w, the reaction impulse at the hands along and across the body (the
integrals of R . e and R . n: zero when free) and the time. Across, the reaction vanishes at
every instant when s = I_P / (M d), the centre of percussion; along, the hands pull the body
round its circle. Exact solution, held (with Phi(t) = int_0^t F / J, (1)): w = s J Phi / I_P,
the reaction across (M d s / I_P - 1) J Phi (:func:`held_exact`).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..integrators.spec import MethodSpec

# Parameter layout.
P_MASS, P_D, P_I_CM, P_S, P_J, P_TAU, P_HELD = 0, 1, 2, 3, 4, 5, 6
#: Derived: the angular acceleration per newton (held s / I_P, free (s - d) / I_cm), the peak
#: force pi J / (2 tau) and pi / tau.
P_SPIN, P_F0, P_OMEGA = 7, 8, 9
N_STRUCK_PARAMS = 10
#: The numbers that describe a strike.
N_STRIKE = 7
#: State layout.
X, Y, PHI, VX, VY, W, J_ALONG, J_ACROSS, T = range(9)


def strike_params(strike, h: float = 0.0) -> np.ndarray:
    """Kernel parameters of a strike ``(M, d, I_cm, s, J, tau, held)`` (kg, m, kg m2, m, N s,
    s, 1 or 0); the same for every step ``h``."""
    strike = np.asarray(strike, dtype=float).reshape(-1)
    if strike.size != N_STRIKE:
        raise ValueError(f"a strike is {N_STRIKE} numbers (M, d, I_cm, s, J, tau, held), "
                         f"got {strike.size}")
    mass, d, i_cm, s, impulse, tau, held = strike
    p = np.zeros(N_STRUCK_PARAMS)
    p[:N_STRIKE] = strike
    p[P_SPIN] = s / (i_cm + mass * d * d) if held else (s - d) / i_cm
    p[P_F0] = 0.5 * math.pi * impulse / tau
    p[P_OMEGA] = math.pi / tau
    return p


@njit(forceinline=True, error_model="numpy")
def force(t, p):
    """Equation (1)."""
    return p[P_F0] * math.sin(p[P_OMEGA] * t) if 0.0 <= t <= p[P_TAU] else 0.0


@njit(forceinline=True, error_model="numpy")
def struck_rhs(phi, vx, vy, w, t, p):
    """Equations (2) held (``P_HELD`` = 1) or the free body's; the rates of the state."""
    f = force(t, p)
    dw = p[P_SPIN] * f
    c, s = math.cos(phi), math.sin(phi)
    mass, d = p[P_MASS], p[P_D]
    if p[P_HELD] != 0.0:
        an = d * dw  # a_cm across and along the body
        ae = -d * w * w
        r_along = mass * ae
        r_across = mass * an - f
    else:
        an = f / mass
        ae = 0.0
        r_along = 0.0
        r_across = 0.0
    return vx, vy, w, ae * c - an * s, ae * s + an * c, dw, r_along, r_across, 1.0


@njit(inline="always")
def rk4_step(x, y, phi, vx, vy, w, j_along, j_across, t, h, p, s):
    """One classical RK4 step of (2); the increments and 0 iterations."""
    a0, a1, a2, a3, a4, a5, a6, a7, a8 = struck_rhs(phi, vx, vy, w, t, p)
    hh = 0.5 * h
    b0, b1, b2, b3, b4, b5, b6, b7, b8 = struck_rhs(
        phi + hh * a2, vx + hh * a3, vy + hh * a4, w + hh * a5, t + hh, p)
    c0, c1, c2, c3, c4, c5, c6, c7, c8 = struck_rhs(
        phi + hh * b2, vx + hh * b3, vy + hh * b4, w + hh * b5, t + hh, p)
    d0, d1, d2, d3, d4, d5, d6, d7, d8 = struck_rhs(
        phi + h * c2, vx + h * c3, vy + h * c4, w + h * c5, t + h, p)
    k = h / 6.0
    return (k * (a0 + 2.0 * (b0 + c0) + d0), k * (a1 + 2.0 * (b1 + c1) + d1),
            k * (a2 + 2.0 * (b2 + c2) + d2), k * (a3 + 2.0 * (b3 + c3) + d3),
            k * (a4 + 2.0 * (b4 + c4) + d4), k * (a5 + 2.0 * (b5 + c5) + d5),
            k * (a6 + 2.0 * (b6 + c6) + d6), k * (a7 + 2.0 * (b7 + c7) + d7), h, 0)


def contact_fraction(t, tau):
    """``Phi(t) = int_0^t F / J``: the share of the impulse delivered by time t, and its
    integral ``int_0^t Phi`` (s) and ``int_0^t Phi^2`` (s), for (1)."""
    t = np.asarray(t, dtype=float)
    tc = np.minimum(t, tau)
    a = math.pi / tau
    phi = 0.5 * (1.0 - np.cos(a * tc))
    int_phi = 0.5 * tc - np.sin(a * tc) / (2.0 * a) + (t - tc)
    int_phi2 = (1.5 * tc - 2.0 * np.sin(a * tc) / a + np.sin(2.0 * a * tc) / (4.0 * a)) / 4.0
    return phi, int_phi, int_phi2 + (t - tc)


def held_exact(t, strike):
    """The exact state at times ``t`` (n,) of a held body struck from rest along +x: (n, 9)."""
    mass, d, i_cm, s, impulse, tau, _ = np.asarray(strike, dtype=float)
    i_p = i_cm + mass * d * d
    frac, int_frac, int_frac2 = contact_fraction(t, tau)
    rate = s * impulse / i_p
    w, phi = rate * frac, rate * int_frac
    out = np.empty(np.shape(t) + (9,))
    out[..., X], out[..., Y] = d * np.cos(phi), d * np.sin(phi)
    out[..., PHI], out[..., W] = phi, w
    out[..., VX], out[..., VY] = -d * w * np.sin(phi), d * w * np.cos(phi)
    out[..., J_ALONG] = -mass * d * rate * rate * int_frac2
    out[..., J_ACROSS] = (mass * d * s / i_p - 1.0) * impulse * frac
    out[..., T] = t
    return out


RK4 = MethodSpec(
    name="rk4",
    title="classical Runge-Kutta",
    order=4,
    step=rk4_step,
    params=strike_params,
    family="Runge-Kutta",
    evaluations=4,
    reference="Kutta (1901); Hairer, Norsett & Wanner, Solving ODEs I (1993), II.1",
    note="steps that end where the contact ends (tau a whole number of steps) keep order 4",
)

METHODS = {RK4.name: RK4}
