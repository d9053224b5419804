"""Fits on per-member point sets: lines, exponentials, their misfits, means with standard
errors, and Richardson's estimate of a method's own bias.

Every fit works row by row on arrays (N, K), one row per member, NaN where a member has no point:
the per-member fits of thousands of ensembles run in a few array operations.
"""

from __future__ import annotations

import math

import numpy as np

from ..util.checks import real_array
from .members import Members

def window_points(mem: Members, low, high):
    """Per-member (t, A) points of the first growth phase with low <= A < high.

    Returns ``t`` and ``A`` of shape (N, K), NaN outside each member's window. For a time series
    the window runs from the last sample below ``low`` before the first sample at or above
    ``high`` up to that sample (the first growth phase only, before any flip); for passage
    times it is the levels in [low, high).
    """
    low = np.asarray(low, dtype=float)[:, None]
    high = np.asarray(high, dtype=float)[:, None]
    if mem.amp is not None:
        amp = mem.amp
        n, T = amp.shape
        k = np.arange(T)[None, :]
        above = amp >= high
        i_hi = np.where(above.any(axis=1), np.argmax(above, axis=1), T)[:, None]
        below = (amp < low) & (k < i_hi)
        last_below = np.where(below.any(axis=1), T - 1 - np.argmax(below[:, ::-1], axis=1), -1)
        inside = (k > last_below[:, None]) & (k < i_hi) & np.isfinite(amp)
        t = np.where(inside, mem.t[None, :], np.nan)
        a = np.where(inside, amp, np.nan)
        return t, a
    levels = mem.levels if mem.levels.ndim == 2 else mem.levels[None, :]  # per row: stacked
    inside = (levels >= low) & (levels < high) & np.isfinite(mem.passage)
    t = np.where(inside, mem.passage, np.nan)
    a = np.where(inside, levels, np.nan)
    return t, a


def line_fit(x, y, weight=None):
    """Least-squares line y = a + b x per row, ignoring NaN; returns (a, b, n)."""
    ok = np.isfinite(x) & np.isfinite(y)
    wgt = ok.astype(float) if weight is None else np.where(ok, weight, 0.0)
    x0 = np.where(ok, x, 0.0)
    y0 = np.where(ok, y, 0.0)
    sw = wgt.sum(axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        xm = (wgt * x0).sum(axis=1) / sw
        ym = (wgt * y0).sum(axis=1) / sw
        dx = np.where(ok, x0 - xm[:, None], 0.0)
        dy = np.where(ok, y0 - ym[:, None], 0.0)
        slope = (wgt * dx * dy).sum(axis=1) / (wgt * dx * dx).sum(axis=1)
    return ym - slope * xm, slope, ok.sum(axis=1)


def rms(res):
    """Root mean square of each row over its non-NaN entries (inf stays inf, none gives NaN)."""
    used = ~np.isnan(res)
    count = used.sum(axis=1)
    total = np.where(used, res, 0.0) ** 2
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(count > 0, np.sqrt(total.sum(axis=1) / count), np.nan)


def exponential_fit(t, a):
    """ln A = alpha + r t per row: returns (r, rms residual of ln A, n points)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        y = np.log(a)
    alpha, r, n = line_fit(t, y)
    res = y - alpha[:, None] - r[:, None] * t
    return r, rms(res), n


def linear_fit(t, a):
    """A = beta + c t per row, relative least squares (weights 1/A^2): (c, rms of ln ratio)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        weight = 1.0 / a**2
    beta, c, n = line_fit(t, a, weight)
    model = beta[:, None] + c[:, None] * t
    with np.errstate(divide="ignore", invalid="ignore"):
        res = np.where(model > 0, np.log(a / model), np.inf)
        res = np.where(np.isfinite(t) & np.isfinite(a), res, np.nan)
    return c, rms(res), n


def mean_stderr(x):
    """Mean, standard error of the mean (NaN below 2 values) and count of the finite values."""
    x = np.asarray(x, dtype=float)
    x = x[np.isfinite(x)]
    n = x.size
    if n == 0:
        return math.nan, math.nan, 0
    mean = float(x.mean())
    stderr = float(x.std(ddof=1) / math.sqrt(n)) if n > 1 else math.nan
    return mean, stderr, n


def growth_line(time, amplitude, rate, low, high):
    """The line ``ln A = intercept + rate t`` through an amplitude's linear phase, for drawing.

    To show a measured growth rate over an ensemble's median amplitude: the window runs from
    the first sample above ``low`` up to the last sample below ``high`` that follows it without
    a gap, and the intercept is the least-squares one at the fixed slope ``rate``.

    Parameters
    ----------
    time : array_like, shape (T,)
        Times in s, ascending.
    amplitude : array_like, shape (T,)
        A positive, growing amplitude (e.g. the ensemble median), any unit.
    rate : float
        The slope, s-1 (e.g. :func:`measured_growth_rate`).
    low, high : float
        The window, in the units of ``amplitude``.

    Returns
    -------
    intercept : float
        ``ln(amplitude)`` of the line at t = 0 (NaN if the window holds fewer than 3 samples).
    window : tuple of float
        First and last time of the window, in s (NaN if no sample is above ``low``).
    """
    amplitude = real_array("amplitude", amplitude)
    time = real_array("time", time, "s")
    above = np.flatnonzero(amplitude > low)
    if above.size == 0:
        return math.nan, (math.nan, math.nan)
    i0 = int(above[0])
    i1 = i0
    while i1 + 1 < amplitude.size and low < amplitude[i1 + 1] < high:
        i1 += 1
    window = (float(time[i0]), float(time[i1]))
    if i1 - i0 + 1 < 3 or not amplitude[i0] < high:
        return math.nan, window
    keep = slice(i0, i1 + 1)
    return float(np.mean(np.log(amplitude[keep]) - rate * time[keep])), window


def richardson_bias(coarse, fine, order):
    """A method's own O(h^p) bias at step h, from the same estimate at h and at h / 2.

    Richardson extrapolation: with ``X(h) = X + c h^p``, ``X(h) - X(h/2) = c h^p (1 - 2^-p)``,
    so the bias of ``coarse`` is ``(coarse - fine) / (1 - 2^-p)``.

    Parameters
    ----------
    coarse, fine : array_like
        The estimate at h and at h / 2 (broadcast together).
    order : array_like
        The method's order p (broadcast; ``inf`` for an exact flow gives the plain difference).

    Returns
    -------
    ndarray
        The bias in the units of the estimate; NaN where either estimate is.
    """
    with np.errstate(invalid="ignore", divide="ignore"):
        return (np.asarray(coarse) - fine) / (1.0 - 2.0 ** -np.asarray(order, dtype=float))


#: The module's public API (the rest serves the package's other modules).
__all__ = ["growth_line", "richardson_bias"]
