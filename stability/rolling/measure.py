"""Ensembles run on scene ``rolling_body`` and measured: :func:`measure_incline` maps the
regime over (theta, mu_s) with scattered friction and shape, :func:`measure_launches` runs a
billiard or bowling ensemble; both return labelled Datasets, against the formulas of
:mod:`stability.rolling.model`.
"""

from __future__ import annotations

import time

import numpy as np
import xarray as xr

from ..engine import propagate_groups
from ..ensemble.chunks import run_plan
from ..ensemble.plan import Plan
from .methods import (
    HEAT, P_K, P_MU_K, P_MU_S, P_TRACK, SWITCHES, T_ROLL, V, W, X, X_ROLL, track_row,
)
from .model import (
    G, SHAPES, launch_formulas, rolling_acceleration, rolls, slipping_acceleration,
    slipping_spin_rate, start_states,
)
from .scene import ROLLING_BODY
from .schema import ROLLING

def measure_incline(shapes, angles, mu_s, *, members=4, mu_ratio=0.8, mu_scatter=0.05,
                    shape_scatter=0.02, duration=1.0, seed=0, options=None) -> xr.Dataset:
    """Release bodies at rest on inclines over a grid of angles (rad) and mu_s, each member
    with its own mu_s, mu_k = mu_ratio mu_s and k scattered (relative, uniform) about the
    cell's; measure the regime, the acceleration and the spin rate from the runs.

    Parameters
    ----------
    shapes : sequence of str
        Names of shapes, keys of :data:`SHAPES`.
    angles : array_like, shape (A,)
        Incline angles in rad.
    mu_s : array_like, shape (S,)
        Nominal static friction coefficients (dimensionless).
    members : int, default 4
        Members per (shape, angle, mu_s) cell.
    mu_ratio : float, default 0.8
        ``mu_k / mu_s`` of every member.
    mu_scatter : float, default 0.05
        Relative half-width of the uniform scatter of mu_s about the cell's.
    shape_scatter : float, default 0.02
        Relative half-width of the uniform scatter of k about the shape's.
    duration : float, default 1.0
        Length of each run in s (one exact step).
    seed : int, default 0
        Seed of the random scatter.
    options : RunOptions, optional
        How and where the members run (:class:`~stability.ensemble.options.RunOptions`): by
        default in one piece here; with a ``store``, chunk by chunk into it, resumable and on
        dask. The result is the same, bitwise.

    Returns
    -------
    xarray.Dataset
        Dimensions ``shape``, ``angle`` (coordinate in degrees), ``mu_s`` and ``replica``:
        per member the regime, acceleration and spin rate from the runs and by the formulas
        and its own mu_s and k; per cell the fraction that slipped, the nominal regime and
        whether the scatter straddles the boundary; per (shape, angle) the boundary mu_s.

    Raises
    ------
    KeyError
        If a name in ``shapes`` is not in :data:`SHAPES`.
    KeyboardInterrupt
        If the run was interrupted.
    """
    scene = ROLLING_BODY
    spec = scene.method("exact")
    rng = np.random.default_rng(seed)
    names = list(shapes)
    k_nominal = np.array([SHAPES[name] for name in names])
    angles, mu_s = np.asarray(angles, dtype=float), np.asarray(mu_s, dtype=float)
    shape = (len(names), angles.size, mu_s.size, members)
    k = k_nominal[:, None, None, None] * (1.0 + shape_scatter * rng.uniform(-1, 1, shape))
    mus = mu_s[None, None, :, None] * (1.0 + mu_scatter * rng.uniform(-1, 1, shape))
    theta = np.broadcast_to(angles[None, :, None, None], shape)
    muk = mu_ratio * mus
    radius = 0.05
    rows = np.tile(track_row(1.0, radius, 1.0, 1.0, angles=(0.0,)), (k.size, 1))
    rows[:, P_K], rows[:, P_MU_S], rows[:, P_MU_K] = k.ravel(), mus.ravel(), muk.ravel()
    rows[:, P_TRACK + 1], rows[:, P_TRACK + 2] = np.sin(theta).ravel(), np.cos(theta).ravel()
    x0 = start_states(0.0, 0.0, rows)
    t0 = time.perf_counter()
    run = run_plan(Plan(scene, spec.name, x0, rows,
                        np.ones(rows.shape[0], int), duration, 1,
                        label="inclines"),
                   options)
    wall = time.perf_counter() - t0
    xf = run.x_final
    slipped = (xf[:, HEAT] > 0.0).reshape(shape)
    own = rolls(theta, mus, k)
    expected_a = np.where(own, rolling_acceleration(theta, k), slipping_acceleration(theta, muk))
    expected_alpha = np.where(own, rolling_acceleration(theta, k) / radius,
                              slipping_spin_rate(theta, muk, k, radius))
    accel = (2.0 * xf[:, X] / duration**2).reshape(shape)
    alpha = (xf[:, W] / duration).reshape(shape)
    nominal = rolls(angles[None, :, None], mu_s[None, None, :], k_nominal[:, None, None])
    fraction = slipped.mean(axis=-1)
    # the cell's scatter box (mu_s and k within their relative spreads) spans the boundary
    tan = np.tan(np.abs(angles))[None, :, None]
    mu_cell, k_cell = mu_s[None, None, :], k_nominal[:, None, None]
    lowest = mu_cell * (1 - mu_scatter) * (1 + 1 / (k_cell * (1 + shape_scatter)))
    highest = mu_cell * (1 + mu_scatter) * (1 + 1 / (k_cell * (1 - shape_scatter)))
    straddles = (lowest < tan) & (tan < highest)
    wrong = (np.round(fraction) == nominal) & ~straddles  # majority against the nominal regime
    data = {
        "slipped": slipped.astype(np.int8),
        "rolls_formula": own.astype(np.int8),
        "acceleration": accel,
        "acceleration_formula": expected_a,
        "spin_rate": alpha,
        "spin_rate_formula": expected_alpha,
        "member_mu_s": mus,
        "member_k": k,
        "slip_fraction": fraction,
        "rolls_nominal": nominal.astype(np.int8),
        "scatter_straddles": straddles.astype(np.int8),
        "wrong_side": wrong.astype(np.int8),
        "boundary_mu_s": np.tan(angles)[None, :] / (1.0 + 1.0 / k_nominal[:, None]),
        "incline_status": run.status.reshape(shape).astype(np.int8),
    }
    ds = xr.Dataset(ROLLING.entries(data), coords=ROLLING.entries({
        "shape": names, "shape_factor": k_nominal, "angle": np.degrees(angles), "mu_s": mu_s,
        "replica": np.arange(members)}))
    ds.attrs.update({"mu_ratio": mu_ratio, "mu_scatter": mu_scatter,
                     "shape_scatter": shape_scatter, "duration": duration, "seed": seed,
                     "radius": radius, "g": G, "method": spec.name, "wall_time": wall})
    return ds


