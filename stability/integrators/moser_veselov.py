"""Discrete Moser-Veselov (DMV) and its order-4 modified-inertia variant.

DMV advances the attitude by the body-frame rotation F that solves
``h hat(m_n) = F J_d - J_d F^T`` (``J_d = tr(I)/2 Id - I``) and sets ``m_{n+1} = F^T m_n``
[Moser & Veselov, Commun. Math. Phys. 139, 217 (1991)]. It is second order, symplectic, equal to
RATTLE on SO(3), and an integrable discretisation: E and |m| are kept exactly (here: to round-off
plus the solver tolerance), so the numerical points lie on the true orbit and only the phase is
wrong [McLachlan & Zanna, Found. Comput. Math. 5, 87 (2005)].

The kernels use the trig-free quaternion form of Hairer & Vilmart (code ``DMV10.f``): with
``F`` the rotation of the unit quaternion ``(1, c) / sqrt(1 + |c|^2)``, the vector c is the fixed
point of ((i, j, k) cyclic)

    c_i = alpha (h/2) m_i / I_i + ((I_j - I_k) / I_i) c_j c_k,      alpha = 1 + |c|^2     (1)

and then

    m_{n+1,i} = m_{n,i} + (4/h) (I_j - I_k) c_j c_k / alpha,        q_{n+1} = q_n (1, c)/sqrt(alpha)

[Hairer & Vilmart, J. Phys. A 39, 13225 (2006); checked in shared/notes/literature.md 3.2]. (1) is
solved by fixed-point iteration from ``c = (h/2) w``, run to round-off: it stops when the change
of c (1-norm) is zero or no smaller than the previous one (the iterates have settled within
rounding), provided it is at most ``DMV_TOL`` times |c| (1-norm); at most
``DMV_MAX_ITER`` sweeps. Stopping at a fixed small tolerance instead leaves a systematic error in
every step, and the energy error then grows linearly (1e5 steps at h |w| ~ 0.1: 3e-14 against
2e-15 when run to round-off; Hairer, McLachlan & Razakarivony, BIT 48 (2008)). The
contraction factor is about ``h |w|``: h |w| ~ 0.1 takes ~13 sweeps, h |w| ~ 0.01 ~7. If it does
not converge (h far too large: no solution exists once h |m| exceeds ~ the spread of the moments)
the kernel returns a zero increment and -1 iterations, which the member loop reports as status 3
(not converged).

``dmv4`` runs the same map with per-step modified inverse moments of inertia
``1/I_i' = CSS / I_i + CDD`` built from the invariants |m|^2 and E (Hairer & Vilmart 2006), which
raises the order of both m and the attitude to 4 at the cost of ~15 flops per step; since the
modification depends only on invariants that the map keeps, E and |m| stay exact.
"""

import numpy as np
from numba import njit

from .rotations import cayley_attitude_increment, unless_failed
from .spec import N_BODY_PARAMS, P_I1, P_I2, P_I3, P_INV1, P_INV2, P_INV3, MethodSpec, body_params

#: Fixed-point stopping rule for (1): the change sum_i |c_i^new - c_i| is 0 or has stopped
#: decreasing, and is at most DMV_TOL sum_i |c_i^new| (16 ulps: a guard against accepting a
#: stagnation far from the fixed point).
DMV_TOL = 16.0 * 2.0**-52
#: Sweeps allowed before the step is declared not converged.
DMV_MAX_ITER = 100

# Hairer & Vilmart (2006), order-4 modified inertia (shared/notes/literature.md 3.2):
#   1/I_i' = CSS / I_i + CDD,  CSS = 1 + h^2 (S1 |m|^2/2 + S2 E),  CDD = h^2 (D1 |m|^2/2 + D2 E),
#   S1 = (I1 + I2 + I3) / (6 I1 I2 I3),  S2 = -(1/I1 + 1/I2 + 1/I3) / 3,
#   D1 = -1 / (3 I1 I2 I3),  D2 = S1.
P_S1, P_S2, P_D1, P_D2 = N_BODY_PARAMS, N_BODY_PARAMS + 1, N_BODY_PARAMS + 2, N_BODY_PARAMS + 3


