"""Estimators on ensembles: growth rate, oscillation frequency, measured Omega^2, flip statistics.

Each estimator takes the Dataset of one ensemble (one body, one spin axis) in either of the two
forms the package writes:

- a **time series**: ``w`` (member, time, axis) in rad s-1 (or (time, axis) for one trajectory,
  as ``integrate`` returns);
- **summaries only** (as ``run_ensemble(..., summaries_only=True)`` writes them): per-member
  ``passage_time`` (member, level), the first time the perpendicular amplitude
  ``sqrt(w_b^2 + w_c^2)`` reaches each ``level`` (rad s-1), the sign changes of the spin-axis
  component (``flip_count``, ``first_flip_time``, ``last_flip_time``) and of one perpendicular
  component (``perp_crossing_count``, ``first_perp_crossing``, ``last_perp_crossing``),
  ``max_perp_amplitude``, ``status`` and the start ``w0`` (member, axis).

Here ``b`` and ``c`` are the two axes perpendicular to the spin axis. Every member is first put in a
**regime** from its own data, so that no rate is forced on a departure that is not exponential
(:func:`member_regimes`):

- *oscillation*: the first perpendicular component crosses zero at least ``MIN_CROSSINGS``
  times and the spin-axis component never does. Frequency from the crossings: consecutive zeros
  of ``w_b`` are half a period apart, so ``Omega = pi (n - 1) / (t_last - t_first)``.
- *exponential growth* / *algebraic drift*: the spin-axis component flips, or the perpendicular
  amplitude grows past ``DEPARTURE_FACTOR`` times its start. The amplitude between those bounds
  is fitted by an exponential (``ln A = a + r t``) and by a straight line (``A = b + c t``, the
  departure along an equal-moment axis, ERRATA 3); the better relative fit names the regime.
- *neutral*: no crossing and no departure within the run (the sphere, or an axis whose period is
  far longer than the run).

The **growth rate** of an exponential member is the least-squares slope of ``ln A`` against
``t`` over the linear phase only: from ``low_factor`` (default ``WINDOW_LOW_FACTOR``) times the
initial amplitude, where the decaying mode ``e^{-lambda t}`` that starts with the growing one
has fallen to ~``1 / low_factor^2`` of it, up to ``WINDOW_HIGH_FRACTION`` of the smaller of the
spin and the member's saturation amplitude (its largest perpendicular amplitude once it has
flipped), where nonlinear terms are ~1e-4 relative (literature notes 1.4 and 2.2). Next to the
equal-moment edges the two eigenvectors are nearly parallel and the decaying mode starts larger
than a0; there a lower edge of 300 a0 and a start of 1e-7 of the spin (three decades of window)
bring the estimator's own bias to a few 1e-6 (the stability map's settings). From passage times
the same fit is the slope of ``ln(level)`` against the passage time; a tracker that interpolates
the passage linearly in A between steps h adds an error up to ``lambda h^2 / 8`` per level, which
averages out over members and shows in the standard error. Uncertainties are standard errors of
the mean over members.

Measured ``Omega^2`` is ``-rate^2`` for growth and ``+frequency^2`` for oscillation
(``w_b'' = -Omega^2 w_b``, ERRATA 2), to put beside the analytic value. A Dataset may record the
growth-rate window it was analysed with (:data:`WINDOW_ATTRS`); the estimators then use it.

Also here: the exact flip intervals of each start and their asymptote
(:func:`exact_flip_intervals`, :func:`complementary_moduli`), the Richardson estimate of an
integrator's own O(h^p) bias (:func:`richardson_bias`), and :func:`analyse_ensemble`, which adds
the exact answers, amplitude quantiles and the measured growth rate to an ensemble's Dataset.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import xarray as xr

from .free_body.model import growth_rate, omega_squared, perpendicular_axes
from .free_body.exact import flip_intervals
from .output.dataset import body_from_attrs
from .schema import ESTIMATES, TENNIS_RACKET
from .util import conventions as cv
from .util.checks import real_array

# Regime codes (int8), per member and per ensemble, declared with the other codes.
from .util.conventions import (
    REGIME_ALGEBRAIC,
    REGIME_EXPONENTIAL,
    REGIME_FLAG_VALUES,
    REGIME_MEANINGS,
    REGIME_NEUTRAL,
    REGIME_OSCILLATION,
    REGIME_UNDETERMINED,
)

#: Lower edge of the growth-rate window, in units of the member's initial perpendicular
#: amplitude a0. A start off the unstable eigenvector carries a decaying mode; at 100 a0 it is
#: below (1/100)^2 = 1e-4 of the growing mode in ln A.
WINDOW_LOW_FACTOR = 100.0
#: Upper edge of the growth-rate window, as a fraction of min(spin, saturation amplitude):
#: nonlinear corrections to ln A are O((A / A_sat)^2) = 1e-4 there (sech form, literature 1.4).
WINDOW_HIGH_FRACTION = 1e-2
#: Dataset attributes that record the growth-rate window an ensemble was analysed with (as a
#: study writes them): :func:`measured_growth_rate` and :func:`measured_omega_squared` use them
#: when no window is passed, so ``ds.stability.measured_growth_rate()`` gives the study's number.
WINDOW_ATTRS = {"low_factor": "growth_window_low_factor",
                "high_fraction": "growth_window_high_fraction"}
#: A member "departs" once its perpendicular amplitude reaches this many times a0; the points
#: from here to the upper edge decide exponential against algebraic departure.
DEPARTURE_FACTOR = 3.0
#: Fewest points in a per-member fit.
MIN_POINTS = 3
#: Fewest zero crossings of the first perpendicular component for a frequency.
MIN_CROSSINGS = 3
#: Fraction of valid members that must share a regime for the ensemble to take it.
MAJORITY = 0.5

#: Sign of Omega^2 each regime stands for (NaN: no statement).
REGIME_SIGN = {
    REGIME_UNDETERMINED: math.nan,
    REGIME_NEUTRAL: 0.0,
    REGIME_OSCILLATION: 1.0,
    REGIME_EXPONENTIAL: -1.0,
    REGIME_ALGEBRAIC: 0.0,
}

# Names of the summaries-only variables (see the module docstring).
PASSAGE = "passage_time"
LEVEL = "level"
AXIS_CROSSINGS = "flip_count"
FIRST_AXIS_CROSSING = "first_flip_time"
LAST_AXIS_CROSSING = "last_flip_time"
PERP_CROSSINGS = "perp_crossing_count"
FIRST_PERP_CROSSING = "first_perp_crossing"
LAST_PERP_CROSSING = "last_perp_crossing"
MAX_PERP = "max_perp_amplitude"
W0 = "w0"
#: The per-member summaries besides the passage times.
_TRACKED = (AXIS_CROSSINGS, FIRST_AXIS_CROSSING, LAST_AXIS_CROSSING, PERP_CROSSINGS,
            FIRST_PERP_CROSSING, LAST_PERP_CROSSING, MAX_PERP)


@dataclass
class Members:
    """Per-member facts the estimators need, from a time series or from summaries.

    The fields are the constructor's parameters and the instance's attributes; build one with
    :func:`members` or :func:`tracked_members`.

    Parameters
    ----------
    axis : int
        Spin axis, 1-based.
    spin : float
        Spin about that axis at the start, rad/s (> 0).
    member : ndarray, shape (N,)
        Member labels.
    a0 : ndarray, shape (N,)
        Initial perpendicular amplitude, rad/s.
    valid : ndarray of bool, shape (N,)
        Members with status ok and finite data.
    t, amp : ndarray, shapes (T,) and (N, T), or None
        Sample times (s) and perpendicular amplitude (rad/s) of a time series.
    levels, passage : ndarray, shapes (L,) and (N, L), or None
        Amplitude levels (rad/s) and first-passage times (s) of a summaries-only run.
    axis_crossings, first_axis, last_axis : ndarray, shape (N,)
        Sign changes of the spin-axis component: count, first and last time (s, NaN if none).
    perp_crossings, first_perp, last_perp : ndarray, shape (N,)
        The same for the first perpendicular component.
    max_perp : ndarray, shape (N,)
        Largest perpendicular amplitude seen, rad/s.
    w0 : ndarray, shape (N, 3), or None
        Initial angular velocity, rad/s, body frame.
    """

    axis: int
    spin: float
    member: np.ndarray
    a0: np.ndarray
    valid: np.ndarray
    t: np.ndarray | None
    amp: np.ndarray | None
    levels: np.ndarray | None
    passage: np.ndarray | None
    axis_crossings: np.ndarray
    first_axis: np.ndarray
    last_axis: np.ndarray
    perp_crossings: np.ndarray
    first_perp: np.ndarray
    last_perp: np.ndarray
    max_perp: np.ndarray
    w0: np.ndarray | None


# ---------------------------------------------------------------------------------------------
# Reading a Dataset


def zero_crossings(t, x):
    """Sign changes of ``x`` along its last axis, with linearly interpolated times.

    Parameters
    ----------
    t : array_like, shape (T,)
        Sample times, s, increasing.
    x : array_like, shape (N, T)
        Signals; NaN samples never make a crossing.

    Returns
    -------
    count : ndarray of int, shape (N,)
    first, last : ndarray, shape (N,)
        Times of the first and last sign change, s; NaN where there is none. A sample that is
        exactly zero counts as negative, so a signal starting at 0 counts its start once it
        goes positive.
    """
    t = real_array("t", t, "s")
    x = np.atleast_2d(real_array("x", x))
    pos = x > 0.0
    ok = np.isfinite(x[:, :-1]) & np.isfinite(x[:, 1:])
    change = (pos[:, :-1] != pos[:, 1:]) & ok
    count = change.sum(axis=1)
    n_rows, n_pairs = change.shape
    first = np.full(n_rows, np.nan)
    last = np.full(n_rows, np.nan)
    has = count > 0
    if n_pairs == 0 or not has.any():
        return count, first, last
    i_first = np.argmax(change, axis=1)
    i_last = n_pairs - 1 - np.argmax(change[:, ::-1], axis=1)
    rows = np.arange(n_rows)

    def at(k):
        x0 = x[rows, k]
        x1 = x[rows, k + 1]
        with np.errstate(invalid="ignore", divide="ignore"):
            return t[k] - x0 * (t[k + 1] - t[k]) / (x1 - x0)

    first[has] = at(i_first)[has]
    last[has] = at(i_last)[has]
    return count, first, last


def members(ds: xr.Dataset, axis=None, spin=None) -> Members:
    """Gather the per-member facts of an ensemble Dataset (time series or summaries only).

    Parameters
    ----------
    ds : xarray.Dataset or Members
        ``w`` (member, time, axis) or (time, axis), or the summaries-only variables.
    axis : int, optional
        Spin axis (1, 2 or 3); default ``ds.attrs["axis"]``, else the largest initial component.
    spin : float, optional
        Spin in rad/s; default ``ds.attrs["spin"]``, else |w_axis| at the start.

    Returns
    -------
    Members
    """
    if isinstance(ds, Members):
        return ds
    if not isinstance(ds, xr.Dataset):
        raise ValueError(f"expected an xarray.Dataset, got {type(ds).__name__}")
    if "w" in ds and cv.TIME in ds["w"].dims:
        return _members_from_series(ds, axis, spin)
    if PASSAGE in ds:
        return _members_from_summaries(ds, axis, spin)
    raise ValueError(
        "the Dataset has neither a time series 'w' (member, time, axis) nor summaries "
        f"('{PASSAGE}' (member, level) and the crossing counts); run the ensemble with saved "
        "samples or with summaries"
    )


def _spin_axis(ds, axis, w0):
    if axis is None:
        axis = ds.attrs.get("axis")
    if axis is None:
        if w0 is None:
            raise ValueError("pass axis=1, 2 or 3: the Dataset does not say which axis spins")
        axis = int(np.argmax(np.nanmedian(np.abs(w0), axis=0))) + 1
    if isinstance(axis, bool) or int(axis) != axis or int(axis) not in cv.AXES:
        raise ValueError(f"axis must be 1, 2 or 3 (the principal axis of the spin), got {axis!r}")
    return int(axis)


def _spin_value(ds, spin, w0, axis):
    if spin is None and ds is not None:
        spin = ds.attrs.get("spin")
    if spin is None and w0 is not None:
        spin = float(np.nanmedian(np.abs(w0[:, axis - 1])))
    if spin is None:
        raise ValueError("pass spin= (rad/s): the Dataset carries neither 'spin' nor w0")
    spin = abs(float(spin))
    if not math.isfinite(spin) or spin == 0.0:
        raise ValueError(f"spin must be finite and nonzero (rad/s), got {spin}")
    return spin


def _status_ok(ds, n):
    if "status" in ds and ds.variables["status"].ndim == 1 and ds.variables["status"].size == n:
        return np.asarray(ds.variables["status"].values) == cv.STATUS_OK
    return np.ones(n, dtype=bool)


def _members_from_series(ds, axis, spin):
    w = ds["w"]
    if cv.MEMBER not in w.dims:
        w = w.expand_dims({cv.MEMBER: [0]})
    w = w.transpose(cv.MEMBER, cv.TIME, cv.AXIS)
    values = np.asarray(w.values, dtype=float)
    t = np.asarray(ds[cv.TIME].values, dtype=float)
    w0 = values[:, 0, :]
    axis = _spin_axis(ds, axis, w0)
    spin = _spin_value(ds, spin, w0, axis)
    b, c = perpendicular_axes(axis)
    amp = np.hypot(values[:, :, b - 1], values[:, :, c - 1])
    n = values.shape[0]
    valid = _status_ok(ds, n) & np.all(np.isfinite(values), axis=(1, 2))
    n_ax, f_ax, l_ax = zero_crossings(t, values[:, :, axis - 1])
    n_pp, f_pp, l_pp = zero_crossings(t, values[:, :, b - 1])
    with np.errstate(invalid="ignore"):
        max_perp = np.nanmax(np.where(np.isfinite(amp), amp, -np.inf), axis=1)
    member = np.asarray(w[cv.MEMBER].values)
    return Members(
        axis=axis, spin=spin, member=member, a0=amp[:, 0], valid=valid, t=t, amp=amp,
        levels=None, passage=None, axis_crossings=n_ax, first_axis=f_ax, last_axis=l_ax,
        perp_crossings=n_pp, first_perp=f_pp, last_perp=l_pp, max_perp=max_perp, w0=w0,
    )


def _members_from_summaries(ds, axis, spin):
    missing = [name for name in _TRACKED if name not in ds]
    if missing:
        raise ValueError(f"summaries-only Dataset lacks {', '.join(missing)}")
    w0 = None
    if W0 in ds:
        w0 = np.asarray(ds.variables[W0].transpose(cv.MEMBER, cv.AXIS).values, dtype=float)
    axis = _spin_axis(ds, axis, w0)
    spin = _spin_value(ds, spin, w0, axis)
    # The Variables, not DataArrays: ~10x cheaper for many small ensembles.
    summaries = {name: ds.variables[name].transpose(cv.MEMBER).values for name in _TRACKED}
    summaries[PASSAGE] = ds.variables[PASSAGE].transpose(cv.MEMBER, LEVEL).values
    n = summaries[PASSAGE].shape[0]
    a0 = None
    if w0 is None:
        if "epsilon" not in ds.attrs:
            raise ValueError("summaries-only Dataset needs 'w0' (member, axis) or "
                             "attrs['epsilon']")
        a0 = np.full(n, float(ds.attrs["epsilon"]) * spin)
    return summary_members(summaries, ds.variables[LEVEL].values, axis, spin, w0=w0, a0=a0,
                           ok=_status_ok(ds, n), member=np.asarray(ds.variables[cv.MEMBER].values))


def summary_members(summaries, levels, axis: int, spin=None, *, w0=None, a0=None, ok=None,
                    member=None) -> Members:
    """Members from the member loop's tracked summaries, with or without their Dataset.

    Parameters
    ----------
    summaries : mapping of str to ndarray
        The summaries-only variables by name (:data:`stability.output.dataset.SUMMARIES`): shape (N,),
        ``passage_time`` (N, n_levels); counts as floats, NaN for masked members.
    levels : array_like, shape (n_levels,)
        Ascending amplitude levels of ``passage_time``, rad/s.
    axis : int
        Spin axis, 1-based.
    spin : float, optional
        Spin in rad/s; by default the median |w0| about ``axis``, as :func:`members` takes it
        for given starts.
    w0 : ndarray, shape (N, 3), optional
        Starts, rad/s; the initial perpendicular amplitude comes from it.
    a0 : ndarray, shape (N,), optional
        Initial perpendicular amplitude, rad/s, when there is no ``w0``.
    ok : ndarray of bool, shape (N,), optional
        Members whose status is ok; default all.
    member : ndarray, shape (N,), optional
        Member labels; default 0 ... N - 1.

    Returns
    -------
    Members
    """
    levels = np.asarray(levels, dtype=float)
    if levels.ndim != 1 or np.any(np.diff(levels) <= 0):
        raise ValueError(f"'{LEVEL}' must be ascending amplitude levels in rad/s")

    def get(name):
        return np.asarray(summaries[name], dtype=float)

    def count(name):  # counts are stored as float with NaN for masked members
        return np.nan_to_num(get(name), nan=0.0).astype(np.int64)

    if spin is None:
        spin = _spin_value(None, None, w0, axis)
    passage = get(PASSAGE)
    n = passage.shape[0]
    if w0 is not None:
        b, c = perpendicular_axes(axis)
        a0 = np.hypot(w0[:, b - 1], w0[:, c - 1])
    ok = np.ones(n, dtype=bool) if ok is None else ok
    return Members(
        axis=axis, spin=spin, member=np.arange(n) if member is None else member, a0=a0,
        valid=ok & np.isfinite(get(MAX_PERP)), t=None, amp=None, levels=levels,
        passage=passage, axis_crossings=count(AXIS_CROSSINGS), first_axis=get(FIRST_AXIS_CROSSING),
        last_axis=get(LAST_AXIS_CROSSING), perp_crossings=count(PERP_CROSSINGS),
        first_perp=get(FIRST_PERP_CROSSING), last_perp=get(LAST_PERP_CROSSING),
        max_perp=get(MAX_PERP), w0=w0,
    )


def tracked_members(extras: dict, w0, axis: int, spin: float, levels, status=None) -> Members:
    """Members from the driver's in-kernel tracking (``propagate(..., track_axis=axis - 1)``).

    Parameters
    ----------
    extras : dict
        ``Propagation.extras``: ``axis_crossings``, ``first_axis_crossing``,
        ``last_axis_crossing``, ``perp_crossings``, ``first_perp_crossing``,
        ``last_perp_crossing``, ``max_perp_amplitude`` (N,), ``passage_time`` (N, n_levels).
    w0 : array_like, shape (N, 3)
        Starts, body frame, rad/s.
    axis : int
        Spin axis, 1-based (the tracked one).
    spin : float
        Spin in rad/s.
    levels : array_like, shape (n_levels,)
        The ascending levels of ``passage_time``, rad/s.
    status : array_like, shape (N,), optional
        Per-member status codes; members not ``STATUS_OK`` are left out of every estimate.

    Returns
    -------
    Members
    """
    w0 = np.atleast_2d(real_array("w0", w0, "rad/s"))
    axis = int(axis)
    b, c = perpendicular_axes(axis)
    n = w0.shape[0]
    valid = np.ones(n, dtype=bool) if status is None else np.asarray(status) == cv.STATUS_OK
    max_perp = np.asarray(extras["max_perp_amplitude"], dtype=float)
    a0 = np.hypot(w0[:, b - 1], w0[:, c - 1])
    return Members(
        axis=axis, spin=abs(float(spin)), member=np.arange(n), a0=a0,
        valid=valid & np.isfinite(max_perp), t=None, amp=None,
        levels=np.asarray(levels, dtype=float),
        passage=np.asarray(extras["passage_time"], dtype=float),
        axis_crossings=np.asarray(extras["axis_crossings"]).astype(np.int64),
        first_axis=np.asarray(extras["first_axis_crossing"], dtype=float),
        last_axis=np.asarray(extras["last_axis_crossing"], dtype=float),
        perp_crossings=np.asarray(extras["perp_crossings"]).astype(np.int64),
        first_perp=np.asarray(extras["first_perp_crossing"], dtype=float),
        last_perp=np.asarray(extras["last_perp_crossing"], dtype=float),
        max_perp=np.maximum(max_perp, a0), w0=w0,
    )


# ---------------------------------------------------------------------------------------------
# Fits on per-member point sets


def _points(mem: Members, low, high):
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


def _line_fit(x, y, weight=None):
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


def _rms(res):
    """Root mean square of each row over its non-NaN entries (inf stays inf, none gives NaN)."""
    used = ~np.isnan(res)
    count = used.sum(axis=1)
    total = np.where(used, res, 0.0) ** 2
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(count > 0, np.sqrt(total.sum(axis=1) / count), np.nan)


def _exponential_fit(t, a):
    """ln A = alpha + r t per row: returns (r, rms residual of ln A, n points)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        y = np.log(a)
    alpha, r, n = _line_fit(t, y)
    res = y - alpha[:, None] - r[:, None] * t
    return r, _rms(res), n


