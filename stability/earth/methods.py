"""Integrators of the oblate Earth torqued by the Sun and the Moon (precession of the equinoxes).

Frame: the inertial ecliptic frame of the epoch (X toward the equinox, Z the ecliptic pole).
Each perturbing body j (the Sun's apparent orbit, the Moon's) moves on a prescribed Kepler
ellipse: mean anomaly ``M = M0 + n t``, eccentricity e, argument of perigee ``w0 + w' t`` from
its ascending node on the ecliptic, inclination i and node longitude ``O0 + O' t`` (the Moon's
node regresses in 18.6 years, its perigee advances in 8.85). Its strength ``k = G M_j / a^3``,
so that ``G M_j / r^3 = k / (1 - e cos E)^3`` (E the eccentric anomaly).

Full model (scene ``lunisolar_earth``): an oblate rigid Earth (A = B < C) with state
``(m, q, t)``: body angular momentum, the body-to-space unit quaternion and the time. The
gravity-gradient (MacCullagh) torque of a point mass in the body direction s is
``3 G M_j / r^3  s x I s = 3 G M_j / r^3 (C - A) s3 (s2, -s1, 0)`` [Goldstein, *Classical
Mechanics*, 3rd ed., section 5.8; Murray & Dermott, *Solar System Dynamics*, 5.2]. The splitting
(as :mod:`stability.heavy_top.methods`, with the time a coordinate) is exact in each part:

- ``K`` (kick): attitude and time frozen, ``m <- m + tau sum_j torque_j``;
- ``D`` (drift): the free symmetric top for ``tau`` and ``t <- t + tau``: ``|m|^2 / (2A)`` turns
  the body about m (``q <- q exp(tau m / (2A))``, m unchanged) and ``(1/C - 1/A) m3^2 / 2`` turns
  it about its axis (``q <- q exp(k tau e3 / 2)``, ``m <- Rz(-k tau) m``, k = m3 (1/C - 1/A));
  the two commute, so D is the exact free flow of an oblate Earth, whatever its spin.

In space the torque of a symmetric Earth depends only on its figure axis, which moves slowly,
so the kicks need resolve the month, not the day: a few steps a day are enough. Strang
K(h/2) D(h) K(h/2) is ``lp2``; Suzuki's composition ``lp4``.

Orbit-averaged model (scene ``precessing_axis``): each orbit replaced by its ring (mean of
``(r . k)^2 / r^3`` over an orbit: ``(1 - (n . k)^2) / (2 a^3 (1 - e^2)^(3/2))``, n the orbit
normal) and the spin by its angular momentum ``C W k``, the figure axis k obeys

    k' = sum_j (3 k_j / (2 (1 - e_j^2)^(3/2))) ((C - A) / (C W)) (n_j . k) (k x n_j),

which turns k about each n_j at ``(3/2) k_j H cos(eps_j) / (W (1 - e_j^2)^(3/2))``: the averaged
(gyroscopic) precession formula, and the Moon's node regression adds the 18.6-year nutation.
State ``(k, t)``; method ``rk4``.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..core.trig import sin_cosm1
from ..integrators.composition import SUZUKI4, partitioned_coefficients
from ..integrators.rotations import exp_coefficients, quaternion_increment
from ..integrators.spec import MethodSpec

#: A perturber's elements, in this order, from its offset in the parameter array.
(O_K, O_E, O_N, O_M0, O_W0, O_WDOT, O_I, O_NODE0, O_NODEDOT) = range(9)
N_ORBIT = 9
#: Parameter layout of the full model: A, C, the Sun's elements, the Moon's, the stage table.
P_A, P_C = 0, 1
P_SUN, P_MOON = 2, 2 + N_ORBIT
P_TABLE = 2 + 2 * N_ORBIT
#: Parameter layout of the averaged model: H / W (s), then the two orbits.
P_H_OVER_W = 0
P_AVG_SUN, P_AVG_MOON = 1, 1 + N_ORBIT
N_AVERAGED = 1 + 2 * N_ORBIT
#: Stage kinds of the splittings.
KICK, DRIFT = 0.0, 1.0
#: Newton iterations of Kepler's equation from E = M + e sin M: the error goes as e^(2^k), so
#: four reach round-off for e < 0.1 (the Moon's 0.055, the Sun's 0.017).
KEPLER_ITERATIONS = 4


@njit(inline="always", error_model="numpy")
def perturber(t, p, o):
    """Unit vector to perturber ``o`` (offset in ``p``) in the ecliptic frame, and G M / r^3."""
    e = p[o + O_E]
    mean = p[o + O_M0] + p[o + O_N] * t
    ecc = mean + e * math.sin(mean)
    for _ in range(KEPLER_ITERATIONS):
        ecc -= (ecc - e * math.sin(ecc) - mean) / (1.0 - e * math.cos(ecc))
    ce, se = math.cos(ecc), math.sin(ecc)
    one_m = 1.0 - e * ce  # r / a
    cf = (ce - e) / one_m
    sf = math.sqrt(1.0 - e * e) * se / one_m
    w = p[o + O_W0] + p[o + O_WDOT] * t
    cw, sw = math.cos(w), math.sin(w)
    cu, su = cw * cf - sw * sf, sw * cf + cw * sf  # argument of latitude u = w + f
    node = p[o + O_NODE0] + p[o + O_NODEDOT] * t
    cn, sn = math.cos(node), math.sin(node)
    ci, si = math.cos(p[o + O_I]), math.sin(p[o + O_I])
    x = cn * cu - sn * ci * su
    y = sn * cu + cn * ci * su
    z = si * su
    return x, y, z, p[o + O_K] / (one_m * one_m * one_m)


@njit(forceinline=True, error_model="numpy")
def to_body(q0, q1, q2, q3, x, y, z):
    """``R(q)^T v``: a space vector in the body frame (q scalar first, body to space)."""
    r11 = 1.0 - 2.0 * (q2 * q2 + q3 * q3)
    r12 = 2.0 * (q1 * q2 - q0 * q3)
    r13 = 2.0 * (q1 * q3 + q0 * q2)
    r21 = 2.0 * (q1 * q2 + q0 * q3)
    r22 = 1.0 - 2.0 * (q1 * q1 + q3 * q3)
    r23 = 2.0 * (q2 * q3 - q0 * q1)
    r31 = 2.0 * (q1 * q3 - q0 * q2)
    r32 = 2.0 * (q2 * q3 + q0 * q1)
    r33 = 1.0 - 2.0 * (q1 * q1 + q2 * q2)
    return (r11 * x + r21 * y + r31 * z, r12 * x + r22 * y + r32 * z,
            r13 * x + r23 * y + r33 * z)


@njit(forceinline=True, error_model="numpy")
def gravity_gradient(q0, q1, q2, q3, t, p, o, dc):
    """Torque (body frame) of perturber ``o`` on the oblate Earth, dc = C - A."""
    x, y, z, gm_r3 = perturber(t, p, o)
    s1, s2, s3 = to_body(q0, q1, q2, q3, x, y, z)
    f = 3.0 * gm_r3 * dc * s3
    return f * s2, -f * s1


@njit(inline="always", error_model="numpy")
def splitting_stage(m1, m2, m3, q0, q1, q2, q3, t, h, p, s):
    """Stage s of a splitting: the kick K or the drift D (module docstring) for weight_s * h.

    Both are computed and the stage's kind selects one (branch-free); the other's time is 0.
    """
    kind = p[P_TABLE + 2 * s]
    tau = p[P_TABLE + 2 * s + 1] * h
    A, C = p[P_A], p[P_C]
    # K: m <- m + tau (torque of the Sun + torque of the Moon); the torque has no axis-3 part.
    tk = tau if kind == KICK else 0.0
    a1, a2 = gravity_gradient(q0, q1, q2, q3, t, p, P_SUN, C - A)
    b1, b2 = gravity_gradient(q0, q1, q2, q3, t, p, P_MOON, C - A)
    # D: q <- q exp(tau m / (2A)) exp(k tau e3 / 2), m <- Rz(-k tau) m, t <- t + tau.
    td = tau if kind == DRIFT else 0.0
    v1, v2, v3 = td * m1 / A, td * m2 / A, td * m3 / A
    ca, cb, cm1, d = exp_coefficients(math.sqrt(v1 * v1 + v2 * v2 + v3 * v3))
    u0, u1, u2, u3 = cm1, d * v1, d * v2, d * v3  # exp(tau m / (2A)) - 1
    angle = td * m3 * (1.0 / C - 1.0 / A)
    sz, cz = sin_cosm1(0.5 * angle)  # exp(angle e3 / 2) - 1 = (cz, 0, 0, sz)
    # (1 + u)(1 + z) - 1 = u + z + u z, z = (cz, 0, 0, sz)
    r0 = u0 + cz + (u0 * cz - u3 * sz)
    r1 = u1 + (u1 * cz + u2 * sz)
    r2 = u2 + (u2 * cz - u1 * sz)
    r3 = u3 + sz + (u0 * sz + u3 * cz)
    e0, e1, e2, e3 = quaternion_increment(q0, q1, q2, q3, r0, r1, r2, r3)
    sa, ca1 = sin_cosm1(angle)  # m <- Rz(-angle) m
    dm1 = ca1 * m1 + sa * m2
    dm2 = ca1 * m2 - sa * m1
    return (tk * (a1 + b1) + dm1, tk * (a2 + b2) + dm2, 0.0, e0, e1, e2, e3, td, 0)


def sequence_params(gammas):
    """``params(earth, h)`` of the Strang step K D K composed with weights ``gammas``.

    ``earth`` is the array of :func:`stability.earth.precession.earth_parameters` (A, C and the two
    orbits); neighbouring kicks merge, so s Strang steps cost s drifts and s + 1 kicks.
    """
    a, b = partitioned_coefficients(gammas)
    table = []
    for a_i, b_i in zip(a[:-1], b):
        table += [(KICK, a_i), (DRIFT, b_i)]
    table.append((KICK, a[-1]))
    table = np.array(table, dtype=float).ravel()

    def params(earth, h=0.0):
        earth = np.asarray(earth, dtype=float).reshape(-1)
        if earth.size != P_TABLE:
            raise ValueError(f"the torqued Earth is described by {P_TABLE} numbers (A, C and "
                             f"the Sun's and Moon's {N_ORBIT} elements), got {earth.size}")
        return np.concatenate([earth, table])

    params.stages = table.size // 2
    return params


def splitting_spec(name, title, order, gammas, reference, note=""):
    """A registry entry for the torqued Earth's splitting composed with ``gammas``."""
    params = sequence_params(gammas)
    return MethodSpec(name=name, title=title, order=order, step=splitting_stage, params=params,
                      family="Lie-Poisson splitting", poisson=True, symmetric=True,
                      evaluations=params.stages, stages=params.stages, reference=reference,
                      note=note)