def modified_inertia_params(moments, h=0.0):
    """Body parameters followed by the Hairer-Vilmart order-4 coefficients S1, S2, D1, D2."""
    p = body_params(moments, h)
    I1, I2, I3 = p[P_I1], p[P_I2], p[P_I3]
    s1 = (I1 + I2 + I3) / (6.0 * I1 * I2 * I3)
    s2 = -(1.0 / I1 + 1.0 / I2 + 1.0 / I3) / 3.0
    d1 = -1.0 / (3.0 * I1 * I2 * I3)
    return np.concatenate([p, [s1, s2, d1, s1]])


@njit(inline="always", error_model="numpy")
def dmv_solve(m1, m2, m3, h, b1, b2, b3, e1, e2, e3):
    """Fixed point c of (1) for inverse moments ``b_i = 1/I_i`` and differences ``e_i = I_j - I_k``.

    Returns ``(c1, c2, c3, alpha, iterations)``; iterations is -1 if the iteration did not settle
    within ``DMV_MAX_ITER`` sweeps (or left the finite numbers).
    """
    hh = 0.5 * h
    k1, k2, k3 = e1 * b1, e2 * b2, e3 * b3  # (I_j - I_k) / I_i
    g1, g2, g3 = hh * m1 * b1, hh * m2 * b2, hh * m3 * b3  # (h/2) w
    c1, c2, c3 = g1, g2, g3
    iterations = -1
    previous = np.inf
    for it in range(DMV_MAX_ITER):
        alpha = 1.0 + c1 * c1 + c2 * c2 + c3 * c3
        n1 = alpha * g1 + k1 * c2 * c3  # Eq. (1)
        n2 = alpha * g2 + k2 * c3 * c1
        n3 = alpha * g3 + k3 * c1 * c2
        # 1-norms: a sum propagates NaN, where max() could skip it and "converge" on NaN
        change = abs(n1 - c1) + abs(n2 - c2) + abs(n3 - c3)
        size = abs(n1) + abs(n2) + abs(n3)
        c1, c2, c3 = n1, n2, n3
        settled = change == 0.0 or change >= previous
        if settled and change <= DMV_TOL * size and size < np.inf:  # finite: overflow is failure
            iterations = it + 1
            break
        previous = change
    alpha = 1.0 + c1 * c1 + c2 * c2 + c3 * c3
    return c1, c2, c3, alpha, iterations


@njit(forceinline=True, error_model="numpy")
def dmv_increment(h, c1, c2, c3, alpha, e1, e2, e3):
    """m_{n+1} - m_n = (4/h) (I_j - I_k) c_j c_k / alpha (Hairer & Vilmart 2006)."""
    s = 4.0 / (h * alpha)
    return s * e1 * c2 * c3, s * e2 * c3 * c1, s * e3 * c1 * c2


@njit(forceinline=True, error_model="numpy")
def _dmv(m1, m2, m3, h, p):
    e1 = p[P_I2] - p[P_I3]
    e2 = p[P_I3] - p[P_I1]
    e3 = p[P_I1] - p[P_I2]
    c1, c2, c3, alpha, it = dmv_solve(m1, m2, m3, h, p[P_INV1], p[P_INV2], p[P_INV3], e1, e2, e3)
    d1, d2, d3 = dmv_increment(h, c1, c2, c3, alpha, e1, e2, e3)
    return d1, d2, d3, c1, c2, c3, it