def _linear_fit(t, a):
    """A = beta + c t per row, relative least squares (weights 1/A^2): (c, rms of ln ratio)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        weight = 1.0 / a**2
    beta, c, n = _line_fit(t, a, weight)
    model = beta[:, None] + c[:, None] * t
    with np.errstate(divide="ignore", invalid="ignore"):
        res = np.where(model > 0, np.log(a / model), np.inf)
        res = np.where(np.isfinite(t) & np.isfinite(a), res, np.nan)
    return c, _rms(res), n


def _saturation(mem: Members):
    """Per-member amplitude scale of the window's upper edge: min(spin, saturation)."""
    flipped = mem.axis_crossings >= 1
    return np.where(flipped, np.minimum(mem.spin, mem.max_perp), mem.spin)


# ---------------------------------------------------------------------------------------------
# Public estimators


def member_regimes(ds: xr.Dataset, axis=None, spin=None) -> xr.Dataset:
    """Classify each member's motion: neutral, oscillation, exponential growth or algebraic drift.

    The rules are in the module docstring; they use the member's own data only (no analytic
    input), so they can be set beside linear theory.

    Parameters
    ----------
    ds : xarray.Dataset or Members
        One ensemble, time series or summaries only (see the module docstring).
    axis : int, optional
        Spin axis, 1-based; by default from ``ds.attrs``.
    spin : float, optional
        Spin in rad/s; by default from ``ds.attrs`` or the start.

    Returns
    -------
    xarray.Dataset
        ``regime`` (member) int8 with CF flag attributes; ``exponential_residual`` and
        ``linear_residual`` (member): rms relative misfit of the two departure models over
        [``DEPARTURE_FACTOR`` a0, upper edge); ``drift_rate`` (member), slope c of the straight
        line ``A = b + c t`` in rad s-2 (meaningful for algebraic drift).
    """
    mem = members(ds, axis, spin)
    regime, exp_rms, lin_rms, drift = _classify(mem)
    return xr.Dataset(
        {
            "regime": ((cv.MEMBER,), regime, _regime_attrs("regime of each member's motion")),
            "exponential_residual": (
                (cv.MEMBER,), exp_rms,
                {"long_name": "rms misfit of ln A to a line in t (exponential model)",
                 "units": cv.UNITS_DIMENSIONLESS},
            ),
            "linear_residual": (
                (cv.MEMBER,), lin_rms,
                {"long_name": "rms relative misfit of A to a line in t (algebraic model)",
                 "units": cv.UNITS_DIMENSIONLESS},
            ),
            "drift_rate": (
                (cv.MEMBER,), drift,
                {"long_name": "slope of the perpendicular amplitude in the algebraic model",
                 "units": "rad s-2"},
            ),
        },
        coords={cv.MEMBER: mem.member},
        attrs={"axis": mem.axis, "spin": mem.spin},
    )


