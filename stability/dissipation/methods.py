"""Step kernels of the damped bodies: RK4 for all three, and for the spherical damper
splittings that keep |H| to round-off.

**The body with a spherical damper** (scene ``sphere_damper``). A rigid shell of principal
moments I = diag(I1, I2, I3) holds at its centre a sphere of moment J in a viscous fluid, whose
torque on the shell is ``c (w_s - w)`` and on the sphere its opposite. The state is the shell's
angular momentum ``m = I w`` and the sphere's ``s = J w_s``, both in the shell's principal frame::

    m' = m x w + c u,    s' = s x w - c u,    w = I^-1 m,  u = w_s - w = s / J - w.      (1)

The total ``H = m + s`` obeys ``H' = H x w``: constant in space, so |H| is kept; the energy
``E = (m . I^-1 m + |s|^2 / J) / 2`` falls at the rate ``c |u|^2``. (1) splits into two flows
each solved exactly:

- ``F`` (c = 0): the free shell, m' = m x w, with s carried along (s' = s x w: the sphere keeps
  its spin in space). Its own splitting into the Lie-Poisson pieces of the free body
  (:mod:`stability.integrators.lie_poisson`): ``A`` turns m and s about body axis 1 by
  ``-t c1 m1``, ``S`` about axis 3 by ``-t c3 m3`` and s about m by ``-t |m| / I2``
  (:func:`~stability.integrators.rotations.carried_rotation`, the heavy top's free flow with
  its vertical); for an axisymmetric shell ``A S A`` is the exact free flow. Or the discrete
  Moser-Veselov map (:mod:`stability.integrators.moser_veselov`), a rotation F of the shell
  that keeps its energy exactly: ``m <- F^T m``, ``s <- F^T s``.
- ``D`` (the viscous coupling alone, no gyroscopic terms): H is constant componentwise and
  the relative rate ``u_k`` relaxes, ``u_k(t) = u_k exp(-r_k t)``, ``r_k = c (1/J + 1/I_k)``;
  so ``m_k <- m_k + mu_k u_k (1 - exp(-r_k t))`` and ``s_k`` by the opposite, with the reduced
  moment ``mu_k = I_k J / (I_k + J)``. (In each axis ``E = H_k^2 / (2 (I_k + J)) +
  mu_k u_k^2 / 2``: D lowers E, and stays exact however stiff the damper is.)

Each piece rotates H or keeps it, so every splitting keeps |H| to round-off. ``lp2`` is the
Strang step ``D(h/2) A(h/2) S(h) A(h/2) D(h/2)``, ``lp4`` its Suzuki composition (order 4; its
negative sub-steps run D backwards, raising E for a moment), ``dmv`` the Strang step
``D(h/2) DMV(h) D(h/2)``: DMV keeps E and D lowers it, so E never rises from step to step (to
round-off), on any body. ``lp2`` does the same where A S A is exact (an axisymmetric shell).

**The body with whip antennas** (scene ``whip_damper``): two pairs of tip masses on springs
with dashpots, bending along the spin axis (:mod:`stability.dissipation.scene`); RK4 only (|H|
drifts as RK4's error does).

**The gyrostat** (scene ``gyrostat``, a dual-spin body): a platform and an axisymmetric rotor on
a frictionless bearing along the platform's principal axis e3, with a spherical damper on the
platform and one in the rotor (either may be absent, c = 0). The state, in the platform's
principal frame: ``m`` the angular momentum of platform and rotor, ``h_r`` the rotor's axial
angular momentum, ``p`` and ``q`` those of the platform's and the rotor's damper spheres::

    w = (m1 / A1, m2 / A2, (m3 - h_r) / (A3 - Jr)),   w_r = (w1, w2, h_r / Jr),
    u_p = p / Jp - w,   u_q = q / Jq - w_r,
    m' = m x w + cp u_p + cq u_q,   h_r' = cq u_q3,
    p' = p x w - cp u_p,            q' = q x w - cq u_q,                               (2)

(A1, A2, A3 the whole body's principal moments, the rotor's included; derivation in
:mod:`stability.dissipation.model_gyrostat`). The total ``H = m + p + q`` obeys ``H' = H x w``: |H|
is kept; the energy falls at ``cp |u_p|^2 + cq |u_q|^2``. RK4 only.

The RK4 kernels are the package's one RK4 text (:func:`stability.integrators.rk4.rk4_source`,
as :func:`stability.define_scene` writes it) applied to each right-hand side.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..integrators.composition import SUZUKI4, strang_table
from ..integrators.moser_veselov import dmv_solve
from ..integrators.rk4 import euler_jvp, euler_rhs, rk4_source
from ..integrators.rotations import cayley_increment, carried_rotation
from ..integrators.spec import (N_BODY_PARAMS, P_A1, P_A3, P_I1, P_I2, P_I3, P_INV1, P_INV2,
                                P_INV3, MethodSpec, body_params)

# --- the spherical damper ----------------------------------------------------------------------

#: Parameter layout after the shell's body block: J, 1/J, c, the relaxation rates r_k, the
#: reduced moments mu_k and the relaxation factors of half a step ``expm1(-r_k h / 2)``; then the
#: stage table of the splittings.
P_J, P_INV_J, P_C = N_BODY_PARAMS, N_BODY_PARAMS + 1, N_BODY_PARAMS + 2
P_RATE = N_BODY_PARAMS + 3  #: r_1, r_2, r_3 at P_RATE + k
P_MU = N_BODY_PARAMS + 6  #: mu_1, mu_2, mu_3 at P_MU + k
P_HALF = N_BODY_PARAMS + 9  #: expm1(-r_k h / 2) at P_HALF + k
P_TABLE = N_BODY_PARAMS + 12
#: Numbers per stage in the table: its kind, its weight (fraction of h) and the relaxation
#: factors ``expm1(-r_k weight h)`` of a D stage (zeros for the others).
STAGE_WIDTH = 5
#: Stage kinds of the splittings: the damper's relaxation D, the flows A and S.
DAMP, AXIS1, SYMMETRIC = 0.0, 1.0, 2.0
#: Numbers that describe a damped body: I1, I2, I3 (the shell), J, c.
N_SPHERE = 5


def sphere_params(values, h: float = 0.0) -> np.ndarray:
    """Kernel row of a body with a spherical damper ``(I1, I2, I3, J, c)`` (kg m2, kg m2,
    N m s) for the step ``h``: the shell's body block, then ``J, 1/J, c``,
    ``r_k = c (1/J + 1/I_k)``, ``mu_k = I_k J / (I_k + J)`` and ``expm1(-r_k h / 2)``.

    The relaxation factors are made here, once, so that the kernels need no exponential (and
    vectorize): run the row with the ``h`` it was made for.

    Raises
    ------
    ValueError
        Not five numbers, a moment or J not positive and finite, or c negative.
    """
    values = np.asarray(values, dtype=float).reshape(-1)
    if values.size != N_SPHERE:
        raise ValueError(f"a body with a spherical damper is {N_SPHERE} numbers "
                         f"(I1, I2, I3, J, c), got {values.size}")
    moments, J, c = values[:3], values[3], values[4]
    if not (np.all(np.isfinite(values)) and np.all(moments > 0) and J > 0 and c >= 0):
        raise ValueError(f"the shell's moments and J must be positive and c >= 0, all finite; "
                         f"got I = {moments.tolist()}, J = {J!r}, c = {c!r}")
    rates = c * (1.0 / J + 1.0 / moments)
    return np.concatenate([body_params(moments, h), [J, 1.0 / J, c], rates,
                           moments * J / (moments + J), np.expm1(-0.5 * h * rates)])


@njit(forceinline=True, error_model="numpy")
def sphere_rhs(m1, m2, m3, s1, s2, s3, p):
    """Equations (1): ``m' = m x w + c u``, ``s' = s x w - c u``."""
    e1, e2, e3 = euler_rhs(m1, m2, m3, p)  # m x w, written without cancellation
    w1, w2, w3 = m1 * p[P_INV1], m2 * p[P_INV2], m3 * p[P_INV3]
    c, inv_j = p[P_C], p[P_INV_J]
    t1, t2, t3 = c * (s1 * inv_j - w1), c * (s2 * inv_j - w2), c * (s3 * inv_j - w3)
    return (e1 + t1, e2 + t2, e3 + t3,
            s2 * w3 - s3 * w2 - t1, s3 * w1 - s1 * w3 - t2, s1 * w2 - s2 * w1 - t3)


@njit(forceinline=True, error_model="numpy")
def sphere_jvp(m1, m2, m3, s1, s2, s3, v1, v2, v3, u1, u2, u3, p):
    """The Jacobian of :func:`sphere_rhs` applied to ``(dm, ds) = (v, u)``, exactly:
    ``dm' = dm x w + m x I^-1 dm + c du_rel``, ``ds' = ds x w + s x I^-1 dm - c du_rel`` with
    ``du_rel = ds / J - I^-1 dm`` (equation (1) of :mod:`stability.dissipation.model` at any
    state)."""
    e1, e2, e3 = euler_jvp(m1, m2, m3, v1, v2, v3, p)
    w1, w2, w3 = m1 * p[P_INV1], m2 * p[P_INV2], m3 * p[P_INV3]
    d1, d2, d3 = v1 * p[P_INV1], v2 * p[P_INV2], v3 * p[P_INV3]
    c, inv_j = p[P_C], p[P_INV_J]
    t1, t2, t3 = c * (u1 * inv_j - d1), c * (u2 * inv_j - d2), c * (u3 * inv_j - d3)
    return (e1 + t1, e2 + t2, e3 + t3,
            u2 * w3 + s2 * d3 - u3 * w2 - s3 * d2 - t1,
            u3 * w1 + s3 * d1 - u1 * w3 - s1 * d3 - t2,
            u1 * w2 + s1 * d2 - u2 * w1 - s2 * d1 - t3)


@njit(forceinline=True, error_model="numpy")
def relaxation(m1, m2, m3, s1, s2, s3, f1, f2, f3, p):
    """The exact flow D for the time t with ``f_k = expm1(-r_k t)``: the increment of m,
    ``-mu_k u_k f_k = mu_k u_k (1 - exp(-r_k t))`` (that of s is its opposite, so H is kept
    exactly); zero where f = 0."""
    inv_j = p[P_INV_J]
    return (-p[P_MU] * (s1 * inv_j - m1 * p[P_INV1]) * f1,
            -p[P_MU + 1] * (s2 * inv_j - m2 * p[P_INV2]) * f2,
            -p[P_MU + 2] * (s3 * inv_j - m3 * p[P_INV3]) * f3)


@njit(inline="always", error_model="numpy")
def splitting_stage(m1, m2, m3, s1, s2, s3, h, p, s):
    """Stage s of ``lp2``/``lp4``: one exact flow D, A or S for ``weight_s * h``.

    Branch-free like the heavy top's: the flows that do not run get zero times (and a D stage's
    factors are zero elsewhere), whose increments are exactly zero.
    """
    row = P_TABLE + STAGE_WIDTH * s
    kind = p[row]
    t = p[row + 1] * h
    d1, d2, d3 = relaxation(m1, m2, m3, s1, s2, s3, p[row + 2], p[row + 3], p[row + 4], p)
    first = kind == AXIS1
    coefficient = -p[P_A3] if first else p[P_A1]  # c1 = -A3, c3 = A1
    theta = (t if kind != DAMP else 0.0) * coefficient * (m1 if first else m3)
    r1, r2, r3, e1, e2, e3 = carried_rotation(m1, m2, m3, s1, s2, s3, first, theta,
                                              t if kind == SYMMETRIC else 0.0, p[P_INV2])
    return d1 + r1, d2 + r2, d3 + r3, e1 - d1, e2 - d2, e3 - d3, 0


@njit(inline="always", error_model="numpy")
def dmv_stage(m1, m2, m3, s1, s2, s3, h, p, s):
    """Stage s of ``dmv``: D(h/2) at s = 0 and 2, the Moser-Veselov rotation F at s = 1.

    F is the Cayley rotation of the fixed point c of the DMV equation of the shell
    (:func:`~stability.integrators.moser_veselov.dmv_solve`); m and s both become F^T m, F^T s.
    A failed solve gives zero increments and -1 iterations (status not converged).
    """
    if s != 1:
        d1, d2, d3 = relaxation(m1, m2, m3, s1, s2, s3, p[P_HALF], p[P_HALF + 1],
                                p[P_HALF + 2], p)
        return d1, d2, d3, -d1, -d2, -d3, 0
    c1, c2, c3, alpha, it = dmv_solve(m1, m2, m3, h, p[P_INV1], p[P_INV2], p[P_INV3],
                                      p[P_I2] - p[P_I3], p[P_I3] - p[P_I1], p[P_I1] - p[P_I2])
    ok = it > 0
    a1, a2, a3 = cayley_increment(m1, m2, m3, c1, c2, c3)
    b1, b2, b3 = cayley_increment(s1, s2, s3, c1, c2, c3)
    return ((a1 if ok else 0.0), (a2 if ok else 0.0), (a3 if ok else 0.0),
            (b1 if ok else 0.0), (b2 if ok else 0.0), (b3 if ok else 0.0), it)


def sphere_splitting_params(gammas):
    """``params(values, h)`` of the Strang step D A S A D composed with weights ``gammas``: the
    row of :func:`sphere_params`, then per stage its kind, weight and relaxation factors."""
    pairs = strang_table(gammas, DAMP, ((AXIS1, 0.5), (SYMMETRIC, 1.0), (AXIS1, 0.5)))
    pairs = pairs.reshape(-1, 2)
    damp = pairs[:, 0] == DAMP

    def params(values, h=0.0):
        row = sphere_params(values, h)
        rates = row[P_RATE:P_RATE + 3]
        factors = np.where(damp[:, None], np.expm1(-np.outer(pairs[:, 1] * h, rates)), 0.0)
        return np.concatenate([row, np.hstack([pairs, factors]).ravel()])

    params.stages = pairs.shape[0]
    return params


# --- the whip antennas ----------------------------------------------------------------------

#: Parameter layout of the whip antennas: I1, I2, I3 (the body without the tips), the mass mu of
#: a pair of tips, the arm b, the spring k and the damping c of a pair; then 1/mu, mu b and
#: 2 mu b^2.
B_I1, B_I2, B_I3, B_MU, B_B, B_K, B_C, B_INV_MU, B_MU_B, B_2MU_B2 = range(10)
#: Numbers that describe a body with whip antennas: I1, I2, I3, mu, b, k, c.
N_WHIP = 7


def whip_params(values, h: float = 0.0) -> np.ndarray:
    """Kernel row of a body with two pairs of whip antennas ``(I1, I2, I3, mu, b, k, c)``
    (kg m2, kg, m, N m-1, N s m-1; mu, k and c of a pair of tips), then ``1/mu``, ``mu b`` and
    ``2 mu b^2``; the same for every step ``h``.

    Raises
    ------
    ValueError
        Not seven numbers, a moment or mu not positive, or b, k, c negative (all finite).
    """
    values = np.asarray(values, dtype=float).reshape(-1)
    if values.size != N_WHIP:
        raise ValueError(f"a body with whip antennas is {N_WHIP} numbers "
                         f"(I1, I2, I3, mu, b, k, c), got {values.size}")
    if not (np.all(np.isfinite(values)) and np.all(values[:4] > 0)
            and np.all(values[4:] >= 0)):
        raise ValueError(f"the moments and mu must be positive and b, k, c >= 0, all finite; "
                         f"got {values.tolist()}")
    mu, b = values[B_MU], values[B_B]
    return np.concatenate([values, [1.0 / mu, mu * b, 2.0 * mu * b * b]])


@njit(forceinline=True, error_model="numpy")
def whip_rates(H1, H2, H3, z2, z3, p2, p3, p):
    """The angular velocity w and the tips' rates from the state (scene ``whip_damper``): the
    arrow system ``K w = (H1, H2 - b p3, H3 + b p2)``,
    ``K = [[I1 + 2 mu b^2, -mu b z2, -mu b z3], [-mu b z2, I2 + mu Z^2, 0],
    [-mu b z3, 0, I3 + mu Z^2]]`` (``Z^2 = z2^2 + z3^2``), then ``z2' = p2 / mu + b w3``,
    ``z3' = p3 / mu - b w2``."""
    b = p[B_B]
    mz2 = p[B_MU] * (z2 * z2 + z3 * z3)
    k11 = p[B_I1] + p[B_2MU_B2]
    k22 = p[B_I2] + mz2
    k33 = p[B_I3] + mz2
    g2, g3 = p[B_MU_B] * z2, p[B_MU_B] * z3
    r2, r3 = H2 - b * p3, H3 + b * p2
    w1 = (H1 + g2 * r2 / k22 + g3 * r3 / k33) / (k11 - g2 * g2 / k22 - g3 * g3 / k33)
    w2 = (r2 + g2 * w1) / k22
    w3 = (r3 + g3 * w1) / k33
    inv_mu = p[B_INV_MU]
    return w1, w2, w3, p2 * inv_mu + b * w3, p3 * inv_mu - b * w2


