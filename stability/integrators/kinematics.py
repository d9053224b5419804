"""Attitude kernels for the methods whose m-kernel has no attitude of its own: RK4 and the
Lie-Poisson rotation sequences (lp2, lp4, lp6, lp8 and any other ``splitting_spec``).

Each twin has the signature of ``MethodSpec.attitude_step`` and advances m exactly as the
method's own kernel does (same operations, so a run with attitude reproduces the m of a run
without it), plus the body-to-space quaternion q (scalar first, Q' = Q hat(w)):

- Lie-Poisson: the flow of ``c_k m_k^2 / 2`` rotates m by ``R_k(-theta)`` and the attitude by
  ``Q <- Q R_k(+theta)``, theta = t c_k m_k; the Casimir part ``|m|^2 / (2 I2)`` of the split
  leaves m fixed and turns the attitude about m, ``Q <- Q exp(h hat(m) / I2)``; its flow commutes
  with the others, so it is applied once per step, at stage 0 [shared/notes/literature.md 3.1;
  Dullweber, Leimkuhler & McLachlan, J. Chem. Phys. 107, 5840 (1997)]. Every factor is a unit
  quaternion, so |q| stays 1 to round-off and R m is kept to round-off.
- RK4: classical RK4 on the joint system ``m' = m x I^-1 m``, ``q' = q (0, w) / 2``; order 4 for
  the attitude too; |q| is not kept exactly (it shrinks by O((h |w|)^6) per step).

``ATTITUDE_TWINS`` maps the m-kernel to its twin; ``stability.attitude.attitude_kernel`` looks a
method's kernel up there when its spec carries no ``attitude_step``.
"""

import math

from numba import njit

from ..trig import sin_cosm1
from .lie_poisson import P_STAGES, rotation_stage
from .rk4 import euler_rhs, rk4_step
from .rotations import quaternion_increment
from .spec import P_A1, P_A3, P_INV1, P_INV2, P_INV3


@njit(inline="always", error_model="numpy")
def rotation_attitude_stage(m1, m2, m3, q0, q1, q2, q3, h, p, s):
    """Stage s of a Lie-Poisson rotation sequence on (m, q); Casimir rotation at stage 0."""
    d1, d2, d3, it = rotation_stage(m1, m2, m3, h, p, s)
    outer = p[P_STAGES + 2 * s] == 0.0
    t = p[P_STAGES + 2 * s + 1] * h
    coefficient = -p[P_A3] if outer else p[P_A1]
    mk = m1 if outer else m3
    sk, ck = sin_cosm1(0.5 * (t * coefficient * mk))  # half of theta: R_k(+theta)
    b1 = sk if outer else 0.0
    b3 = 0.0 if outer else sk
    # Casimir: rotation about m by phi = h |m| / I2, once per step.
    norm = math.sqrt(m1 * m1 + m2 * m2 + m3 * m3)
    phi = (h if s == 0 else 0.0) * p[P_INV2] * norm
    sc, cc = sin_cosm1(0.5 * phi)
    scale = sc / norm if norm > 0.0 else 0.0
    a1, a2, a3 = scale * m1, scale * m2, scale * m3
    # r - 1 = (1 + a)(1 + b) - 1 = a + (1 + a) b, with a = r_casimir - 1, b = r_k - 1.
    u0, u1, u2, u3 = quaternion_increment(1.0 + cc, a1, a2, a3, ck, b1, 0.0, b3)
    e0, e1, e2, e3 = quaternion_increment(q0, q1, q2, q3, cc + u0, a1 + u1, a2 + u2, a3 + u3)
    return d1, d2, d3, e0, e1, e2, e3, it


@njit(inline="always")
def _qdot(q0, q1, q2, q3, w1, w2, w3):
    """q' = q (0, w) / 2."""
    e0, e1, e2, e3 = quaternion_increment(q0, q1, q2, q3, 0.0, w1, w2, w3)
    return 0.5 * e0, 0.5 * e1, 0.5 * e2, 0.5 * e3


@njit(inline="always")
def rk4_attitude_step(m1, m2, m3, q0, q1, q2, q3, h, p, s):
    """Classical RK4 on (m, q); the m part is the same arithmetic as ``rk4_step``."""
    b1, b2, b3 = p[P_INV1], p[P_INV2], p[P_INV3]
    hh = 0.5 * h
    a1, a2, a3 = euler_rhs(m1, m2, m3, p)
    ka0, ka1, ka2, ka3 = _qdot(q0, q1, q2, q3, b1 * m1, b2 * m2, b3 * m3)
    y1, y2, y3 = m1 + hh * a1, m2 + hh * a2, m3 + hh * a3
    bb1, bb2, bb3 = euler_rhs(y1, y2, y3, p)
    kb0, kb1, kb2, kb3 = _qdot(
        q0 + hh * ka0, q1 + hh * ka1, q2 + hh * ka2, q3 + hh * ka3, b1 * y1, b2 * y2, b3 * y3
    )
    y1, y2, y3 = m1 + hh * bb1, m2 + hh * bb2, m3 + hh * bb3
    c1, c2, c3 = euler_rhs(y1, y2, y3, p)
    kc0, kc1, kc2, kc3 = _qdot(
        q0 + hh * kb0, q1 + hh * kb1, q2 + hh * kb2, q3 + hh * kb3, b1 * y1, b2 * y2, b3 * y3
    )
    y1, y2, y3 = m1 + h * c1, m2 + h * c2, m3 + h * c3
    d1, d2, d3 = euler_rhs(y1, y2, y3, p)
    kd0, kd1, kd2, kd3 = _qdot(
        q0 + h * kc0, q1 + h * kc1, q2 + h * kc2, q3 + h * kc3, b1 * y1, b2 * y2, b3 * y3
    )
    w = h / 6.0
    return (
        w * (a1 + 2.0 * (bb1 + c1) + d1),
        w * (a2 + 2.0 * (bb2 + c2) + d2),
        w * (a3 + 2.0 * (bb3 + c3) + d3),
        w * (ka0 + 2.0 * (kb0 + kc0) + kd0),
        w * (ka1 + 2.0 * (kb1 + kc1) + kd1),
        w * (ka2 + 2.0 * (kb2 + kc2) + kd2),
        w * (ka3 + 2.0 * (kb3 + kc3) + kd3),
        0,
    )


#: m-kernel -> its attitude twin, for specs that declare no ``attitude_step``.
ATTITUDE_TWINS = {rotation_stage: rotation_attitude_stage, rk4_step: rk4_attitude_step}
