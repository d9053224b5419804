"""The tennis-racket study measured chunk by chunk, where each chunk ran.

Each chunk of the ensemble (:class:`TennisChunks`, the free body's chunk run with the study's
measurement) is measured while its time series are in memory: every member's growth rate
fitted over its linear phase (the fit of :func:`stability.measured_growth_rate`, member by
member), its exact flip interval 2K/nu, the asymptote (2/lambda) ln(4/k') and k', its largest
attitude error where the attitude is carried, and the histogram over the chunk's ok members of
the perpendicular amplitude at each time (log bins,
:func:`stability.ensemble.combine.log_histogram`), counted in the fit's pass over each member's
samples.
The chunk keeps these and the time series of its members in the study's series sample
(:func:`stability.ensemble.combine.series_sample`), nothing more: a study of a million members
holds their summaries, never their series. :meth:`TennisChunks.joiner` joins the chunks as
they come; :func:`finish_analysis` reduces them to the ensemble's numbers (the mean growth rate,
the amplitude quantiles from the summed histograms, the line of the growth figure) and
:func:`analysis_headline` to the numbers the study's summary ends with;
:func:`analyse_ensemble` does both for an ensemble held in memory with its time series.
"""

from __future__ import annotations

import math
import time

import numpy as np
import xarray as xr

from ...analysis.fits import growth_line, mean_stderr
from ...analysis.growth_fit import canonical_growth_rates, series_growth_rates
from ...analysis.regimes import WINDOW_ATTRS, WINDOW_HIGH_FRACTION, WINDOW_LOW_FACTOR
from ...ensemble.combine import (SERIES_MEMBER, SUMMED, ChunkJoin, histogram_quantiles,
                                 log_edges, sampled_in, series_sample)
from ...util import conventions as cv
from ..measure import complementary_moduli, exact_flip_intervals
from ..model import growth_rate, omega_squared
from ...ensemble.schema import ENSEMBLE
from ..results import canonical_to_w, carried_attitude, members_dataset
from ..schema import TENNIS_RACKET
from ..streamed import EnsembleChunks, numbered

#: The module's public API, listed in the API reference: the analysis of a measured ensemble (the
#: chunk's measurement, :class:`TennisChunks` and its helpers, serves the study's run).
__all__ = ["analyse_ensemble", "finish_analysis", "analysis_headline"]

#: Per-member numbers the measurement adds to the ensemble's summaries (for memory estimates).
STUDY_MEMBER_NUMBERS = 5

#: The dimension of the amplitude histogram's bins.
AMPLITUDE_BIN = "amplitude_bin"


def amplitude_edges(body, spin: float, epsilon: float) -> np.ndarray:
    """Log-bin edges spanning every perpendicular amplitude of a free body started at
    ``epsilon * spin`` from a spin ``spin``: from half the start up to |L| / I_min, the most
    |w| can reach (|L| <= I_max |w0|), with a margin of 1 %."""
    moments = np.asarray(body.moments, dtype=float)
    start = epsilon * spin
    high = 1.01 * spin * math.sqrt(1.0 + epsilon**2) * moments.max() / moments.min()
    return log_edges(0.5 * start, max(high, 2.0 * start))


def measure_series(time, w, ok, w0, body, axis: int, spin: float, window, edges):
    """The study's numbers of members from their time series, in compiled code where it counts.

    Parameters
    ----------
    time : ndarray, shape (T,)
        Sample times, s.
    w : ndarray, shape (N, T, 3)
        Angular velocity samples, body frame, rad/s.
    ok : ndarray of bool, shape (N,)
        Members whose status is ok.
    w0 : ndarray, shape (N, 3)
        Starts, rad/s.
    body : RigidBody
    axis : int
        Spin axis, 1-based.
    spin : float
        Spin rate, rad/s.
    window : (float, float)
        The growth-rate window ``(low_factor, high_fraction)``.
    edges : ndarray
        Bin edges of the amplitude histogram (:func:`amplitude_edges`).

    Returns
    -------
    numbers : dict of ndarray, shape (N,)
        ``member_growth_rate`` (:func:`stability.analysis.growth_fit.series_growth_rates`),
        ``exact_flip_interval``, ``flip_interval_asymptote``, ``complementary_modulus``.
    counts : ndarray of int32, shape (T, bins)
        The ok members' perpendicular amplitudes per time in the bins ``edges``.
    """
    rate, _, counts = series_growth_rates(time, w, axis, spin, *window, valid=ok, edges=edges)
    return {"member_growth_rate": rate, **_exact_numbers(body, w0)}, counts  # of the ok members


