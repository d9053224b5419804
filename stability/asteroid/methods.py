r"""A tumbler that loses energy inside and keeps its angular momentum: the equations and their
methods.

A tumbling asteroid flexes as it turns, and its inelastic interior turns some of its
rotational energy into heat while the total angular momentum stays fixed, so it relaxes to a
spin about its major axis (Burns & Safronov, MNRAS 165, 403 (1973)). The simplest dissipation
with exactly these properties is the double bracket of Bloch, Krishnaprasad, Marsden & Ratiu
(Comm. Math. Phys. 175, 1 (1996)), added to Euler's equations of the body angular momentum m:

.. math::

    \dot m = m \times \omega + \alpha\, m \times (m \times \omega),
    \qquad \omega = I^{-1} m,                                                          (1)

with :math:`\alpha \ge 0` (kg^-1 m^-2 s). Dotted with m the added term vanishes, so
:math:`|m| = L` is kept; dotted with :math:`\omega` it gives
:math:`\dot E = -\alpha\, |m \times \omega|^2 \le 0`, zero only where m lies along a principal
axis. (1) is :math:`\dot m = m \times \Omega` with :math:`\Omega = \omega + \alpha\, m \times
\omega`, a rotation of m at every instant. The one parameter stands for the interior's whole
response: one damping time, fixed by the linear decay about the major axis
(:func:`stability.asteroid.model.wobble_rate`), where a real body's anelastic rate also
depends on the wobble's amplitude.

Parameters per body: ``(I1, I2, I3, alpha)``, the canonical (ascending) principal moments and
the damping coefficient (:func:`relaxation_params`). The kernel evaluates m x omega as the free
body's kernels do, ``(A1 m2 m3, A2 m3 m1, A3 m1 m2)`` without cancellation
(:func:`stability.integrators.rk4.euler_rhs`); its RK4 is the package's one RK4 text
(:func:`stability.integrators.rk4.rk4_source`) applied to (1).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..integrators.rk4 import euler_jvp, euler_rhs, rk4_source
from ..integrators.rotations import cross
from ..integrators.spec import N_BODY_PARAMS, MethodSpec, body_params
from ..util.checks import real_array

#: Index of alpha in the kernel parameters, after the body's (:func:`body_params`).
P_ALPHA = N_BODY_PARAMS
N_RELAXATION_PARAMS = N_BODY_PARAMS + 1


def relaxation_params(parameters, h: float = 0.0) -> np.ndarray:
    """Kernel parameters of a body ``(I1, I2, I3, alpha)``; the same for every step ``h``.

    Parameters
    ----------
    parameters : array_like, shape (4,)
        Canonical principal moments ``I1 <= I2 <= I3`` (kg m^2) and the damping coefficient
        ``alpha >= 0`` (kg^-1 m^-2 s) of (1).
    h : float, default 0.0
        Step in s; not used.

    Returns
    -------
    ndarray, shape (N_RELAXATION_PARAMS,)
        The body's parameters (:func:`stability.integrators.spec.body_params`) and alpha at
        :data:`P_ALPHA`.
    """
    values = real_array("parameters", parameters).reshape(-1)
    if values.size != 4:
        raise ValueError(f"a relaxing tumbler's parameters are 4 numbers (I1, I2, I3, alpha), "
                         f"got {values.size}")
    if not np.all(np.isfinite(values)):
        raise ValueError(f"a relaxing tumbler's parameters must be finite, got "
                         f"{tuple(float(x) for x in values)}")
    moments, alpha = values[:3], float(values[3])
    if not (moments[0] > 0.0 and moments[0] <= moments[1] <= moments[2]):
        raise ValueError(f"the moments (I1, I2, I3) must be positive and ascending (the "
                         f"canonical frame), got {tuple(float(x) for x in moments)}")
    if alpha < 0.0:
        raise ValueError(f"alpha must be >= 0 (it removes energy; 0 is the free body), "
                         f"got {alpha}")
    p = np.empty(N_RELAXATION_PARAMS)
    p[:N_BODY_PARAMS] = body_params(moments)
    p[P_ALPHA] = alpha
    return p


@njit(forceinline=True, error_model="numpy")
def relaxation_rhs(m1, m2, m3, p):
    """Equation (1): ``m x w + alpha m x (m x w)``."""
    c1, c2, c3 = euler_rhs(m1, m2, m3, p)
    d1, d2, d3 = cross(m1, m2, m3, c1, c2, c3)
    alpha = p[P_ALPHA]
    return c1 + alpha * d1, c2 + alpha * d2, c3 + alpha * d3


@njit(forceinline=True, error_model="numpy")
def relaxation_jvp(m1, m2, m3, v1, v2, v3, p):
    """The Jacobian of (1) applied to ``v``, exactly: with ``c = m x w`` and ``c' = J_c v``
    (:func:`stability.integrators.rk4.euler_jvp`), ``c' + alpha (v x c + m x c')``."""
    c1, c2, c3 = euler_rhs(m1, m2, m3, p)
    e1, e2, e3 = euler_jvp(m1, m2, m3, v1, v2, v3, p)
    f1, f2, f3 = cross(v1, v2, v3, c1, c2, c3)
    g1, g2, g3 = cross(m1, m2, m3, e1, e2, e3)
    alpha = p[P_ALPHA]
    return e1 + alpha * (f1 + g1), e2 + alpha * (f2 + g2), e3 + alpha * (f3 + g3)


exec(rk4_source(3, "relaxation_rhs", "rk4_step"))  # noqa: S102 (the package's one RK4 text)


RK4 = MethodSpec(
    name="rk4",
    title="classical Runge-Kutta",
    order=4,
    step=rk4_step,  # noqa: F821 (made above)
    params=relaxation_params,
    family="Runge-Kutta",
    evaluations=4,
    reference="Kutta (1901); Hairer, Norsett & Wanner, Solving ODEs I (1993), II.1",
)

#: The methods of the scene ``relaxing_tumbler`` by name.
METHODS = {RK4.name: RK4}
