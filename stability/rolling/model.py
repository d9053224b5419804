"""Rolling with and without slipping: the formulas of a round body under Coulomb friction.

A round body with I = k M R^2 (k: :data:`SHAPES`) under Coulomb friction (mu_s >= mu_k); the
equations and the exact event-located step are in :mod:`stability.rolling.methods`.

On an incline of angle theta, released at rest [course notes, corrected: ERRATA.md section 4]:

- it rolls without slipping iff ``tan(theta) <= mu_s (1 + M R^2 / I)``, with
  ``a = g sin(theta) / (1 + I / (M R^2))`` (:func:`rolls`, :func:`rolling_acceleration`);
- otherwise it slips: ``a = g (sin(theta) - mu_k cos(theta))`` and the spin grows at
  ``mu_k M g R cos(theta) / I`` (:func:`slipping_acceleration`, :func:`slipping_spin_rate`).

Launched along a level floor with speed v0 and spin w0, friction acts on the slip u = v - R w
until it vanishes: the body rolls from ``t = |v0 - R w0| / (mu_k g (1 + M R^2 / I))`` on, at
``(v0 + (I / (M R^2)) R w0) / (1 + I / (M R^2))`` (angular momentum about the contact point is
kept), having turned ``M (v0 - R w0)^2 k / (2 (1 + k))`` of energy into heat
(:func:`launch_formulas`).

The ensembles run on scene ``rolling_body`` and their measurement are in
:mod:`stability.rolling.measure`.
"""

from __future__ import annotations

import numpy as np

from .methods import MODE, P_K, P_MU_S, P_R, P_SECTIONS, P_TRACK, V, W, X, X_ROLL

#: I / (M R^2) of the shapes by name.
SHAPES = {"sphere": 0.4, "cylinder": 0.5, "spherical_shell": 2.0 / 3.0, "hoop": 1.0}
#: Standard gravity (m s-2).
G = 9.80665


def rolls(theta, mu_s, k):
    """Released at rest on an incline of ``theta`` (rad), does it roll without slipping?

    Parameters
    ----------
    theta : float or array_like
        Incline angle in rad (its sign does not matter).
    mu_s : float or array_like
        Static friction coefficient (dimensionless).
    k : float or array_like
        Shape factor ``I / (M R^2)`` (dimensionless, :data:`SHAPES`).

    Returns
    -------
    bool or ndarray of bool
        True where ``tan(theta) <= mu_s (1 + 1 / k)``; the arguments broadcast.
    """
    return np.tan(np.abs(theta)) <= mu_s * (1.0 + 1.0 / np.asarray(k, dtype=float))


def rolling_acceleration(theta, k, g=G):
    """``g sin(theta) / (1 + k)`` (m s-2).

    Parameters
    ----------
    theta : float or array_like
        Incline angle in rad, positive downhill.
    k : float or array_like
        Shape factor ``I / (M R^2)`` (dimensionless).
    g : float, default G
        Gravity in m s-2.

    Returns
    -------
    float or ndarray
        Acceleration along the incline of a body rolling without slipping, in m s-2.
    """
    return g * np.sin(theta) / (1.0 + np.asarray(k, dtype=float))


def slipping_acceleration(theta, mu_k, g=G):
    """``g (sin(theta) - mu_k cos(theta))`` (m s-2), the body slipping forward.

    Parameters
    ----------
    theta : float or array_like
        Incline angle in rad, positive downhill.
    mu_k : float or array_like
        Kinetic friction coefficient (dimensionless).
    g : float, default G
        Gravity in m s-2.

    Returns
    -------
    float or ndarray
        Acceleration along the incline in m s-2.
    """
    return g * (np.sin(theta) - mu_k * np.cos(theta))


