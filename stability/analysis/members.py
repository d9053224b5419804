"""The members of an ensemble, as the estimators take them: from a Dataset or from the loop.

An ensemble's Dataset (one body, one spin axis) comes in either of the two forms the package
writes (a study that keeps the series of a sample of its members, along ``series_member``, is
read from its series when the sample holds every member, else from its summaries):

- a **time series**: ``w`` (member, time, axis) in rad s-1 (or (time, axis) for one trajectory,
  as ``integrate`` returns);
- **summaries only** (as ``run_ensemble(..., keep=Keep(save_every=0))`` writes them): per-member
  ``passage_time`` (member, level), the first time the perpendicular amplitude
  ``sqrt(w_b^2 + w_c^2)`` reaches each ``level`` (rad s-1), the sign changes of the spin-axis
  component (``flip_count``, ``first_flip_time``, ``last_flip_time``) and of one perpendicular
  component (``perp_crossing_count``, ``first_perp_crossing``, ``last_perp_crossing``),
  ``max_perp_amplitude``, ``status`` and the start ``w0`` (member, axis).

Here ``b`` and ``c`` are the two axes perpendicular to the spin axis. :func:`members` gathers
either form into one :class:`Members`; :func:`summary_members` and :func:`tracked_members` build
it from the member loop's tracking without a Dataset.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass

import numpy as np
import xarray as xr

from ..util import conventions as cv
from ..util.checks import real_array, real_number, scalar
from ..util.conventions import perpendicular_axes

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
    if "w" in ds and cv.SERIES_MEMBER in ds["w"].dims:  # the series of a sample of members
        kept = ds[cv.SERIES_MEMBER].values
        if cv.MEMBER in ds.dims and np.array_equal(kept, ds[cv.MEMBER].values):
            return _members_from_series(_sample_as_members(ds), axis, spin)
        if PASSAGE in ds:
            return _members_from_summaries(ds, axis, spin)
    if "w" in ds and cv.TIME in ds["w"].dims:
        return _members_from_series(ds, axis, spin)
    if PASSAGE in ds:
        return _members_from_summaries(ds, axis, spin)
    raise ValueError(
        "the Dataset has neither a time series 'w' (member, time, axis) nor summaries "
        f"('{PASSAGE}' (member, level) and the crossing counts); run the ensemble with saved "
        "samples or with summaries"
    )


def _sample_as_members(ds: xr.Dataset) -> xr.Dataset:
    """A Dataset whose series sample holds every member, its series along ``member``."""
    series = [name for name, var in ds.data_vars.items() if cv.SERIES_MEMBER in var.dims]
    moved = ds[series].drop_vars(cv.SERIES_MEMBER).rename({cv.SERIES_MEMBER: cv.MEMBER})
    return ds.drop_vars(series + [cv.SERIES_MEMBER]).assign(moved)


def _spin_axis(ds, axis, w0):
    axis = scalar(axis)
    if axis is None and "axis" in ds.attrs:
        axis = scalar(ds.attrs["axis"])
        if not _is_axis(axis):
            raise ValueError(f"the Dataset's attribute axis must be 1, 2 or 3 (the principal "
                             f"axis of the spin), got {axis!r}; pass axis= to override it")
    if axis is None:
        if w0 is None:
            raise ValueError("pass axis=1, 2 or 3: the Dataset does not say which axis spins")
        axis = int(np.argmax(np.nanmedian(np.abs(w0), axis=0))) + 1
    if not _is_axis(axis):
        raise ValueError(f"axis must be 1, 2 or 3 (the principal axis of the spin), got {axis!r}")
    return int(axis)


def _is_axis(axis) -> bool:
    """True for 1, 2 or 3 as a number (not a boolean or a string)."""
    return (isinstance(axis, numbers.Real) and not isinstance(axis, (bool, np.bool_))
            and axis in cv.AXES)


def _spin_value(ds, spin, w0, axis):
    if spin is None and ds is not None:
        spin = ds.attrs.get("spin")
    if spin is None and w0 is not None:
        spin = float(np.nanmedian(np.abs(w0[:, axis - 1])))
    if spin is None:
        raise ValueError("pass spin= (rad/s): the Dataset carries neither 'spin' nor w0")
    spin = abs(real_number("spin", spin, "rad/s"))
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
        The summaries-only variables by name (:data:`stability.output.dataset.SUMMARIES`): shape
        (N,), ``passage_time`` (N, n_levels); counts as floats, NaN for masked members.
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


#: The module's public API (the rest serves the package's other modules).
__all__ = ["Members", "members", "perpendicular_amplitude", "sign_change_times", "summary_members",
           "tracked_members", "zero_crossings"]
