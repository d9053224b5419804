"""Estimators on ensembles: growth rate, oscillation frequency, measured Omega^2, flips.

Each takes the Dataset of one ensemble (either form, :mod:`.members`) or its gathered
:class:`~.members.Members`, classifies its members (:mod:`.regimes`) and fits only those whose
regime the estimate stands for.

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
the mean over members. The **frequency** of an oscillating member comes from the zeros of
``w_b``, half a period apart: ``Omega = pi (n - 1) / (t_last - t_first)``.

Measured ``Omega^2`` is ``-rate^2`` for growth and ``+frequency^2`` for oscillation
(``w_b'' = -Omega^2 w_b``, ERRATA 2), to put beside the analytic value. A Dataset may record the
growth-rate window it was analysed with (:data:`~.regimes.WINDOW_ATTRS`); the estimators then
use it.
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from ..ensemble.schema import ESTIMATES
from ..util import conventions as cv
from ..util.checks import real_number
from ..util.conventions import REGIME_EXPONENTIAL, REGIME_OSCILLATION, perpendicular_axes
from .fits import exponential_fit, mean_stderr, window_points
from .members import Members, members
from .regimes import (MIN_POINTS, REGIME_SIGN, WINDOW_ATTRS, WINDOW_HIGH_FRACTION,
                      WINDOW_LOW_FACTOR, classify, ensemble_regime, saturation)

def member_rates(mem: Members, regime, low_factor, high_fraction):
    high = high_fraction * saturation(mem)
    t, a = window_points(mem, low_factor * mem.a0, high)
    rate, _, n_pts = exponential_fit(t, a)
    ok = (regime == REGIME_EXPONENTIAL) & (n_pts >= MIN_POINTS)
    return np.where(ok, rate, np.nan)


def member_frequencies(mem: Members, regime):
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

    A Dataset that records each member's rate (``member_growth_rate``, fitted where the
    members ran over the window it records: the tennis-racket study's) gives those, the same
    fit of the same series, when no other window, axis or spin is asked for.
    """
    recorded = isinstance(ds, xr.Dataset) and FITTED in ds and axis is None and spin is None
    if recorded:
        recorded = (growth_window(ds, None, None)
                    == growth_window(ds, low_factor, high_fraction))
    low_factor, high_fraction = growth_window(ds, low_factor, high_fraction)
    mem = members(ds, axis, spin)
    if recorded:  # fitted member by member where the members ran, over this window
        rate = np.asarray(ds[FITTED].values, dtype=float)
    else:
        regime, *_ = classify(mem)
        rate = member_rates(mem, regime, low_factor, high_fraction)
    mean, stderr, n = mean_stderr(rate)
    return estimate_dataset(
        mem, "growth_rate", "exponential growth rate of the perpendicular amplitude",
        cv.UNITS_RATE, rate, mean, stderr, n,
        window=f"[{low_factor:g} x initial amplitude, {high_fraction:g} x min(spin, saturation))",
    )


#: The per-member growth rates a measured ensemble records (its window in :data:`WINDOW_ATTRS`).
FITTED = "member_growth_rate"


def growth_window(ds, low_factor, high_fraction):
    """The growth-rate window: as passed, else as recorded in ``ds.attrs``, else the default."""
    attrs = ds.attrs if isinstance(ds, xr.Dataset) else {}
    if low_factor is None:
        low_factor = float(attrs.get(WINDOW_ATTRS["low_factor"], WINDOW_LOW_FACTOR))
    if high_fraction is None:
        high_fraction = float(attrs.get(WINDOW_ATTRS["high_fraction"], WINDOW_HIGH_FRACTION))
    return checked_window(low_factor, high_fraction)