def _classify(mem: Members):
    n = mem.a0.size
    high = WINDOW_HIGH_FRACTION * _saturation(mem)
    t, a = _points(mem, DEPARTURE_FACTOR * mem.a0, high)
    _, exp_rms, n_pts = _exponential_fit(t, a)
    drift, lin_rms, _ = _linear_fit(t, a)
    flipped = mem.axis_crossings >= 1
    oscillating = (~flipped) & (mem.perp_crossings >= MIN_CROSSINGS)
    departed = flipped | (mem.max_perp > DEPARTURE_FACTOR * mem.a0)
    fitted = n_pts >= MIN_POINTS
    regime = np.full(n, REGIME_UNDETERMINED, dtype=np.int8)
    growth = departed & ~oscillating & fitted
    regime[growth & (exp_rms <= lin_rms)] = REGIME_EXPONENTIAL
    regime[growth & (lin_rms < exp_rms) & (drift > 0)] = REGIME_ALGEBRAIC
    regime[oscillating] = REGIME_OSCILLATION
    regime[~departed & ~oscillating] = REGIME_NEUTRAL
    regime[~mem.valid] = REGIME_UNDETERMINED
    return regime, exp_rms, lin_rms, np.where(regime == REGIME_ALGEBRAIC, drift, np.nan)


