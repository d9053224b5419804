"""What the dissipation studies read from a run: nutation angles, fitted rates, the end state.

Every function works on NumPy arrays of one member's samples (or of many, where the shapes say
so) and knows nothing of scenes or Datasets.
"""

from __future__ import annotations

import numpy as np

#: Fewest samples a fitted window holds.
MIN_FIT_SAMPLES = 8
#: Least growth (or decay) a fitted window spans, in e-folds: less is not a linear regime
#: long enough to fit.
MIN_FIT_EFOLDS = 1.0


def nutation_angle(H, axis: int = 0) -> np.ndarray:
    """The angle (rad) between body axis ``axis`` and the angular momentum H (..., 3):
    ``atan2(sqrt(H_b^2 + H_c^2), H_a)``, in [0, pi].

    Parameters
    ----------
    H : array_like, shape (..., 3)
        Angular momentum in the body frame, kg m2 s-1.
    axis : int
        Body axis, 0, 1 or 2.
    """
    H = np.asarray(H, dtype=float)
    across = [k for k in range(3) if k != axis]
    return np.arctan2(np.hypot(H[..., across[0]], H[..., across[1]]), H[..., axis])


def nutation_amplitude(H, moments, axis: int = 0) -> np.ndarray:
    """The sine of the angle between body axis ``axis`` and the angular momentum H (..., 3) as a
    rigid body's motion keeps it: ``sqrt(sum_k H_k^2 w_k / max w) / |H|`` over the other axes,
    ``w_k = |1/A_a - 1/A_k|`` (``moments`` A, kg m2).

    Across equal moments it is the angle's sine (``|H_a| / |H|`` about an axis whose plane of
    equal moments holds the other axis). Across unequal ones the angle itself swings twice a
    nutation between two values, and samples taken at a slower cadence alias that swing into
    a fitted rate; this, a constant of the rigid motion, does not swing.

    Parameters
    ----------
    H : array_like, shape (..., 3)
        Angular momentum in the body frame, kg m2 s-1.
    moments : array_like, shape (3,)
        The whole system's principal moments A, kg m2.
    axis : int
        Body axis, 0, 1 or 2.
    """
    H = np.asarray(H, dtype=float)
    A = np.asarray(moments, dtype=float)
    weights = np.abs(1.0 / A[axis] - 1.0 / A)
    weights[axis] = 0.0
    weights = weights / weights.max()
    return np.sqrt(np.sum(H * H * weights, axis=-1)) / np.linalg.norm(H, axis=-1)


def exponential_rate(t, amplitude, keep) -> float:
    """The rate (s-1) of ``amplitude ~ exp(rate t)``: the least-squares slope of
    ``ln(amplitude)`` over the samples ``keep``; NaN when they are fewer than
    :data:`MIN_FIT_SAMPLES` or span less than :data:`MIN_FIT_EFOLDS` e-folds.

    Parameters
    ----------
    t, amplitude : ndarray, shape (n,)
        Times (s) and positive amplitudes.
    keep : ndarray of bool, shape (n,)
        The window.
    """
    t = np.asarray(t, dtype=float)
    amplitude = np.asarray(amplitude, dtype=float)
    keep = np.asarray(keep, dtype=bool) & np.isfinite(amplitude) & (amplitude > 0.0)
    if keep.sum() < MIN_FIT_SAMPLES:
        return np.nan
    log = np.log(amplitude[keep])
    if log.max() - log.min() < MIN_FIT_EFOLDS:
        return np.nan
    return float(np.polyfit(t[keep], log, 1)[0])


def growth_window(t, theta, settle, top):
    """The samples of a growing nutation in its linear regime: after ``settle`` (s), once the
    faster modes have died away, and while ``theta <= top`` (rad), before the first sample
    above it.

    Parameters
    ----------
    t : ndarray, shape (n,)
        Sample times, s.
    theta : ndarray, shape (n,)
        Nutation angles, rad.
    settle : float
        Time (s) the faster modes take to die away.
    top : float
        Largest value of the linear regime.
    """
    t = np.asarray(t, dtype=float)
    theta = np.asarray(theta, dtype=float)
    above = np.flatnonzero(~(theta <= top))
    end = above[0] if above.size else theta.size
    keep = np.zeros(theta.size, dtype=bool)
    keep[:end] = t[:end] >= settle
    return keep


def decay_window(t, departure, top, floor, settle):
    """The samples of a dying departure (``|cos theta|`` from the major axis, say) in its
    linear regime: from ``settle`` (s) after it first falls to ``top``, while it stays above
    ``floor`` (round-off).

    Parameters
    ----------
    t : ndarray, shape (n,)
        Sample times, s.
    departure : ndarray, shape (n,)
        The departure from the major axis (1).
    top : float
        Largest value of the linear regime.
    floor : float
        Smallest value fitted (round-off below).
    settle : float
        Time (s) the faster modes take to die away.
    """
    t = np.asarray(t, dtype=float)
    departure = np.abs(np.asarray(departure, dtype=float))
    below = np.flatnonzero(departure <= top)
    if not below.size:
        return np.zeros(departure.size, dtype=bool)
    return (t >= t[below[0]] + settle) & (departure >= floor) & np.isfinite(departure)


def relative_drift(values) -> np.ndarray:
    """``max_k |v_k / v_0 - 1|`` over the last axis of ``values`` (..., n), NaN samples
    skipped: the largest relative change of an invariant.

    Parameters
    ----------
    values : ndarray, shape (..., n)
        Samples along the last axis.
    """
    values = np.asarray(values, dtype=float)
    return np.nanmax(np.abs(values / values[..., :1] - 1.0), axis=-1)


def largest_rise(values) -> np.ndarray:
    """``max_k (v_{k+1} - v_k) / |v_0|`` over the last axis (..., n), 0 when it never rises:
    how far a quantity that should only fall (the energy) ever went up, relative to its start.

    Parameters
    ----------
    values : ndarray, shape (..., n)
        Samples along the last axis.
    """
    values = np.asarray(values, dtype=float)
    rise = np.diff(values, axis=-1) / np.abs(values[..., :1])
    return np.maximum(np.nanmax(rise, axis=-1, initial=-np.inf), 0.0)
