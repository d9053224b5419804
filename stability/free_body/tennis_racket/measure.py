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
they come; :func:`stability.free_body.tennis_racket.analysis.finish_analysis` reduces them (the mean
growth rate, the amplitude quantiles from the summed histograms).
"""

from __future__ import annotations

import math
import time

import numpy as np
import xarray as xr

from ...analysis.growth_fit import canonical_growth_rates, series_growth_rates
from ...ensemble.combine import (SERIES_MEMBER, SUMMED, ChunkJoin, log_edges,
                                 sampled_in, series_sample)
from ...util import conventions as cv
from ..measure import complementary_moduli, exact_flip_intervals
from ...ensemble.schema import ENSEMBLE
from ..results import canonical_to_w, carried_attitude, members_dataset
from ..schema import TENNIS_RACKET
from ..streamed import EnsembleChunks, numbered

__all__ = ["TennisChunks", "amplitude_edges", "measure_series", "kept_chunk", "measure_chunk"]

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
