"""The state as physics engines hold it, and its conversions from and to the package's.

Engines store a rigid body's rotation as the space-frame angular velocity ``omega_w`` and a unit
quaternion q (body to space, scalar first, Hamilton product): the state ``(omega_w1, omega_w2,
omega_w3, q0, q1, q2, q3)`` of scene ``engine_body``, in the canonical body frame
(``I1 <= I2 <= I3``). The package's free body holds ``(m, q)``, the body-frame angular momentum
and the same quaternion (scene ``free_body_attitude``). :func:`world_state` and
:func:`body_state` take one to the other (``omega_w = R(q) I^-1 m``, ``m = I R(q)^T omega_w``),
through :func:`rotate`.

The physics is the torque-free rigid body's, whose equations, exact motion and linear theory
are the free body's (:mod:`stability.free_body.model`, :mod:`stability.free_body.exact`); what
this family adds are the engines' update rules (:mod:`stability.engine_body.methods`), which are
its methods, not its model.
"""

from __future__ import annotations

import numpy as np


def rotate(q, x, transpose=False):
    """``R(q / |q|) x`` (or ``R^T x``) for quaternions q (N, 4) and vectors x (N, 3).

    Parameters
    ----------
    q : array_like, shape (N, 4)
        Body-to-space quaternions, scalar first (normalised here).
    x : array_like, shape (N, 3)
        Vectors, one per quaternion.
    transpose : bool, default False
        Apply ``R^T`` (space to body) instead of R.
    """
    q = np.asarray(q, dtype=float)
    x = np.asarray(x, dtype=float)
    v = q[:, 1:]
    s = 2.0 / np.sum(q * q, axis=1)[:, None]
    u = np.cross(v, x)
    c = -q[:, :1] if transpose else q[:, :1]
    return x + s * (c * u + np.cross(v, u))


def world_state(moments, m_body, q):
    """Engine states (N, 7) from body angular momenta m (N, 3) and attitudes q (N, 4)
    (canonical moments): ``omega_w = R(q) I^-1 m``.

    Parameters
    ----------
    moments : array_like, shape (3,)
        Principal moments ``I1 <= I2 <= I3``, kg m2.
    m_body : array_like, shape (N, 3) or (3,)
        Body-frame angular momenta, kg m2 s-1.
    q : array_like, shape (N, 4) or (4,)
        Body-to-space quaternions, scalar first.
    """
    m = np.atleast_2d(np.asarray(m_body, dtype=float))
    q = np.broadcast_to(np.asarray(q, dtype=float), (m.shape[0], 4))
    return np.concatenate([rotate(q, m / np.asarray(moments, dtype=float)), q], axis=1)


def body_state(x, moments):
    """``(m, q)`` of engine states x (N, 7): ``m = I R(q)^T omega_w`` (N, 3) and q (N, 4).

    Parameters
    ----------
    x : array_like, shape (N, 7)
        Engine states ``(omega_w, q)``.
    moments : array_like, shape (3,)
        Principal moments ``I1 <= I2 <= I3``, kg m2.
    """
    x = np.asarray(x, dtype=float)
    return np.asarray(moments, dtype=float) * rotate(x[:, 3:], x[:, :3], True), x[:, 3:].copy()
