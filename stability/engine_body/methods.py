"""The update rules physics and game engines use for a torque-free rigid body.

Engines store the space-frame angular velocity ``omega_w`` and a unit quaternion q (body to
space, scalar first, Hamilton product) and each frame of step h do a velocity update, then a
rotation update. State ``(omega_w1, omega_w2, omega_w3, q0, q1, q2, q3)``, canonical frame
(``I1 <= I2 <= I3``), parameters :func:`~stability.integrators.spec.body_params`. With
``R = R(q / |q|)`` at the start of the step, ``I_w = R diag(I) R^T`` and the body angular
velocity ``w = R^T omega_w``, the gyroscopic update ``omega_w + h I_w^-1 (-omega_w x I_w
omega_w)`` is ``R (w + dw)`` with ``I dw = h (I w) x w``: explicit Euler on Euler's equations in
body coordinates (computed so, increments without cancellation). The rotation update is always

    q' = normalize(q + (h/2) (0, omega) q)                                          (R)

with omega the old (``explicit_euler``) or the new (all the others) space angular velocity.
Because (R) with the new omega turns the body about omega' itself, the body angular velocity
after such a step is exactly the velocity rule's body update. Consequences: the body motion of
``semi_implicit_euler`` is explicit Euler on Euler's equations (energy grows by
``dw . I dw / 2`` a step), while ``explicit_euler`` also turns the new velocity about the old
one by the step angle, which takes ``dw . I dw`` off the energy: it loses energy at the rate
the semi-implicit rule gains it (the engines that report an energy gain advance the attitude
with the updated velocity, as ``semi_implicit_euler`` does). Both rescalings drift toward the
separatrix ``2 E I2 = |L|^2``. ``no_gyroscopic`` keeps the body angular velocity constant: no
intermediate-axis flip. Every rule keeps |q| = 1 to rounding; none keeps the spatial angular
momentum. Sources: each spec's ``reference`` (Bullet #346, #357; ODE patch 185; Catto, GDC 2015;
Jolt ``MotionProperties.inl``; Avian #738, #993; NVIDIAGameWorks/PhysX#394; Godot #50173, #80703).
"""

from __future__ import annotations

import math

from numba import njit

from ..integrators.rotations import rotate_increment, solve3
from ..integrators.spec import (
    P_A1, P_A2, P_A3, P_I1, P_I2, P_I3, P_INV1, P_INV2, P_INV3, MethodSpec, body_params,
)


@njit(forceinline=True, error_model="numpy")
def rotate3(q0, q1, q2, q3, x1, x2, x3, sign):
    """``R x`` (sign = 1) or ``R^T x`` (sign = -1) for ``R = R(q / |q|)``:
    ``x + (2 / |q|^2) (sign q0 v x x + v x (v x x))`` with v = (q1, q2, q3)."""
    s = 2.0 / (q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3)
    d1, d2, d3 = rotate_increment(q1, q2, q3, x1, x2, x3, sign * q0 * s, s)
    return x1 + d1, x2 + d2, x3 + d3


@njit(forceinline=True, error_model="numpy")
def _rotation_update(q0, q1, q2, q3, o1, o2, o3, h):
    """Increment of (R): ``u / |u| - q`` with ``u = q + d``, ``d = (h/2) (0, omega) q``.

    d is orthogonal to q, so ``|u|^2 = |q|^2 + |d|^2``; ``1/|u| - 1`` is formed without
    cancellation.
    """
    k = 0.5 * h
    d0 = -k * (o1 * q1 + o2 * q2 + o3 * q3)
    d1 = k * (q0 * o1 + o2 * q3 - o3 * q2)
    d2 = k * (q0 * o2 + o3 * q1 - o1 * q3)
    d3 = k * (q0 * o3 + o1 * q2 - o2 * q1)
    n2 = q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3 + (d0 * d0 + d1 * d1 + d2 * d2 + d3 * d3)
    n = math.sqrt(n2)
    inv = 1.0 / n
    cm1 = (1.0 - n2) * inv / (1.0 + n)  # 1/|u| - 1
    return (d0 * inv + q0 * cm1, d1 * inv + q1 * cm1, d2 * inv + q2 * cm1, d3 * inv + q3 * cm1)


@njit(forceinline=True, error_model="numpy")
def _gyroscopic(w1, w2, w3, h, p):
    """Explicit Euler increment of the body angular momentum: ``h (I w) x w`` (= h m x I^-1 m)."""
    m1, m2, m3 = p[P_I1] * w1, p[P_I2] * w2, p[P_I3] * w3
    return h * p[P_A1] * m2 * m3, h * p[P_A2] * m3 * m1, h * p[P_A3] * m1 * m2


