"""Dual-spin maps: a gyrostat's nutation, measured, against its eigenvalues and the energy sink.

A gyrostat (:mod:`.model_gyrostat`, whose :class:`~.model_gyrostat.DualSpinBody` is
the map's body) with an axisymmetric platform of transverse moment ``A_t`` and a
rotor of axial moment ``Jr`` spins with its platform at ``w_p`` about the rotor's axis. Over a map
of the inertia ratio ``A3 / A_t`` (the whole body's spin-axis moment over its transverse one: below
1 a minor-axis spinner, above 1 a major-axis one) and the rotor's spin ``Omega`` relative to the
platform, for each placement of the damper (on the platform, in the rotor, or both), one group of
members starts turning rigidly with H tilted by each initial nutation angle of a list (where the
nutation grows, lowered by its growth over the settling). Each damper's viscous coefficient is a
multiple of its energy-sink optimum ``c* = J h / A_t`` in that cell, so that "weak" and "strong"
mean the same everywhere on the map. Each group runs until its nutation has grown past the fitted
range or decayed by ``efolds`` e-folds at the linear rate (at most ``max_time``), keeping at least
:data:`MIN_SAMPLES` states; from each member's kept states (:mod:`.measure`):

- the nutation angle theta between e3 and H; its rate fitted in the linear regime (after the
  dampers' own faster modes have died away, while ``floor <= theta <= fit_top``) beside the
  linear eigenvalue, where the window spans at least one e-fold;
- its trend: the same least-squares slope over the window however short, whose sign is the
  measured verdict (decays or grows) even near the boundary, where the rate is too slow to fit;
- |H|'s largest relative change and the energy's largest rise between kept states.

Per cell: the verdicts of the eigenvalues, of the energy-sink criterion
(:func:`~.model_gyrostat.energy_sink_rate`) and of the measurement (each "undetermined" on a
boundary, or where the members disagree), and the nutation frequencies each body sees.
"""

from __future__ import annotations

import math
import time

import numpy as np
import xarray as xr

from .schema import DUAL_SPIN
from ..ensemble.chunks import run_plan
from ..ensemble.plan import Plan
from .model_gyrostat import (axisymmetric_eigenvalues, energy_sink_rate, first_order_rate,
                             tilted_spin)
from .measure import (MIN_FIT_SAMPLES, exponential_rate, largest_rise, nutation_angle,
                      relative_drift)
from .scene import GYROSTAT, gyrostat_energy, gyrostat_momentum

#: Where the dampers are: on the platform, in the rotor, or one on each.
PLACEMENTS = ("platform", "rotor", "both")
#: Dimension names.
PLACEMENT, RATIO, SPEED, START = "placement", "ratio", "speed", "start"
#: e-folds of the dampers' own faster modes waited before the nutation is fitted.
SETTLE_EFOLDS = 12.0
#: Nutation angles below this (rad) are round-off, not fitted.
FLOOR = 1e-10
#: Fewest states a cell keeps (its step shrinks if need be).
MIN_SAMPLES = 64
#: e-folds a growing nutation runs past the fitted range (from the smallest start).
GROWTH_MARGIN = 0.5
#: Most e-folds a growing nutation's start is lowered by (its growth over the settling).
MAX_HEADROOM = 9.0
#: A growth rate within this of 0, relative to the nutation's eigenvalue, is a boundary's 0.
NEUTRAL = 1e-10
#: Verdict flags: the nutation grows, decays, or too few samples to say.
GROWS, DECAYS, UNDETERMINED = 0, 1, 2


def _fastest(values, w_p, speed, lam) -> float:
    """The fastest rate (s-1) a step must resolve: the spins, the transverse eigenvalues and
    the dampers' axial relaxations."""
    A3, Jr, Jp, cp, Jq, cq = values[2:]
    axial = cp * (1.0 / Jp + 1.0 / (A3 - Jr)) + cq * (1.0 / Jq + 1.0 / Jr)
    return float(max(abs(w_p), abs(w_p + speed), np.abs(lam).max(), axial))


