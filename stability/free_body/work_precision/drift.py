"""Invariant errors over long runs: bounded, a round-off random walk, or a linear drift.

:func:`long_horizon` follows a few members for ``>= 1e6`` steps and keeps the RMS over them of
the relative energy and |L| errors against time. The log-log slope of the error reached so far
(:func:`envelope`, :func:`log_slope`) says which behaviour it is (:func:`drift_kind`): 0 for a
bounded error (Poisson splittings), 1/2 for a round-off random walk (Brouwer's law), 1 for a
linear drift (RK4's energy).
"""

from __future__ import annotations

import math

import numpy as np

from ..propagate import propagate

#: Long-horizon log-log slopes that separate the three behaviours of an invariant's error:
#: below BOUNDED_SLOPE "bounded", above DRIFT_SLOPE "linear drift", between them "random walk".
BOUNDED_SLOPE = 0.25
DRIFT_SLOPE = 0.75
#: Relative invariant errors below this are round-off (~1e4 ulps), whatever their slope.
ROUNDOFF_LEVEL = 1e-12


def long_horizon(spec, body, w0, h, steps, samples):
    """Energy and |L| error against time over ``steps`` steps: RMS over the members.

    Parameters
    ----------
    spec : MethodSpec or str
    body : RigidBody
    w0 : ndarray, shape (N, 3)
        Starts, rad/s.
    h : float
        Step, s.
    steps, samples : int
        Steps, and states kept per member (every ``steps // samples``-th).

    Returns
    -------
    t : ndarray, shape (S,)
        Times of the kept states, s.
    energy, momentum : ndarray, shape (S,)
        RMS over members of E / E0 - 1 and |L| / |L0| - 1 (NaN once a member failed).
    wall : float
        Kernel seconds.
    """
    moments = body.moments
    m0 = moments * w0
    save_every = steps // samples
    run = propagate(spec, moments, m0, h, steps, save_every=save_every, progress=False)
    m = run.saved  # (N, S, 3)
    e0 = np.sum(m0 * m0 / moments, axis=1)
    l0 = np.linalg.norm(m0, axis=1)
    de = np.sum(m * m / moments, axis=2) / e0[:, None] - 1.0
    dl = np.linalg.norm(m, axis=2) / l0[:, None] - 1.0
    t = h * save_every * np.arange(1, m.shape[1] + 1)
    rms = lambda x: np.sqrt(np.mean(x * x, axis=0))  # noqa: E731 - NaN propagates on purpose
    return t, rms(de), rms(dl), run.wall_time


def envelope(err) -> np.ndarray:
    """Running maximum of |err| over time: the error reached so far.

    NaNs are skipped; only those before the first number stay NaN.

    Parameters
    ----------
    err : array_like, shape (S,)
        An error against time (signed or not), dimensionless.

    Returns
    -------
    ndarray, shape (S,)
        ``max(|err[:k + 1]|)`` over the non-NaN entries at each k (``numpy.fmax``): NaN only
        before the first number.
    """
    err = np.abs(np.asarray(err, dtype=float))
    return np.fmax.accumulate(err) if err.size else err


def log_slope(t, err, decades=2.0) -> float:
    """Least-squares slope of log(envelope(err)) against log(t) over the last ``decades`` of t.

    The envelope (running maximum) turns an oscillating but bounded error into a plateau
    (slope 0), so the slope separates bounded, random-walk (1/2) and drifting (1) errors.

    Parameters
    ----------
    t : array_like, shape (S,)
        Times, ascending and > 0, s.
    err : array_like, shape (S,)
        The error at each time, dimensionless.
    decades : float, default 2.0
        The fit uses the times ``t >= t[-1] * 10 ** -decades``.

    Returns
    -------
    float
        The slope, dimensionless; NaN if fewer than three finite, positive envelope points lie
        in the window.
    """
    t, err = np.asarray(t), envelope(err)
    keep = (t >= t[-1] * 10.0**-decades) & np.isfinite(err) & (err > 0)
    if np.count_nonzero(keep) < 3:
        return np.nan
    return float(np.polyfit(np.log(t[keep]), np.log(err[keep]), 1)[0])


def drift_kind(slope: float, size: float = math.inf) -> str:
    """In words, the behaviour of an invariant's error from its long-run log-log slope and size.

    "bounded" (slope < BOUNDED_SLOPE), "linear drift" (slope > DRIFT_SLOPE) or "random walk"
    in between; an error that stays below ROUNDOFF_LEVEL is "round-off", and its slope then
    tells an unbiased random walk (t^(1/2), Brouwer's law) from a biased one (closer to t).

    Parameters
    ----------
    slope : float
        Long-run log-log slope (:func:`log_slope`).
    size : float, default inf
        Largest relative error reached (the maximum of :func:`envelope`), dimensionless;
        the default never counts as round-off.

    Returns
    -------
    str
        ``"bounded"``, ``"random walk"``, ``"linear drift"``, ``"round-off, bounded"``,
        ``"round-off, grows like t^<slope>"``, or ``"n/a"`` for a NaN slope.
    """
    if not np.isfinite(slope):
        return "n/a"
    if size <= ROUNDOFF_LEVEL:
        if slope < BOUNDED_SLOPE:
            return "round-off, bounded"
        return f"round-off, grows like t^{slope:.2f}"
    if slope < BOUNDED_SLOPE:
        return "bounded"
    if slope > DRIFT_SLOPE:
        return "linear drift"
    return "random walk"