def measure_launches(*, radius, mass, k, mu_k, speeds, spin_ratios, members, mu_scatter=0.1,
                     samples=200, seed=0, paths=5, options=None) -> xr.Dataset:
    """Launch ``members`` balls along a level floor, speed uniform in ``speeds`` (m s-1), spin
    ``w0 = ratio v0 / R`` with the ratio uniform in ``spin_ratios`` (negative: backspin), mu_k
    scattered (relative, uniform); the time, place and speed of the start of pure rolling and
    the heat, from the runs, against :func:`launch_formulas`.

    Parameters
    ----------
    radius : float
        Radius R in m.
    mass : float
        Mass M in kg.
    k : float
        Shape factor ``I / (M R^2)`` (dimensionless).
    mu_k : float
        Nominal kinetic friction coefficient (dimensionless); mu_s is set equal to each
        member's mu_k.
    speeds : tuple of float
        ``(low, high)`` bounds of the launch speed in m s-1.
    spin_ratios : tuple of float
        ``(low, high)`` bounds of ``R w0 / v0`` (1: launched rolling; negative: backspin).
    members : int
        Number of balls.
    mu_scatter : float, default 0.1
        Relative half-width of the uniform scatter of mu_k.
    samples : int, default 200
        Steps over the run, which lasts 1.25 times the longest ``t_roll`` of the formulas.
    seed : int, default 0
        Seed of the random draws.
    paths : int, default 5
        Members (spread over the spin ratios) whose every sample is kept.
    options : RunOptions, optional
        How and where the members run (:class:`~stability.ensemble.options.RunOptions`): by
        default in one piece here; with a ``store``, chunk by chunk into it, resumable and on
        dask. The result is the same, bitwise.

    Returns
    -------
    xarray.Dataset
        Per ``member``: the launch, mu_k, the time, place and speed of the start of pure
        rolling, the heat and the energy lost, from the runs and by the formulas; per
        (``path``, ``time``): the speed ``v`` and ``R w`` of the kept members.

    Raises
    ------
    KeyboardInterrupt
        If the run was interrupted.
    """
    scene = ROLLING_BODY
    spec = scene.method("exact")
    rng = np.random.default_rng(seed)
    v0 = rng.uniform(*speeds, members)
    ratio = rng.uniform(*spin_ratios, members)
    w0 = ratio * v0 / radius
    muk = mu_k * (1.0 + mu_scatter * rng.uniform(-1, 1, members))
    rows = np.tile(track_row(k, radius, 1.0, 1.0, mass=mass), (members, 1))
    rows[:, P_MU_S] = rows[:, P_MU_K] = muk
    formulas = launch_formulas(v0, w0, k, radius, muk, mass)
    duration = 1.25 * float(formulas["t_roll"].max())
    x0 = start_states(v0, w0, rows)
    h = duration / samples
    t0 = time.perf_counter()
    run = run_plan(Plan(scene, spec.name, x0, rows, np.ones(members, int),
                        h, samples, label="launches"),
                   options)
    wall = time.perf_counter() - t0
    xf = run.x_final
    e0 = 0.5 * mass * (v0**2 + k * radius**2 * w0**2)
    e1 = 0.5 * mass * (xf[:, V] ** 2 + k * radius**2 * xf[:, W] ** 2)
    # a few members again, every sample kept, for the figure (bitwise the same run)
    keep = np.argsort(ratio)[np.linspace(0, members - 1, min(paths, members)).astype(int)]
    kept = propagate_groups(scene, spec, x0[keep], rows[keep], np.ones(keep.size, int), h,
                            samples, save_every=1, progress=False)
    path = np.concatenate([x0[keep, None, :], kept.saved], axis=1)
    data = {
        "v0": v0, "w0": w0, "spin_ratio": ratio, "mu_k": muk,
        "t_roll": xf[:, T_ROLL],
        "t_roll_formula": formulas["t_roll"],
        "x_roll": xf[:, X_ROLL],
        "x_roll_formula": formulas["x_roll"],
        "v_final": xf[:, V],
        "v_final_formula": formulas["v_final"],
        "heat": xf[:, HEAT],
        "energy_lost": e0 - e1,
        "energy_lost_formula": formulas["energy_lost"],
        "switches": xf[:, SWITCHES].astype(np.int64),
        "launch_status": run.status.astype(np.int8),
        "path_v": path[:, :, V],
        "path_rw": radius * path[:, :, W],
        "path_member": keep,
    }
    ds = xr.Dataset(ROLLING.entries(data), coords=ROLLING.entries({
        "member": np.arange(members), "time": np.arange(samples + 1) * h}))
    ds.attrs.update({"radius": radius, "mass": mass, "shape_factor": k, "mu_k": mu_k,
                     "mu_scatter": mu_scatter, "seed": seed, "g": G, "method": spec.name,
                     "duration": duration, "wall_time": wall})
    return ds