def slipping_spin_rate(theta, mu_k, k, radius, g=G):
    """``mu_k M g R cos(theta) / I = mu_k g cos(theta) / (k R)`` (rad s-2).

    Parameters
    ----------
    theta : float or array_like
        Incline angle in rad.
    mu_k : float or array_like
        Kinetic friction coefficient (dimensionless).
    k : float or array_like
        Shape factor ``I / (M R^2)`` (dimensionless).
    radius : float or array_like
        Radius R in m.
    g : float, default G
        Gravity in m s-2.

    Returns
    -------
    float or ndarray
        Angular acceleration of a body slipping forward, in rad s-2.
    """
    return mu_k * g * np.cos(theta) / (np.asarray(k, dtype=float) * radius)


def launch_formulas(v0, w0, k, radius, mu_k, mass=1.0, g=G) -> dict:
    """Time and distance to pure rolling, final speed and energy turned into heat of a body
    launched along a level floor with speed ``v0`` (m s-1) and spin ``w0`` (rad s-1).

    Parameters
    ----------
    v0 : float or array_like
        Launch speed in m s-1.
    w0 : float or array_like
        Launch spin in rad s-1 (rolling forward: ``w0 = v0 / R``; negative: backspin).
    k : float or array_like
        Shape factor ``I / (M R^2)`` (dimensionless).
    radius : float or array_like
        Radius R in m.
    mu_k : float or array_like
        Kinetic friction coefficient (dimensionless).
    mass : float, default 1.0
        Mass M in kg (only the energy depends on it).
    g : float, default G
        Gravity in m s-2.

    Returns
    -------
    dict of str to ndarray
        ``"t_roll"``: time to pure rolling (s); ``"x_roll"``: distance covered by then (m);
        ``"v_final"``: the rolling speed (m s-1); ``"energy_lost"``: kinetic energy turned
        into heat (J). The arguments broadcast.
    """
    v0, w0, k = (np.asarray(a, dtype=float) for a in (v0, w0, k))
    u0 = v0 - radius * w0
    t_roll = np.abs(u0) / (mu_k * g * (1.0 + 1.0 / k))
    return {
        "t_roll": t_roll,
        "x_roll": v0 * t_roll - 0.5 * np.sign(u0) * mu_k * g * t_roll**2,
        "v_final": (v0 + k * radius * w0) / (1.0 + k),
        "energy_lost": 0.5 * mass * u0**2 * k / (1.0 + k),
    }


def start_states(v0, w0, rows, x0=0.0) -> np.ndarray:
    """Scene states (N, 9) of bodies at ``x0`` with speed ``v0`` and spin ``w0`` on the tracks
    ``rows`` (N, n_params), the regime set as the start requires: slipping if u0 != 0, else
    rolling where static friction can hold it, slipping forward where it cannot.

    Parameters
    ----------
    v0 : float or array_like, shape (N,)
        Speed of the centre in m s-1.
    w0 : float or array_like, shape (N,)
        Spin in rad s-1.
    rows : array_like, shape (N, n_params)
        Group parameters, one row per body (:func:`stability.rolling.methods.track_row`);
        a single row is taken as shape (1, n_params).
    x0 : float or array_like, shape (N,), default 0.0
        Position along the track in m.

    Returns
    -------
    ndarray, shape (N, 9)
        Start states of scene ``rolling_body``.
    """
    rows = np.atleast_2d(rows)
    n = rows.shape[0]
    x = np.zeros((n, 9))
    x[:, X] = x0
    x[:, V] = v0
    x[:, W] = w0
    x[:, X_ROLL] = x0
    u0 = x[:, V] - rows[:, P_R] * x[:, W]
    # the section at x0 (moving forward from a section's start)
    starts = rows[:, P_TRACK::3][:, :int(rows[:, P_SECTIONS].max())]
    j = np.sum(starts <= x[:, [X]], axis=1) - 1
    sn = rows[np.arange(n), P_TRACK + 3 * j + 1]
    cs = rows[np.arange(n), P_TRACK + 3 * j + 2]
    # the kernel's can_roll, over all members
    holds = rows[:, P_K] * np.abs(sn) <= rows[:, P_MU_S] * cs * (1.0 + rows[:, P_K])
    x[:, MODE] = np.where(u0 != 0.0, np.sign(u0), np.where(holds, 0.0, np.sign(sn)))
    return x