def _regime_attrs(long_name):
    """The regime flags' attributes (:data:`stability.schema.ESTIMATES`) under ``long_name``."""
    return ESTIMATES["regime"].on((), long_name=long_name).attrs()


def _mean_stderr(x):
    """Mean, standard error of the mean (NaN below 2 values) and count of the finite values."""
    x = np.asarray(x, dtype=float)
    x = x[np.isfinite(x)]
    n = x.size
    if n == 0:
        return math.nan, math.nan, 0
    mean = float(x.mean())
    stderr = float(x.std(ddof=1) / math.sqrt(n)) if n > 1 else math.nan
    return mean, stderr, n


def _member_rates(mem: Members, regime, low_factor, high_fraction):
    high = high_fraction * _saturation(mem)
    t, a = _points(mem, low_factor * mem.a0, high)
    rate, _, n_pts = _exponential_fit(t, a)
    ok = (regime == REGIME_EXPONENTIAL) & (n_pts >= MIN_POINTS)
    return np.where(ok, rate, np.nan)


def _member_frequencies(mem: Members, regime):
    with np.errstate(invalid="ignore", divide="ignore"):
        freq = math.pi * (mem.perp_crossings - 1) / (mem.last_perp - mem.first_perp)
    return np.where(regime == REGIME_OSCILLATION, freq, np.nan)


def measured_growth_rate(
    ds: xr.Dataset, axis=None, spin=None, *, low_factor=None, high_fraction=None,
) -> xr.Dataset:
    """Exponential growth rate of the perpendicular amplitude, fitted on the linear phase only.

    Per member, the slope of ``ln sqrt(w_b^2 + w_c^2)`` against time (or of ``ln(level)``
    against passage time) between ``low_factor`` times the initial amplitude and
    ``high_fraction`` of min(spin, saturation amplitude); only members whose departure is
    exponential (:func:`member_regimes`) are fitted. Cost O(members x samples).

    Parameters
    ----------
    ds : xarray.Dataset or Members
        One ensemble, time series or summaries only (module docstring).
    axis, spin : optional
        Spin axis (1-based) and spin (rad/s); by default from ``ds.attrs``.
    low_factor, high_fraction : float, optional
        The window; by default the one recorded in ``ds.attrs`` (:data:`WINDOW_ATTRS`), else
        ``WINDOW_LOW_FACTOR`` and ``WINDOW_HIGH_FRACTION``.

    Returns
    -------
    xarray.Dataset
        ``growth_rate`` and ``growth_rate_stderr`` (s-1): mean over fitted members and its
        standard error; ``member_growth_rate`` (member), NaN where not fitted; ``n_fitted``.

    Notes
    -----
    With the default window the estimator's own bias is ~1e-5 relative (tested on synthetic
    saturating signals); the integrator's O(h^p) bias in the rate comes on top of it.
    """
    low_factor, high_fraction = _window(ds, low_factor, high_fraction)
    mem = members(ds, axis, spin)
    regime, *_ = _classify(mem)
    rate = _member_rates(mem, regime, low_factor, high_fraction)
    mean, stderr, n = _mean_stderr(rate)
    return _estimate_dataset(
        mem, "growth_rate", "exponential growth rate of the perpendicular amplitude",
        cv.UNITS_RATE, rate, mean, stderr, n,
        window=f"[{low_factor:g} x initial amplitude, {high_fraction:g} x min(spin, saturation))",
    )


def _window(ds, low_factor, high_fraction):
    """The growth-rate window: as passed, else as recorded in ``ds.attrs``, else the default."""
    attrs = ds.attrs if isinstance(ds, xr.Dataset) else {}
    if low_factor is None:
        low_factor = float(attrs.get(WINDOW_ATTRS["low_factor"], WINDOW_LOW_FACTOR))
    if high_fraction is None:
        high_fraction = float(attrs.get(WINDOW_ATTRS["high_fraction"], WINDOW_HIGH_FRACTION))
    return low_factor, high_fraction


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