def _exact_numbers(body, w0) -> dict:
    """Each start's exact flip interval 2K/nu, its asymptote and k'."""
    exact, asymptote = exact_flip_intervals(body, None, w0)
    return {"exact_flip_interval": exact, "flip_interval_asymptote": asymptote,
            "complementary_modulus": complementary_moduli(body, w0)}


def kept_chunk(summaries: xr.Dataset, time, numbers: dict, counts, edges, axis: int,
               sample: np.ndarray, series: dict) -> xr.Dataset:
    """A chunk as the study keeps it: its members' ``summaries`` (a Dataset along ``member``,
    without time series) with the study's ``numbers``, the amplitude histogram ``counts``
    (summed over chunks) and the time series ``series`` (name to an array over the members
    at positions ``sample``, in that order: ``w``, and ``q``, ``q_norm_error``,
    ``attitude_error`` with the attitude), along ``series_member``."""
    out = summaries.assign(TENNIS_RACKET.entries(numbers))
    out.coords[cv.TIME] = TENNIS_RACKET.entry(cv.TIME, np.asarray(time, dtype=float))
    out.coords[AMPLITUDE_BIN] = TENNIS_RACKET.entry(AMPLITUDE_BIN, np.sqrt(edges[:-1] * edges[1:]))
    out["amplitude_bin_bounds"] = TENNIS_RACKET.entry(
        "amplitude_bin_bounds", np.stack([edges[:-1], edges[1:]], axis=1))
    out["perp_amplitude_count"] = TENNIS_RACKET.entry("perp_amplitude_count", counts, axis=axis)
    out["perp_amplitude_count"].attrs[SUMMED] = 1
    out.coords[SERIES_MEMBER] = TENNIS_RACKET.entry(
        SERIES_MEMBER, out[cv.MEMBER].values[sample])
    if "q" in series:
        out.coords[cv.QUATERNION] = TENNIS_RACKET.entry(cv.QUATERNION, np.arange(4))
    for name, value in series.items():
        out[name] = TENNIS_RACKET.entry(name, value)
    return out


def measure_chunk(ds: xr.Dataset, body, axis: int, spin: float, window, sample: np.ndarray,
                  edges: np.ndarray) -> xr.Dataset:
    """A Dataset of members with their time series (as :func:`stability.run_ensemble` gives
    it, ``w`` (member, time, axis)) reduced to what the study keeps: :func:`measure_series`
    and :func:`kept_chunk`, the series of the members at positions ``sample``."""
    ok = (ds.status == cv.STATUS_OK).values
    w = ds.w.transpose(cv.MEMBER, cv.TIME, cv.AXIS).values
    numbers, counts = measure_series(ds[cv.TIME].values, w, ok, ds.w0.values, body, axis, spin,
                                     window, edges)
    names = [name for name in ("w", "q", "q_norm_error", "attitude_error") if name in ds]
    series = {name: ds[name].transpose(cv.MEMBER, *ENSEMBLE[name].dims[1:]).values
              for name in names}
    if "attitude_error" in series:
        numbers["attitude_error_max"] = series["attitude_error"].max(axis=1)
    series = {name: value[sample] for name, value in series.items()}
    summaries = ds.drop_vars(names + [cv.TIME] + ([cv.QUATERNION] if "q" in ds else []))
    return kept_chunk(summaries, ds[cv.TIME].values, numbers, counts, edges, axis, sample,
                      series)