@njit(forceinline=True, error_model="numpy")
def whip_rhs(H1, H2, H3, z2, z3, p2, p3, p):
    """``H' = H x w``, ``z2' = p2 / mu + b w3``, ``z3' = p3 / mu - b w2``,
    ``p2' = mu (z2 (w2^2 + w3^2) - b w1 w2) - k z2 - c z2'`` and
    ``p3' = mu (z3 (w2^2 + w3^2) - b w1 w3) - k z3 - c z3'``."""
    w1, w2, w3, dz2, dz3 = whip_rates(H1, H2, H3, z2, z3, p2, p3, p)
    mu, b, k, c = p[B_MU], p[B_B], p[B_K], p[B_C]
    across = w2 * w2 + w3 * w3
    return (H2 * w3 - H3 * w2, H3 * w1 - H1 * w3, H1 * w2 - H2 * w1, dz2, dz3,
            mu * (z2 * across - b * w1 * w2) - k * z2 - c * dz2,
            mu * (z3 * across - b * w1 * w3) - k * z3 - c * dz3)


# --- the gyrostat ----------------------------------------------------------------------------

#: Parameter layout of the gyrostat: 1/A1, 1/A2, 1/(A3 - Jr) (the platform's inverse moments,
#: the rotor's transverse moment included, its axial one not), 1/Jr, then 1/Jp, cp (the platform's
#: damper) and 1/Jq, cq (the rotor's); then the eight numbers as given.
G_INV_A1, G_INV_A2, G_INV_A3, G_INV_JR, G_INV_JP, G_CP, G_INV_JQ, G_CQ = range(8)
G_VALUES = 8  #: A1, A2, A3, Jr, Jp, cp, Jq, cq at G_VALUES + k
#: Numbers that describe a gyrostat: A1, A2, A3, Jr, Jp, cp, Jq, cq.
N_GYROSTAT = 8


