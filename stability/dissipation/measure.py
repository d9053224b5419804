"""What the dissipation studies read from a run, and the damped bodies' runs measured: the
Explorer-like ensembles.

The readings (nutation angles, fitted rates, the end state; :func:`nutation_angle`,
:func:`exponential_rate`, ...) work on NumPy arrays of one member's samples (or of many, where
the shapes say so) and know nothing of scenes or Datasets; the gyrostat's maps
(:mod:`.measure_gyrostat`) read their runs with them too.

**The Explorer-like ensembles** (:func:`measure_explorer`). For each damper (a spherical damper
at each damping of a list, and one set of whip antennas) one group of members starts turning
rigidly at the body's spin about its long (least-inertia) axis with H tilted by each initial
nutation angle of a list (:func:`~.model.tilted_rotation`). Each group runs until its slowest
member, extrapolated at its linear growth rate, has passed the flat-spin angle, and ``tail``
e-folds of the decay about the major axis beyond. From each member's kept states:

- the nutation angle theta between the long axis and H against time; its growth rate fitted
  in the linear regime (after the damper's own faster modes have died away, while
  ``theta <= fit_top``) beside the linear eigenvalue (:mod:`.model`) and the energy-sink
  estimate, and the rate at which ``|cos theta|`` then dies away about the major axis beside
  its eigenvalue;
- the time to the flat spin (theta passing ``flat_angle``, from the member loop's tracking,
  interpolated within the step);
- the end state: theta, |H|'s largest relative change, the energy lost against
  ``|H|^2 / 2 (1/A_min - 1/A_max)`` and the end energy against ``|H|^2 / (2 A_max)``, and
  how far the energy ever rose from one kept state to the next.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Callable

import numpy as np
import xarray as xr

from ..util import conventions as cv
from ..ensemble.chunks import run_plan
from ..ensemble.options import run_options
from ..ensemble.plan import Plan
from ..engine.scene import Scene
from .model import (best_damping, energy_lost, energy_sink_optimum, energy_sink_rate,
                    equivalent_transverse_moment, moving_eigenvalues, sphere_eigenvalues,
                    tilted_rotation, whip_eigenvalues)
from .scene import (SPHERE_DAMPER, WHIP_DAMPER, sphere_energy, sphere_moments,
                    sphere_momentum, sphere_rigid_state, whip_energy, whip_momentum,
                    whip_moments, whip_rigid_state)

#: Fewest samples a fitted window holds.
MIN_FIT_SAMPLES = 8
#: Least growth (or decay) a fitted window spans, in e-folds: less is not a linear regime
#: long enough to fit.
MIN_FIT_EFOLDS = 1.0


def nutation_angle(H, axis: int = 0) -> np.ndarray:
    """The angle (rad) between body axis ``axis`` and the angular momentum H (..., 3):
    ``atan2(sqrt(H_b^2 + H_c^2), H_a)``, in [0, pi].

    Parameters
    ----------
    H : array_like, shape (..., 3)
        Angular momentum in the body frame, kg m2 s-1.
    axis : int
        Body axis, 0, 1 or 2.
    """
    H = np.asarray(H, dtype=float)
    across = [k for k in range(3) if k != axis]
    return np.arctan2(np.hypot(H[..., across[0]], H[..., across[1]]), H[..., axis])


def nutation_amplitude(H, moments, axis: int = 0) -> np.ndarray:
    """The sine of the angle between body axis ``axis`` and the angular momentum H (..., 3) as a
    rigid body's motion keeps it: ``sqrt(sum_k H_k^2 w_k / max w) / |H|`` over the other axes,
    ``w_k = |1/A_a - 1/A_k|`` (``moments`` A, kg m2).

    Across equal moments it is the angle's sine (``|H_a| / |H|`` about an axis whose plane of
    equal moments holds the other axis). Across unequal ones the angle itself swings twice a
    nutation between two values, and samples taken at a slower cadence alias that swing into
    a fitted rate; this, a constant of the rigid motion, does not swing.

    Parameters
    ----------
    H : array_like, shape (..., 3)
        Angular momentum in the body frame, kg m2 s-1.
    moments : array_like, shape (3,)
        The whole system's principal moments A, kg m2.
    axis : int
        Body axis, 0, 1 or 2.
    """
    H = np.asarray(H, dtype=float)
    A = np.asarray(moments, dtype=float)
    weights = np.abs(1.0 / A[axis] - 1.0 / A)
    weights[axis] = 0.0
    weights = weights / weights.max()
    return np.sqrt(np.sum(H * H * weights, axis=-1)) / np.linalg.norm(H, axis=-1)


def exponential_rate(t, amplitude, keep) -> float:
    """The rate (s-1) of ``amplitude ~ exp(rate t)``: the least-squares slope of
    ``ln(amplitude)`` over the samples ``keep``; NaN when they are fewer than
    :data:`MIN_FIT_SAMPLES` or span less than :data:`MIN_FIT_EFOLDS` e-folds.

    Parameters
    ----------
    t, amplitude : ndarray, shape (n,)
        Times (s) and positive amplitudes.
    keep : ndarray of bool, shape (n,)
        The window.
    """
    t = np.asarray(t, dtype=float)
    amplitude = np.asarray(amplitude, dtype=float)
    keep = np.asarray(keep, dtype=bool) & np.isfinite(amplitude) & (amplitude > 0.0)
    if keep.sum() < MIN_FIT_SAMPLES:
        return np.nan
    log = np.log(amplitude[keep])
    if log.max() - log.min() < MIN_FIT_EFOLDS:
        return np.nan
    return float(np.polyfit(t[keep], log, 1)[0])


def growth_window(t, theta, settle, top):
    """The samples of a growing nutation in its linear regime: after ``settle`` (s), once the
    faster modes have died away, and while ``theta <= top`` (rad), before the first sample
    above it.

    Parameters
    ----------
    t : ndarray, shape (n,)
        Sample times, s.
    theta : ndarray, shape (n,)
        Nutation angles, rad.
    settle : float
        Time (s) the faster modes take to die away.
    top : float
        Largest value of the linear regime.
    """
    t = np.asarray(t, dtype=float)
    theta = np.asarray(theta, dtype=float)
    above = np.flatnonzero(~(theta <= top))
    end = above[0] if above.size else theta.size
    keep = np.zeros(theta.size, dtype=bool)
    keep[:end] = t[:end] >= settle
    return keep


def decay_window(t, departure, top, floor, settle):
    """The samples of a dying departure (``|cos theta|`` from the major axis, say) in its
    linear regime: from ``settle`` (s) after it first falls to ``top``, while it stays above
    ``floor`` (round-off).

    Parameters
    ----------
    t : ndarray, shape (n,)
        Sample times, s.
    departure : ndarray, shape (n,)
        The departure from the major axis (1).
    top : float
        Largest value of the linear regime.
    floor : float
        Smallest value fitted (round-off below).
    settle : float
        Time (s) the faster modes take to die away.
    """
    t = np.asarray(t, dtype=float)
    departure = np.abs(np.asarray(departure, dtype=float))
    below = np.flatnonzero(departure <= top)
    if not below.size:
        return np.zeros(departure.size, dtype=bool)
    return (t >= t[below[0]] + settle) & (departure >= floor) & np.isfinite(departure)


def relative_drift(values) -> np.ndarray:
    """``max_k |v_k / v_0 - 1|`` over the last axis of ``values`` (..., n), NaN samples
    skipped: the largest relative change of an invariant.

    Parameters
    ----------
    values : ndarray, shape (..., n)
        Samples along the last axis.
    """
    values = np.asarray(values, dtype=float)
    return np.nanmax(np.abs(values / values[..., :1] - 1.0), axis=-1)


def largest_rise(values) -> np.ndarray:
    """``max_k (v_{k+1} - v_k) / |v_0|`` over the last axis (..., n), 0 when it never rises:
    how far a quantity that should only fall (the energy) ever went up, relative to its start.

    Parameters
    ----------
    values : ndarray, shape (..., n)
        Samples along the last axis.
    """
    values = np.asarray(values, dtype=float)
    rise = np.diff(values, axis=-1) / np.abs(values[..., :1])
    return np.maximum(np.nanmax(rise, axis=-1, initial=-np.inf), 0.0)


# --- The Explorer-like ensembles ---------------------------------------------------------------

#: Dimension names.
DAMPING = "damping"
ANGLE = "angle"
SAMPLE = "sample"
WHIP_ANGLE = "whip_angle"
WHIP_SAMPLE = "whip_sample"
#: e-folds of the damper's own faster modes waited before the growth is fitted.
SETTLE_EFOLDS = 12.0
#: Departures from the major axis below this are round-off, not fitted.
DECAY_FLOOR = 1e-9


@dataclass(frozen=True)
class Damper:
    """A damped body's scene and what the ensembles need of it, in NumPy.

    The fields are the constructor's parameters and the instance's attributes.

    Parameters
    ----------
    scene : Scene
    rigid_state : callable
        ``rigid_state(values, w) -> x``: states turning rigidly at ``w`` (N, 3).
    moments : callable
        ``moments(values) -> A``: the whole system's principal moments.
    eigenvalues : callable
        ``eigenvalues(values, axis, spin)``: the nutation's linear eigenvalues.
    energy : callable
        ``energy(x, values)``.
    momentum : callable
        ``momentum(x) -> H`` (..., 3).
    """

    scene: Scene
    rigid_state: Callable
    moments: Callable
    eigenvalues: Callable
    energy: Callable
    momentum: Callable


SPHERE = Damper(SPHERE_DAMPER, sphere_rigid_state, sphere_moments, sphere_eigenvalues,
                sphere_energy, sphere_momentum)
WHIPS = Damper(WHIP_DAMPER, whip_rigid_state, whip_moments, whip_eigenvalues, whip_energy,
               whip_momentum)


@dataclass(frozen=True)
class Whips:
    """Four whip antennas as two pairs of tip masses on springs with dashpots.

    The fields are the constructor's parameters and the instance's attributes.

    Parameters
    ----------
    mass : float
        Mass of a pair of tips, kg.
    arm : float
        Distance of the tips from the long axis, m.
    frequency_ratio : float
        The tips' natural frequency over the nutation frequency the body feels,
        ``nu = W (A_t - A_s) / A_t`` (1: tuned).
    damping_ratio : float
        The tips' damping ratio.
    """

    mass: float
    arm: float
    frequency_ratio: float = 1.0
    damping_ratio: float = 0.1

    def values(self, moments, spin) -> np.ndarray:
        """The scene's parameter set ``(I1, I2, I3, mu, b, k, c)`` on a body of ``moments``
        spun at ``spin``: ``k = mu w_n^2``, ``c = 2 zeta mu w_n``, ``w_n = ratio nu``."""
        moments = np.asarray(moments, dtype=float)
        A = whip_moments([*moments, self.mass, self.arm, 0.0, 0.0])
        natural = self.frequency_ratio * spin * (A[1] - A[0]) / A[1]
        return np.array([*moments, self.mass, self.arm, self.mass * natural**2,
                         2.0 * self.damping_ratio * self.mass * natural])


def run_damped(damper, method, group_values, angles, *, spin, step_angle=0.5, tail=6.0,
               samples=2000, fit_top=0.02, flat_angle=math.radians(80.0), seed=0,
               label=None, options=None) -> dict:
    """Groups of one damped body, each with its parameter set, every initial nutation angle a
    member; run and measured (module docstring).

    Parameters
    ----------
    damper : Damper
    method : str
        A method of the damper's scene.
    group_values : sequence of ndarray, length G
        The scene's parameter set of each group (axis 1 the long, least-inertia axis).
    angles : array_like, shape (K,)
        Initial nutation angles, rad.
    spin : float
        The spin about the long axis at the start, rad s-1.
    step_angle : float
        ``h`` times the fastest member's angular speed, rad.
    tail : float
        e-folds of the decay about the major axis run past the flat spin.
    samples : int
        States kept by the longest group (the others keep fewer, at the same interval).
    fit_top : float
        Largest nutation angle (rad) of the linear regime fitted.
    flat_angle : float
        The nutation angle (rad) that counts as a flat spin.
    seed : int
        Seed of the members' azimuths (irrelevant to the physics of a symmetric body).
    label : str, optional
        The progress bar's label.
    options : RunOptions, optional
        How and where the members run (:class:`~stability.ensemble.options.RunOptions`): by
        default in one piece here; with a ``store``, chunk by chunk into it, resumable and on
        dask. The result is the same, bitwise.

    Returns
    -------
    dict
        Arrays (G, K) by name (rates, times, end state; see :data:`VARIABLES`), the kept
        angles and energies (G, K, S), the sample times (G, S), ``status``, ``step``,
        ``t_end``, ``save_every``, ``wall_time`` and ``member_steps``.
    """
    angles = np.asarray(angles, dtype=float)
    G, K = len(group_values), angles.size
    spec = damper.scene.method(method)
    azimuths = np.random.default_rng(seed).uniform(0.0, 2.0 * np.pi, K)
    x0, rows, hs, steps = [], [], np.empty(G), np.empty(G, dtype=np.int64)
    theory = {key: np.empty((G, K)) for key in ("growth", "fast", "decay", "H")}
    for g, values in enumerate(group_values):
        A = damper.moments(values)
        major = A.size - 1 - int(np.argmax(A[::-1]))
        w, H = tilted_start(damper, values, spin, angles, azimuths)
        x0.append(damper.rigid_state(values, w))
        theory["H"][g] = H
        for k in range(K):
            lam = damper.eigenvalues(values, 0, H[k] / A[0])
            theory["growth"][g, k], theory["fast"][g, k] = lam[0].real, lam[2].real
            after = moving_eigenvalues(damper.eigenvalues(values, major, H[k] / A[major]))
            theory["decay"][g, k] = np.max(after.real)
        settle = SETTLE_EFOLDS / np.abs(theory["fast"][g])
        growth = theory["growth"][g]
        decay = np.where(theory["decay"][g] < -1e-3 * growth, -theory["decay"][g], growth)
        t_end = settle + np.log(np.tan(flat_angle) / np.tan(angles)) / growth + tail / decay
        hs[g] = step_angle / np.linalg.norm(w, axis=1).max()
        steps[g] = int(math.ceil(t_end.max() / hs[g]))
        rows.append(spec.params(values, hs[g]))
    save_every = max(1, int(steps.max()) // samples)
    x0 = np.concatenate(x0)
    t0 = time.perf_counter()
    run = run_plan(Plan(
        damper.scene, spec.name, x0, np.array(rows), np.full(G, K), hs, steps,
        save_every=save_every, axes=[0, 1, 2], levels=[[math.sin(flat_angle)]],
        label=label or f"{damper.scene.name} ({method})"), options)
    wall = time.perf_counter() - t0
    kept = np.concatenate([x0[:, None, :], run.saved], axis=1).reshape(G, K, -1, x0.shape[1])
    t = np.arange(kept.shape[2])[None, :] * save_every * hs[:, None]
    t = np.where(np.arange(kept.shape[2])[None, :] <= (steps // save_every)[:, None], t, np.nan)
    out = _measured(damper, group_values, kept, t, theory, angles, fit_top, flat_angle)
    out["flat_time"] = run.extras["passage_time"][:, 0].reshape(G, K)
    end = run.x_final.reshape(G, K, -1)
    out.update(_end_state(damper, group_values, kept[:, :, 0], end, theory["H"]))
    out.update(status=run.status.reshape(G, K), step=hs, t_end=steps * hs, sample_time=t,
               save_every=save_every, wall_time=wall, member_steps=int(K * steps.sum()))
    return out


def tilted_start(damper, values, spin, angles, azimuths):
    """The rigid turn about the long axis with H tilted from it (:func:`~.model.tilted_rotation`
    with the system's moments), what a damped body's run starts from.

    Parameters
    ----------
    damper : Damper
    values : ndarray
        The scene's parameter set (axis 1 the long, least-inertia axis).
    spin : float
        The spin W about the long axis, rad s-1.
    angles : array_like, shape (K,)
        Nutation angles between the long axis and H, rad.
    azimuths : array_like, shape (K,)
        Directions of the tilt, rad.

    Returns
    -------
    w : ndarray, shape (K, 3)
        The angular velocities, rad s-1.
    H : ndarray, shape (K,)
        ``|H|``, kg m2 s-1; ``|H| / A_1`` is the spin the linear theory takes.
    """
    A = damper.moments(values)
    w = tilted_rotation(A, spin, angles, azimuths)
    return w, np.linalg.norm(w * A, axis=1)


def _measured(damper, group_values, kept, t, theory, angles, fit_top, flat_angle) -> dict:
    """Rates fitted from the kept states, beside the linear theory; angles and energies."""
    G, K = theory["growth"].shape
    H = damper.momentum(kept)
    theta = nutation_angle(H, 0)
    norm = np.linalg.norm(H, axis=-1)
    energy = np.stack([damper.energy(kept[g], group_values[g]) for g in range(G)])
    growth, decay = np.full((G, K), np.nan), np.full((G, K), np.nan)
    for g in range(G):
        A = damper.moments(group_values[g])
        major = A.size - 1 - int(np.argmax(A[::-1]))
        # the angles a rigid motion keeps (the angles themselves swing on unequal moments)
        nutation = np.arcsin(np.minimum(nutation_amplitude(H[g], A, 0), 1.0))
        departures = nutation_amplitude(H[g], A, major)  # |cos theta| on a symmetric body
        for k in range(K):
            settle = SETTLE_EFOLDS / abs(theory["fast"][g, k])
            growth[g, k] = exponential_rate(
                t[g], nutation[k], growth_window(t[g], nutation[k], settle, fit_top))
            departure = departures[k]
            decay[g, k] = exponential_rate(
                t[g], departure, decay_window(t[g], departure, fit_top, DECAY_FLOOR, settle))
    with np.errstate(invalid="ignore", divide="ignore"):
        return {
            "growth_rate_measured": growth,
            "growth_rate_linear": theory["growth"],
            "growth_rate_error": growth / theory["growth"] - 1.0,
            "decay_rate_measured": decay,
            "decay_rate_linear": theory["decay"],
            "decay_rate_error": decay / theory["decay"] - 1.0,
            "flat_time_linear": (np.log(math.tan(flat_angle) / np.tan(angles))[None, :]
                                 / theory["growth"]),
            "angular_momentum_drift": relative_drift(norm),
            "energy_rise": largest_rise(energy),
            "theta": np.degrees(theta),
            "energy_ratio": energy / energy[:, :, :1],
        }


def _end_state(damper, group_values, start, end, H) -> dict:
    """The end state against the spin about the major axis with the same |H|."""
    G, K = H.shape
    out = {key: np.empty((G, K)) for key in ("end_angle", "energy_lost", "energy_lost_formula",
                                             "end_energy_error", "flat_energy_ratio")}
    for g, values in enumerate(group_values):
        A = damper.moments(values)
        H_end = damper.momentum(end[g])
        out["end_angle"][g] = np.degrees(nutation_angle(H_end, 0))
        e0, e1 = damper.energy(start[g], values), damper.energy(end[g], values)
        out["energy_lost"][g] = e0 - e1
        out["energy_lost_formula"][g] = energy_lost(H[g], A[0], A.max())
        flat = 0.5 * H[g] ** 2 / A.max()
        out["end_energy_error"][g] = e1 / flat - 1.0
        out["flat_energy_ratio"][g] = flat / e0
    out["energy_lost_error"] = out["energy_lost"] / out["energy_lost_formula"] - 1.0
    return out


def measure_explorer(body, J, factors, angles, *, method="lp2", step_angle=0.5, tail=6.0,
                     samples=2000, fit_top=0.02, flat_angle=math.radians(80.0),
                     end_tolerance=math.radians(1.0), whips=None, whip_angles=None,
                     whip_step_angle=0.06, whip_tail=25.0, seed=0, options=None) -> xr.Dataset:
    """An Explorer-like body with a spherical damper at each damping, and with whip antennas:
    rates, times to the flat spin and end states against the theory.

    Parameters
    ----------
    body : Cylinder or Spinner
        The body (:data:`~stability.dissipation.model.EXPLORER_1`, a cylinder, or measured
        moments, :class:`~stability.dissipation.model.Spinner`): its moments, the spin axis's
        first, and its spin.
    J : float
        The sphere's moment of inertia, kg m2.
    factors : array_like, shape (D,)
        Dampings c in units of the energy sink's optimum ``c* = J W I_s / I_t`` (I_t the
        :func:`~stability.dissipation.model.equivalent_transverse_moment` of unequal ones).
    angles : array_like, shape (K,)
        Initial nutation angles, rad.
    method : str
        A method of scene ``sphere_damper``.
    step_angle, tail, samples, fit_top, flat_angle, seed
        As :func:`run_damped` takes them.
    end_tolerance : float
        How close to 90 degrees (rad) an end state counts as the major axis.
    whips : Whips, optional
        The whip antennas run beside the sphere (RK4, each angle a member); none by default.
    whip_angles : array_like, optional
        Their initial nutation angles, rad (default ``angles``).
    whip_step_angle : float
        Their ``h`` times the angular speed, rad.
    whip_tail : float
        Their run past the flat spin, in e-folds of their linear growth: their approach to the
        major axis is algebraic, not exponential (no linear decay there).
    options : RunOptions, optional
        How and where the members run (:class:`~stability.ensemble.options.RunOptions`): by
        default in one piece here; with a ``store``, chunk by chunk into it, resumable and on
        dask. The result is the same, bitwise.

    Returns
    -------
    xarray.Dataset
        Dims (damping, angle), (damping, angle, sample) and, with ``whips``, (angle) and
        (angle, whip_sample); see :data:`VARIABLES`.
    """
    I = np.asarray(body.moments, dtype=float)
    W = float(body.spin)
    angles = np.asarray(angles, dtype=float)
    factors = np.asarray(factors, dtype=float)
    I_t = equivalent_transverse_moment(I)
    c_sink = energy_sink_optimum(I[0], I_t, J, W)
    options = run_options(options)
    shared = dict(spin=W, samples=samples, fit_top=fit_top, flat_angle=flat_angle, seed=seed)
    sphere = run_damped(SPHERE, method, [np.array([*I, J, f * c_sink]) for f in factors],
                        angles, step_angle=step_angle, tail=tail,
                        options=options.within("sphere"), **shared)
    dims, samples_dims = (DAMPING, ANGLE), (DAMPING, ANGLE, SAMPLE)
    data = {name: (dims, sphere[name]) for name in VARIABLES if name in sphere
            and np.ndim(sphere[name]) == 2 and name not in ("sample_time",)}
    data.update({
        "theta": (samples_dims, sphere["theta"]),
        "energy_ratio": (samples_dims, sphere["energy_ratio"]),
        "sample_time": ((DAMPING, SAMPLE), sphere["sample_time"]),
        "c": ((DAMPING,), factors * c_sink),
        "step": ((DAMPING,), sphere["step"]),
        "t_end": ((DAMPING,), sphere["t_end"]),
        "growth_rate_energy_sink": (dims, energy_sink_rate(  # the spin of |H| about axis 1
            I[0], I_t, J, factors[:, None] * c_sink, W / np.cos(angles)[None, :])),
        "major_axis_end": (dims, _major(sphere["end_angle"], end_tolerance)),
    })
    data["status"] = (dims, sphere["status"].astype(np.int8))
    attrs = {"member_steps": sphere["member_steps"], "wall_time": sphere["wall_time"],
             "save_every": sphere["save_every"]}
    coords = {DAMPING: (DAMPING, factors, {"long_name": "damping c over the energy sink's "
                                                        "optimum c*",
                                           "units": cv.UNITS_DIMENSIONLESS}),
              ANGLE: (ANGLE, np.degrees(angles), {"long_name": "initial nutation angle",
                                                  "units": "degree"})}
    if whips is not None:
        values = whips.values(I, W)
        whip_angles = angles if whip_angles is None else np.asarray(whip_angles, dtype=float)
        run = run_damped(WHIPS, "rk4", [values], whip_angles, step_angle=whip_step_angle,
                         tail=whip_tail, options=options.within("whips"), **shared)
        for name in WHIP_VARIABLES:
            data[f"whip_{name}"] = ((WHIP_ANGLE,), run[name][0])
        data["whip_status"] = ((WHIP_ANGLE,), run["status"][0].astype(np.int8))
        data["whip_major_axis_end"] = ((WHIP_ANGLE,), _major(run["end_angle"][0],
                                                             end_tolerance))
        data["whip_theta"] = ((WHIP_ANGLE, WHIP_SAMPLE), run["theta"][0])
        data["whip_sample_time"] = ((WHIP_SAMPLE,), run["sample_time"][0])
        data["whip_energy_ratio"] = ((WHIP_ANGLE, WHIP_SAMPLE), run["energy_ratio"][0])
        attrs.update(whip_values=values, whip_step=float(run["step"][0]),
                     whip_t_end=float(run["t_end"][0]), whip_method="rk4",
                     whip_step_angle=whip_step_angle, whip_tail=whip_tail,
                     whip_mass=whips.mass, whip_arm=whips.arm,
                     whip_frequency_ratio=whips.frequency_ratio,
                     whip_damping_ratio=whips.damping_ratio)
        coords[WHIP_ANGLE] = (WHIP_ANGLE, np.degrees(whip_angles),
                              {"long_name": "initial nutation angle of the whip antennas' "
                                            "members", "units": "degree"})
        attrs["member_steps"] += run["member_steps"]
        attrs["wall_time"] += run["wall_time"]
    ds = xr.Dataset(
        {name: (d, v, dict(ATTRIBUTES[name.removeprefix("whip_")]))
         for name, (d, v) in data.items()}, coords=coords)
    for name in ds.data_vars:
        if name.startswith("whip_"):
            ds[name].attrs["long_name"] = "whip antennas: " + ds[name].attrs["long_name"]
    ds.attrs.update({
        "body": body.name, "body_sources": body.sources,
        **{k: getattr(body, k) for k in ("length", "diameter", "mass") if hasattr(body, k)},
        "spin": W, "moments": I, "transverse_moment": I_t,
        "J": J, "c_energy_sink_optimum": c_sink,
        "c_linear_optimum": best_damping(I, J, W), "method": method,
        "step_angle": step_angle, "tail": tail, "fit_top": fit_top,
        "flat_angle": math.degrees(flat_angle), "end_tolerance": math.degrees(end_tolerance),
        **attrs})
    return ds


def _major(end_angle, tolerance) -> np.ndarray:
    """1 where an end state's nutation angle is within ``tolerance`` (rad) of 90 degrees."""
    return (np.abs(np.asarray(end_angle) - 90.0) <= math.degrees(tolerance)).astype(np.int8)