LP2 = splitting_spec(
    "lp2", "free oblate Earth + lunisolar kick (Strang)", 2, (1.0,),
    "Touma & Wisdom, Astron. J. 107, 1189 (1994)",
    note="exact free rotation: the step resolves the month, not the day")
LP4 = splitting_spec(
    "lp4", "Suzuki composition of the free Earth + kick splitting", 4, SUZUKI4,
    "Suzuki, Phys. Lett. A 146, 319 (1990); Touma & Wisdom (1994)",
    note="fourth order at 5 drifts and 6 kicks per step")

#: Methods of the full model, by name.
METHODS = {spec.name: spec for spec in (LP2, LP4)}


# ---------------------------------------------------------------------------------------------
# The orbit-averaged model


@njit(forceinline=True, error_model="numpy")
def ring_normal(t, p, o):
    """Normal of perturber ``o``'s orbit at time t and its averaged strength
    ``3 k / (2 (1 - e^2)^(3/2))`` (s-2)."""
    node = p[o + O_NODE0] + p[o + O_NODEDOT] * t
    si, ci = math.sin(p[o + O_I]), math.cos(p[o + O_I])
    e2 = 1.0 - p[o + O_E] * p[o + O_E]
    return (si * math.sin(node), -si * math.cos(node), ci,
            1.5 * p[o + O_K] / (e2 * math.sqrt(e2)))