def gyrostat_params(values, h: float = 0.0) -> np.ndarray:
    """Kernel row of a gyrostat ``(A1, A2, A3, Jr, Jp, cp, Jq, cq)`` (kg m2 and N m s): the
    whole body's principal moments (the rotor's included), the rotor's axial moment, and the
    moment and viscous coefficient of the platform's damper and of the rotor's (c = 0: no
    damper); the same for every step ``h``.

    Raises
    ------
    ValueError
        Not eight numbers, not all finite, a moment not positive, ``A3 <= Jr`` (the platform
        itself has no axial moment left), or a coefficient negative.
    """
    values = np.asarray(values, dtype=float).reshape(-1)
    if values.size != N_GYROSTAT:
        raise ValueError(f"a gyrostat is {N_GYROSTAT} numbers (A1, A2, A3, Jr, Jp, cp, Jq, cq), "
                         f"got {values.size}")
    A1, A2, A3, Jr, Jp, cp, Jq, cq = values
    if not (np.all(np.isfinite(values)) and min(A1, A2, A3, Jr, Jp, Jq) > 0
            and cp >= 0 and cq >= 0):
        raise ValueError(f"the moments A1, A2, A3, Jr, Jp, Jq must be positive and cp, cq >= 0, "
                         f"all finite; got {values.tolist()}")
    if not A3 > Jr:
        raise ValueError(f"A3 (the whole body's axial moment, {A3!r}) must exceed the rotor's "
                         f"Jr ({Jr!r}): the platform's own axial moment is A3 - Jr")
    return np.concatenate([[1.0 / A1, 1.0 / A2, 1.0 / (A3 - Jr), 1.0 / Jr, 1.0 / Jp, cp,
                            1.0 / Jq, cq], values])


