"""The tennis-racket study's analysis: the measured chunks of an ensemble reduced to its
numbers (the mean growth rate, the amplitude quantiles, the line of the growth figure), and the
numbers its summary ends with.
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from ...analysis.fits import growth_line, mean_stderr
from ...analysis.regimes import WINDOW_ATTRS, WINDOW_HIGH_FRACTION, WINDOW_LOW_FACTOR
from ...ensemble.combine import histogram_quantiles, series_sample
from ..schema import TENNIS_RACKET
from ...util import conventions as cv
from ..model import growth_rate, omega_squared
from .measure import amplitude_edges, measure_chunk

def analyse_ensemble(ds: xr.Dataset, body, axis: int, spin: float, epsilon: float, *,
                     low_factor=WINDOW_LOW_FACTOR, high_fraction=WINDOW_HIGH_FRACTION,
                     series_members="all") -> xr.Dataset:
    """An ensemble held in memory with its time series, measured as one chunk
    (:func:`~stability.free_body.tennis_racket.measure.measure_chunk`) and analysed
    (:func:`finish_analysis`): what the study gives for these members.

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
    series_members : int or "all"
        Members whose time series are kept (:func:`stability.ensemble.combine.series_sample`).
    """
    n = ds.sizes[cv.MEMBER]
    measured = measure_chunk(ds, body, axis, spin, (low_factor, high_fraction),
                             series_sample(n, series_members), amplitude_edges(body, spin, epsilon))
    return finish_analysis(measured, body, axis, spin, epsilon, low_factor=low_factor,
                           high_fraction=high_fraction)


def finish_analysis(ds: xr.Dataset, body, axis: int, spin: float, epsilon: float, *,
                    low_factor=WINDOW_LOW_FACTOR,
                    high_fraction=WINDOW_HIGH_FRACTION) -> xr.Dataset:
    """The measured chunks of an ensemble, joined
    (:mod:`stability.free_body.tennis_racket.measure`), with the ensemble's numbers: the
    reductions over members, no pass over their series.

    Adds ``perp_amplitude_median`` / ``_p10`` / ``_p90`` (time, rad/s over members with status
    ok: from the summed histograms ``perp_amplitude_count``, within one bin of 0.46 % of the
    exact quantiles), and attributes ``omega_squared`` (s-2), ``growth_rate_analytic``,
    ``growth_rate_fitted`` with its ``_stderr`` and ``_members`` (s-1: the mean and standard
    error of ``member_growth_rate``, the fit of :func:`measured_growth_rate` over the window
    ``low_factor``, ``high_fraction``, recorded as :data:`WINDOW_ATTRS`, so that
    ``ds.stability.measured_growth_rate()`` gives the same number), and the line of the
    measured rate through the median amplitude over its linear phase (:func:`growth_line`:
    ``growth_fit_intercept`` and ``growth_fit_window`` in s), for the growth figure.

    Parameters
    ----------
    ds : xarray.Dataset
        The joined chunks (``member_growth_rate``, ``perp_amplitude_count``,
        ``amplitude_bin_bounds`` and the summaries).
    body : RigidBody
    axis : int
        Spin axis, 1-based.
    spin, epsilon : float
        Spin rate W (rad/s) and the perturbation relative to it.
    low_factor, high_fraction : float
        The growth-rate window the members were fitted over, recorded as :data:`WINDOW_ATTRS`.
    """
    omega2 = float(omega_squared(body, axis, spin))
    rate = float(growth_rate(body, axis, spin))
    fitted, stderr, n_fitted = mean_stderr(ds.member_growth_rate.values)
    bounds = ds.amplitude_bin_bounds.values
    edges = np.append(bounds[:, 0], bounds[-1, 1])
    quantiles = histogram_quantiles(ds.perp_amplitude_count.values, edges, [0.1, 0.5, 0.9])
    intercept, window = growth_line(ds[cv.TIME].values, quantiles[:, 1], fitted,
                                    low_factor * epsilon * spin, high_fraction * spin)
    ds = ds.copy()
    for k, name in enumerate(("p10", "median", "p90")):
        ds[f"perp_amplitude_{name}"] = TENNIS_RACKET.entry(
            f"perp_amplitude_{name}", quantiles[:, k], quantile=name, axis=axis)
    ds.attrs.update({
        "spin_axis_resolved": axis,
        "omega_squared": omega2,
        "omega_squared_units": cv.UNITS_RATE_SQUARED,
        "growth_rate_analytic": rate,
        "growth_rate_fitted": fitted,
        "growth_rate_units": cv.UNITS_RATE,
        "growth_fit_intercept": intercept,
        "growth_fit_window": np.array(window),
        "growth_rate_fitted_stderr": stderr,
        "growth_rate_fitted_members": int(n_fitted),
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
    if "attitude_error_max" in ds:  # scene free_body_attitude
        values["max_attitude_error"] = worst("attitude_error_max")
        rows.append(("max attitude error, angle to the exact attitude",
                     f"{values['max_attitude_error']:.1e}", "rad"))
    return rows, values


#: The module's public API (the rest serves the package's other modules).
__all__ = ["analyse_ensemble", "finish_analysis", "analysis_headline"]
