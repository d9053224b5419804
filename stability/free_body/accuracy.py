"""References to score a run against: exact final states, the conditioning floor, error statistics.

- :func:`exact_final_w`: w(T) of every start from the exact solution (Jacobi elliptic functions,
  :func:`stability.exact_omega`, ~1e-14 relative), the reference of the work-precision study.
- :func:`conditioning_floor`: how far the exact w(T) moves when each start is rounded once.
  Near the separatrix the final error has a floor set by conditioning, not by the method: the
  flip time depends on D2 = L^2 - 2 E I2 (literature notes 1.5, 2.2), and members whose D2 is
  close to zero amplify one rounding of D2 (u L^2, u = 2^-53) into an error of 1e-9 or more in
  w(T). It is the error of a method that rounds its whole state once, at the level of ulp(|m|),
  somewhere along the run; a composition does that at every stage, and its max error over a
  tennis ensemble stalls near the floor, while a compensated one-stage update (rk4: only the
  small increment is rounded) can go below it. The members near the separatrix set the max,
  which is why the p99 and the median are reported beside it.
- :func:`attitude_reference`: the attitude at T from SciPy's DOP853 at rtol = atol = 1e-13 on
  (w, q), all members as one system (the exact attitude is not in the package).
- :func:`final_errors` and :func:`error_statistics`: per-member relative errors of w, the energy
  and |L| at the end, and their (max, p99, median) over members (:data:`METRICS`).
"""

from __future__ import annotations

import numpy as np

from .model import euler_system
from ..core.body import RigidBody
from .exact import exact_omega_of_starts

#: Statistics over members, in the order :func:`error_statistics` returns them.
METRICS = ("max", "p99", "median")


def error_statistics(values) -> np.ndarray:
    """(max, p99, median) over the finite ``values``; NaN if there are none.

    Parameters
    ----------
    values : array_like, shape (N,)

    Returns
    -------
    ndarray, shape (3,)
        In the order of :data:`METRICS`.
    """
    values = np.asarray(values, dtype=float)
    values = values[np.isfinite(values)]
    if values.size == 0:
        return np.full(len(METRICS), np.nan)
    return np.array([values.max(), np.percentile(values, 99.0), np.median(values)])


def exact_final_w(body: RigidBody, w0, t_end: float) -> np.ndarray:
    """w(t_end) of the torque-free body for each start.

    Parameters
    ----------
    body : RigidBody
    w0 : ndarray, shape (N, 3)
        Starts, rad/s.
    t_end : float
        Time, s.

    Returns
    -------
    ndarray, shape (N, 3)
        The exact solution (:func:`stability.exact_omega`, ~1e-14 relative) at ``t_end``.
    """
    return exact_omega_of_starts(body, np.atleast_2d(np.asarray(w0, dtype=float)), t_end)


def conditioning_floor(body: RigidBody, w0, t_end: float, w_ref, seed: int = 0) -> np.ndarray:
    """Relative change of the exact w(t_end) when D2 of each start moves by one rounding; (N,).

    A method rounds its state at every step, by about one ulp of |m| in each component; far
    from the saddle (during a flip) that changes D2 by about u L^2, u = 2^-53, and the flip
    times by u L^2 / (nu |D2|). Here each start m0 is shifted along the sphere |m| = L, in the
    direction of the tangential energy gradient, by just enough to change D2 by u L^2 (random
    sign), and the exact solution from there is compared with ``w_ref``, the exact solution
    from the unshifted start: the error one rounding of the whole state at the level of ulp(|m|)
    causes (each stage of a composition makes one; the driver's compensated update of a
    one-stage method rounds only the increment).

    Parameters
    ----------
    body : RigidBody
    w0 : ndarray, shape (N, 3)
        Starts, rad/s.
    t_end : float
        Time, s.
    w_ref : ndarray, shape (N, 3)
        :func:`exact_final_w` of the starts.
    seed : int
        Seed of the random signs.
    """
    moments = body.moments
    w0 = np.asarray(w0, dtype=float)
    m0 = moments * w0
    L2 = np.sum(m0 * m0, axis=1)
    unit = m0 / np.sqrt(L2)[:, None]
    g = w0 - np.sum(w0 * unit, axis=1)[:, None] * unit  # grad_m E, tangential to the sphere
    g2 = np.sum(g * g, axis=1)
    signs = np.random.default_rng(np.random.SeedSequence(seed)).choice([-1.0, 1.0], len(w0))
    intermediate = np.sort(moments)[1]
    d_energy = -signs * 2.0**-53 * L2 / (2.0 * intermediate)  # dD2 = -2 I2 dE at fixed L
    shifted = m0 + np.where(g2 > 0, d_energy / np.where(g2 > 0, g2, 1.0), 0.0)[:, None] * g
    w_shifted = exact_final_w(body, shifted / moments, t_end)
    return np.linalg.norm(w_shifted - w_ref, axis=1) / np.linalg.norm(w_ref, axis=1)