@njit(forceinline=True, error_model="numpy")
def gyrostat_rhs(m1, m2, m3, hr, p1, p2, p3, q1, q2, q3, p):
    """Equations (2): ``m' = m x w + cp u_p + cq u_q``, ``h_r' = cq u_q3``,
    ``p' = p x w - cp u_p``, ``q' = q x w - cq u_q``."""
    w1, w2, w3 = m1 * p[G_INV_A1], m2 * p[G_INV_A2], (m3 - hr) * p[G_INV_A3]
    cp, cq, inv_p, inv_q = p[G_CP], p[G_CQ], p[G_INV_JP], p[G_INV_JQ]
    a1, a2, a3 = cp * (p1 * inv_p - w1), cp * (p2 * inv_p - w2), cp * (p3 * inv_p - w3)
    b1, b2 = cq * (q1 * inv_q - w1), cq * (q2 * inv_q - w2)
    b3 = cq * (q3 * inv_q - hr * p[G_INV_JR])
    return (m2 * w3 - m3 * w2 + a1 + b1, m3 * w1 - m1 * w3 + a2 + b2,
            m1 * w2 - m2 * w1 + a3 + b3, b3,
            p2 * w3 - p3 * w2 - a1, p3 * w1 - p1 * w3 - a2, p1 * w2 - p2 * w1 - a3,
            q2 * w3 - q3 * w2 - b1, q3 * w1 - q1 * w3 - b2, q1 * w2 - q2 * w1 - b3)


