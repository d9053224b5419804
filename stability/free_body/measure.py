"""The free body's measures: Omega^2 measured beside linear theory, flips beside the exact motion.

The estimators of :mod:`stability.analysis` with the free body's theory filled in: the analytic
Omega^2 of the body a Dataset records (:func:`~stability.free_body.model.omega_squared`), and
each start's exact flip interval 2K/nu and its asymptote (:mod:`stability.free_body.exact`).
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from ..analysis.estimates import (ESTIMATE_ATTRS, FLIP_MEMBER_NAMES, flip_estimate, growth_window,
                                  omega_squared_estimate)
from ..analysis.members import members
from ..analysis.regimes import regime_attrs
from ..output.dataset import body_from_attrs
from ..util import conventions as cv
from ..core.body import RigidBody
from ..util.checks import real_array, real_number
from .exact import flip_intervals
from .model import omega_squared

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
    if analytic is not None:
        analytic = real_number("analytic", analytic, "s-2")
        if not np.isfinite(analytic):
            raise ValueError(f"analytic must be finite (Omega^2 in s-2), got {analytic}")
    low_factor, high_fraction = growth_window(ds, low_factor, high_fraction)
    mem = members(ds, axis, spin)
    if analytic is None and isinstance(ds, xr.Dataset):
        analytic = _analytic_from_attrs(ds, mem)
    est = omega_squared_estimate(mem, analytic, low_factor=low_factor,
                                 high_fraction=high_fraction)
    regime = est.pop("member_regime")
    data = {name: ((), value, ESTIMATE_ATTRS[name]) for name, value in est.items()}
    data["regime"] = ((), np.int8(est["regime"]), ESTIMATE_ATTRS["regime"])
    data["member_regime"] = ((cv.MEMBER,), regime, regime_attrs("regime of each member"))
    return xr.Dataset(data, coords={cv.MEMBER: mem.member},
                      attrs={"axis": mem.axis, "spin": mem.spin})


def _analytic_from_attrs(ds, mem):
    if not all(k in ds.attrs for k in ("I1", "I2", "I3")):
        return None
    return omega_squared(body_from_attrs(ds.attrs), mem.axis, mem.spin)


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
    if body is not None and not isinstance(body, RigidBody):
        raise ValueError(f"body must be a stability.RigidBody, got {type(body).__name__}")
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
        if name in FLIP_MEMBER_NAMES:
            long_name, units = FLIP_MEMBER_NAMES[name]
            data[name] = ((cv.MEMBER,), value, {"long_name": long_name, "units": units})
        else:
            data[name] = ((), value, ESTIMATE_ATTRS[name])
    return xr.Dataset(data, coords={cv.MEMBER: mem.member},
                      attrs={"axis": mem.axis, "spin": mem.spin})


def _is_intermediate(moments, axis):
    moments = np.asarray(moments, dtype=float)
    others = np.delete(moments, axis - 1)
    return bool(others.min() < moments[axis - 1] < others.max())


#: The module's public API (the rest serves the package's other modules).
__all__ = ["complementary_moduli", "exact_flip_intervals", "flip_statistics",
           "measured_omega_squared"]