def perpendicular_amplitude(w: xr.DataArray, axis: int) -> xr.DataArray:
    """``sqrt(w_b^2 + w_c^2)``: the part of ``w`` perpendicular to body ``axis`` (1, 2, 3).

    Parameters
    ----------
    w : xarray.DataArray
        Angular velocity with an ``axis`` dimension (coordinates 1, 2, 3), in rad/s.
    axis : int

    Returns
    -------
    xarray.DataArray
        Same dims as ``w`` without ``axis``, in rad/s (NaN where a component is).
    """
    perp = w.sel({cv.AXIS: list(perpendicular_axes(axis))})
    amp = np.sqrt((perp**2).sum(cv.AXIS, skipna=False))
    amp.attrs = {"long_name": f"amplitude perpendicular to axis {axis}",
                 "units": cv.UNITS_ANGULAR_VELOCITY}
    return amp


def sign_change_times(t, x) -> np.ndarray:
    """Times where ``x`` changes sign (sign bit), by linear interpolation between samples.

    Parameters
    ----------
    t, x : ndarray, shape (T,)

    Returns
    -------
    ndarray, shape (K,)
        In the units of ``t``, ascending.
    """
    s = np.flatnonzero(np.signbit(x[1:]) != np.signbit(x[:-1]))
    return t[s] - x[s] * (t[s + 1] - t[s]) / (x[s + 1] - x[s])


def measured_frequency(ds: xr.Dataset, axis=None, spin=None) -> xr.Dataset:
    """Angular frequency of the perpendicular oscillation about a stable axis.

    Per member, from the zero crossings of the first perpendicular component ``w_b``: n
    crossings span n - 1 half periods, so ``Omega = pi (n - 1) / (t_last - t_first)``; only
    members in the oscillation regime (at least ``MIN_CROSSINGS`` crossings, no flip) count.
    Crossing times are linearly interpolated between samples, an error O((Omega dt)^3 / Omega)
    per crossing, divided by the whole span.

    Parameters
    ----------
    ds : xarray.Dataset or Members
        One ensemble, time series or summaries only.
    axis, spin : optional
        Spin axis (1-based) and spin (rad/s); by default from ``ds.attrs``.

    Returns
    -------
    xarray.Dataset
        ``oscillation_frequency`` and ``oscillation_frequency_stderr`` (rad s-1),
        ``member_oscillation_frequency`` (member), ``n_fitted``.
    """
    mem = members(ds, axis, spin)
    regime, *_ = _classify(mem)
    freq = _member_frequencies(mem, regime)
    mean, stderr, n = _mean_stderr(freq)
    return _estimate_dataset(
        mem, "oscillation_frequency", "angular frequency of the perpendicular oscillation",
        cv.UNITS_ANGULAR_VELOCITY, freq, mean, stderr, n,
        window=f"zero crossings of w_{perpendicular_axes(mem.axis)[0]}",
    )


def _estimate_dataset(mem, name, long_name, units, per_member, mean, stderr, n, window):
    return xr.Dataset(
        {
            name: ((), mean, {"long_name": long_name, "units": units}),
            f"{name}_stderr": (
                (), stderr,
                {"long_name": f"standard error of the {long_name} over members", "units": units},
            ),
            f"member_{name}": (
                (cv.MEMBER,), per_member, {"long_name": f"{long_name}, per member", "units": units}
            ),
            "n_fitted": ((), n, {"long_name": "members fitted", "units": cv.UNITS_DIMENSIONLESS}),
        },
        coords={cv.MEMBER: mem.member},
        attrs={"axis": mem.axis, "spin": mem.spin, "window": window},
    )


def _ensemble_regime(regime, valid):
    r = regime[valid]
    if r.size == 0:
        return REGIME_UNDETERMINED
    counts = np.bincount(r.astype(np.int64), minlength=len(REGIME_FLAG_VALUES))
    best = int(np.argmax(counts))
    return best if counts[best] > MAJORITY * r.size else REGIME_UNDETERMINED


#: Units and long names of the ensemble estimates (scalars of :func:`omega_squared_estimate`
#: and :func:`flip_estimate`), as the register declares them (:data:`stability.schema.ESTIMATES`).
ESTIMATE_ATTRS = {name: var.attrs() for name, var in ESTIMATES.items()}


def omega_squared_estimate(mem: Members, analytic=None, *, low_factor=WINDOW_LOW_FACTOR,
                           high_fraction=WINDOW_HIGH_FRACTION) -> dict:
    """The numbers of :func:`measured_omega_squared` as a dict, from gathered members.

    For loops over many ensembles (the stability map), where building a Dataset per ensemble
    would cost more than the estimate. Keys: those of ``ESTIMATE_ATTRS`` from ``regime`` to
    ``n_fitted`` (Python scalars), and ``member_regime`` (ndarray, shape (N,)).

    Parameters
    ----------
    mem : Members
        The ensemble's members (:func:`members`, :func:`tracked_members`).
    analytic : float, optional
        Analytic Omega^2 in s-2 for the relative error and the sign check; NaN if not given.
    low_factor : float, default WINDOW_LOW_FACTOR
        Lower edge of the growth-rate window, as a multiple of the initial amplitude.
    high_fraction : float, default WINDOW_HIGH_FRACTION
        Upper edge of the growth-rate window, as a fraction of min(spin, saturation
        amplitude) (see :func:`measured_growth_rate`).

    Returns
    -------
    dict
        The estimates named above; Omega^2 in s-2, rates in s-1, frequencies in rad/s.
    """
    return omega_squared_estimates([mem], [analytic], low_factor=low_factor,
                                   high_fraction=high_fraction)[0]


def omega_squared_estimates(mems, analytic=None, *, low_factor=WINDOW_LOW_FACTOR,
                            high_fraction=WINDOW_HIGH_FRACTION) -> list:
    """:func:`omega_squared_estimate` of many ensembles, bitwise the same numbers.

    The per-member fits of every summaries-only ensemble with the same number of levels run in
    one pass of array operations over all their members (row by row, as for one ensemble), so
    that thousands of small ensembles (the stability map) do not each pay numpy's per-call cost.

    Parameters
    ----------
    mems : sequence of Members
    analytic : sequence of float, optional
        Analytic Omega^2 of each ensemble, s-2.
    low_factor, high_fraction : float
        The growth-rate window (:func:`omega_squared_estimate`).

    Returns
    -------
    list of dict
        :func:`omega_squared_estimate` of each ensemble, in order.
    """
    mems = list(mems)
    analytic = [None] * len(mems) if analytic is None else list(analytic)
    out = [None] * len(mems)
    for indices in _stacks(mems):
        mem = mems[indices[0]] if len(indices) == 1 else _stacked([mems[k] for k in indices])
        regime, _, _, drift = _classify(mem)
        rate = _member_rates(mem, regime, low_factor, high_fraction)
        freq = _member_frequencies(mem, regime)
        lo = 0
        for k in indices:
            rows = slice(lo, lo + mems[k].a0.size)
            lo = rows.stop
            out[k] = _omega_squared_of(regime[rows], rate[rows], freq[rows], drift[rows],
                                       mems[k].valid, analytic[k])
    return out