@njit(forceinline=True, error_model="numpy")
def gyrostat_jvp(m1, m2, m3, hr, p1, p2, p3, q1, q2, q3,
                 dm1, dm2, dm3, dhr, dp1, dp2, dp3, dq1, dq2, dq3, p):
    """The Jacobian of :func:`gyrostat_rhs` applied to ``(dm, dh_r, dp, dq)``, exactly:
    equations (2) differentiated at any state, with ``dw = (dm1/A1, dm2/A2, (dm3 - dh_r) /
    (A3 - Jr))``, ``du_p = dp/Jp - dw``, ``du_q = dq/Jq - (dw1, dw2, dh_r/Jr)`` and
    ``d(a x w) = da x w + a x dw``."""
    w1, w2, w3 = m1 * p[G_INV_A1], m2 * p[G_INV_A2], (m3 - hr) * p[G_INV_A3]
    d1, d2, d3 = dm1 * p[G_INV_A1], dm2 * p[G_INV_A2], (dm3 - dhr) * p[G_INV_A3]
    cp, cq, inv_p, inv_q = p[G_CP], p[G_CQ], p[G_INV_JP], p[G_INV_JQ]
    a1, a2, a3 = cp * (dp1 * inv_p - d1), cp * (dp2 * inv_p - d2), cp * (dp3 * inv_p - d3)
    b1, b2 = cq * (dq1 * inv_q - d1), cq * (dq2 * inv_q - d2)
    b3 = cq * (dq3 * inv_q - dhr * p[G_INV_JR])
    return (dm2 * w3 + m2 * d3 - dm3 * w2 - m3 * d2 + a1 + b1,
            dm3 * w1 + m3 * d1 - dm1 * w3 - m1 * d3 + a2 + b2,
            dm1 * w2 + m1 * d2 - dm2 * w1 - m2 * d1 + a3 + b3, b3,
            dp2 * w3 + p2 * d3 - dp3 * w2 - p3 * d2 - a1,
            dp3 * w1 + p3 * d1 - dp1 * w3 - p1 * d3 - a2,
            dp1 * w2 + p1 * d2 - dp2 * w1 - p2 * d1 - a3,
            dq2 * w3 + q2 * d3 - dq3 * w2 - q3 * d2 - b1,
            dq3 * w1 + q3 * d1 - dq1 * w3 - q1 * d3 - b2,
            dq1 * w2 + q1 * d2 - dq2 * w1 - q2 * d1 - b3)


