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
principal. Derived here; checked against the integrated equations (the order test of
``tests/test_registry.py``) and by its own residual (``tests/asteroid/test_exact.py``).
"""

from __future__ import annotations

import numpy as np

from ..util.checks import real_array, vectors3

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


def _turned(t, kappa, c, length):
    """Z(t) / sign(z0) of the module docstring, without cancellation at small or large
    kappa t."""
    kt = kappa * t
    if kt == 0.0:
        return length / np.sqrt(1.0 + c) * t  # z0 t
    root0 = np.sqrt(1.0 + c)
    if kt > 1.0:  # e^(kappa t) may overflow: factor it out
        tail = np.log((1.0 + np.sqrt(1.0 + c * np.exp(-kt))) / (1.0 + root0))
        return length * t + 2.0 * length / kappa * tail
    grown = np.expm1(0.5 * kt) + np.expm1(kt) / (np.sqrt(np.exp(kt) + c) + root0)
    return 2.0 * length / kappa * np.log1p(grown / (1.0 + root0))


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
        Time (s), >= 0.

    Returns
    -------
    ndarray, shape (N, 3), or None
    """
    values = real_array("parameters", parameters).reshape(-1)
    moments, alpha = values[:3], float(values[3])
    axis = symmetry_axis(moments)
    if axis is None:
        return None
    m0 = vectors3("m0", m0)
    order = AXIS_ORDER[axis]
    x0, y0, z0 = (m0[:, k] for k in order)
    across, along = moments[order[0]], moments[axis]
    mu = (across - along) / (across * along)  # 1/C - 1/A
    out = np.empty_like(m0)
    for n in range(len(m0)):
        r2 = x0[n] * x0[n] + y0[n] * y0[n]
        u0 = z0[n] * z0[n]
        length = np.sqrt(r2 + u0)
        if r2 == 0.0 or u0 == 0.0:  # a spin about a principal axis stays
            out[n] = m0[n]
            continue
        kappa = -2.0 * alpha * mu * length * length
        c = r2 / u0  # L^2 / z0^2 - 1
        with np.errstate(over="ignore"):
            z = np.copysign(length / np.sqrt(1.0 + c * np.exp(-kappa * t)), z0[n])
            shrink = np.sqrt((1.0 + c) / (np.exp(kappa * t) + c))
        angle = -mu * np.copysign(_turned(float(t), kappa, c, length), z0[n])
        cos, sin = np.cos(angle), np.sin(angle)
        out[n, order[0]] = shrink * (x0[n] * cos - y0[n] * sin)
        out[n, order[1]] = shrink * (x0[n] * sin + y0[n] * cos)
        out[n, order[2]] = z
    return out


__all__ = ["AXIS_ORDER", "relaxed_momentum", "symmetry_axis"]