@njit(forceinline=True, error_model="numpy")
def _dmv4(m1, m2, m3, h, p):
    b1, b2, b3 = p[P_INV1], p[P_INV2], p[P_INV3]
    half_l2 = 0.5 * (m1 * m1 + m2 * m2 + m3 * m3)
    energy = 0.5 * (m1 * m1 * b1 + m2 * m2 * b2 + m3 * m3 * b3)
    h2 = h * h
    css = 1.0 + h2 * (p[P_S1] * half_l2 + p[P_S2] * energy)
    cdd = h2 * (p[P_D1] * half_l2 + p[P_D2] * energy)
    b1m, b2m, b3m = css * b1 + cdd, css * b2 + cdd, css * b3 + cdd
    # I_j' - I_k' = (b_k' - b_j') / (b_j' b_k') with b_k' - b_j' = CSS (I_j - I_k) / (I_j I_k):
    # no cancellation for nearly equal moments.
    e1 = css * (p[P_I2] - p[P_I3]) * b2 * b3 / (b2m * b3m)
    e2 = css * (p[P_I3] - p[P_I1]) * b3 * b1 / (b3m * b1m)
    e3 = css * (p[P_I1] - p[P_I2]) * b1 * b2 / (b1m * b2m)
    c1, c2, c3, alpha, it = dmv_solve(m1, m2, m3, h, b1m, b2m, b3m, e1, e2, e3)
    d1, d2, d3 = dmv_increment(h, c1, c2, c3, alpha, e1, e2, e3)
    return d1, d2, d3, c1, c2, c3, it


@njit(inline="always", error_model="numpy")
def dmv_step(m1, m2, m3, h, p, s):
    """One DMV step; increment of m and fixed-point sweeps (-1 and a zero increment if failed)."""
    d1, d2, d3, c1, c2, c3, it = _dmv(m1, m2, m3, h, p)
    return unless_failed(d1, d2, d3, it)


@njit(inline="always", error_model="numpy")
def dmv_attitude_step(m1, m2, m3, q0, q1, q2, q3, h, p, s):
    """DMV on (m, q): also ``q <- q (1, c)/sqrt(1 + |c|^2)``; increments of m and q, sweeps."""
    d1, d2, d3, c1, c2, c3, it = _dmv(m1, m2, m3, h, p)
    return cayley_attitude_increment(d1, d2, d3, q0, q1, q2, q3, c1, c2, c3, it)


@njit(inline="always", error_model="numpy")
def dmv4_step(m1, m2, m3, h, p, s):
    """One order-4 modified-inertia DMV step; increment of m and fixed-point sweeps."""
    d1, d2, d3, c1, c2, c3, it = _dmv4(m1, m2, m3, h, p)
    return unless_failed(d1, d2, d3, it)


@njit(inline="always", error_model="numpy")
def dmv4_attitude_step(m1, m2, m3, q0, q1, q2, q3, h, p, s):
    """Order-4 DMV on (m, q); increments of m and q, fixed-point sweeps."""
    d1, d2, d3, c1, c2, c3, it = _dmv4(m1, m2, m3, h, p)
    return cayley_attitude_increment(d1, d2, d3, q0, q1, q2, q3, c1, c2, c3, it)


DMV = MethodSpec(
    name="dmv",
    title="discrete Moser-Veselov (quaternion fixed-point form)",
    order=2,
    step=dmv_step,
    params=body_params,
    family="Moser-Veselov",
    poisson=True,
    preserves_casimir=True,
    preserves_energy=True,
    symmetric=True,
    implicit=True,
    evaluations=1,
    reference=(
        "Moser & Veselov, Commun. Math. Phys. 139, 217 (1991); Hairer & Vilmart, "
        "J. Phys. A 39, 13225 (2006)"
    ),
    attitude_step=dmv_attitude_step,
    note=(
        "E and |L| to round-off and no regime changes near the separatrix; only the phase errs "
        "(order 2, large constant); ~13 fixed-point sweeps per step at h |w| ~ 0.1"
    ),
    # Median w error after 40 rad 0.28 at 0.3 rad, 0.47 at 0.4 (invariants to round-off).
    max_step_angle=0.3,
)

DMV4 = MethodSpec(
    name="dmv4",
    title="discrete Moser-Veselov with order-4 modified inertia",
    order=4,
    step=dmv4_step,
    params=modified_inertia_params,
    family="Moser-Veselov",
    poisson=True,
    preserves_casimir=True,
    preserves_energy=True,
    symmetric=True,
    implicit=True,
    evaluations=1,
    reference="Hairer & Vilmart, J. Phys. A 39, 13225 (2006)",
    attitude_step=dmv4_attitude_step,
    note=(
        "dmv's invariants at fourth order for ~15 extra flops per step; attitude also order 4"
    ),
    max_step_angle=1.0,  # median w error after 40 rad 0.29 at 1 rad, 0.68 at 1.2
)
