"""Montgomery's geometric phase and the twist of a tossed racket, exact and from a run.

Frames and Euler angles as in :mod:`stability.free_body.exact_attitude` (canonical frame, L along
space Z, body z along the smallest-moment axis: the handle). Two angles per member, each from two
independent routes:

- **Montgomery's angle** (Montgomery, Am. J. Phys. 59, 394 (1991)). Over one period T of the
  body motion (m(T) = m(0)) the body turns about the fixed L: R(T) R(0)^T = Rot(L/|L|, dtheta)
  with

      dtheta = 2 E T / |L| - S   (mod 2 pi),

  S the oriented solid angle enclosed by the body-frame path of m/|m| (positive when the
  enclosed region lies to the left of the direction of motion, seen from outside the sphere).
  Routes: the attitude (from a run: :func:`run_angles`; exactly: phi(T) of the exact series)
  and the formula (:func:`montgomery_formula`, S by the spectrally converging trapezoid rule of
  the closed integral of (1 - cos(vartheta)) d(varphi) about the axis the path encircles).
- **The twist** (the tennis-racket effect proper: Ashbaugh, Chicone & Cushman, J. Dyn. Diff.
  Eq. 3, 67 (1991); Van Damme, Mardesic & Sugny, Physica D 338, 17 (2017)). phi is the
  handle's precession about L and psi = atan2(m2, m3) the body's turn about its handle. Over
  the time window centred on a flip (m2 = 0) in which phi advances by exactly 2 pi, psi changes
  by close to, not exactly, pi. Routes: the exact motion (:func:`exact_angles`) and a run
  (:func:`run_angles`); the flip and the window are roots found to round-off
  (:func:`stability.core.roots.bracketed_newton`) on each route's own solution.
"""

from __future__ import annotations

import math

import numpy as np

from ...core.quaternions import (
    quaternion_conjugate, quaternion_multiply, quaternion_to_matrix, spatial_angular_momentum,
)
from ..exact import MAJOR, PRECESS3
from ..exact_attitude import FreeMotion, l_frame, precession_rate, spin_angle
from ...core.roots import bracketed_newton

TWO_PI = 2.0 * math.pi

#: Samples per window for following psi continuously across it.
_PSI_SAMPLES = 257


def wrap(angle):
    """``angle`` reduced to [-pi, pi) (rad), any shape.

    Parameters
    ----------
    angle : array_like
        Angles in rad.

    Returns
    -------
    ndarray
        The reduced angles in rad, same shape as ``angle``.
    """
    return np.mod(np.asarray(angle, dtype=float) + math.pi, TWO_PI) - math.pi


def rotation_about(q_start, q_end, axis) -> np.ndarray:
    """Angle in rad, in [-pi, pi), of the rotation R(q_end) R(q_start)^T about ``axis`` (..., 3).

    Right-handed about the axis; exact when that rotation's axis is ``axis``.

    Parameters
    ----------
    q_start, q_end : array_like, shape (..., 4)
        Body-to-space quaternions, scalar first, at the start and the end.
    axis : array_like, shape (..., 3)
        The axis, space frame, any nonzero length (normalised before use).

    Returns
    -------
    ndarray, shape (...)
        The angle in rad, in [-pi, pi).
    """
    d = quaternion_multiply(q_end, quaternion_conjugate(q_start))
    n = np.asarray(axis, dtype=float)
    n = n / np.linalg.norm(n, axis=-1, keepdims=True)
    return wrap(2.0 * np.arctan2(np.sum(d[..., 1:] * n, axis=-1), d[..., 0]))


def _body_rate(m, moments):
    """m' = m x w of canonical body angular momenta (..., 3)."""
    return np.cross(m, m / moments)


def solid_angle(fm: FreeMotion, nodes: int = 64) -> float:
    """Oriented solid angle S (sr) enclosed by m/|m| over one period, in (-4 pi, 4 pi).

    The closed integral of (1 - cos vartheta) dvarphi about the pole n = +-e_k, k the axis the
    path encircles (axis 3 above the separatrix, axis 1 below), written as
    ``(x y' - y x') / (|L| (|L| + z))`` in time with (x, y, z) the components of m along a
    right-handed frame (a, b, n); the trapezoid rule over the period converges geometrically,
    and the nodes are doubled until two estimates agree to 1e-15 of 4 pi.

    Parameters
    ----------
    fm : FreeMotion
        One member's exact motion (:func:`stability.free_body.exact_attitude.free_motion`).
    nodes : int, default 64
        Trapezoid nodes per period to start from; doubled up to 2**16.

    Returns
    -------
    float
        The solid angle S in sr.
    """
    m0 = fm.m(0.0)[0]
    k = 2 if fm.kind in (MAJOR, PRECESS3) else 0  # the axis the path circles: 3, else 1
    sign = 1.0 if m0[k] >= 0.0 else -1.0
    a_i, b_i = (k + 1) % 3, (k + 2) % 3  # (a, b, n) right-handed: e_{k+1} x e_{k+2} = e_k
    previous = math.nan
    while True:
        t = np.arange(nodes) * (fm.period / nodes)
        m = fm.m(t)
        dm = _body_rate(m, fm.moments)
        x, y, z = m[:, a_i], sign * m[:, b_i], sign * m[:, k]
        dx, dy = dm[:, a_i], sign * dm[:, b_i]
        s = float(np.mean((x * dy - y * dx) / (fm.momentum * (fm.momentum + z)))) * fm.period
        if abs(s - previous) <= 1e-15 * 4.0 * math.pi or nodes >= 2**16:
            return s
        previous, nodes = s, 2 * nodes