# --- RK4 of the right-hand sides: the package's one RK4 text ----------------------------------

exec(rk4_source(6, "sphere_rhs", "sphere_rk4_step"))  # noqa: S102 (a fixed text of ours)
exec(rk4_source(7, "whip_rhs", "whip_rk4_step"))  # noqa: S102
exec(rk4_source(10, "gyrostat_rhs", "gyrostat_rk4_step"))  # noqa: S102

_RK4 = dict(title="classical Runge-Kutta", order=4, family="Runge-Kutta", evaluations=4,
            reference="Kutta (1901); Hairer, Norsett & Wanner, Solving ODEs I, Table II.1.2")

SPHERE_RK4 = MethodSpec(
    name="rk4", step=sphere_rk4_step, params=sphere_params,  # noqa: F821 (made above)
    note="cheapest per step; |H| drifts with RK4's error, E need not fall every step, and a "
         "stiff damper (h r_k > 2.8) blows it up", **_RK4)
SPHERE_LP2 = MethodSpec(
    name="lp2", title="Strang splitting: damper relaxation and Lie-Poisson free flow", order=2,
    step=splitting_stage, params=sphere_splitting_params((1.0,)),
    family="splitting (exact flows)", preserves_casimir=True, symmetric=True,
    evaluations=5, stages=5,
    reference="Strang (1968); McLachlan, PRL 71, 3043 (1993); Touma & Wisdom, AJ 107, 1189 "
              "(1994); the relaxation solved exactly",
    note="|H| to round-off at any damping; E falls every step where the shell is "
         "axisymmetric (its free flow is then exact)")
