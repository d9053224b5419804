"""The strikes run and measured: :func:`measure_strikes`, ensembles of strikes on scene
``struck_body`` (the contact a half-sine impulse, :mod:`stability.struck.methods`) against the
formulas of :mod:`stability.struck.model`.
"""

from __future__ import annotations

import time

import numpy as np
import xarray as xr

from ..analysis.members import zero_crossings
from ..ensemble.chunks import run_plan
from ..ensemble.plan import Plan
from ..util.checks import positive_float
from .methods import J_ACROSS, J_ALONG, PHI, VX, VY, W, X, strike_params
from .model import (
    HOLD, PIVOT, STRIKE, StruckBody, centre_of_percussion, check_pivot, hand_velocity,
    reaction_impulse,
)
from .scene import STRUCK_BODY
from .schema import BAT

def measure_strikes(body: StruckBody, pivots, strikes, impulse=12.0, contact_time=7e-4,
                    steps_per_contact=64, sting=0.1, method="rk4", options=None) -> xr.Dataset:
    """Strike ``body`` at each point of ``strikes`` for hands at each of ``pivots`` (m from the
    end held), held and free; the state at the end of the contact against the formulas.

    Per (hold, pivot) the centre of percussion is measured where the runs' reaction impulse
    (held) or hand velocity (free) crosses zero, and, held, the sweet zone where the reaction
    is at most ``sting`` J. Returns a labelled Dataset.

    Parameters
    ----------
    body : StruckBody
        The body struck (:func:`baseball_bat`, :func:`tennis_racket`).
    pivots : float or array_like, shape (P,)
        Positions of the hands in m from the end held, each checked by :func:`check_pivot`.
    strikes : array_like, shape (S,)
        Strike points in m from the end held, on the body; at least two (sorted before use).
    impulse : float, default 12.0
        Impulse J of each strike in N s.
    contact_time : float, default 7e-4
        Duration of the half-sine contact force in s.
    steps_per_contact : int, default 64
        Steps over the contact; the run ends with it.
    sting : float, default 0.1
        Edge of the sweet zone: the reaction impulse across the hands as a fraction of J.
    method : str, default "rk4"
        Name of a method that runs scene ``struck_body``.
    options : RunOptions, optional
        How and where the members run (:class:`~stability.ensemble.options.RunOptions`): by
        default in one piece here; with a ``store``, chunk by chunk into it, resumable and on
        dask. The result is the same, bitwise.

    Returns
    -------
    xarray.Dataset
        Dimensions ``hold`` (held, free), ``pivot``, ``strike`` and ``edge`` (near, far): the
        measured velocities and reaction impulses, the formulas', the centres of percussion
        and sweet zones measured and by the formulas, the member status and the body's
        outline; lengths in m from the end held.

    Raises
    ------
    ValueError
        If a pivot or strike point is off the body, a pivot is at the centre of mass, fewer
        than two strike points are given, ``impulse`` or ``contact_time`` is not > 0, or
        ``method`` does not run the scene.
    KeyboardInterrupt
        If the run was interrupted.
    """
    scene = STRUCK_BODY
    spec = scene.method(method)
    impulse = positive_float("impulse", impulse, "N s")
    contact_time = positive_float("contact_time", contact_time, "s")
    pivots = np.array([check_pivot(body, p) for p in np.atleast_1d(pivots)])
    strikes = np.sort(np.asarray(strikes, dtype=float).reshape(-1))
    if strikes.size < 2:
        raise ValueError("give at least two strike points")
    off = (strikes < 0.0) | (strikes > body.length)
    if off.any():
        raise ValueError(f"strike point {strikes[off][0]:g} m is off the {body.name} (0 to "
                         f"{body.length:g} m from the end held)")
    holds = np.array([1.0, 0.0])
    grid = np.stack(np.meshgrid(holds, pivots, strikes, indexing="ij"), axis=-1).reshape(-1, 3)
    rows = [strike_params((body.mass, body.centre - p, body.inertia, s - p, impulse,
                           contact_time, held)) for held, p, s in grid]
    x0 = np.zeros((grid.shape[0], scene.width))
    x0[:, X] = body.centre - grid[:, 1]
    h = contact_time / steps_per_contact
    t0 = time.perf_counter()
    run = run_plan(Plan(scene, spec.name, x0, np.array(rows),
                        np.ones(grid.shape[0], int), h, steps_per_contact,
                        label=f"strikes ({method})"),
                   options)
    wall = time.perf_counter() - t0
    shape = (holds.size, pivots.size, strikes.size)
    xf = run.x_final
    phi = xf[:, PHI]
    n = np.stack([-np.sin(phi), np.cos(phi)], axis=-1)  # across the body, at the end
    v_cm = xf[:, [VX, VY]]
    d = (body.centre - grid[:, 1])
    v_hand = v_cm - (d * xf[:, W])[:, None] * n
    measured = {
        "angular_velocity": xf[:, W],
        "cm_velocity_across": np.sum(v_cm * n, axis=-1),
        "hand_velocity_across": np.sum(v_hand * n, axis=-1),
        "reaction_impulse_across": xf[:, J_ACROSS],
        "reaction_impulse_along": xf[:, J_ALONG],
    }
    measured = {key: value.reshape(shape) for key, value in measured.items()}
    p2, s2 = pivots[:, None], strikes[None, :]
    formula_reaction = reaction_impulse(body, p2, s2, impulse)
    formula_hand = hand_velocity(body, p2, s2, impulse)
    # first sign change beyond the hands of each pivot's curve (strikes before them masked)
    beyond = np.where(strikes[None, :] > pivots[:, None], 1.0, np.nan)
    cop = np.array([zero_crossings(strikes, measured[key][k] * beyond)[1] for k, key in
                    enumerate(("reaction_impulse_across", "hand_velocity_across"))])
    ratio = measured["reaction_impulse_across"][0] / impulse * beyond
    zone = np.column_stack([zero_crossings(strikes, ratio - level)[1]
                            for level in (-sting, sting)])
    q = np.array([centre_of_percussion(body, p) for p in pivots])
    zone_formula = pivots[:, None] + (q - pivots)[:, None] * np.array([1.0 - sting, 1.0 + sting])
    zone_formula = np.where(zone_formula <= body.length, zone_formula, np.nan)

    data = {
        **measured,
        "reaction_impulse_formula": formula_reaction,
        "hand_velocity_formula": formula_hand,
        "percussion_centre_measured": cop,
        "percussion_centre_formula": q,
        "sweet_zone_measured": zone,
        "sweet_zone_formula": zone_formula,
        "status": run.status.reshape(shape).astype(np.int8),
        "outline": body.outline,
    }
    ds = xr.Dataset(BAT.entries(data), coords=BAT.entries({
        HOLD: ["held", "free"], PIVOT: pivots, STRIKE: strikes, "edge": ["near", "far"]}))
    ds.attrs.update({
        **body.describe(), "impulse": impulse, "contact_time": contact_time, "sting": sting,
        "method": spec.name, "step": h, "steps_per_contact": steps_per_contact,
        "wall_time": wall, "member_steps": int(grid.shape[0] * steps_per_contact),
    })
    return ds

