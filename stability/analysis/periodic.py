"""Measuring periodic signals from samples: level crossings, extrema and means.

A run stores a member's state every few steps; the quantities of a periodic motion (its
period, its turning points, the mean of a rate over it) are read from those samples here, to
an accuracy set by the integrator rather than by the sampling:

- :func:`level_crossings` and :func:`extrema` locate the crossings of a level and the turning
  points on the cubic Hermite interpolant of the samples and their time derivatives (which the
  state gives exactly): errors O(dt^4) in time and value, against O(dt^2) for straight lines.
- :func:`weighted_mean` is the weighted Birkhoff average of Das & Yorke [Nonlinearity 31, 491
  (2018)]: the samples weighted by the bump ``exp(-1 / (s (1 - s)))`` over the run, ``s`` the
  fraction of the run. For a smooth periodic or quasi-periodic signal it converges faster than
  any power of the number of periods, where a plain mean over a window that is not a whole
  number of periods has an error ~ 1 / (number of periods).
"""

from __future__ import annotations

import numpy as np

#: Bisection steps of the roots on [0, 1]: 2^-60 is below double rounding.
_BISECTIONS = 60


def _hermite(x0, x1, m0, m1, s):
    """Cubic Hermite interpolant on [0, 1] with end values x0, x1 and end slopes m0, m1."""
    s2 = s * s
    s3 = s2 * s
    return ((2.0 * s3 - 3.0 * s2 + 1.0) * x0 + (s3 - 2.0 * s2 + s) * m0
            + (-2.0 * s3 + 3.0 * s2) * x1 + (s3 - s2) * m1)


def _hermite_slope(x0, x1, m0, m1, s):
    """d/ds of :func:`_hermite`."""
    s2 = s * s
    return ((6.0 * s2 - 6.0 * s) * (x0 - x1) + (3.0 * s2 - 4.0 * s + 1.0) * m0
            + (3.0 * s2 - 2.0 * s) * m1)


def _bisect(f, lo_sign, n):
    """Root on [0, 1] of each of ``n`` functions ``f(s)`` whose sign at 0 is ``lo_sign``."""
    lo = np.zeros(n)
    hi = np.ones(n)
    for _ in range(_BISECTIONS):
        mid = 0.5 * (lo + hi)
        same = np.sign(f(mid)) == lo_sign
        lo = np.where(same, mid, lo)
        hi = np.where(same, hi, mid)
    return 0.5 * (lo + hi)


def _samples(t, x, dxdt):
    t = np.asarray(t, dtype=float)
    x = np.asarray(x, dtype=float)
    dxdt = np.asarray(dxdt, dtype=float)
    if not (t.ndim == x.ndim == dxdt.ndim == 1 and t.shape == x.shape == dxdt.shape):
        raise ValueError(f"t, x and dxdt must be 1-d arrays of one length, got shapes "
                         f"{t.shape}, {x.shape}, {dxdt.shape}")
    keep = np.isfinite(t) & np.isfinite(x) & np.isfinite(dxdt)
    return t[keep], x[keep], dxdt[keep]


def level_crossings(t, x, dxdt, level, direction=1):
    """Times where the signal crosses ``level`` upwards (``direction=1``) or downwards (-1).

    Parameters
    ----------
    t : array_like, shape (T,)
        Sample times, increasing (NaN samples, e.g. past a member's end, are dropped).
    x, dxdt : array_like, shape (T,)
        The signal and its time derivative at the samples.
    level : float
    direction : {1, -1}

    Returns
    -------
    ndarray, shape (K,)
        Crossing times, ascending: on each interval where ``x - level`` changes sign in the
        given direction, the root of the cubic Hermite interpolant (bisection to round-off).
    """
    t, x, dxdt = _samples(t, x, dxdt)
    y = (x - level) * direction
    k = np.flatnonzero((y[:-1] < 0.0) & (y[1:] >= 0.0))
    dt = t[k + 1] - t[k]
    y0, y1 = y[k], y[k + 1]
    m0, m1 = direction * dxdt[k] * dt, direction * dxdt[k + 1] * dt
    s = _bisect(lambda s: _hermite(y0, y1, m0, m1, s), -1.0, k.size)
    return t[k] + s * dt


def extrema(t, x, dxdt, kind="min"):
    """Local minima (``kind="min"``) or maxima (``"max"``) of the sampled signal.

    Parameters
    ----------
    t, x, dxdt : array_like, shape (T,)
        As in :func:`level_crossings`.
    kind : {"min", "max"}

    Returns
    -------
    times, values : ndarray, shape (K,)
        On each interval where ``dxdt`` changes sign (- to + for a minimum), the turning point
        of the cubic Hermite interpolant: the root of its (quadratic) slope, found by bisection.
    """
    if kind not in ("min", "max"):
        raise ValueError(f"kind must be 'min' or 'max', got {kind!r}")
    t, x, dxdt = _samples(t, x, dxdt)
    sign = 1.0 if kind == "min" else -1.0
    d = sign * dxdt
    k = np.flatnonzero((d[:-1] < 0.0) & (d[1:] >= 0.0))
    dt = t[k + 1] - t[k]
    x0, x1 = x[k], x[k + 1]
    m0, m1 = dxdt[k] * dt, dxdt[k + 1] * dt
    s = _bisect(lambda s: sign * _hermite_slope(x0, x1, m0, m1, s), -1.0, k.size)
    return t[k] + s * dt, _hermite(x0, x1, m0, m1, s)


def mean_period(crossings):
    """Mean spacing of successive same-direction crossings: ``(t_K - t_1) / (K - 1)``; NaN
    with fewer than two.

    Parameters
    ----------
    crossings : array_like, shape (K,)
        Crossing times, ascending (e.g. from :func:`level_crossings`).

    Returns
    -------
    float
        The mean period, in the units of ``crossings``.
    """
    crossings = np.asarray(crossings, dtype=float)
    if crossings.size < 2:
        return np.nan
    return (crossings[-1] - crossings[0]) / (crossings.size - 1)


def weighted_mean(f, axis=-1):
    """Weighted Birkhoff average of equally spaced samples ``f`` along ``axis``.

    The weight of sample k of N is ``exp(-1 / (s (1 - s)))`` at ``s = (k + 1/2) / N``
    (Das & Yorke 2018), normalised to sum 1. For a smooth (quasi-)periodic signal sampled
    finely enough to resolve it, the error falls faster than any power of the number of
    periods covered. NaN if any sample is NaN.

    Parameters
    ----------
    f : array_like
        Samples, equally spaced in time along ``axis``.
    axis : int, default -1
        The time axis.

    Returns
    -------
    ndarray or float
        The average, with the shape of ``f`` without ``axis``, in the units of ``f``.
    """
    f = np.asarray(f, dtype=float)
    n = f.shape[axis]
    s = (np.arange(n) + 0.5) / n
    w = np.exp(-1.0 / (s * (1.0 - s)))
    w /= w.sum()
    return np.tensordot(np.moveaxis(f, axis, -1), w, axes=([-1], [0]))