_ONE, _RATE, _TIME, _ENERGY = (cv.UNITS_DIMENSIONLESS, cv.UNITS_RATE, cv.UNITS_TIME,
                               cv.UNITS_ENERGY)
#: Long names and units of every variable (the whips' carry the same, prefixed).
ATTRIBUTES = {
    "growth_rate_measured": {"long_name": "growth rate of the nutation angle fitted in the "
                             "linear regime", "units": _RATE},
    "growth_rate_linear": {"long_name": "growth rate of the nutation by the linear "
                           "eigenvalue", "units": _RATE},
    "growth_rate_error": {"long_name": "measured / linear growth rate - 1", "units": _ONE},
    "growth_rate_energy_sink": {"long_name": "growth rate of the nutation by the energy-sink "
                                "estimate", "units": _RATE},
    "decay_rate_measured": {"long_name": "rate of |cos theta| about the major axis, fitted",
                            "units": _RATE},
    "decay_rate_linear": {"long_name": "rate of the departure from the major axis by the "
                          "linear eigenvalue", "units": _RATE},
    "decay_rate_error": {"long_name": "measured / linear decay rate - 1", "units": _ONE},
    "flat_time": {"long_name": "time to the flat spin (nutation angle passing the flat-spin "
                  "angle)", "units": _TIME},
    "flat_time_linear": {"long_name": "time to the flat spin at the linear growth rate, "
                         "tan(theta) = tan(theta0) exp(rate t)", "units": _TIME},
    "angular_momentum_drift": {"long_name": "largest relative change of |H| over the kept "
                               "states", "units": _ONE},
    "energy_rise": {"long_name": "largest rise of the energy between kept states, relative "
                    "to the start", "units": _ONE},
    "end_angle": {"long_name": "nutation angle at the end", "units": "degree"},
    "energy_lost": {"long_name": "energy lost, start to end", "units": _ENERGY},
    "energy_lost_formula": {"long_name": "|H|^2 / 2 (1/A_min - 1/A_max)", "units": _ENERGY},
    "energy_lost_error": {"long_name": "energy lost / formula - 1", "units": _ONE},
    "end_energy_error": {"long_name": "end energy / (|H|^2 / (2 A_max)) - 1", "units": _ONE},
    "flat_energy_ratio": {"long_name": "energy of the flat spin |H|^2 / (2 A_max) over the "
                          "start's", "units": _ONE},
    "major_axis_end": {"long_name": "ends spinning about the major axis (1) or not (0)",
                       "units": _ONE, "flag_values": np.array([0, 1], dtype=np.int8),
                       "flag_meanings": "other_axis major_axis"},
    "theta": {"long_name": "nutation angle between the long axis and H", "units": "degree"},
    "energy_ratio": {"long_name": "energy over its start", "units": _ONE},
    "sample_time": {"long_name": "time of the kept states", "units": _TIME},
    "c": {"long_name": "viscous coefficient of the spherical damper", "units": "N m s"},
    "step": {"long_name": "integration step h", "units": _TIME},
    "t_end": {"long_name": "run time", "units": _TIME},
    "status": {"long_name": "member status", "units": _ONE,
               "flag_values": np.array(cv.STATUS_FLAG_VALUES, dtype=np.int8),
               "flag_meanings": cv.STATUS_MEANINGS},
}
#: The variables of the spherical damper's members (dims damping, angle).
VARIABLES = tuple(ATTRIBUTES)
#: The whip antennas' measured variables (dim angle), stored as ``whip_<name>``.
WHIP_VARIABLES = ("growth_rate_measured", "growth_rate_linear", "growth_rate_error",
                  "flat_time", "flat_time_linear", "angular_momentum_drift", "energy_rise",
                  "end_angle", "energy_lost", "energy_lost_formula", "energy_lost_error",
                  "end_energy_error")
