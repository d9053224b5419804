"""What the heavy top's studies measure from ensemble runs: the sleeping top's tilt growth
across the critical spin (:func:`measure_sleeping_tops`) and released gyroscopes' precession and
nutation against the exact motion (:func:`measure_gyroscopes`).

**The sleeping top's stability map** (study ``sleeping_top``). For every top (here: one body
at several pivot distances l) and every spin w3, an ensemble of ``members`` tops starts upright
but for a tilt ``tilt`` at random azimuths, spinning at w3 about the symmetry axis, with no
transverse angular velocity. All ensembles run in one call of the member loop (scene
``heavy_top``, groups with their own top, step and horizon), tracking ``sin(tilt)`` and its first
passages of a ladder of levels. The growth rate of each member is the slope of ``ln(level)``
against passage time over the linear phase (:mod:`stability.analysis`), from ``low_factor``
times the start (the decaying mode has died away) up to ``high_fraction`` in ``sin(tilt)`` (the
nonlinear terms are ~high_fraction^2); it is set beside the analytic
``sqrt(4 A M g l - C^2 w3^2) / (2 A)`` (:mod:`stability.heavy_top.model`). Above the critical
spin the tilt stays bounded: no member reaches the window and the measured rate is 0, with the
largest tilt amplification reported.

Near the threshold the two modes ``e^{(i beta +- lambda) t}`` start with equal and large
amplitudes ~ beta / (2 lambda) times the start, so the decaying one dies only after the growing
one has grown by ~beta / lambda: the window must start later there, and the relative error grows
as ~(beta / (2 lambda L))^2 for a window starting at L times the start. ``relative_error`` is
reported for every spin; the study's claim (1e-3) is for spins with lambda above a stated
fraction of its value at zero spin.

**The gyroscope** (study ``gyroscope``). For every tilt theta0 and spin w3 of a grid, one group
of symmetric tops (scene ``heavy_top``) is released at theta0 with spin w3 and a precession rate
``phi'(0) = release x M g l / (C w3)`` for each ``release`` (0: at rest, the cusped path of the
figure axis; < 0: loops; between 0 and 1: waves). Each member runs ``periods`` nutation periods,
its state sampled ``samples_per_period`` times a period, and three numbers are read from the
samples (:mod:`stability.analysis.periodic`):

- the nutation period, from the upward crossings of cos(theta) = g3 through the middle of its
  range (cubic Hermite interpolation with ``g3' = g1 w2 - g2 w1``), as a frequency 2 pi / T;
- the nutation amplitude, theta_max - theta_min, from the turning points of g3 on the same
  interpolant, averaged over the periods;
- the mean precession rate, the weighted Birkhoff average of
  ``phi' = (w1 g1 + w2 g2) / (g1^2 + g2^2)`` (the vertical component of w less its part along
  the figure axis, over sin^2(theta)).

Each is set beside the exact value for the member's own start (:mod:`stability.heavy_top.exact`)
and beside the fast-top (gyroscopic) approximations ``M g l / (C w3)``, ``C w3 / A`` and
``2 |1 - release| A M g l sin(theta0) / (C w3)^2`` (:mod:`stability.heavy_top.model`), which the
exact values approach as w3 grows. For the figure, one (tilt, spin) cell's paths of the figure
axis (theta and phi, phi the trapezoidal integral of phi') are kept over a few nutation periods,
with the exact paths at the same times.
"""

from __future__ import annotations

import math
import time

import numpy as np
import xarray as xr

from ..analysis.estimates import measured_growth_rate
from ..analysis.periodic import extrema, level_crossings, mean_period, weighted_mean
from ..ensemble.chunks import run_plan
from ..ensemble.plan import Plan
from .scene import HEAVY_TOP
from .schema import GYROSCOPE, SLEEPING_TOP
from ..util import conventions as cv
from . import exact as exact_top
from .model import (
    critical_spin, gyroscopic_nutation_amplitude, gyroscopic_nutation_frequency,
    gyroscopic_precession_rate, sleeping_frequencies, sleeping_growth_rate, tilt_members,
    tilted_starts,
)