SPHERE_LP4 = MethodSpec(
    name="lp4", title="Suzuki composition of lp2 (5 stages)", order=4,
    step=splitting_stage, params=sphere_splitting_params(SUZUKI4),
    family="splitting (exact flows)", preserves_casimir=True, symmetric=True,
    evaluations=21, stages=21, reference="Suzuki, Phys. Lett. A 146, 319 (1990)",
    note="|H| to round-off, order 4; its backward sub-steps may raise E within a step")
SPHERE_DMV = MethodSpec(
    name="dmv", title="Strang splitting: damper relaxation and Moser-Veselov free flow",
    order=2, step=dmv_stage, params=sphere_params, family="splitting (exact flows)",
    preserves_casimir=True, symmetric=True, implicit=True, evaluations=3, stages=3,
    reference="Moser & Veselov, Commun. Math. Phys. 139, 217 (1991); Hairer & Vilmart, "
              "J. Phys. A 39, 13225 (2006)",
    note="|H| to round-off and E falling every step on any body; ~10 fixed-point sweeps a step")

#: The methods of scene ``sphere_damper``, by name.
SPHERE_METHODS = {spec.name: spec for spec in (SPHERE_RK4, SPHERE_LP2, SPHERE_LP4, SPHERE_DMV)}

WHIP_RK4 = MethodSpec(name="rk4", step=whip_rk4_step, params=whip_params,  # noqa: F821
                      note="|H| and the energy balance to RK4's error", **_RK4)
#: The methods of scene ``whip_damper``, by name.
WHIP_METHODS = {WHIP_RK4.name: WHIP_RK4}

GYROSTAT_RK4 = MethodSpec(name="rk4", step=gyrostat_rk4_step,  # noqa: F821 (made above)
                          params=gyrostat_params,
                          note="|H| and the energy balance to RK4's error; a stiff damper "
                               "(h c (1/J + 1/A) > 2.8) blows it up", **_RK4)
#: The methods of scene ``gyrostat``, by name.
GYROSTAT_METHODS = {GYROSTAT_RK4.name: GYROSTAT_RK4}