def checked_window(low_factor, high_fraction):
    """``(low_factor, high_fraction)`` as floats if they make a window, else ValueError: the
    fit starts at ``low_factor >= 1`` times the initial amplitude and ends at a fraction
    ``0 < high_fraction <= 1`` of min(spin, saturation)."""
    low = real_number("low_factor", low_factor)
    high = real_number("high_fraction", high_fraction)
    if not (math.isfinite(low) and low >= 1.0):
        raise ValueError(f"low_factor must be >= 1 (the fit starts at low_factor times the "
                         f"initial amplitude), got {low_factor!r}")
    if not (0.0 < high <= 1.0):
        raise ValueError(f"high_fraction must be in (0, 1] (the fit ends at that fraction of "
                         f"min(spin, saturation)), got {high_fraction!r}")
    return low, high


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
    regime, *_ = classify(mem)
    freq = member_frequencies(mem, regime)
    mean, stderr, n = mean_stderr(freq)
    return estimate_dataset(
        mem, "oscillation_frequency", "angular frequency of the perpendicular oscillation",
        cv.UNITS_ANGULAR_VELOCITY, freq, mean, stderr, n,
        window=f"zero crossings of w_{perpendicular_axes(mem.axis)[0]}",
    )


def estimate_dataset(mem, name, long_name, units, per_member, mean, stderr, n, window):
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


#: Units and long names of the ensemble estimates (scalars of :func:`omega_squared_estimate`
#: and :func:`flip_estimate`), as the register declares them
#: (:data:`stability.ensemble.schema.ESTIMATES`).
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
    low_factor, high_fraction = checked_window(low_factor, high_fraction)
    analytic = [None] * len(mems) if analytic is None else list(analytic)
    out = [None] * len(mems)
    for indices in _stacks(mems):
        mem = mems[indices[0]] if len(indices) == 1 else _stacked([mems[k] for k in indices])
        regime, _, _, drift = classify(mem)
        rate = member_rates(mem, regime, low_factor, high_fraction)
        freq = member_frequencies(mem, regime)
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
    r_mean, r_se, r_n = mean_stderr(rate)
    f_mean, f_se, f_n = mean_stderr(freq)
    d_mean, _, _ = mean_stderr(drift)
    ens = ensemble_regime(regime, valid)
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
    first_m, first_se, _ = mean_stderr(first)
    int_m, int_se, n_int = mean_stderr(interval)
    rel_m, rel_se, _ = mean_stderr(rel)
    return {
        "flip_count": np.where(mem.valid, n, 0), "first_flip_time": first,
        "flip_interval": interval, "flip_interval_exact": exact,
        "flip_interval_asymptote": asymptote,
        "first_flip_time_mean": first_m, "first_flip_time_stderr": first_se,
        "flip_interval_mean": int_m, "flip_interval_stderr": int_se,
        "flip_interval_exact_mean": mean_stderr(np.where(has, exact, np.nan))[0],
        "flip_interval_asymptote_mean": mean_stderr(np.where(has, asymptote, np.nan))[0],
        "flip_interval_relative_error": rel_m, "flip_interval_relative_error_stderr": rel_se,
        "n_flips_mean": float(n[mem.valid].mean()) if mem.valid.any() else math.nan,
        "n_with_interval": n_int,
    }


#: Long names of the per-member flip variables.
FLIP_MEMBER_NAMES = {
    "flip_count": ("number of sign changes of the spin-axis component of w (flips)",
                   cv.UNITS_DIMENSIONLESS),
    "first_flip_time": ("time of the first flip", cv.UNITS_TIME),
    "flip_interval": ("mean time between flips", cv.UNITS_TIME),
    "flip_interval_exact": ("exact flip interval 2K/nu of the member's start", cv.UNITS_TIME),
    "flip_interval_asymptote": ("asymptotic flip interval (2/lambda) ln(4/k')", cv.UNITS_TIME),
}


#: The module's public API (the rest serves the package's other modules).
__all__ = ["ESTIMATE_ATTRS", "flip_estimate", "measured_frequency", "measured_growth_rate",
           "omega_squared_estimate", "omega_squared_estimates"]
