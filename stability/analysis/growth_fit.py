"""The growth-rate fit of :func:`stability.measured_growth_rate`, member by member, compiled.

:func:`series_growth_rates` gives each member of a time series ``w`` (member, time, axis) the
rate :func:`~stability.analysis.estimates.member_rates` gives it from the same series: the
regime of :func:`~stability.analysis.regimes.classify` (exponential growth, oscillation,
algebraic drift, neutral, undetermined) and, for an exponential member, the least-squares slope
of ``ln A`` over its linear phase (:func:`~stability.analysis.fits.window_points`, the first
growth phase from ``low_factor`` times the start to ``high_fraction`` of min(spin, saturation)).
One pass over each member's samples, members side by side on Numba's threads: a chunk of an
ensemble is measured in less time than its member loop took. The sums run in sample order, so
a rate differs from the NumPy estimator's (pairwise sums) by rounding only, ~1e-15 relative.
"""

from __future__ import annotations

import math

import numpy as np
import numba
from numba import njit, prange

from ..core.body import canonical_m_to_w
from ..ensemble.combine import log_bin, log_bins
from ..util import conventions as cv
from .regimes import DEPARTURE_FACTOR, MIN_CROSSINGS, MIN_POINTS, WINDOW_HIGH_FRACTION

__all__ = ["series_growth_rates", "canonical_growth_rates"]


@njit(cache=True, error_model="numpy")
def _window(amp, low, high):
    """The first growth phase of ``amp``: samples ``first ... end - 1`` (low <= A < high,
    from the last sample below ``low`` before the first at or above ``high``)."""
    n = amp.size
    end = n
    for k in range(n):
        if amp[k] >= high:
            end = k
            break
    first = 0
    for k in range(end - 1, -1, -1):
        if amp[k] < low:
            first = k + 1
            break
    return first, end


@njit(cache=True, error_model="numpy")
def _line(t, y, wgt, first, end):
    """Weighted least-squares line y = a + b t over the finite points of first ... end - 1:
    (a, b, n); NaN for fewer than two distinct times."""
    sw = 0.0
    swx = 0.0
    swy = 0.0
    n = 0
    for k in range(first, end):
        if math.isfinite(t[k]) and math.isfinite(y[k]):
            sw += wgt[k]
            swx += wgt[k] * t[k]
            swy += wgt[k] * y[k]
            n += 1
    xm = swx / sw
    ym = swy / sw
    sxy = 0.0
    sxx = 0.0
    for k in range(first, end):
        if math.isfinite(t[k]) and math.isfinite(y[k]):
            dx = t[k] - xm
            sxy += wgt[k] * dx * (y[k] - ym)
            sxx += wgt[k] * dx * dx
    slope = sxy / sxx
    return ym - slope * xm, slope, n


@njit(cache=True, error_model="numpy")
def _exponential(t, amp, first, end, logs, ones):
    """ln A = alpha + r t over the window: (r, rms residual of ln A, n points)."""
    for k in range(first, end):
        logs[k] = math.log(amp[k]) if amp[k] > 0.0 else (-math.inf if amp[k] == 0.0 else math.nan)
    alpha, r, n = _line(t, logs, ones, first, end)
    total = 0.0
    used = 0
    for k in range(first, end):
        res = logs[k] - alpha - r * t[k]
        if not math.isnan(res):
            total += res * res
            used += 1
    return r, (math.sqrt(total / used) if used > 0 else math.nan), n


@njit(cache=True, error_model="numpy")
def _linear(t, amp, first, end, weights):
    """A = beta + c t, weights 1/A^2: (c, rms of ln(A / model))."""
    for k in range(first, end):
        weights[k] = 1.0 / amp[k] ** 2
    beta, c, _ = _line(t, amp, weights, first, end)
    total = 0.0
    used = 0
    for k in range(first, end):
        if not (math.isfinite(t[k]) and math.isfinite(amp[k])):
            continue
        model = beta + c * t[k]
        res = math.log(amp[k] / model) if model > 0.0 else math.inf
        if not math.isnan(res):
            total += res * res
            used += 1
    return c, (math.sqrt(total / used) if used > 0 else math.nan)


@njit(cache=True, error_model="numpy")
def _crossings(x):
    """Sign changes of ``x`` between finite neighbours (a zero counts as negative)."""
    count = 0
    for k in range(x.size - 1):
        if math.isfinite(x[k]) and math.isfinite(x[k + 1]) and (x[k] > 0.0) != (x[k + 1] > 0.0):
            count += 1
    return count