#: Members fitted together at most: the fits' temporaries then stay in the CPU's cache.
_STACK_ROWS = 2048


def _stacks(mems) -> list:
    """Indices of ``mems`` fitted together: summaries-only ensembles with the same number of
    levels, up to :data:`_STACK_ROWS` members; a time series alone."""
    stacks, open_stacks = [], {}
    for k, mem in enumerate(mems):
        if mem.amp is not None:
            stacks.append([k])
            continue
        key = mem.levels.size
        stack = open_stacks.get(key)
        if stack is None or stack[1] + mem.a0.size > _STACK_ROWS:
            stack = open_stacks[key] = [[], 0]
            stacks.append(stack[0])
        stack[0].append(k)
        stack[1] += mem.a0.size
    return stacks


def _stacked(mems) -> Members:
    """The members of summaries-only ensembles (same number of levels) one after another;
    the spin and the levels become per-row arrays."""
    def rows(name):
        return np.concatenate([getattr(m, name) for m in mems])

    return Members(
        axis=0, spin=np.concatenate([np.full(m.a0.size, m.spin) for m in mems]),
        member=rows("member"), a0=rows("a0"), valid=rows("valid"), t=None, amp=None,
        levels=np.concatenate([np.broadcast_to(m.levels, m.passage.shape) for m in mems]),
        passage=rows("passage"), axis_crossings=rows("axis_crossings"),
        first_axis=rows("first_axis"), last_axis=rows("last_axis"),
        perp_crossings=rows("perp_crossings"), first_perp=rows("first_perp"),
        last_perp=rows("last_perp"), max_perp=rows("max_perp"), w0=None,
    )


def _omega_squared_of(regime, rate, freq, drift, valid, analytic) -> dict:
    """One ensemble's Omega^2 estimate from its members' regimes, rates and frequencies."""
    r_mean, r_se, r_n = _mean_stderr(rate)
    f_mean, f_se, f_n = _mean_stderr(freq)
    d_mean, _, _ = _mean_stderr(drift)
    ens = _ensemble_regime(regime, valid)
    n_fitted = 0
    if ens == REGIME_EXPONENTIAL and r_n:
        value, err, n_fitted = -(r_mean**2), 2.0 * r_mean * r_se, r_n
    elif ens == REGIME_OSCILLATION and f_n:
        value, err, n_fitted = f_mean**2, 2.0 * f_mean * f_se, f_n
    else:
        value, err = math.nan, math.nan
    analytic = math.nan if analytic is None else float(analytic)
    rel = (value - analytic) / abs(analytic) if analytic != 0.0 else math.nan
    sign = REGIME_SIGN[ens]
    agrees = bool(sign == np.sign(analytic)) if math.isfinite(sign) else False
    if math.isfinite(analytic) and analytic != 0.0 and math.isfinite(value):
        agrees = agrees and bool(np.sign(value) == np.sign(analytic))
    return {
        "regime": ens, "omega_squared_measured": value, "omega_squared_measured_stderr": err,
        "omega_squared": analytic, "relative_error": rel, "sign_agrees": agrees,
        "growth_rate": r_mean, "growth_rate_stderr": r_se,
        "oscillation_frequency": f_mean, "oscillation_frequency_stderr": f_se,
        "drift_rate": d_mean, "n_fitted": n_fitted, "member_regime": regime,
    }


def measured_omega_squared(ds: xr.Dataset, axis=None, spin=None, *, analytic=None,
                           low_factor=None, high_fraction=None) -> xr.Dataset:
    """Measured Omega^2 of an ensemble, beside the analytic value of linear theory.

    The ensemble takes the regime of more than half of its valid members; Omega^2 is then
    ``-growth_rate^2`` (exponential growth), ``+frequency^2`` (oscillation) or not measured
    (algebraic drift, neutral, undetermined: reported by ``regime``, no rate forced). The
    uncertainty is propagated from the standard error: ``2 |x| stderr(x)``.

    Parameters
    ----------
    ds : xarray.Dataset or Members
        One ensemble, time series or summaries only.
    axis, spin : optional
        Spin axis (1-based) and spin (rad/s); by default from ``ds.attrs``.
    analytic : float, optional
        Analytic Omega^2 in s-2 for the relative error; by default computed with
        ``stability.omega_squared`` when ``ds.attrs`` carries ``I1, I2, I3``.
    low_factor, high_fraction : float, optional
        Growth-rate window (see :func:`measured_growth_rate`).

    Returns
    -------
    xarray.Dataset
        Scalars ``regime``, ``omega_squared_measured`` and ``omega_squared_measured_stderr``
        (s-2), ``growth_rate``, ``oscillation_frequency`` (and their standard errors),
        ``drift_rate`` (rad s-2, algebraic drift), ``omega_squared`` (analytic, s-2),
        ``relative_error`` ((measured - analytic) / |analytic|), ``sign_agrees`` (the regime's
        sign against the analytic sign; a zero analytic value agrees with drift or neutral),
        ``n_fitted``; per member ``member_regime``.
    """
    low_factor, high_fraction = _window(ds, low_factor, high_fraction)
    mem = members(ds, axis, spin)
    if analytic is None and isinstance(ds, xr.Dataset):
        analytic = _analytic_from_attrs(ds, mem)
    est = omega_squared_estimate(mem, analytic, low_factor=low_factor,
                                 high_fraction=high_fraction)
    regime = est.pop("member_regime")
    data = {name: ((), value, ESTIMATE_ATTRS[name]) for name, value in est.items()}
    data["regime"] = ((), np.int8(est["regime"]), ESTIMATE_ATTRS["regime"])
    data["member_regime"] = ((cv.MEMBER,), regime, _regime_attrs("regime of each member"))
    return xr.Dataset(data, coords={cv.MEMBER: mem.member},
                      attrs={"axis": mem.axis, "spin": mem.spin})


def _analytic_from_attrs(ds, mem):
    if not all(k in ds.attrs for k in ("I1", "I2", "I3")):
        return None
    return omega_squared(body_from_attrs(ds.attrs), mem.axis, mem.spin)


# ---------------------------------------------------------------------------------------------
# Flips


def exact_flip_intervals(body, axis: int, w0):
    """Each start's exact flip interval 2K/nu and its asymptote (2/lambda) ln(4/k').

    Defined for spin about the intermediate axis only (flips happen there); NaN elsewhere.

    Parameters
    ----------
    body : RigidBody
    axis : int or None
        Spin axis, 1-based; None: every start, whatever its axis (for a start near a stable
        axis, the limits :func:`stability.free_body.exact.flip_interval` gives).
    w0 : array_like, shape (N, 3)
        Starts, body frame, rad/s.

    Returns
    -------
    exact, asymptote : ndarray, shape (N,)
        In s (:func:`stability.free_body.exact.flip_interval` and
        :func:`stability.free_body.exact.flip_interval_asymptote`;
        literature notes 1.5, Abramowitz-Stegun 17.3.26).
    """
    w0 = np.atleast_2d(real_array("w0", w0, "rad/s"))
    if axis is None or _is_intermediate(body.moments, axis):

        exact, asymptote, _ = flip_intervals(body, w0)
        return exact, asymptote
    return np.full(w0.shape[0], np.nan), np.full(w0.shape[0], np.nan)


