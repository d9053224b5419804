"""The sleeping top's stability map: measured against analytic tilt growth, across the threshold.

For every top (here: one body at several pivot distances l) and every spin w3, an ensemble of
``members`` tops starts upright but for a tilt ``tilt`` at random azimuths, spinning at w3 about
the symmetry axis, with no transverse angular velocity. All ensembles run in one call of the
member loop (scene ``heavy_top``, groups with their own top, step and horizon), tracking
``sin(tilt)`` and its first passages of a ladder of levels. The growth rate of each member is the
slope of ``ln(level)`` against passage time over the linear phase (:mod:`stability.estimators`),
from ``low_factor`` times the start (the decaying mode has died away) up to ``high_fraction`` in
``sin(tilt)`` (the nonlinear terms are ~high_fraction^2); it is set beside the analytic
``sqrt(4 A M g l - C^2 w3^2) / (2 A)`` (:mod:`stability.heavy_top.model`). Above the critical spin the tilt
stays bounded: no member reaches the window and the measured rate is 0, with the largest tilt
amplification reported.

Near the threshold the two modes ``e^{(i beta +- lambda) t}`` start with equal and large
amplitudes ~ beta / (2 lambda) times the start, so the decaying one dies only after the growing
one has grown by ~beta / lambda: the window must start later there, and the relative error grows
as ~(beta / (2 lambda L))^2 for a window starting at L times the start. ``relative_error`` is
reported for every spin; the study's claim (1e-3) is for spins with lambda above a stated
fraction of its value at zero spin.
"""

from __future__ import annotations

import math
import time

import numpy as np
import xarray as xr

from ..util import conventions as cv
from .. import estimators as est
from ..scene_ensemble import GroupedRun, propagate_stored
from ..scenes import SCENES
from ..schema import SLEEPING_TOP
from .model import critical_spin, sleeping_frequencies, sleeping_growth_rate
from .model import tilt_members, tilted_starts

#: Dimension names.
SPIN = "spin"
LENGTH = "length"


def _horizon(rate, tilt, high, t_stable):
    """Run time: until a growing tilt has passed ``high`` with margin; ``t_stable`` if bounded."""
    with np.errstate(divide="ignore"):
        t_grow = (math.log(high / tilt) + 3.0) / rate
    return np.where(rate > 0.0, np.minimum(t_grow, 50.0 * t_stable), t_stable)


def measure_sleeping_tops(tops, spins, *, members=64, tilt=1e-9, method="lp4",
                          step_angle=0.02, t_stable=2.0, low_factor=1e3, high_fraction=1e-2,
                          levels_per_decade=8, seed=0, progress=None,
                          stored=None) -> xr.Dataset:
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
    progress : bool, optional
        Progress bar (default: for runs longer than a few seconds).
    stored : dict, optional
        Keyword arguments of :func:`stability.scene_ensemble.propagate_stored` (``store``,
        ``resume``, ``scheduler`` ...): the tops run chunk by chunk into a store, resumable and
        on dask; by default in one piece here. The result is the same, bitwise.

    Returns
    -------
    xarray.Dataset
        Dims (length, spin); see :data:`stability.schema.SLEEPING_TOP`.
    """
    tops = list(tops)
    spins = np.asarray(spins, dtype=float)
    scene = SCENES["heavy_top"]
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
    run = propagate_stored(GroupedRun(scene.name, spec.name, x0, np.array(params), sizes, hs,
                                      steps, axes=np.tile([2, 0, 1], (hs.size, 1)),
                                      levels=np.tile(levels, (hs.size, 1)),
                                      label=f"sleeping tops ({method})"),
                           progress=progress, **(stored or {}))
    wall = time.perf_counter() - t0
    out = {name: np.full(hs.size, np.nan) for name in
           ("growth_rate_measured", "growth_rate_stderr", "amplification", "n_fitted",
            "members_failed")}
    for g in range(hs.size):
        rows = slice(g * members, (g + 1) * members)
        extras = {key: value[rows] for key, value in run.extras.items()}
        mem = tilt_members(extras, x0[rows], run.status[rows], levels)
        fit = est.measured_growth_rate(mem, low_factor=low_factor, high_fraction=high_fraction)
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