def montgomery_formula(fm: FreeMotion) -> tuple[float, float, float]:
    """Montgomery's angle from the formula: ``(wrap(2 E T / |L| - S), 2 E T / |L|, S)`` in rad.

    Parameters
    ----------
    fm : FreeMotion
        One member's exact motion (:func:`stability.free_body.exact_attitude.free_motion`).

    Returns
    -------
    tuple of float
        Montgomery's angle wrapped to [-pi, pi), the dynamic phase ``2 E T / |L|`` and the
        solid angle S (:func:`solid_angle`), all in rad.
    """
    dynamic = 2.0 * fm.energy * fm.period / fm.momentum
    s = solid_angle(fm)
    return float(wrap(dynamic - s)), dynamic, s


def _continuous_change(psi) -> np.ndarray:
    """Change of an angle sampled densely enough along the last axis (wrapped increments)."""
    return np.sum(wrap(np.diff(psi, axis=-1)), axis=-1)


def _window_bracket(moments, momentum):
    """phi' lies in [|L|/I3, |L|/I2], so the half window lies in [pi I2/|L|, pi I3/|L|]."""
    return (math.pi * moments[:, 1] / momentum * (1.0 - 1e-6),
            math.pi * moments[:, 2] / momentum * (1.0 + 1e-6))


def _nearest_sign_change(t, x, t_near):
    """Per row, the sample interval [t_k, t_k+1] where x changes sign nearest ``t_near``."""
    change = np.sign(x[:, :-1]) * np.sign(x[:, 1:]) <= 0.0
    centre = 0.5 * (t[:, :-1] + t[:, 1:])
    distance = np.where(change, np.abs(centre - t_near[:, None]), np.inf)
    k = np.argmin(distance, axis=1)
    rows = np.arange(t.shape[0])
    found = np.isfinite(distance[rows, k])
    return np.where(found, t[rows, k], np.nan), np.where(found, t[rows, k + 1], np.nan)


def exact_angles(motions, t_near) -> dict:
    """Both angles of each member from its exact motion.

    Parameters
    ----------
    motions : sequence of FreeMotion
    t_near : array_like, shape (N,)
        The twist is measured about the flip nearest this time (s).

    Returns
    -------
    dict of ndarray, shape (N,)
        ``montgomery`` (phi(T) of the exact series, wrapped), ``montgomery_formula``,
        ``solid_angle``, ``dynamic_phase``, ``flip_time``, ``half_window``, ``twist``.
    """
    n = len(motions)
    t_near = np.broadcast_to(np.asarray(t_near, dtype=float), (n,))
    period = np.array([fm.period for fm in motions])
    momentum = np.array([fm.momentum for fm in motions])
    moments = np.array([fm.moments for fm in motions])
    formula = np.array([montgomery_formula(fm) for fm in motions])

    grid = t_near[:, None] + period[:, None] * np.linspace(-0.5, 0.5, 65)
    m2 = np.array([fm.m(g)[:, 1] for fm, g in zip(motions, grid)])

    def m2_and_slope(t):
        m = np.array([fm.m(tj)[0] for fm, tj in zip(motions, t)])
        return m[:, 1], _body_rate(m, moments)[:, 1]

    flip = bracketed_newton(m2_and_slope, *_nearest_sign_change(grid, m2, t_near))

    def window(delta):
        value = np.array([fm.phi(f + d) - fm.phi(f - d) for fm, f, d in zip(motions, flip, delta)])
        slope = np.array([fm.phi_rate([f + d, f - d]).sum()
                          for fm, f, d in zip(motions, flip, delta)])
        return value - TWO_PI, slope

    half = bracketed_newton(window, *_window_bracket(moments, momentum))
    s = np.linspace(-1.0, 1.0, _PSI_SAMPLES)
    twist = np.array([_continuous_change(spin_angle(fm.m(f + d * s)))
                      if np.isfinite(f + d) else np.nan for fm, f, d in zip(motions, flip, half)])
    return {
        "montgomery": wrap(np.array([fm.phi(fm.period) for fm in motions])),
        "montgomery_formula": formula[:, 0],
        "dynamic_phase": formula[:, 1],
        "solid_angle": formula[:, 2],
        "flip_time": flip,
        "half_window": half,
        "twist": twist,
    }