def attitude_reference(body: RigidBody, w0, t_end: float):
    """Attitude at t_end of each start, from the identity: scipy DOP853 on (w, q), one system.

    The exact attitude (Celledoni, Fasso, Safstrom & Zanna 2008) is not in the package; the
    reference is DOP853 at rtol = atol = 1e-13 on Euler's equations and ``q' = q (0, w) / 2``
    (``stability.free_body.attitude``'s convention: body-to-space, scalar first) for all members as
    one system. Its accuracy is measured on its w part against the exact solution.

    Parameters
    ----------
    body : RigidBody
        The body.
    w0 : array_like, shape (N, 3) or (3,)
        Starts, rad/s; every member starts at the identity attitude.
    t_end : float
        Time, s.

    Returns
    -------
    q_ref : ndarray, shape (N, 4)
        Unit quaternions at t_end.
    w_error : ndarray, shape (N,)
        Relative error of the reference's w(t_end) against :func:`exact_final_w`, per member:
        attitude errors below about this are not resolved.
    """
    from scipy.integrate import solve_ivp

    w0 = np.atleast_2d(np.asarray(w0, dtype=float))
    n = w0.shape[0]
    rhs_w = euler_system(body, n)

    def rhs(t, y):
        w1, w2, w3 = y[:n], y[n : 2 * n], y[2 * n : 3 * n]
        q0, q1, q2, q3 = y[3 * n : 4 * n], y[4 * n : 5 * n], y[5 * n : 6 * n], y[6 * n :]
        dq = 0.5 * np.concatenate((
            -(q1 * w1 + q2 * w2 + q3 * w3),  # q (0, w): scalar part -q_v . w
            q0 * w1 + q2 * w3 - q3 * w2,  # vector part q0 w + q_v x w
            q0 * w2 + q3 * w1 - q1 * w3,
            q0 * w3 + q1 * w2 - q2 * w1,
        ))
        return np.concatenate((rhs_w(t, y[: 3 * n]), dq))

    y0 = np.concatenate((np.ascontiguousarray(w0.T).ravel(), np.repeat([1.0, 0.0, 0.0, 0.0], n)))
    sol = solve_ivp(rhs, (0.0, t_end), y0, method="DOP853", rtol=1e-13, atol=1e-13,
                    t_eval=[t_end])
    y = sol.y[:, -1]
    w_end = y[: 3 * n].reshape(3, n).T
    q = y[3 * n :].reshape(4, n).T
    w_error = (np.linalg.norm(w_end - exact_final_w(body, w0, t_end), axis=1)
               / np.linalg.norm(w_end, axis=1))
    return q / np.linalg.norm(q, axis=1, keepdims=True), w_error


def final_errors(moments, w0, w_end, w_ref) -> dict:
    """Per-member relative errors at the end: w against the reference, energy and |L| drift.

    Parameters
    ----------
    moments : array_like, shape (3,)
        Principal moments, kg m^2.
    w0, w_end, w_ref : ndarray, shape (N, 3)
        Starts, the run's final states (NaN for failed members) and the reference, rad/s.

    Returns
    -------
    dict
        Arrays of shape (N,): ``w`` = |w - w_ref| / |w_ref|, ``energy`` = |E / E0 - 1|,
        ``momentum`` = | |L| / |L0| - 1 |.
    """
    moments = np.asarray(moments, dtype=float)
    m0, m1 = moments * w0, moments * w_end
    e0 = np.sum(m0 * w0, axis=1)
    e1 = np.sum(m1 * w_end, axis=1)
    l0 = np.linalg.norm(m0, axis=1)
    l1 = np.linalg.norm(m1, axis=1)
    return {
        "w": np.linalg.norm(w_end - w_ref, axis=1) / np.linalg.norm(w_ref, axis=1),
        "energy": np.abs(e1 / e0 - 1.0),
        "momentum": np.abs(l1 / l0 - 1.0),
    }