@njit(inline="always", error_model="numpy")
def averaged_rhs(k1, k2, k3, t, p):
    """``k'`` of the orbit-averaged model (module docstring), and ``t' = 1``."""
    d1 = 0.0
    d2 = 0.0
    d3 = 0.0
    for o in (P_AVG_SUN, P_AVG_MOON):
        n1, n2, n3, strength = ring_normal(t, p, o)
        f = strength * p[P_H_OVER_W] * (n1 * k1 + n2 * k2 + n3 * k3)
        d1 += f * (k2 * n3 - k3 * n2)
        d2 += f * (k3 * n1 - k1 * n3)
        d3 += f * (k1 * n2 - k2 * n1)
    return d1, d2, d3, 1.0


@njit(inline="always")
def averaged_rk4_step(k1, k2, k3, t, h, p, s):
    """One classical RK4 step of the averaged model; the increment of (k, t)."""
    hh = 0.5 * h
    a1, a2, a3, a4 = averaged_rhs(k1, k2, k3, t, p)
    b1, b2, b3, b4 = averaged_rhs(k1 + hh * a1, k2 + hh * a2, k3 + hh * a3, t + hh * a4, p)
    c1, c2, c3, c4 = averaged_rhs(k1 + hh * b1, k2 + hh * b2, k3 + hh * b3, t + hh * b4, p)
    d1, d2, d3, d4 = averaged_rhs(k1 + h * c1, k2 + h * c2, k3 + h * c3, t + h * c4, p)
    w = h / 6.0
    return (w * (a1 + 2.0 * (b1 + c1) + d1), w * (a2 + 2.0 * (b2 + c2) + d2),
            w * (a3 + 2.0 * (b3 + c3) + d3), w * (a4 + 2.0 * (b4 + c4) + d4), 0)


def averaged_params(earth, h=0.0):
    """Kernel parameters of the averaged model: ``(H / W, Sun's orbit, Moon's orbit)``."""
    earth = np.asarray(earth, dtype=float).reshape(-1)
    if earth.size != N_AVERAGED:
        raise ValueError(f"the averaged model takes {N_AVERAGED} numbers (H / W and the two "
                         f"orbits' {N_ORBIT} elements), got {earth.size}")
    return earth


AVERAGED_RK4 = MethodSpec(
    name="rk4", title="classical Runge-Kutta on the orbit-averaged axis", order=4,
    step=averaged_rk4_step, params=averaged_params, family="Runge-Kutta", evaluations=4,
    reference="Kutta (1901)", note="steps of days: the fastest motion is the 18.6-year nutation")

#: Methods of the averaged model.
AVERAGED_METHODS = {"rk4": AVERAGED_RK4}