@njit(cache=True, error_model="numpy")
def _member(t, w, valid, a, b, c, spin, low_factor, high_fraction, exponential, algebraic,
            oscillation, neutral, undetermined, amp, tt, scratch, ones):
    """One member's (rate, regime) from its samples ``w`` (T, 3); its amplitudes into ``amp``.
    ``tt`` and ``scratch`` (T,) are work space, ``ones`` (T,) all ones."""
    n_times = w.shape[0]
    max_perp = -math.inf
    finite = True
    for k in range(n_times):
        amp[k] = math.hypot(w[k, b], w[k, c])
        for j in range(3):
            if not math.isfinite(w[k, j]):
                finite = False
        if math.isfinite(amp[k]) and amp[k] > max_perp:
            max_perp = amp[k]
    for k in range(n_times):  # NaN samples leave every window
        tt[k] = t[k] if math.isfinite(amp[k]) else math.nan
    a0 = amp[0]
    flipped = _crossings(w[:, a]) >= 1
    oscillating = (not flipped) and _crossings(w[:, b]) >= MIN_CROSSINGS
    departed = flipped or max_perp > DEPARTURE_FACTOR * a0
    saturation = min(spin, max_perp) if flipped else spin

    first, end = _window(amp, DEPARTURE_FACTOR * a0, WINDOW_HIGH_FRACTION * saturation)
    _, exp_rms, n_pts = _exponential(tt, amp, first, end, scratch, ones)
    drift, lin_rms = _linear(tt, amp, first, end, scratch)
    regime = undetermined
    if departed and not oscillating and n_pts >= MIN_POINTS:
        if exp_rms <= lin_rms:
            regime = exponential
        elif lin_rms < exp_rms and drift > 0.0:
            regime = algebraic
    if oscillating:
        regime = oscillation
    if not departed and not oscillating:
        regime = neutral
    if not (valid and finite):
        regime = undetermined
    rate = math.nan
    if regime == exponential:
        first, end = _window(amp, low_factor * a0, high_fraction * saturation)
        r, _, n = _exponential(tt, amp, first, end, scratch, ones)
        if n >= MIN_POINTS:
            rate = r
    if not valid:
        amp[:] = math.nan
    return rate, regime


@njit(cache=True, parallel=True, error_model="numpy")
def _rates(t, w0, m, canonical, perm, signs, moments, valid, a, b, c, spin, low_factor,
           high_fraction, exponential, algebraic, oscillation, neutral, undetermined,
           amplitudes, keep, log_low, width, counts):
    """Every member's (rate, regime), the members in one contiguous block per entry of
    ``counts`` (n_blocks, T, bins), each block on one thread with its own work space.

    ``canonical``: the samples are ``w0`` then ``m`` (canonical angular momenta, (N, T - 1,
    3)), each turned into body-frame w as it is read
    (:func:`stability.core.body.canonical_m_to_w`: the numbers of the series built first);
    else ``m`` is the body-frame series (N, T, 3). ``keep``: each member's amplitudes into
    ``amplitudes[i]`` (N, T); else into the block's row of ``amplitudes`` (n_blocks, T), and
    counted (when ``counts`` has bins) in the log bins of :func:`log_bin`."""
    n_members, n_times = valid.size, t.size
    n_blocks, _, n_bins = counts.shape
    rates = np.empty(n_members)
    regimes = np.empty(n_members, dtype=np.int8)
    size = (n_members + n_blocks - 1) // n_blocks
    for block in prange(n_blocks):
        w = np.empty((n_times, 3))
        tt = np.empty(n_times)
        scratch = np.empty(n_times)
        ones = np.ones(n_times)
        for i in range(block * size, min(n_members, (block + 1) * size)):
            if canonical:
                w[0] = w0[i]
                canonical_m_to_w(m[i, : n_times - 1], perm, signs, moments, w[1:])
                series = w
            else:
                series = m[i]
            amp = amplitudes[i] if keep else amplitudes[block]
            rates[i], regimes[i] = _member(
                t, series, valid[i], a, b, c, spin, low_factor, high_fraction, exponential,
                algebraic, oscillation, neutral, undetermined, amp, tt, scratch, ones)
            if n_bins > 0:
                for k in range(n_times):
                    v = amp[k]
                    if math.isfinite(v) and v > 0.0:
                        counts[block, k, log_bin(v, log_low, width, n_bins)] += 1
    return rates, regimes