def complementary_moduli(body, w0) -> np.ndarray:
    """The complementary modulus k' of each start's Jacobi functions; (N,), dimensionless.

    ``k'^2 = 1 - k^2`` (:func:`stability.free_body.exact.elliptic_parameters`): proportional to the
    perturbation near the separatrix, where the flip interval goes as (2/lambda) ln(4/k').

    Parameters
    ----------
    body : RigidBody
        Moments in any order.
    w0 : array_like, shape (N, 3)
        Starts, body frame, rad/s; one start of shape (3,) is taken as (1, 3).

    Returns
    -------
    ndarray, shape (N,)
        k' of each start (0 on the separatrix, 1 for a symmetric body, NaN for a sphere).
    """

    return flip_intervals(body, np.atleast_2d(np.asarray(w0, dtype=float)))[2]


def flip_estimate(mem: Members, exact=None, asymptote=None) -> dict:
    """The numbers of :func:`flip_statistics` as a dict, from gathered members.

    Parameters
    ----------
    mem : Members
    exact, asymptote : ndarray, shape (N,), optional
        Each member's exact flip interval and its asymptote (:func:`exact_flip_intervals`).

    Returns
    -------
    dict
        Per member (ndarray, shape (N,)): ``flip_count`` (int), ``first_flip_time``,
        ``flip_interval``, ``flip_interval_exact``, ``flip_interval_asymptote``; scalars: the
        ``ESTIMATE_ATTRS`` keys from ``first_flip_time_mean`` to ``n_with_interval``.
    """
    n_members = mem.a0.size
    nan = np.full(n_members, np.nan)
    exact = nan if exact is None else np.asarray(exact, dtype=float)
    asymptote = nan if asymptote is None else np.asarray(asymptote, dtype=float)
    n = np.where(mem.valid, mem.axis_crossings, 0).astype(np.int64)
    first = np.where(mem.valid & (n >= 1), mem.first_axis, np.nan)
    with np.errstate(invalid="ignore", divide="ignore"):
        interval = np.where(n >= 2, (mem.last_axis - mem.first_axis) / (n - 1), np.nan)
        rel = (interval - exact) / exact
    has = np.isfinite(interval)
    first_m, first_se, _ = _mean_stderr(first)
    int_m, int_se, n_int = _mean_stderr(interval)
    rel_m, rel_se, _ = _mean_stderr(rel)
    return {
        "flip_count": np.where(mem.valid, n, 0), "first_flip_time": first,
        "flip_interval": interval, "flip_interval_exact": exact,
        "flip_interval_asymptote": asymptote,
        "first_flip_time_mean": first_m, "first_flip_time_stderr": first_se,
        "flip_interval_mean": int_m, "flip_interval_stderr": int_se,
        "flip_interval_exact_mean": _mean_stderr(np.where(has, exact, np.nan))[0],
        "flip_interval_asymptote_mean": _mean_stderr(np.where(has, asymptote, np.nan))[0],
        "flip_interval_relative_error": rel_m, "flip_interval_relative_error_stderr": rel_se,
        "n_flips_mean": float(n[mem.valid].mean()) if mem.valid.any() else math.nan,
        "n_with_interval": n_int,
    }


#: Long names of the per-member flip variables.
_FLIP_MEMBER_NAMES = {
    "flip_count": ("number of sign changes of the spin-axis component of w (flips)",
                   cv.UNITS_DIMENSIONLESS),
    "first_flip_time": ("time of the first flip", cv.UNITS_TIME),
    "flip_interval": ("mean time between flips", cv.UNITS_TIME),
    "flip_interval_exact": ("exact flip interval 2K/nu of the member's start", cv.UNITS_TIME),
    "flip_interval_asymptote": ("asymptotic flip interval (2/lambda) ln(4/k')", cv.UNITS_TIME),
}


def flip_statistics(ds: xr.Dataset, axis=None, spin=None, *, body=None) -> xr.Dataset:
    """Flips of the spin-axis component: first-flip time and flip interval against exact theory.

    A flip is a sign change of the spin-axis component (the body turning over, +w -> -w about
    the intermediate axis). Per member: the number of flips, the time of the first, and the mean
    interval ``(t_last - t_first) / (n - 1)`` (n >= 2). Beside them the exact interval ``2K/nu``
    of the member's own start and the small-perturbation asymptote ``(2 / lambda) ln(4 / k')``
    (:func:`exact_flip_intervals`).

    Parameters
    ----------
    ds : xarray.Dataset or Members
        One ensemble, time series or summaries only (the start ``w0`` is needed for the exact
        values).
    axis, spin : optional
        Spin axis (1-based) and spin (rad/s); by default from ``ds.attrs``.
    body : RigidBody, optional
        Default: built from ``ds.attrs`` ``I1, I2, I3``; without a body only the measured
        statistics are returned.

    Returns
    -------
    xarray.Dataset
        Per member (member): ``flip_count`` (an integer, as named in a run's Dataset),
        ``first_flip_time``, ``flip_interval``,
        ``flip_interval_exact``, ``flip_interval_asymptote`` (s); scalars: their means over
        members (``*_mean``), ``flip_interval_relative_error`` (mean over members of
        (measured - exact) / exact) and its standard error, ``n_flips_mean``,
        ``n_with_interval``.
    """
    mem = members(ds, axis, spin)
    if body is None and isinstance(ds, xr.Dataset) and all(
        k in ds.attrs for k in ("I1", "I2", "I3")
    ):
        body = body_from_attrs(ds.attrs)
    exact = asymptote = None
    if body is not None and mem.w0 is not None:
        exact, asymptote = exact_flip_intervals(body, mem.axis, mem.w0)
    est = flip_estimate(mem, exact, asymptote)
    data = {}
    for name, value in est.items():
        if name in _FLIP_MEMBER_NAMES:
            long_name, units = _FLIP_MEMBER_NAMES[name]
            data[name] = ((cv.MEMBER,), value, {"long_name": long_name, "units": units})
        else:
            data[name] = ((), value, ESTIMATE_ATTRS[name])
    return xr.Dataset(data, coords={cv.MEMBER: mem.member},
                      attrs={"axis": mem.axis, "spin": mem.spin})


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


