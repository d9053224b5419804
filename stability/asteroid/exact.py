r"""The exact relaxation of an axisymmetric tumbler (equation (1) of
:mod:`stability.asteroid.methods`).

Let the body be symmetric about axis s, with moment C about it and A across it, and write
m = (x, y, z) in a right-handed order that ends with axis s (``(m1, m2, m3)`` for
``I1 = I2``, ``(m2, m3, m1)`` for ``I2 = I3``). With :math:`\mu = 1/C - 1/A`,
:math:`m \times \omega = \mu z\, (y, -x, 0)`, and (1) becomes

.. math::

    \dot z = -\alpha \mu\, z\, (L^2 - z^2), \qquad
    \frac{d}{dt}(x + i y) = \big(\alpha \mu z^2 - i \mu z\big)\, (x + i y).

So :math:`u = z^2` grows (or falls) logistically at the rate :math:`\kappa = -2 \alpha \mu L^2`,
:math:`u(t) = L^2 / (1 + c\, e^{-\kappa t})` with :math:`c = L^2 / z_0^2 - 1`; the part across
the axis shrinks in proportion, :math:`r^2 = r_0^2 (1 + c) / (e^{\kappa t} + c)`, and turns by
the angle :math:`-\mu Z(t)`, :math:`Z = \int_0^t z\, dt`, which the substitution
:math:`y = e^{\kappa t}` integrates in closed form:

.. math::

    Z(t) = \operatorname{sign}(z_0)\, \frac{2 L}{\kappa}
    \ln \frac{e^{\kappa t / 2} + \sqrt{e^{\kappa t} + c}}{1 + \sqrt{1 + c}}.

An oblate body (axis s the major axis, :math:`\mu < 0`, :math:`\kappa > 0`) ends spinning about
its axis; a prolate one (axis s the minor axis) ends spinning across it, where every axis is
principal.

The formulas are evaluated in ``s = |z_0| / L`` and ``rho = r_0 / L`` (no square of a start
near an axis overflows), with :math:`e^{\pm\kappa t / 2}` inside ``hypot`` (overflow and
underflow give the limits), and :math:`\ln` of the ratio above from ``log1p`` where it is near
1, by its series where :math:`|\kappa t| < 10^{-12}`: to a few roundings in every regime
(against mpmath, ``tests/asteroid/test_exact.py``). Derived here; checked against the
integrated equations (the order test of ``tests/test_registry.py``) and by its own residual.
"""

from __future__ import annotations

import math

import numpy as np

from ..integrators.spec import P_I1
from ..util.checks import real_number, vectors3
from .methods import P_ALPHA, relaxation_params

#: The state's components (x, y, z) for a body symmetric about axis 3 and about axis 1.
AXIS_ORDER = {2: (0, 1, 2), 0: (1, 2, 0)}


def symmetry_axis(moments) -> int | None:
    """The symmetry axis (0 or 2) of canonical moments ``I1 <= I2 <= I3``; None if the body is
    triaxial or spherical."""
    i1, i2, i3 = (float(x) for x in moments)
    if i1 == i2 != i3:
        return 2
    if i2 == i3 != i1:
        return 0
    return None


def _turned(t, kappa, s, rho):
    """Z(t) / z0 of the module docstring, with ``s = |z0| / L`` and ``rho = r0 / L``: ``Z =
    2 L / kappa ln R``, ``R = (s e^(kappa t / 2) + sqrt(s^2 e^(kappa t) + rho^2)) / (s + n0)``,
    ``n0 = sqrt(s^2 + rho^2) = 1``; ln R from log1p of R - 1 written without cancellation where
    R is near 1, from the ratio where it is not, with e^(kappa t) factored out where it would
    overflow, and by its series where kappa t is too small for 1 / kappa."""
    kt = kappa * t
    if abs(kt) < 1e-12:  # z = z0 (1 + rho^2 kappa t / 2): the next term is below a rounding
        return t * (1.0 + 0.25 * rho * rho * kt)
    n0 = math.hypot(s, rho)
    if kt > 700.0:  # e^(kappa t) would overflow: ln R = kappa t / 2 + ln((s + ...) / (s + n0))
        tail = math.log((s + math.hypot(s, rho * math.exp(-0.5 * kt))) / (s + n0))
        return (0.5 * kt + tail) / (s * 0.5 * kt) * t
    now = math.hypot(s * math.exp(0.5 * kt), rho)  # sqrt(s^2 e^(kappa t) + rho^2)
    excess = (s * math.expm1(0.5 * kt) + s * s * math.expm1(kt) / (now + n0)) / (s + n0)
    if abs(excess) < 0.5:
        log_ratio = math.log1p(excess)
    else:
        log_ratio = math.log(s * math.exp(0.5 * kt) + now) - math.log(s + n0)
    return log_ratio / (s * 0.5 * kt) * t


def relaxed_momentum(m0, parameters, t) -> np.ndarray | None:
    """The exact body angular momenta (N, 3) at time ``t`` of an axisymmetric tumbler from
    ``m0`` (N, 3) at time 0; None for a triaxial or spherical body.

    Parameters
    ----------
    m0 : array_like, shape (N, 3)
        Body angular momenta at t = 0 (kg m^2/s), canonical frame.
    parameters : array_like, shape (4,)
        ``(I1, I2, I3, alpha)`` (:func:`stability.asteroid.methods.relaxation_params`).
    t : float
        Time (s).

    Returns
    -------
    ndarray, shape (N, 3), or None
    """
    p = relaxation_params(parameters)
    moments, alpha = p[P_I1:P_I1 + 3], float(p[P_ALPHA])
    axis = symmetry_axis(moments)
    if axis is None:
        return None
    m0 = vectors3("m0", m0)
    t = real_number("t", t, "s")
    order = AXIS_ORDER[axis]
    across, along = moments[order[0]], moments[axis]
    mu = (across - along) / (across * along)  # 1/C - 1/A
    out = np.empty_like(m0)
    for n, m in enumerate(m0):
        x0, y0, z0 = (float(m[k]) for k in order)
        r0 = math.hypot(x0, y0)
        length = math.hypot(r0, z0)
        if r0 == 0.0 or z0 == 0.0:  # a spin about a principal axis stays
            out[n] = m
            continue
        s, rho = abs(z0) / length, r0 / length
        kappa = -2.0 * alpha * mu * length * length
        kt = kappa * t
        with np.errstate(over="ignore", under="ignore"):  # e^(+-kappa t / 2) may be inf or 0
            z = math.copysign(length * s / np.hypot(s, rho * np.exp(-0.5 * kt)), z0)
            shrink = math.hypot(s, rho) / np.hypot(s * np.exp(0.5 * kt), rho)
        angle = -mu * z0 * _turned(t, kappa, s, rho)
        cos, sin = math.cos(angle), math.sin(angle)
        out[n, order[0]] = shrink * (x0 * cos - y0 * sin)
        out[n, order[1]] = shrink * (x0 * sin + y0 * cos)
        out[n, order[2]] = z
    return out


__all__ = ["AXIS_ORDER", "relaxed_momentum", "symmetry_axis"]