def _arguments(t, n, axis, spin, low_factor, high_fraction, valid):
    """The kernels' arguments shared by both entries: the times, the valid members, the spin
    axis and the two perpendicular to it (0-based), the spin, the window, the regime codes."""
    t = np.ascontiguousarray(t, dtype=np.float64)
    valid = np.ones(n, dtype=np.bool_) if valid is None else np.asarray(valid, dtype=np.bool_)
    b, c = cv.perpendicular_axes(int(axis))
    return (t, valid, int(axis) - 1, b - 1, c - 1, abs(float(spin)), float(low_factor),
            float(high_fraction), cv.REGIME_EXPONENTIAL, cv.REGIME_ALGEBRAIC,
            cv.REGIME_OSCILLATION, cv.REGIME_NEUTRAL, cv.REGIME_UNDETERMINED)


def _fit(t, w0, m, canonical, frame, moments, n, axis, spin, low_factor, high_fraction,
         valid, edges):
    """Both entries' call of the kernel: (rates, regimes, amplitudes or their counts)."""
    t, valid, *rest = _arguments(t, n, axis, spin, low_factor, high_fraction, valid)
    perm, signs = frame
    blocks = max(1, min(numba.get_num_threads(), n))
    if edges is None:  # every member's amplitudes kept, nothing counted
        log_low, width, n_bins = 0.0, 1.0, 0
        amplitudes = np.empty((n, t.size))
    else:  # one row of work space per block, the amplitudes counted
        log_low, width, n_bins = log_bins(edges)
        amplitudes = np.empty((blocks, t.size))
    counts = np.zeros((blocks, t.size if n_bins else 0, n_bins), dtype=np.int32)
    rates, regimes = _rates(
        t, w0, m, canonical, np.asarray(perm, dtype=np.int64),
        np.asarray(signs, dtype=np.float64), np.asarray(moments, dtype=np.float64), valid,
        *rest, amplitudes, edges is None, log_low, width, counts)
    if edges is None:
        return rates, regimes, amplitudes
    return rates, regimes, counts.sum(axis=0).astype(np.int32)


def canonical_growth_rates(t, w0, m, frame, moments, axis: int, spin: float,
                           low_factor: float, high_fraction: float, valid=None, edges=None):
    """:func:`series_growth_rates` of members whose samples after the start are the member
    loop's canonical angular momenta ``m`` (N, >= T - 1, 3) in the frame ``frame = (perm,
    signs)`` (:func:`stability.core.body.canonical_frame`) of a body of ``moments``: the body-
    frame series is never built (the same numbers as from it)."""
    w0 = np.ascontiguousarray(w0, dtype=np.float64)
    return _fit(t, w0, m, True, frame, moments, w0.shape[0], axis, spin, low_factor,
                high_fraction, valid, edges)


def series_growth_rates(t, w, axis: int, spin: float, low_factor: float, high_fraction: float,
                        valid=None, edges=None):
    """Each member's growth rate fitted over its linear phase, its regime and its amplitude.

    Parameters
    ----------
    t : array_like, shape (T,)
        Sample times, s.
    w : array_like, shape (N, T, 3)
        Angular velocity samples, rad/s.
    axis : int
        Spin axis, 1-based.
    spin : float
        Spin rate, rad/s (> 0).
    low_factor, high_fraction : float
        The window (:func:`~stability.analysis.estimates.measured_growth_rate`).
    valid : array_like of bool, shape (N,), optional
        Members whose status is ok; default all.
    edges : ndarray, optional
        Log-bin edges (:func:`stability.ensemble.combine.log_edges`): the amplitudes are then
        counted as they are made, :func:`~stability.ensemble.combine.log_histogram` of them
        (the same counts), and never kept.

    Returns
    -------
    rates : ndarray, shape (N,)
        s-1; NaN where the member's departure is not exponential or its window holds fewer
        than ``MIN_POINTS`` samples.
    regimes : ndarray of int8, shape (N,)
        The regime codes of :mod:`stability.util.conventions`.
    amplitudes : ndarray, shape (N, T)
        The perpendicular amplitude ``sqrt(w_b^2 + w_c^2)`` of each sample, rad/s; NaN for the
        members not ``valid``. With ``edges``, their counts instead: int32 (T, bins) over the
        ``valid`` members.
    """
    w = np.ascontiguousarray(w, dtype=np.float64)
    return _fit(t, np.empty((0, 3)), w, False, (np.arange(3), np.ones(3)), np.ones(3),
                w.shape[0], axis, spin, low_factor, high_fraction, valid, edges)