#: Dimension names.
SPIN = "spin"
LENGTH = "length"
TILT = "tilt"
RELEASE = "release"
PATH_TIME = "path_time"


def _horizon(rate, tilt, high, t_stable):
    """Run time: until a growing tilt has passed ``high`` with margin; ``t_stable`` if bounded."""
    with np.errstate(divide="ignore"):
        t_grow = (math.log(high / tilt) + 3.0) / rate
    return np.where(rate > 0.0, np.minimum(t_grow, 50.0 * t_stable), t_stable)


def measure_sleeping_tops(tops, spins, *, members=64, tilt=1e-9, method="lp4",
                          step_angle=0.02, t_stable=2.0, low_factor=1e3, high_fraction=1e-2,
                          levels_per_decade=8, seed=0, options=None) -> xr.Dataset:
    """Measured and analytic growth rates of sleeping tops over tops and spins.

    Parameters
    ----------
    tops : sequence of HeavyTop
        Symmetric tops (one per ``length`` coordinate: their l).
    spins : array_like, shape (S,)
        Spins w3 about the symmetry axis, rad s-1, >= 0.
    members : int
        Members per (top, spin).
    tilt : float
        Initial tilt, rad (small: the linear regime).
    method : str
        A method of scene ``heavy_top``.
    step_angle : float
        Step h = step_angle / (the fastest rate of the ensemble: spin, fast nutation
        C w3 / A or the fall rate sqrt(M g l / A)).
    t_stable : float
        Run time of the stable ensembles, s; unstable ones run until their tilt has grown past
        the window (at most 50 t_stable).
    low_factor, high_fraction : float
        The growth-rate window, in units of the start and in sin(tilt).
    levels_per_decade : int
        Density of the ladder of tilt levels.
    seed : int
        Seed of the members' azimuths (member k of every ensemble has the same azimuth).
    options : RunOptions, optional
        How and where the members run (:class:`~stability.ensemble.options.RunOptions`): by
        default in one piece here; with a ``store``, chunk by chunk into it, resumable and on
        dask. The result is the same, bitwise.

    Returns
    -------
    xarray.Dataset
        Dims (length, spin); see :data:`stability.heavy_top.schema.SLEEPING_TOP`.
    """
    tops = list(tops)
    spins = np.asarray(spins, dtype=float)
    scene = HEAVY_TOP
    spec = scene.method(method)
    levels = np.logspace(math.log10(10.0 * tilt), -0.5,
                         int(round((-0.5 - math.log10(10.0 * tilt)) * levels_per_decade)) + 1)
    x0, params, hs, steps, analytic = [], [], [], [], []
    for top in tops:
        A, _, C = top.pivot_moments
        rate = sleeping_growth_rate(top, spins)
        fastest = np.maximum.reduce([spins, C * spins / A,
                                     np.full(spins.shape, math.sqrt(top.mgl / A))])
        h = step_angle / fastest
        t_end = _horizon(rate, tilt, high_fraction, t_stable)
        for k, w in enumerate(spins):
            x0.append(tilted_starts(w, tilt, members, top=top, seed=seed))
            params.append(spec.params(top.parameters, h[k]))
        hs.append(h)
        steps.append(np.ceil(t_end / h).astype(np.int64))
        analytic.append(rate)
    shape = (len(tops), spins.size)
    hs = np.concatenate(hs)
    steps = np.concatenate(steps)
    x0 = np.concatenate(x0)
    sizes = np.full(hs.size, members)
    t0 = time.perf_counter()
    run = run_plan(Plan(scene, spec.name, x0, np.array(params), sizes, hs,
                        steps, axes=np.tile([2, 0, 1], (hs.size, 1)),
                        levels=np.tile(levels, (hs.size, 1)),
                        label=f"sleeping tops ({method})"),
                   options)
    wall = time.perf_counter() - t0
    out = {name: np.full(hs.size, np.nan) for name in
           ("growth_rate_measured", "growth_rate_stderr", "amplification", "n_fitted",
            "members_failed")}
    for g in range(hs.size):
        rows = slice(g * members, (g + 1) * members)
        extras = {key: value[rows] for key, value in run.extras.items()}
        mem = tilt_members(extras, x0[rows], run.status[rows], levels)
        fit = measured_growth_rate(mem, low_factor=low_factor, high_fraction=high_fraction)
        n = int(fit["n_fitted"])
        out["n_fitted"][g] = n
        out["members_failed"][g] = int(np.sum(run.status[rows] != cv.STATUS_OK))
        out["amplification"][g] = float(np.nanmax(mem.max_perp[mem.valid] / mem.a0[mem.valid]))
        grown = np.mean(mem.max_perp[mem.valid] >= high_fraction) > 0.5
        out["growth_rate_measured"][g] = float(fit["growth_rate"]) if grown else 0.0
        out["growth_rate_stderr"][g] = float(fit["growth_rate_stderr"]) if grown else 0.0
    analytic = np.stack(analytic)
    measured = out["growth_rate_measured"].reshape(shape)
    with np.errstate(invalid="ignore", divide="ignore"):
        relative = np.where(analytic > 0, (measured - analytic) / analytic, np.nan)
    lengths = np.array([top.length for top in tops])
    crit = np.array([critical_spin(top) for top in tops])
    slow, fast = zip(*(sleeping_frequencies(top, spins) for top in tops))
    fall = np.array([sleeping_growth_rate(top, 0.0) for top in tops])
    data = {
        "growth_rate_measured": measured,
        "growth_rate_stderr": out["growth_rate_stderr"].reshape(shape),
        "growth_rate_analytic": analytic,
        "relative_error": relative,
        "rate_fraction": analytic / fall[:, None],
        "tilt_amplification": out["amplification"].reshape(shape),
        "slow_frequency": np.stack(slow),
        "fast_frequency": np.stack(fast),
        "step": hs.reshape(shape),
        "t_end": (steps * hs).reshape(shape),
        "n_fitted": out["n_fitted"].reshape(shape).astype(np.int64),
        "members_failed": out["members_failed"].reshape(shape).astype(np.int64),
        "critical_spin": crit,
        "mgl": np.array([top.mgl for top in tops]),
        "pivot_moment_transverse": np.array([t.pivot_moments[0] for t in tops]),
    }
    ds = xr.Dataset(SLEEPING_TOP.entries(data),
                    coords=SLEEPING_TOP.entries({LENGTH: lengths, SPIN: spins}))
    ds.attrs.update({
        "critical_spin": float(crit[0]) if crit.size == 1 else crit,
        "method": spec.name, "members": members, "initial_tilt": tilt,
        "step_angle": step_angle, "growth_window_low_factor": low_factor,
        "growth_window_high_fraction": high_fraction, "wall_time": wall,
        "member_steps": int((sizes * steps).sum()),
    })
    return ds