@njit(forceinline=True, error_model="numpy")
def _finish(x0, x1, x2, q0, q1, q2, q3, g1, g2, g3, h, new, it):
    """Increments of the state from the body velocity increment g: ``omega_w' = omega_w + R g``,
    then (R) with the new (``new``) or the old omega_w."""
    e1, e2, e3 = rotate3(q0, q1, q2, q3, g1, g2, g3, 1.0)
    o1 = x0 + e1 if new else x0
    o2 = x1 + e2 if new else x1
    o3 = x2 + e3 if new else x2
    r0, r1, r2, r3 = _rotation_update(q0, q1, q2, q3, o1, o2, o3, h)
    return e1, e2, e3, r0, r1, r2, r3, it


@njit(inline="always")
def explicit_euler_step(x0, x1, x2, q0, q1, q2, q3, h, p, s):
    """``omega_w' = omega_w - h I_w^-1 (omega_w x I_w omega_w)``, (R) with the old omega_w."""
    w1, w2, w3 = rotate3(q0, q1, q2, q3, x0, x1, x2, -1.0)
    d1, d2, d3 = _gyroscopic(w1, w2, w3, h, p)
    return _finish(x0, x1, x2, q0, q1, q2, q3, p[P_INV1] * d1, p[P_INV2] * d2, p[P_INV3] * d3,
                   h, False, 0)


@njit(inline="always")
def semi_implicit_euler_step(x0, x1, x2, q0, q1, q2, q3, h, p, s):
    """The same velocity update, (R) with the new omega_w (symplectic Euler)."""
    w1, w2, w3 = rotate3(q0, q1, q2, q3, x0, x1, x2, -1.0)
    d1, d2, d3 = _gyroscopic(w1, w2, w3, h, p)
    return _finish(x0, x1, x2, q0, q1, q2, q3, p[P_INV1] * d1, p[P_INV2] * d2, p[P_INV3] * d3,
                   h, True, 0)


@njit(inline="always", error_model="numpy")
def implicit_euler_step(x0, x1, x2, q0, q1, q2, q3, h, p, s):
    """``I (w2 - w1) + h w2 x I w2 = 0`` in body coordinates, one Newton step from w1 with
    ``J = I + h ([w1]x I - [I w1]x)``; then (R) with the new omega_w. Returns 1 iteration, or
    -1 and a zero increment when J is singular."""
    i1, i2, i3 = p[P_I1], p[P_I2], p[P_I3]
    w1, w2, w3 = rotate3(q0, q1, q2, q3, x0, x1, x2, -1.0)
    m1, m2, m3 = i1 * w1, i2 * w2, i3 * w3
    f1 = h * (w2 * m3 - w3 * m2)  # f(w1) = h w1 x I w1
    f2 = h * (w3 * m1 - w1 * m3)
    f3 = h * (w1 * m2 - w2 * m1)
    # J = I + h ([w]x diag(I) - [m]x), [a]x = [[0, -a3, a2], [a3, 0, -a1], [-a2, a1, 0]]
    g1, g2, g3 = solve3(
        i1, h * (-w3 * i2 + m3), h * (w2 * i3 - m2),
        h * (w3 * i1 - m3), i2, h * (-w1 * i3 + m1),
        h * (-w2 * i1 + m2), h * (w1 * i2 - m1), i3,
        -f1, -f2, -f3,
    )
    ok = abs(g1) + abs(g2) + abs(g3) < math.inf
    return _finish(x0, x1, x2, q0, q1, q2, q3, g1 if ok else 0.0, g2 if ok else 0.0,
                   g3 if ok else 0.0, h, True, 1 if ok else -1)


@njit(forceinline=True, error_model="numpy")
def _rescaled(x0, x1, x2, q0, q1, q2, q3, h, p, energy):
    """Explicit Euler ``L' = L + h L x w`` on ``L = I w``, then ``L' <- sigma L'`` with
    ``|sigma L'| = |L|`` or (``energy``) the old kinetic energy; ``L' - L`` is perpendicular
    to L and to w, so ``sigma = 1 / sqrt(1 + rho)``, ``rho = |d|^2 / |L|^2`` or
    ``d.I^-1 d / L.I^-1 L``."""
    b1, b2, b3 = p[P_INV1], p[P_INV2], p[P_INV3]
    w1, w2, w3 = rotate3(q0, q1, q2, q3, x0, x1, x2, -1.0)
    m1, m2, m3 = p[P_I1] * w1, p[P_I2] * w2, p[P_I3] * w3
    d1, d2, d3 = _gyroscopic(w1, w2, w3, h, p)
    if energy:
        rho = (b1 * d1 * d1 + b2 * d2 * d2 + b3 * d3 * d3) / (m1 * w1 + m2 * w2 + m3 * w3)
    else:
        rho = (d1 * d1 + d2 * d2 + d3 * d3) / (m1 * m1 + m2 * m2 + m3 * m3)
    root = math.sqrt(1.0 + rho)
    sigma = 1.0 / root
    sm1 = -rho * sigma / (1.0 + root)  # sigma - 1
    return _finish(x0, x1, x2, q0, q1, q2, q3, b1 * (sigma * d1 + sm1 * m1),
                   b2 * (sigma * d2 + sm1 * m2), b3 * (sigma * d3 + sm1 * m3), h, True, 0)