def analyse_ensemble(ds: xr.Dataset, body, axis: int, spin: float, epsilon: float, *,
                     low_factor=WINDOW_LOW_FACTOR,
                     high_fraction=WINDOW_HIGH_FRACTION) -> xr.Dataset:
    """An ensemble's time series with the exact answers and the measured growth rate added.

    Adds ``exact_flip_interval`` and ``flip_interval_asymptote`` (member, s; every start,
    :func:`exact_flip_intervals` with ``axis=None``), ``complementary_modulus`` (member),
    ``perp_amplitude_median`` / ``_p10`` / ``_p90`` (time, rad/s over members with status ok),
    and attributes ``omega_squared`` (s-2), ``growth_rate_analytic``, ``growth_rate_fitted``
    with its ``_stderr`` and ``_members`` (s-1: :func:`measured_growth_rate` over the window
    ``low_factor``, ``high_fraction``, recorded as :data:`WINDOW_ATTRS`, so that
    ``ds.stability.measured_growth_rate()`` gives the same number), and the line of the
    measured rate through the median amplitude over its linear phase (:func:`growth_line`:
    ``growth_fit_intercept`` and ``growth_fit_window`` in s), for the growth figure.

    Parameters
    ----------
    ds : xarray.Dataset
        :func:`stability.run_ensemble` with saved samples (``w`` (member, time, axis)).
    body : RigidBody
    axis : int
        Spin axis, 1-based.
    spin, epsilon : float
        Spin rate W (rad/s) and the perturbation relative to it.
    low_factor, high_fraction : float
        The growth-rate window (:func:`measured_growth_rate`).
    """
    omega2 = float(omega_squared(body, axis, spin))
    rate = float(growth_rate(body, axis, spin))
    ok = ds.status == cv.STATUS_OK
    exact, asymptote = exact_flip_intervals(body, None, ds.w0.values)
    kprime = complementary_moduli(body, ds.w0.values)
    amp = perpendicular_amplitude(ds.w.where(ok), axis)
    quantiles = amp.quantile([0.1, 0.5, 0.9], dim=cv.MEMBER, skipna=True)
    measured = measured_growth_rate(ds, low_factor=low_factor, high_fraction=high_fraction)
    fitted = float(measured.growth_rate)
    intercept, window = growth_line(ds[cv.TIME].values, quantiles.sel(quantile=0.5).values,
                                    fitted, low_factor * epsilon * spin, high_fraction * spin)

    ds = ds.assign(TENNIS_RACKET.entries({
        "exact_flip_interval": exact, "flip_interval_asymptote": asymptote,
        "complementary_modulus": kprime}))
    for q, name in ((0.1, "p10"), (0.5, "median"), (0.9, "p90")):
        ds[f"perp_amplitude_{name}"] = TENNIS_RACKET.entry(
            f"perp_amplitude_{name}", quantiles.sel(quantile=q).values, quantile=name, axis=axis)
    ds.attrs.update({
        "spin_axis_resolved": axis,
        "omega_squared": omega2,
        "omega_squared_units": cv.UNITS_RATE_SQUARED,
        "growth_rate_analytic": rate,
        "growth_rate_fitted": fitted,
        "growth_rate_units": cv.UNITS_RATE,
        "growth_fit_intercept": intercept,
        "growth_fit_window": np.array(window),
        "growth_rate_fitted_stderr": float(measured.growth_rate_stderr),
        "growth_rate_fitted_members": int(measured.n_fitted),
        WINDOW_ATTRS["low_factor"]: float(low_factor),
        WINDOW_ATTRS["high_fraction"]: float(high_fraction),
    })
    return ds


def analysis_headline(ds: xr.Dataset):
    """The numbers an analysed ensemble (:func:`analyse_ensemble`) ends with: Omega^2, the
    analytic and measured growth rates, the measured flip intervals against the exact 2K/nu,
    the largest invariant errors (and attitude error, where the attitude was carried), over the
    members with status ok.

    Parameters
    ----------
    ds : xarray.Dataset
        An ensemble with saved samples, analysed by :func:`analyse_ensemble`.

    Returns
    -------
    rows : list of (str, str, str)
        Label, value and unit, for the printed summary.
    values : dict
        The same numbers as floats: ``members``, ``members_ok``, ``omega_squared``,
        ``growth_rate``, ``growth_rate_fitted`` (and ``_stderr``), ``growth_rate_rel_error``,
        ``median_flip_interval``, ``median_exact_flip_interval``,
        ``max_flip_interval_rel_error``, ``max_energy_error``, ``max_angular_momentum_error``
        and ``max_attitude_error``.
    """
    ok = (ds.status == cv.STATUS_OK).values
    n_ok = int(ok.sum())

    def worst(name):
        return float(np.nanmax(np.abs(ds[name].values[ok]))) if n_ok else math.nan

    rate, fitted = ds.attrs["growth_rate_analytic"], ds.attrs["growth_rate_fitted"]
    stderr = ds.attrs["growth_rate_fitted_stderr"]
    measured = ds.mean_flip_interval.values[ok]
    exact = ds.exact_flip_interval.values[ok]
    both = np.isfinite(measured) & np.isfinite(exact)
    flips = both.any()
    values = {
        "members": ok.size, "members_ok": n_ok, "omega_squared": ds.attrs["omega_squared"],
        "growth_rate": rate, "growth_rate_fitted": fitted, "growth_rate_fitted_stderr": stderr,
        "growth_rate_rel_error": (fitted - rate) / rate if rate > 0 else math.nan,
        "median_flip_interval": float(np.median(measured[both])) if flips else math.nan,
        "median_exact_flip_interval": float(np.median(exact[both])) if flips else math.nan,
        "max_flip_interval_rel_error": float(np.max(
            np.abs(measured[both] - exact[both]) / exact[both])) if flips else math.nan,
        "max_energy_error": worst("energy_error"),
        "max_angular_momentum_error": worst("angular_momentum_error"),
    }
    v = values
    rows = [
        ("members (ok / all)", f"{n_ok} / {ok.size}", ""),
        ("Omega^2 (analytic)", f"{v['omega_squared'] + 0.0:.6g}", "s-2"),  # no "-0"
        ("growth rate sqrt(-Omega^2) (analytic)", f"{rate:.6f}", "s-1"),
        ("growth rate fitted (mean over members, linear phase)", f"{fitted:.6f}", "s-1"),
        ("  its standard error", f"{stderr:.1e}", "s-1"),
        ("  relative error of the fit", f"{v['growth_rate_rel_error']:.1e}", ""),
        ("median flip interval, measured", f"{v['median_flip_interval']:.6f}", "s"),
        ("median flip interval, exact 2K/nu", f"{v['median_exact_flip_interval']:.6f}", "s"),
        ("  max relative difference over members", f"{v['max_flip_interval_rel_error']:.1e}",
         ""),
        ("max |relative energy error|", f"{v['max_energy_error']:.1e}", ""),
        ("max |relative |L| error|", f"{v['max_angular_momentum_error']:.1e}", ""),
    ]
    if "attitude_error" in ds:  # scene free_body_attitude
        values["max_attitude_error"] = worst("attitude_error")
        rows.append(("max attitude error, angle to the exact attitude",
                     f"{values['max_attitude_error']:.1e}", "rad"))
    return rows, values


def _is_intermediate(moments, axis):
    moments = np.asarray(moments, dtype=float)
    others = np.delete(moments, axis - 1)
    return bool(others.min() < moments[axis - 1] < others.max())


__all__ = [
    "DEPARTURE_FACTOR", "ESTIMATE_ATTRS", "MIN_CROSSINGS", "MIN_POINTS", "Members",
    "REGIME_ALGEBRAIC", "REGIME_EXPONENTIAL", "REGIME_MEANINGS", "REGIME_NEUTRAL",
    "REGIME_OSCILLATION", "REGIME_UNDETERMINED", "WINDOW_ATTRS", "WINDOW_HIGH_FRACTION",
    "WINDOW_LOW_FACTOR", "analyse_ensemble", "analysis_headline", "complementary_moduli",
    "exact_flip_intervals", "flip_estimate", "flip_statistics", "growth_line",
    "measured_frequency", "measured_growth_rate", "measured_omega_squared", "member_regimes",
    "members", "omega_squared_estimate", "omega_squared_estimates", "perpendicular_amplitude",
    "perpendicular_axes", "richardson_bias", "sign_change_times", "summary_members",
    "tracked_members", "zero_crossings",
]
