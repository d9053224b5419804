"""Integrators of the heavy top: RK4 and Lie-Poisson splittings exact in each part.

The heavy top on a fixed pivot (scene ``heavy_top``) has the state ``(m, g)``: the body angular
momentum about the pivot and the body-frame unit vector of the upward vertical. With principal
moments about the pivot I = diag(I1, I2, I3), w = I^-1 m and c = M g l chi (chi: the body-frame
unit vector from the pivot to the centre of mass), its equations are the Lie-Poisson equations
of H = m . I^-1 m / 2 + c . g on the dual of se(3) [Holm, Marsden & Ratiu, *Geometric Mechanics*
(2009), section 7.4; Marsden & Ratiu, *Introduction to Mechanics and Symmetry*, 15.10]::

    m' = m x w + g x c,    g' = g x w.                                   (1)

Casimirs: |g| and g . m; the energy H is kept by the flow.

The splitting writes H = T + V and the kinetic energy as the free body's split
(:mod:`stability.integrators.lie_poisson`), T = |m|^2 / (2 I2) + c1 m1^2 / 2 + c3 m3^2 / 2 with
c1 = (I2 - I1) / (I1 I2), c3 = (I2 - I3) / (I2 I3). Every piece has an exact flow [Touma &
Wisdom, Astron. J. 107, 1189 (1994); Dullweber, Leimkuhler & McLachlan, J. Chem. Phys. 107, 5840
(1997)]:

- ``K`` (kick, V = c . g): g is frozen and m' = g x c, so m <- m + t g x c;
- ``A`` (c1 m1^2 / 2): m and g both turn about body axis 1 by the angle -t c1 m1 (m1 is kept);
- ``S`` (|m|^2 / (2 I2) + c3 m3^2 / 2, the free symmetric top): m and g turn about axis 3 by
  -t c3 m3, and g turns about m by -t |m| / I2. The two commute ({|m|^2, m3^2} = 0), so S is
  the exact free flow of a top with I1 = I2; for such a top c1 = 0, A is the identity and the
  splitting is "free rotation of the body with the vertical carried along, then the gravity
  kick with the vertical frozen".

Each part is an exact rotation or a translation of m along g x c with g fixed, so |g| and g . m
are kept to round-off and the map is Poisson (energy error bounded, no drift). The Strang step
is K(h/2) A(h/2) S(h) A(h/2) K(h/2); compositions of it (Suzuki's, order 4) merge the kicks that
meet. The sequence is data in the parameter array, as for the free body, so every method of the
family runs one stage kernel (``splitting_stage``).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..integrators.composition import SUZUKI4, strang_table
from ..integrators.rk4 import euler_jvp, euler_rhs
from ..integrators.rotations import carried_rotation
from ..integrators.spec import (
    N_BODY_PARAMS, P_A1, P_A3, P_INV1, P_INV2, P_INV3, MethodSpec, body_params,
)

# Parameter layout: the body block (moments about the pivot, stability.integrators.spec), then
# c = M g l chi in the body frame (N m), then the stage table of the splittings.
P_C1, P_C2, P_C3 = N_BODY_PARAMS, N_BODY_PARAMS + 1, N_BODY_PARAMS + 2
#: Stage s of a splitting: its kind at P_TABLE + 2 s and its weight (fraction of h) next to it.
P_TABLE = N_BODY_PARAMS + 3
#: Stage kinds.
KICK, AXIS1, SYMMETRIC = 0.0, 1.0, 2.0
#: Numbers that describe a top to the kernels: I1, I2, I3 about the pivot, then c1, c2, c3.
N_TOP = 6


def top_params(top, h: float = 0.0) -> np.ndarray:
    """Kernel parameters of a top ``(I1, I2, I3, c1, c2, c3)`` (moments about the pivot in
    kg m2, ``c = M g l chi`` in N m); the same for every step ``h``."""
    top = np.asarray(top, dtype=float).reshape(-1)
    if top.size != N_TOP:
        raise ValueError(f"a top is described by {N_TOP} numbers (I1, I2, I3, c1, c2, c3), "
                         f"got {top.size}")
    return np.concatenate([body_params(top[:3], h), top[3:]])


@njit(forceinline=True, error_model="numpy")
def top_rhs(m1, m2, m3, g1, g2, g3, p):
    """Equations (1): ``m' = m x w + g x c``, ``g' = g x w`` with ``w = I^-1 m``."""
    e1, e2, e3 = euler_rhs(m1, m2, m3, p)  # m x w, written without cancellation
    c1, c2, c3 = p[P_C1], p[P_C2], p[P_C3]
    w1, w2, w3 = m1 * p[P_INV1], m2 * p[P_INV2], m3 * p[P_INV3]
    return (
        e1 + g2 * c3 - g3 * c2,
        e2 + g3 * c1 - g1 * c3,
        e3 + g1 * c2 - g2 * c1,
        g2 * w3 - g3 * w2,
        g3 * w1 - g1 * w3,
        g1 * w2 - g2 * w1,
    )


@njit(forceinline=True, error_model="numpy")
def top_jvp(m1, m2, m3, g1, g2, g3, v1, v2, v3, u1, u2, u3, p):
    """The Jacobian of :func:`top_rhs` applied to ``(dm, dg) = (v, u)``, exactly:
    ``dm' = dm x w + m x I^-1 dm + dg x c``, ``dg' = dg x w + g x I^-1 dm`` (equations (1)
    differentiated at any state; the scene's tangent equations)."""
    e1, e2, e3 = euler_jvp(m1, m2, m3, v1, v2, v3, p)  # dm x w + m x I^-1 dm
    c1, c2, c3 = p[P_C1], p[P_C2], p[P_C3]
    w1, w2, w3 = m1 * p[P_INV1], m2 * p[P_INV2], m3 * p[P_INV3]
    d1, d2, d3 = v1 * p[P_INV1], v2 * p[P_INV2], v3 * p[P_INV3]
    return (
        e1 + u2 * c3 - u3 * c2,
        e2 + u3 * c1 - u1 * c3,
        e3 + u1 * c2 - u2 * c1,
        u2 * w3 - u3 * w2 + g2 * d3 - g3 * d2,
        u3 * w1 - u1 * w3 + g3 * d1 - g1 * d3,
        u1 * w2 - u2 * w1 + g1 * d2 - g2 * d1,
    )


@njit(inline="always")
def rk4_step(m1, m2, m3, g1, g2, g3, h, p, s):
    """One classical RK4 step on equations (1); the increment of (m, g) and 0 iterations."""
    hh = 0.5 * h
    a1, a2, a3, a4, a5, a6 = top_rhs(m1, m2, m3, g1, g2, g3, p)
    b1, b2, b3, b4, b5, b6 = top_rhs(m1 + hh * a1, m2 + hh * a2, m3 + hh * a3,
                                     g1 + hh * a4, g2 + hh * a5, g3 + hh * a6, p)
    c1, c2, c3, c4, c5, c6 = top_rhs(m1 + hh * b1, m2 + hh * b2, m3 + hh * b3,
                                     g1 + hh * b4, g2 + hh * b5, g3 + hh * b6, p)
    d1, d2, d3, d4, d5, d6 = top_rhs(m1 + h * c1, m2 + h * c2, m3 + h * c3,
                                     g1 + h * c4, g2 + h * c5, g3 + h * c6, p)
    w = h / 6.0
    return (
        w * (a1 + 2.0 * (b1 + c1) + d1),
        w * (a2 + 2.0 * (b2 + c2) + d2),
        w * (a3 + 2.0 * (b3 + c3) + d3),
        w * (a4 + 2.0 * (b4 + c4) + d4),
        w * (a5 + 2.0 * (b5 + c5) + d5),
        w * (a6 + 2.0 * (b6 + c6) + d6),
        0,
    )


@njit(inline="always", error_model="numpy")
def splitting_stage(m1, m2, m3, g1, g2, g3, h, p, s):
    """Stage s of a splitting: one exact flow K, A or S (module docstring) for weight_s * h.

    Branch-free: the kick's time and the rotation angles are selected by the stage's kind (a
    stage-uniform value) and are zero for the flows that do not run, whose increments are then
    exactly zero. Increments are formed with cos - 1 (``sin_cosm1``), so small angles lose
    nothing.
    """
    kind = p[P_TABLE + 2 * s]
    t = p[P_TABLE + 2 * s + 1] * h
    # K: m <- m + t g x c.
    tk = t if kind == KICK else 0.0
    c1, c2, c3 = p[P_C1], p[P_C2], p[P_C3]
    k1 = tk * (g2 * c3 - g3 * c2)
    k2 = tk * (g3 * c1 - g1 * c3)
    k3 = tk * (g1 * c2 - g2 * c1)
    # A or S: m and g turn about body axis 1 (A) or 3 (S) by -theta, theta = t c_k m_k; S
    # also turns g about m by -t |m| / I2 (the kick is on m only).
    first = kind == AXIS1
    tr = t if kind != KICK else 0.0
    coefficient = -p[P_A3] if first else p[P_A1]  # c1 = -A3, c3 = A1
    theta = tr * coefficient * (m1 if first else m3)
    r1, r2, r3, e1, e2, e3 = carried_rotation(m1, m2, m3, g1, g2, g3, first, theta,
                                              t if kind == SYMMETRIC else 0.0, p[P_INV2])
    return k1 + r1, k2 + r2, k3 + r3, e1, e2, e3, 0


def sequence_params(gammas):
    """``params(top, h)`` of the Strang step K A S A K composed with weights ``gammas``.

    Strang step i of weight g_i is K(g_i/2) A(g_i/2) S(g_i) A(g_i/2) K(g_i/2); the kicks of
    neighbouring steps merge, so s steps cost 4 s + 1 stages.
    """
    table = strang_table(gammas, KICK, ((AXIS1, 0.5), (SYMMETRIC, 1.0), (AXIS1, 0.5)))

    def params(top, h=0.0):
        return np.concatenate([top_params(top, h), table])

    params.stages = table.size // 2
    return params


def splitting_spec(name, title, order, gammas, reference, note="", max_step_angle=None):
    """A registry entry for the heavy top's splitting composed with ``gammas``."""
    params = sequence_params(gammas)
    return MethodSpec(
        name=name,
        title=title,
        order=order,
        step=splitting_stage,
        params=params,
        family="Lie-Poisson splitting",
        poisson=True,
        preserves_casimir=True,
        symmetric=True,
        evaluations=params.stages,
        stages=params.stages,
        reference=reference,
        note=note,
        max_step_angle=max_step_angle,
    )


RK4 = MethodSpec(
    name="rk4",
    title="classical Runge-Kutta",
    order=4,
    step=rk4_step,
    params=top_params,
    family="Runge-Kutta",
    evaluations=4,
    reference="Kutta (1901); Hairer, Norsett & Wanner, Solving ODEs I, Table II.1.2",
    note="cheapest per step; |g|, g . m and the energy drift linearly",
)
LP2 = splitting_spec(
    "lp2",
    "Lie-Poisson splitting (free top + gravity kick, Strang)",
    2,
    (1.0,),
    "Touma & Wisdom, Astron. J. 107, 1189 (1994); Dullweber, Leimkuhler & McLachlan, "
    "J. Chem. Phys. 107, 5840 (1997)",
    note="keeps |g| and g . m to round-off, energy error bounded; exact free flow of a "
         "symmetric top",
)
LP4 = splitting_spec(
    "lp4",
    "Suzuki composition of the heavy-top splitting (5 stages)",
    4,
    SUZUKI4,
    "Suzuki, Phys. Lett. A 146, 319 (1990); Touma & Wisdom (1994)",
    note="fourth order at 21 exact flows per step; the Casimirs to round-off",
)

#: The heavy top's methods, by name.
METHODS = {spec.name: spec for spec in (RK4, LP2, LP4)}