def _observables(samples, A, C):
    """cos(theta), its rate and phi' of states (..., 6)."""
    m, g = samples[..., 0:3], samples[..., 3:6]
    w1, w2 = m[..., 0] / A, m[..., 1] / A
    g1, g2, g3 = g[..., 0], g[..., 1], g[..., 2]
    phi_rate = (w1 * g1 + w2 * g2) / (g1 * g1 + g2 * g2)
    return g3, g1 * w2 - g2 * w1, phi_rate


def _measure_member(t, u, du, phi_rate):
    """(nutation frequency, amplitude, mean precession rate) of one member's samples."""
    keep = np.isfinite(u) & np.isfinite(du) & np.isfinite(phi_rate)
    t, u, du, phi_rate = t[keep], u[keep], du[keep], phi_rate[keep]
    middle = 0.5 * (u.min() + u.max())
    period = mean_period(level_crossings(t, u, du, middle, direction=1))
    _, lows = extrema(t, u, du, "min")
    _, highs = extrema(t, u, du, "max")
    if lows.size and highs.size:
        amplitude = math.acos(np.clip(lows.mean(), -1, 1)) - math.acos(np.clip(highs.mean(), -1, 1))
    else:
        amplitude = math.nan
    return 2.0 * math.pi / period, amplitude, float(weighted_mean(phi_rate))