@njit(inline="always")
def rescaled_momentum_step(x0, x1, x2, q0, q1, q2, q3, h, p, s):
    """Explicit Euler on L, rescaled to the old |L|; (R) with the new omega_w."""
    return _rescaled(x0, x1, x2, q0, q1, q2, q3, h, p, False)


@njit(inline="always")
def rescaled_energy_step(x0, x1, x2, q0, q1, q2, q3, h, p, s):
    """Explicit Euler on L, rescaled to the old energy; (R) with the new omega_w."""
    return _rescaled(x0, x1, x2, q0, q1, q2, q3, h, p, True)


@njit(inline="always")
def no_gyroscopic_step(x0, x1, x2, q0, q1, q2, q3, h, p, s):
    """``omega_w' = omega_w``; (R) with it."""
    r0, r1, r2, r3 = _rotation_update(q0, q1, q2, q3, x0, x1, x2, h)
    return 0.0, 0.0, 0.0, r0, r1, r2, r3, 0


_COMMON = dict(params=body_params, family="engine update rule", evaluations=1)

EXPLICIT_EULER = MethodSpec(
    name="explicit_euler", title="explicit Euler (world frame)", order=1,
    step=explicit_euler_step,
    reference="the explicit gyroscopic term of ODE (SourceForge opende patch 185) and Bullet "
              "(bulletphysics/bullet3 #346, #357), here with the attitude also from the old state",
    note="loses energy at the rate semi_implicit_euler gains it; the engines' reported energy "
         "gain is that rule's", **_COMMON)
SEMI_IMPLICIT_EULER = MethodSpec(
    name="semi_implicit_euler", title="semi-implicit (symplectic) Euler", order=1,
    step=semi_implicit_euler_step,
    reference="the usual engine step (velocity, then position with the new velocity); energy "
              "gain: bulletphysics/bullet3 #357, opende patch 185, avianphysics/avian #400",
    note="the body motion is explicit Euler on Euler's equations: energy grows ~ h t",
    **_COMMON)
IMPLICIT_EULER = MethodSpec(
    name="implicit_euler", title="implicit Euler, one Newton step (body frame)", order=1,
    step=implicit_euler_step, implicit=True,
    reference="Catto, Numerical Methods, GDC 2015; erincatto/box3d src/solver.c; Bullet "
              "computeGyroscopicImpulseImplicit_Body (bulletphysics/bullet3 #346)",
    note="stable at any step, but energy and |L| decrease monotonically (~ h t)", **_COMMON)
RESCALED_MOMENTUM = MethodSpec(
    name="rescaled_momentum", title="explicit Euler on L rescaled to |L|", order=1,
    step=rescaled_momentum_step, preserves_casimir=True,
    reference="Jolt MotionProperties::ApplyGyroscopicForceInternal (jrouwe/JoltPhysics #809); "
              "avianphysics/avian #738, #993",
    note="keeps |L| but its energy drifts toward L^2 / (2 I2), the separatrix", **_COMMON)
RESCALED_ENERGY = MethodSpec(
    name="rescaled_energy", title="explicit Euler on L rescaled to the energy", order=1,
    step=rescaled_energy_step, preserves_energy=True,
    reference="the energy-keeping variant of Jolt's rescaling (avianphysics/avian #993)",
    note="keeps the energy but |L| drifts, again toward the separatrix", **_COMMON)
NO_GYROSCOPIC = MethodSpec(
    name="no_gyroscopic", title="no gyroscopic term (omega_w constant)", order=0.0,
    step=no_gyroscopic_step,
    reference="PhysX 4 rigid bodies (NVIDIAGameWorks/PhysX#394), Godot Physics "
              "(godotengine/godot #50173, #80703), Unity (forum thread 259514)",
    note="not consistent with Euler's equations: the body turns about a fixed space axis "
         "and never flips", **_COMMON)

ENGINE_RULES = {spec.name: spec for spec in (EXPLICIT_EULER, SEMI_IMPLICIT_EULER, IMPLICIT_EULER,
                                             RESCALED_MOMENTUM, RESCALED_ENERGY, NO_GYROSCOPIC)}
