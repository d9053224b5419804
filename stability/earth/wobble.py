"""The Earth's free wobble, measured: an ensemble for the period, one member for the cones.

:func:`measure_free_wobble` runs an ensemble of rigid Earths whose rotation axis starts
``offset`` away from the figure axis in random directions (:func:`stability.run_ensemble`,
summaries only) and measures the period of the rotation axis's circling of the figure axis in
the body frame from the zero crossings of ``w1`` (:func:`stability.measured_frequency`); it sets
it beside Euler's period (:func:`stability.earth.model.euler_period`). One member is also run with
its attitude (:func:`stability.integrate`) over one period, so that the rotation axis can be
drawn in the body frame (the body cone about the figure axis) and in space (the space cone
about the fixed angular momentum).
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import xarray as xr

from ..util import conventions as cv
from ..core.quaternions import quaternion_to_matrix
from .model import ARCSEC, CHANDLER_PERIOD_DAYS, DAY, euler_period, oblate_euler_period
from ..free_body.attitude import attitude_methods
from ..free_body.spin_ensembles import completed, run_ensemble
from ..free_body.keep import Keep
from ..free_body.ensemble_plan import ensemble_memory
from ..analysis.estimates import measured_frequency
from ..free_body.integrate import integrate
from ..ensemble.chunks import default_chunk_members
from ..ensemble.options import run_options
from .schema import EARTH_WOBBLE

#: Dimension of the cone member's samples.
CONE_TIME = "cone_time"


def wobble_methods() -> tuple[str, ...]:
    """The methods the wobble runs with: those that carry the attitude (the pole's path is the
    attitude's)."""
    return attitude_methods()


def wobble_memory(members: int) -> int:
    """Bytes of the summaries of a wobble run (the free-body ensemble's bound, no series kept).

    Parameters
    ----------
    members : int
        Members of the run.

    Returns
    -------
    int
        Bytes.
    """
    return ensemble_memory(members, 0)


def _angle(u, v):
    """Angle between rows of u and v (rad), by atan2 of |u x v| and u . v (accurate when tiny)."""
    return np.arctan2(np.linalg.norm(np.cross(u, v), axis=-1), np.sum(u * v, axis=-1))


def measure_free_wobble(body, spin, offset, *, members=16, periods=3.0, steps_per_turn=20,
                        method="lp4", seed=0, cone_samples=1000, options=None) -> xr.Dataset:
    """Measured free-wobble period of a body spun about its largest axis, and its cones.

    Parameters
    ----------
    body : RigidBody
        Nearly symmetric, axis 3 the largest moment (the figure axis).
    spin : float
        W, rad s-1 (Earth: 2 pi / sidereal day).
    offset : float
        Angle between the rotation axis and the figure axis at the start, rad.
    members : int, default 16
        Ensemble members (random directions of the offset).
    periods : float, default 3.0
        Run length in Euler periods (at least 2, for the crossings).
    steps_per_turn : int, default 20
        Steps per turn of the body (h = 2 pi / (W steps_per_turn)).
    method : str, default "lp4"
        A free-body method that carries the attitude.
    seed : int, default 0
        Seed of the random directions of the offset (:func:`stability.run_ensemble`).
    cone_samples : int, default 1000
        Samples of the cone member over one period (about).
    options : RunOptions, optional
        How and where the members run (:class:`~stability.ensemble.options.RunOptions`): by
        default in one piece here; with a ``store``, chunk by chunk into it, resumable and on
        dask. The result is the same, bitwise.

    Returns
    -------
    xarray.Dataset
        Periods in days (86400 s); the cone member's rotation axis in the body frame and in
        space, and its angles from the figure axis and from L, in arcseconds.
    """
    moments = body.moments
    h = 2.0 * math.pi / (spin * steps_per_turn)
    t_euler = euler_period(moments, spin)
    steps = int(math.ceil(periods * t_euler / h))
    options = run_options(options)
    if options.store is not None and options.chunk_members is None:
        options = replace(options, chunk_members=default_chunk_members(members, members * steps))
    ens = run_ensemble(body, 3, spin, offset, members, h=h, t_end=steps * h, seed=seed,
                       method=method, keep=Keep(save_every=0), options=options)
    completed(ens)
    freq = measured_frequency(ens)
    period = 2.0 * math.pi / float(freq.oscillation_frequency)
    member_period = 2.0 * math.pi / freq.member_oscillation_frequency.values
    stderr = period * float(freq.oscillation_frequency_stderr) / float(freq.oscillation_frequency)

    # One member with its attitude over one period, for the cones.
    w0 = ens.w0.values[0]
    one = int(math.ceil(t_euler / h))
    save_every = max(1, one // cone_samples)
    one = (one // save_every + 1) * save_every
    cone = integrate(body, w0, one * h, h, method=method, save_every=save_every,
                     scene="free_body_attitude", progress=options.progress)
    completed(cone)
    w_body = cone.w.values
    R = quaternion_to_matrix(cone.q.values)
    w_space = np.einsum("tij,tj->ti", R, w_body)
    figure_space = R[:, :, 2]
    L = R[0] @ (moments * w0)
    L = np.broadcast_to(L / np.linalg.norm(L), w_space.shape)
    e3 = np.broadcast_to([0.0, 0.0, 1.0], w_body.shape)
    euler_days = t_euler / DAY
    oblate_days = oblate_euler_period(moments, spin) / DAY
    ds = xr.Dataset(
        EARTH_WOBBLE.entries({
            "wobble_period_measured": period / DAY,
            "wobble_period_stderr": stderr / DAY,
            "member_wobble_period": member_period / DAY,
            "wobble_period_euler": euler_days,
            "wobble_period_oblate": oblate_days,
            "relative_error": (period / DAY - euler_days) / euler_days,
            "w_body": w_body,
            "w_space": w_space,
            "body_cone_angle": _angle(w_body, e3) / ARCSEC,
            "space_cone_angle": _angle(w_space, L) / ARCSEC,
            "figure_axis_angle": _angle(figure_space, L) / ARCSEC,
        }),
        coords=EARTH_WOBBLE.entries({
            cv.MEMBER: ens[cv.MEMBER].values,
            CONE_TIME: cone.time.values / DAY,
            cv.AXIS: list(cv.AXES),
        }),
        attrs={
            "moments": moments, "spin": spin, "offset_arcsec": offset / ARCSEC,
            "method": method, "h": h, "members": members, "periods": periods,
            "member_steps": members * steps,
            "chandler_period_days": CHANDLER_PERIOD_DAYS,
            "chandler_note": (
                f"the observed Chandler wobble has a period of about {CHANDLER_PERIOD_DAYS:g} "
                f"days, longer than this rigid body's {euler_days:.1f} days because the Earth "
                "is not rigid: the elastic mantle, the oceans and the fluid core yield to the "
                "wobble (Smith & Dahlen 1981)"),
        },
    )
    return ds