class TennisChunks(EnsembleChunks):
    """The free body's chunk run (:class:`~stability.free_body.streamed.EnsembleChunks`) with
    the tennis-racket study's measurement (:func:`measure_chunk`) and combination.

    Parameters
    ----------
    kwargs : dict
        Keyword arguments of :func:`stability.run_ensemble` for the whole run (with
        ``chunk_members`` resolved).
    window : (float, float)
        The growth-rate window ``(low_factor, high_fraction)``.
    series_members : int or "all"
        Members whose time series are kept (:func:`series_sample`).
    plan : optional
        The run's plan, when the caller has it.
    """

    def __init__(self, kwargs: dict, window, series_members, plan=None):
        super().__init__(kwargs, plan)
        self.window = (float(window[0]), float(window[1]))
        self.series_members = series_members

    def __getstate__(self):
        return {**super().__getstate__(), "window": self.window,
                "series_members": self.series_members}

    def __call__(self, part, run, lo: int, hi: int, threads):
        """The chunk of members lo to hi - 1 measured (:func:`measure_series`) and kept
        (:func:`kept_chunk`): its series go no further than the sample's."""
        plan = self.plan
        sub, members = self.member_run(run, lo, hi, series=plan.attitude)
        started = time.perf_counter()
        edges = amplitude_edges(plan.body, plan.spin, plan.epsilon)
        axis = plan.a + 1
        ok = members.status == cv.STATUS_OK
        sample = sampled_in(series_sample(plan.members, self.series_members), lo, hi)
        if members.w is None:  # read from the loop's canonical m: only the sample's w built
            t = members.time
            m = run.saved[:, : t.size - 1, :3]
            frame = self.frame()
            rate, _, counts = canonical_growth_rates(
                t, members.w0, m, frame, plan.body.moments, axis, plan.spin, *self.window,
                valid=ok, edges=edges)
            numbers = {"member_growth_rate": rate, **_exact_numbers(plan.body, members.w0)}
            w = np.empty((sample.size, t.size, 3))  # the sample's alone
            w[:, 0] = members.w0[sample]
            canonical_to_w(np.ascontiguousarray(m[sample]), frame, plan.body.moments,
                           w[:, 1:])
            w[~ok[sample]] = np.nan  # as finish_run masks a member that failed
        else:
            numbers, counts = measure_series(members.time, members.w, ok, members.w0,
                                             plan.body, axis, plan.spin, self.window, edges)
            w = members.w[sample]
        series = {"w": w}
        if members.q is not None:  # the attitude against the exact one, as run_ensemble's
            q, norm_error, error = carried_attitude(plan.body.moments, members.w0,
                                                    members.time, members.q)
            series.update(q=q[sample], q_norm_error=norm_error[sample],
                          attitude_error=error[sample])
            numbers["attitude_error_max"] = error.max(axis=1)
        measuring = time.perf_counter() - started
        t = members.time
        members.w = members.q = None  # the summaries' Dataset: no member's series
        summaries = numbered(members_dataset(sub, members, threads), lo)
        started = time.perf_counter()
        out = kept_chunk(summaries, t, numbers, counts, edges, axis, sample, series)
        out.attrs["measure_time"] = measuring + time.perf_counter() - started
        return out

    def identity(self, run) -> dict:
        """The run's identity with what the measurement keeps: a store of another window or
        another sample is not resumed."""
        return {**super().identity(run),
                "tennis_racket": {"window": list(self.window),
                                  "series_members": self.series_members}}

    def joiner(self, members: int) -> ChunkJoin:
        """What joins the chunks in memory as they come
        (:class:`stability.ensemble.combine.ChunkJoin`)."""
        return ChunkJoin(members)


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

