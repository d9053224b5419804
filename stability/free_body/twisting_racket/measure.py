"""The twisting racket: an ensemble of tossed bodies, Montgomery's angle and the twist per member.

:func:`tossed_members` draws the ensemble: a spin W about the middle axis nudged by epsilon W
across it (epsilon log-uniform, random direction), the body's own moments or shapes scattered about
them. :func:`measure_twisting` runs every member with its attitude over two periods of its body
motion (scene ``free_body_attitude``, each member its own step T / n so that the run lands on t =
T), and measures both angles of :mod:`stability.free_body.twisting_racket.geometric_phase` from the
run and from the exact motion, into one Dataset.
"""

from __future__ import annotations

import math
import time

import numpy as np
import xarray as xr

from ...util import conventions as cv
from ..attitude import propagate_attitudes
from ...core.quaternions import IDENTITY
from ...output.dataset import storable_attrs
from ...ensemble.starts import seed_sequence
from ..exact_attitude import exact_attitudes, free_motion
from .geometric_phase import exact_angles, run_angles, wrap
from ..schema import TWISTING_RACKET

#: Instants of the flip drawn for the first member (across its twist window).
SNAPSHOTS = 7


def tossed_members(moments, members, spin, epsilon_range, shape_scatter, seed=0):
    """Draw an ensemble of bodies tossed about their middle axis.

    Parameters
    ----------
    moments : array_like, shape (3,)
        The body's principal moments (kg m^2), any order.
    members : int
    spin : float
        W in rad/s.
    epsilon_range : (float, float)
        The nudge across the axis, relative to W, log-uniform between the two.
    shape_scatter : float
        Members ``members // 2`` onwards scatter I1 and I2 (canonical) by factors exp(u),
        u uniform in [-s, s], and keep the body's flatness I3 / (I1 + I2); 0 keeps the body.
    seed : int or None

    Returns
    -------
    moments : ndarray, shape (N, 3)
        Canonical (ascending) moments of each member, kg m^2.
    w0 : ndarray, shape (N, 3)
        Starts in rad/s, canonical frame: W along axis 2 plus the nudge in the (1, 3) plane.
    epsilon : ndarray, shape (N,)
    """
    rng = np.random.default_rng(seed_sequence(seed))
    base = np.sort(np.asarray(moments, dtype=float))
    flatness = base[2] / (base[0] + base[1])
    lo, hi = (math.log(e) for e in epsilon_range)
    epsilon = np.exp(rng.uniform(lo, hi, members))
    angle = rng.uniform(0.0, 2.0 * math.pi, members)
    u = rng.uniform(-shape_scatter, shape_scatter, (members, 2))
    u[: members // 2] = 0.0
    pair = base[:2] * np.exp(u)
    shapes = np.sort(np.column_stack([pair, flatness * pair.sum(axis=1)]), axis=1)
    w0 = np.column_stack([epsilon * spin * np.cos(angle), np.full(members, float(spin)),
                          epsilon * spin * np.sin(angle)])
    return shapes, w0, epsilon


def measure_twisting(moments, w0, *, method="lp8", steps_per_period=2000, save_every=4,
                     epsilon=None, options=None) -> xr.Dataset:
    """Montgomery's angle and the twist of each member, from a run and exactly.

    Parameters
    ----------
    moments : array_like, shape (N, 3)
        Canonical (ascending) moments, kg m^2, three distinct per member.
    w0 : array_like, shape (N, 3)
        Starts in rad/s, canonical frame, off the separatrix.
    method : str, default "lp8"
        An attitude method (``stability.free_body.attitude.attitude_methods()``).
    steps_per_period : int, default 2000
        Steps per period T of each member's body motion; the run covers 2 T.
    save_every : int, default 4
        Saved states every so many steps (the twist follows psi along them).
    epsilon : array_like, shape (N,), optional
        The nudges, stored with the members.
    options : RunOptions, optional
        How and where the members run (:class:`~stability.ensemble.options.RunOptions`): by
        default in one piece here; with a ``store``, chunk by chunk into it, resumable and on
        dask. The result is the same, bitwise.

    Returns
    -------
    xarray.Dataset
        Per member (``member``): the moments and starts, the period, both angles from the run
        and from the exact motion (Montgomery's also from the formula), their differences, the
        twist's defect from pi; and the first member's attitude at :data:`SNAPSHOTS` instants of
        its flip (``snapshot``).
    """
    moments = np.atleast_2d(np.asarray(moments, dtype=float))
    w0 = np.atleast_2d(np.asarray(w0, dtype=float))
    n = moments.shape[0]
    motions = [free_motion(I, w) for I, w in zip(moments, w0)]
    period = np.array([fm.period for fm in motions])
    t_start = time.perf_counter()
    runs = propagate_attitudes(method, moments, moments * w0, np.tile(IDENTITY, (n, 1)),
                               period / steps_per_period, 2 * steps_per_period,
                               save_every=save_every, label=f"tossed bodies ({method})",
                               options=options)
    run_wall = time.perf_counter() - t_start
    exact = exact_angles(motions, period)
    ran = run_angles(runs, period, exact["flip_time"])  # the same flip: nearest the exact one
    status = runs.run.status.astype(np.int8)

    flip, half = exact["flip_time"][0], exact["half_window"][0]
    snapshot_time = flip + half * np.linspace(-1.0, 1.0, SNAPSHOTS)
    snapshot_q = exact_attitudes(moments[:1], w0[:1], snapshot_time, IDENTITY)[0]

    data = {
        "moments": moments,
        "w0": w0,
        "epsilon": np.full(n, np.nan) if epsilon is None else np.asarray(epsilon),
        "status": status,
        "period": period,
        "montgomery_run": ran["montgomery"],
        "montgomery_exact": exact["montgomery"],
        "montgomery_formula": exact["montgomery_formula"],
        "dynamic_phase": exact["dynamic_phase"],
        "solid_angle": exact["solid_angle"],
        "montgomery_error": np.abs(wrap(ran["montgomery"] - exact["montgomery_formula"])),
        "flip_time_run": ran["flip_time"],
        "flip_time_exact": exact["flip_time"],
        "half_window_run": ran["half_window"],
        "half_window_exact": exact["half_window"],
        "twist_run": ran["twist"],
        "twist_exact": exact["twist"],
        "twist_error": np.abs(ran["twist"] - exact["twist"]),
        "twist_defect": math.pi - np.abs(exact["twist"]),
        "snapshot_time": snapshot_time,
        "snapshot_q": snapshot_q,
    }
    coords = {cv.MEMBER: np.arange(n), cv.AXIS: np.array(cv.AXES), cv.QUATERNION: np.arange(4)}
    attrs = {"method": runs.spec.name, "steps_per_period": steps_per_period,
             "save_every": save_every, "run_wall_time": run_wall,
             "space_frame": "L along space Z; body z along the smallest-moment axis (handle)"}
    return xr.Dataset(TWISTING_RACKET.entries(data), coords=TWISTING_RACKET.entries(coords),
                      attrs=storable_attrs(attrs))