def measure_dual_spin(body, ratios, speeds, angles, *, placements=PLACEMENTS, step_angle=0.2,
                      efolds=4.0, max_time=3000.0, fit_top=0.02, samples=600, seed=0,
                      options=None) -> xr.Dataset:
    """The dual-spin map: every cell and start run, measured, and set beside the theory.

    Parameters
    ----------
    body : DualSpinBody
    ratios : array_like, shape (R,)
        Inertia ratios ``A3 / A_t``.
    speeds : array_like, shape (S,)
        The rotor's spins relative to the platform, rad s-1.
    angles : array_like, shape (K,)
        Nominal initial nutation angles, rad, all below ``fit_top``: where the nutation grows
        the members start lower, by its linear growth over the settling (at most
        :data:`MAX_HEADROOM` e-folds), so that the fit starts near them.
    placements : sequence of str
        Of :data:`PLACEMENTS`.
    step_angle : float
        ``h`` times the fastest rate of a cell (:func:`_fastest`), rad.
    efolds : float
        e-folds of a decaying nutation's linear rate run past the settling (a growing one runs
        until the smallest start is :data:`GROWTH_MARGIN` e-folds past ``fit_top``).
    max_time : float
        The longest a cell runs past its settling, s (near the boundary the rates vanish).
    fit_top : float
        Largest nutation angle (rad) of the linear regime fitted.
    samples : int
        States kept by the longest cell (the others keep fewer, at the same interval, and at
        least :data:`MIN_SAMPLES`: a short cell's step shrinks to keep them).
    seed : int
        Seed of the members' azimuths (irrelevant to an axisymmetric platform's physics).
    options : RunOptions, optional
        How and where the members run (:class:`~stability.ensemble.options.RunOptions`): by
        default in one piece here; with a ``store``, chunk by chunk into it, resumable and on
        dask. The result is the same, bitwise.

    Returns
    -------
    xarray.Dataset
        Dims (placement, ratio, speed) and (placement, ratio, speed, start); declared in
        :data:`stability.dissipation.schema.DUAL_SPIN`.
    """
    ratios = np.asarray(ratios, dtype=float)
    speeds = np.asarray(speeds, dtype=float)
    angles = np.asarray(angles, dtype=float)
    placements = tuple(placements)
    P, R, S, K = len(placements), ratios.size, speeds.size, angles.size
    spec = GYROSTAT.method("rk4")
    w_p = float(body.platform_spin)
    azimuths = np.random.default_rng(seed).uniform(0.0, 2.0 * np.pi, K)
    cells = [(placement, ratio, speed) for placement in placements for ratio in ratios
             for speed in speeds]
    G = len(cells)
    group_values, x0, starts = [], [], np.empty((G, K))
    growth_efolds = math.log(fit_top / angles.min()) + GROWTH_MARGIN
    hs, steps = np.empty(G), np.empty(G, dtype=np.int64)
    theory = {key: np.empty(G) for key in ("linear", "fast", "sink", "first", "settle",
                                           "scale")}
    for g, (placement, ratio, speed) in enumerate(cells):
        values = body.values(placement, ratio, speed)
        lam = axisymmetric_eigenvalues(values, w_p, speed)
        sigma = lam[0].real
        theory["linear"][g], theory["fast"][g] = sigma, lam[2].real
        theory["scale"][g] = abs(lam[0])
        theory["sink"][g] = energy_sink_rate(values, w_p, speed)
        theory["first"][g] = first_order_rate(values, w_p, speed)
        settle = min(SETTLE_EFOLDS / (sigma - lam[2].real), max_time)
        theory["settle"][g] = settle
        span = growth_efolds if sigma > 0.0 else efolds
        run_time = settle + min(span / abs(sigma) if sigma != 0.0 else math.inf, max_time)
        hs[g] = step_angle / _fastest(values, w_p, speed, lam)
        steps[g] = int(math.ceil(run_time / hs[g]))
        group_values.append(values)
        # A growing nutation starts lower, by its linear growth over the settling, so that
        # the fit begins near the nominal angle (below fit_top) whatever the settling.
        starts[g] = angles * math.exp(-min(max(sigma, 0.0) * settle, MAX_HEADROOM))
        x0.append(tilted_spin(values, w_p, speed, starts[g], azimuths))
    # Every cell keeps at least MIN_SAMPLES states: the short ones take smaller steps.
    save_every = max(1, int(steps.max()) // samples)
    short = steps < MIN_SAMPLES * save_every
    hs[short] *= steps[short] / (MIN_SAMPLES * save_every)
    steps[short] = MIN_SAMPLES * save_every
    rows = [spec.params(values, h) for values, h in zip(group_values, hs)]
    x0 = np.concatenate(x0)
    t0 = time.perf_counter()
    run = run_plan(Plan(
        GYROSTAT, spec.name, x0, np.array(rows), np.full(G, K), hs, steps,
        save_every=save_every, label="dual-spin map (rk4)"), options)
    wall = time.perf_counter() - t0
    kept = np.concatenate([x0[:, None, :], run.saved], axis=1).reshape(G, K, -1, x0.shape[1])
    index = np.arange(kept.shape[2])
    t = np.where(index[None, :] <= (steps // save_every)[:, None],
                 index[None, :] * save_every * hs[:, None], np.nan)
    measured = _measured(group_values, kept, t, theory, fit_top)
    end = nutation_angle(gyrostat_momentum(run.x_final.reshape(G, K, -1)), 2)

    cell, member = (PLACEMENT, RATIO, SPEED), (PLACEMENT, RATIO, SPEED, START)
    shape, member_shape = (P, R, S), (P, R, S, K)
    h = (body.transverse_moment * ratios[:, None] * w_p  # (ratio, speed)
         + body.rotor_moment * speeds[None, :])
    lam_p = h / body.transverse_moment - w_p
    lam_r = lam_p - speeds[None, :]
    linear = theory["linear"].reshape(shape)
    sink = theory["sink"].reshape(shape)
    neutral = NEUTRAL * theory["scale"].reshape(shape)  # on a boundary, to round-off
    with np.errstate(divide="ignore", invalid="ignore"):
        rate_error = measured["rate"] / theory["linear"][:, None] - 1.0
        sink_error = sink / linear - 1.0
    data = {
        "rate_measured": measured["rate"].reshape(member_shape),
        "rate_error": rate_error.reshape(member_shape),
        "trend_measured": measured["trend"].reshape(member_shape),
        "angular_momentum_drift": measured["drift"].reshape(member_shape),
        "energy_rise": measured["rise"].reshape(member_shape),
        "end_angle": np.degrees(end).reshape(member_shape),
        "status": run.status.reshape(member_shape).astype(np.int8),
        "start_angle": np.degrees(starts).reshape(member_shape),
        "rate_linear": linear,
        "rate_energy_sink": sink,
        "rate_first_order": theory["first"].reshape(shape),
        "rate_sink_error": sink_error,
        "verdict_linear": _sign_verdict(linear, neutral),
        "verdict_energy_sink": _sign_verdict(sink, neutral),
        "verdict_measured": _verdict(measured["trend"]).reshape(shape),
        "c_platform": np.array([v[5] for v in group_values]).reshape(shape),
        "c_rotor": np.array([v[7] for v in group_values]).reshape(shape),
        "settle_time": theory["settle"].reshape(shape),
        "step": hs.reshape(shape),
        "t_end": (steps * hs).reshape(shape),
        "axial_momentum": h,
        "nutation_frequency_platform": lam_p,
        "nutation_frequency_rotor": lam_r,
    }
    dims = {name: (member if np.ndim(value) == 4 else cell if np.ndim(value) == 3
                   else (RATIO, SPEED)) for name, value in data.items()}
    ds = xr.Dataset(
        {name: (dims[name], value, DUAL_SPIN.attrs(name)) for name, value in data.items()},
        coords=DUAL_SPIN.entries({PLACEMENT: np.array(placements), RATIO: ratios,
                                  SPEED: speeds, START: np.degrees(angles)}))
    ds.attrs.update({
        "transverse_moment": body.transverse_moment, "rotor_moment": body.rotor_moment,
        "damper_moment": body.damper_moment, "platform_spin": w_p,
        "platform_damping": body.platform_damping, "rotor_damping": body.rotor_damping,
        "method": spec.name, "step_angle": step_angle, "efolds": efolds, "max_time": max_time,
        "fit_top": fit_top, "save_every": save_every, "wall_time": wall,
        "member_steps": int(K * steps.sum()),
    })
    return ds


def _measured(group_values, kept, t, theory, fit_top) -> dict:
    """Per member: the fitted rate, the trend, |H|'s drift and the energy's largest rise."""
    G, K = kept.shape[:2]
    H = gyrostat_momentum(kept)
    theta = nutation_angle(H, 2)
    rate, trend = np.full((G, K), np.nan), np.full((G, K), np.nan)
    rise = np.empty((G, K))
    for g in range(G):
        for k in range(K):
            keep = _window(t[g], theta[g, k], theory["settle"][g], fit_top)
            rate[g, k] = exponential_rate(t[g], theta[g, k], keep)
            if keep.sum() >= MIN_FIT_SAMPLES:
                trend[g, k] = np.polyfit(t[g][keep], np.log(theta[g, k][keep]), 1)[0]
        rise[g] = largest_rise(gyrostat_energy(kept[g], group_values[g]))
    return {"rate": rate, "trend": trend, "rise": rise,
            "drift": relative_drift(np.linalg.norm(H, axis=-1))}


def _window(t, theta, settle, top):
    """The linear regime's samples: after ``settle`` (s), up to the first sample above
    ``top`` (rad), and above :data:`FLOOR`."""
    above = np.flatnonzero(~(theta <= top))
    end = above[0] if above.size else theta.size
    keep = np.zeros(theta.size, dtype=bool)
    keep[:end] = (t[:end] >= settle) & (theta[:end] >= FLOOR)
    return keep


def _sign_verdict(rate, neutral) -> np.ndarray:
    """DECAYS where ``rate < -neutral``, GROWS where ``rate > neutral``, UNDETERMINED between
    (a cell on a boundary)."""
    out = np.full(np.shape(rate), UNDETERMINED, dtype=np.int8)
    out[rate < -neutral] = DECAYS
    out[rate > neutral] = GROWS
    return out


def _verdict(trend) -> np.ndarray:
    """Per cell (the last axis: its members): DECAYS where every member's trend is negative,
    GROWS where every one is positive, UNDETERMINED otherwise."""
    trend = np.asarray(trend, dtype=float)
    out = np.full(trend.shape[0], UNDETERMINED, dtype=np.int8)
    with np.errstate(invalid="ignore"):
        out[np.all(trend < 0.0, axis=-1)] = DECAYS
        out[np.all(trend > 0.0, axis=-1)] = GROWS
    return out