def _handle_azimuth(a, q):
    """phi read off attitudes q: the azimuth of the handle about L in the frame A (rad)."""
    handle = quaternion_to_matrix(quaternion_multiply(quaternion_conjugate(a), q))[..., :, 0]
    return np.arctan2(handle[..., 0], -handle[..., 1])


def run_angles(runs, period, t_near) -> dict:
    """Both angles of each member from a run (:class:`stability.free_body.attitude.AttitudeRuns`).

    The run must reach ``period`` exactly at a saved step (Montgomery's angle is read off the
    attitude there) and cover the twist's window about the flip nearest ``t_near``; the flip
    and the window are roots of the run's own solution (:meth:`AttitudeRuns.state_at`).

    Parameters
    ----------
    runs : AttitudeRuns
        The run, from :func:`stability.free_body.attitude.propagate_attitudes` (canonical frame).
    period : float or array_like, shape (N,)
        Each member's period T of the body motion in s.
    t_near : array_like, shape (N,)
        The twist is measured about the flip nearest this time (s).

    Returns
    -------
    dict of ndarray, shape (N,)
        ``montgomery``, ``flip_time``, ``half_window``, ``twist`` (rad and s), NaN where the
        window does not fit in the run.

    Raises
    ------
    ValueError
        If the run does not reach each member's period at a saved step.
    """
    n = runs.saved.shape[0]
    rows = np.arange(n)
    period = np.broadcast_to(np.asarray(period, dtype=float), (n,))
    times = runs.times
    x = runs.saved
    m0, q0 = x[:, 0, :3], x[:, 0, 3:]
    a = l_frame(m0, q0)
    k_period = np.rint(period / (runs.h * runs.save_every)).astype(np.int64)
    if np.any(k_period >= times.shape[1]) or not np.allclose(
            times[rows, np.minimum(k_period, times.shape[1] - 1)], period, rtol=1e-12):
        raise ValueError("the run must reach each member's period T at a saved step: take h = "
                         "T / n with n a multiple of save_every, over at least n steps")
    space_l = spatial_angular_momentum(q0, m0)
    montgomery = rotation_about(q0, x[rows, k_period, 3:], space_l)

    raw = _handle_azimuth(a[:, None, :], x[..., 3:])
    phi_saved = np.concatenate([np.zeros((n, 1)), np.cumsum(wrap(np.diff(raw, axis=1)), 1)], 1)
    interval = runs.h * runs.save_every

    def state_and_phi(t):
        state = runs.state_at(t)
        k = np.clip(np.floor(t / interval).astype(np.int64), 0, times.shape[1] - 1)
        phi = phi_saved[rows, k] + wrap(_handle_azimuth(a, state[:, 3:]) - raw[rows, k])
        return state, phi

    def m2_and_slope(t):
        m = runs.state_at(t)[:, :3]
        return m[:, 1], _body_rate(m, runs.moments)[:, 1]

    flip = bracketed_newton(m2_and_slope, *_nearest_sign_change(times, x[..., 1], t_near))
    momentum = np.linalg.norm(m0, axis=1)
    lo, hi = _window_bracket(runs.moments, momentum)
    fits = (flip - hi >= 0.0) & (flip + hi <= times[:, -1])
    flip = np.where(fits, flip, np.nan)

    def window(delta):
        after, phi_after = state_and_phi(np.nan_to_num(flip + delta))
        before, phi_before = state_and_phi(np.nan_to_num(flip - delta))
        slope = (precession_rate(after[:, :3], runs.moments)
                 + precession_rate(before[:, :3], runs.moments))
        return phi_after - phi_before - TWO_PI, slope

    half = np.where(fits, bracketed_newton(window, lo, hi), np.nan)
    start = np.nan_to_num(flip - half)
    end = np.nan_to_num(flip + half)
    psi_start = spin_angle(runs.state_at(start)[:, :3])
    psi_end = spin_angle(runs.state_at(end)[:, :3])
    inside = (times > start[:, None]) & (times < end[:, None])
    twist = np.empty(n)
    for j in range(n):  # psi along the saved states inside the window, then its ends
        path = np.concatenate([[psi_start[j]], spin_angle(x[j, inside[j], :3]), [psi_end[j]]])
        twist[j] = _continuous_change(path)
    return {
        "montgomery": montgomery,
        "flip_time": flip,
        "half_window": half,
        "twist": np.where(fits, twist, np.nan),
    }