def measure_gyroscopes(top, spins, tilts, releases=(-1.0, 0.0, 0.5), *, method="lp4",
                       step_angle=0.02, periods=40, samples_per_period=64, seed=0,
                       path_tilt=None, path_spin=None, path_periods=3.0,
                       options=None) -> xr.Dataset:
    """Measured nutation and precession of released gyroscopes, with the exact values.

    Parameters
    ----------
    top : HeavyTop
        A symmetric top.
    spins : array_like, shape (S,)
        Spins w3 about the symmetry axis, rad s-1, > 0.
    tilts : array_like, shape (K,)
        Release tilts theta0 from the vertical, rad, in (0, pi).
    releases : sequence of float, shape (R,)
        phi'(0) in units of ``M g l / (C w3)``; one member per (tilt, spin, release).
    method : str
        A method of scene ``heavy_top``.
    step_angle : float
        Step h = step_angle / max(w3, the nutation frequency), rad.
    periods : float
        Run length in nutation periods (of the group's slowest member); the weighted mean of
        phi' converges faster than any power of it (40 gives ~1e-12).
    samples_per_period : int
        States kept per nutation period (at the fastest spin).
    seed : int
        Seed of the members' azimuths (irrelevant to the physics).
    path_tilt, path_spin : float, optional
        The cell whose figure-axis paths are kept (nearest grid values; default: the middle
        tilt, the lowest spin).
    path_periods : float
        Length of the kept paths, in nutation periods.
    options : RunOptions, optional
        How and where the members run (:class:`~stability.ensemble.options.RunOptions`): by
        default in one piece here; with a ``store``, chunk by chunk into it, resumable and on
        dask. The result is the same, bitwise.

    Returns
    -------
    xarray.Dataset
        Dims (tilt, spin, release) and (release, path_time); see
        :data:`stability.heavy_top.schema.GYROSCOPE`. The tilt coordinate is in degrees.
    """
    spins = np.asarray(spins, dtype=float)
    tilts = np.asarray(tilts, dtype=float)
    releases = np.asarray(releases, dtype=float)
    scene = HEAVY_TOP
    spec = scene.method(method)
    A, _, C = top.pivot_moments
    mgl = top.mgl
    n_rel = releases.size
    x0, params, hs, steps = [], [], [], []
    shape = (tilts.size, spins.size, n_rel)
    exact = {key: np.empty(shape) for key in ("frequency", "amplitude", "precession")}
    for i, tilt in enumerate(tilts):
        for j, spin in enumerate(spins):
            start = tilted_starts(spin, tilt, n_rel, top=top, seed=seed,
                                  precession_rate=releases * mgl / (C * spin))
            period = exact_top.nutation_period(start, A, C, mgl)
            u1, u2, _ = exact_top.nutation_roots(start, A, C, mgl)
            exact["frequency"][i, j] = 2.0 * np.pi / period
            exact["amplitude"][i, j] = np.arccos(u1) - np.arccos(u2)
            exact["precession"][i, j] = exact_top.mean_precession_rate(start, A, C, mgl)
            h = step_angle / max(spin, 2.0 * np.pi / period.min())
            x0.append(start)
            params.append(spec.params(top.parameters, h))
            hs.append(h)
            steps.append(int(math.ceil(periods * period.max() / h)))
    hs = np.array(hs)
    steps = np.array(steps, dtype=np.int64)
    x0 = np.concatenate(x0)
    sizes = np.full(hs.size, n_rel)
    fastest = (2.0 * np.pi / exact["frequency"]).reshape(hs.size, n_rel).min(axis=1)
    save_every = max(1, int(np.min(fastest / hs) // samples_per_period))
    t0 = time.perf_counter()
    run = run_plan(Plan(scene, spec.name, x0, np.array(params), sizes, hs,
                        steps, save_every=save_every,
                        label=f"gyroscopes ({method})"),
                   options)
    wall = time.perf_counter() - t0
    samples = np.concatenate([x0[:, None, :], run.saved], axis=1)
    u, du, phi_rate = _observables(samples, A, C)
    measured = {key: np.empty(hs.size * n_rel) for key in exact}
    for n in range(hs.size * n_rel):
        t = np.arange(samples.shape[1]) * save_every * hs[n // n_rel]
        (measured["frequency"][n], measured["amplitude"][n],
         measured["precession"][n]) = _measure_member(t, u[n], du[n], phi_rate[n])
    measured = {key: value.reshape(shape) for key, value in measured.items()}
    status = run.status.reshape(shape)

    # The kept paths: the cell nearest (path_tilt, path_spin).
    i = int(np.argmin(np.abs(tilts - (np.median(tilts) if path_tilt is None else path_tilt))))
    j = int(np.argmin(np.abs(spins - (spins.min() if path_spin is None else path_spin))))
    g = i * spins.size + j
    rows = slice(g * n_rel, (g + 1) * n_rel)
    dt = save_every * hs[g]
    n_path = min(samples.shape[1], int(math.ceil(path_periods * 2.0 * np.pi
                                                 / exact["frequency"][i, j].min() / dt)) + 1)
    t_path = np.arange(n_path) * dt
    rate = phi_rate[rows, :n_path]
    path_phi = np.concatenate([np.zeros((n_rel, 1)),
                               np.cumsum(0.5 * dt * (rate[:, 1:] + rate[:, :-1]), axis=1)], axis=1)
    path_theta = np.arccos(np.clip(u[rows, :n_path], -1.0, 1.0))
    path_theta_exact = np.arccos(np.clip(exact_top.cos_theta(t_path, x0[rows], A, C, mgl),
                                         -1.0, 1.0))
    path_phi_exact = exact_top.precession_angle(t_path, x0[rows], A, C, mgl)

    tilt3 = tilts[:, None, None]
    spin3 = spins[None, :, None]
    with np.errstate(invalid="ignore", divide="ignore"):
        errors = {key: (measured[key] - exact[key]) / exact[key] for key in exact}
    data = {
        "precession_rate_measured": measured["precession"],
        "precession_rate_exact": exact["precession"],
        "precession_rate_error": errors["precession"],
        "precession_rate_gyroscopic": gyroscopic_precession_rate(top, spins),
        "nutation_frequency_measured": measured["frequency"],
        "nutation_frequency_exact": exact["frequency"],
        "nutation_frequency_error": errors["frequency"],
        "nutation_frequency_gyroscopic": gyroscopic_nutation_frequency(top, spins),
        "nutation_amplitude_measured": measured["amplitude"],
        "nutation_amplitude_exact": exact["amplitude"],
        "nutation_amplitude_error": errors["amplitude"],
        "nutation_amplitude_gyroscopic": gyroscopic_nutation_amplitude(
            top, spin3, tilt3, releases[None, None, :]) + np.zeros(shape),
        "status": status.astype(np.int8),
        "step": hs.reshape(tilts.size, spins.size),
        "t_end": (steps * hs).reshape(tilts.size, spins.size),
        "path_theta": path_theta,
        "path_phi": path_phi,
        "path_theta_exact": path_theta_exact,
        "path_phi_exact": path_phi_exact,
    }
    ds = xr.Dataset(GYROSCOPE.entries(data), coords=GYROSCOPE.entries({
        TILT: np.round(np.degrees(tilts), 10), SPIN: spins, RELEASE: releases,
        PATH_TIME: t_path}))
    ds.attrs.update({
        **top.describe(), "method": spec.name, "step_angle": step_angle, "periods": periods,
        "samples_per_period": samples_per_period, "save_every": save_every,
        "path_tilt": float(np.degrees(tilts[i])), "path_spin": float(spins[j]),
        "wall_time": wall, "member_steps": int((sizes * steps).sum()),
    })
    return ds

