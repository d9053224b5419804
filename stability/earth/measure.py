"""The Earth's free wobble and the precession of the equinoxes, measured.

**The free wobble**: an ensemble for the period, one member for the cones.
:func:`measure_free_wobble` runs an ensemble of rigid Earths whose rotation axis
starts ``offset`` away from the figure axis in random directions (:func:`stability.run_ensemble`,
summaries only) and measures the period of the rotation axis's circling of the figure axis in
the body frame from the zero crossings of ``w1`` (:func:`stability.measured_frequency`); it sets
it beside Euler's period (:func:`stability.earth.model.euler_period`). One member is also run with
its attitude (:func:`stability.integrate`) over one period, so that the rotation axis can be
drawn in the body frame (the body cone about the figure axis) and in space (the space cone
about the fixed angular momentum).

**The precession of the equinoxes** (:func:`measure_equinoxes`; the model and the formula in
:mod:`stability.earth.model`). The figure axis k in the ecliptic frame of the epoch gives the
longitude of the equinox ``phi = atan2(k1, -k2)`` and the obliquity ``eps = angle(k, Z)``
(:func:`equinox_angles`); a least-squares fit of a line plus the nutation terms
(:func:`fit_precession`) gives the precession rate ``-phi'`` and the amplitudes of the 18.6-year
nutation in longitude (``Delta psi = -Delta phi``) and obliquity. They are set beside the
averaged formula (:func:`~stability.earth.model.precession_formula`) and the published values.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import xarray as xr

from ..util import conventions as cv
from ..core.quaternions import quaternion_to_matrix
from .methods import O_K
from .model import (ARCSEC, CHANDLER_PERIOD_DAYS, DAY, DYNAMICAL_ELLIPTICITY, MODELS,
                    NOMINAL_SPIN, OBLIQUITY, PUBLISHED_NUTATION_LONGITUDE,
                    PUBLISHED_NUTATION_OBLIQUITY, PUBLISHED_PRECESSION, TORQUES, YEAR,
                    averaged_parameters, averaged_start, earth_parameters, euler_period,
                    full_start, member_orbits, nutation_frequencies, oblate_euler_period,
                    precession_formula)
from ..free_body.attitude import attitude_methods
from ..free_body.spin_ensembles import completed, run_ensemble
from ..free_body.keep import Keep
from ..free_body.ensemble_plan import ensemble_memory
from ..analysis.estimates import measured_frequency
from ..free_body.integrate import integrate
from ..ensemble.chunks import default_chunk_members, run_plan
from ..ensemble.options import run_options
from ..ensemble.plan import Plan
from .scene import LUNISOLAR_EARTH, PRECESSING_AXIS, figure_axes
from .schema import EARTH_WOBBLE, EQUINOXES

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


# --- The precession of the equinoxes ------------------------------------------------------------

def equinox_angles(k):
    """Longitude of the equinox ``phi = atan2(k1, -k2)`` (unwrapped along the last time axis)
    and obliquity (rad) of figure axes ``k`` (..., 3).

    Parameters
    ----------
    k : ndarray, shape (..., T, 3)
        Unit figure axes in the ecliptic frame of the epoch, time along the second-last axis.

    Returns
    -------
    phi, eps : ndarray, shape (..., T)
        Longitude of the equinox and obliquity, rad.
    """
    phi = np.unwrap(np.arctan2(k[..., 0], -k[..., 1]), axis=-1)
    eps = np.arctan2(np.hypot(k[..., 0], k[..., 1]), k[..., 2])
    return phi, eps


def fit_precession(t, phi, eps, frequencies):
    """Least-squares fit of ``a + b t + sum_f (c_f cos f t + s_f sin f t)`` to phi and eps.

    Parameters
    ----------
    t : ndarray, shape (T,)
        Times, s.
    phi, eps : ndarray, shape (T,)
        Longitude of the equinox and obliquity, rad.
    frequencies : sequence of float
        Angular frequencies of the periodic terms fitted, rad s-1; the first is the node's.

    Returns
    -------
    dict
        ``precession_rate`` (-b of phi, rad s-1), ``obliquity_rate`` (b of eps),
        ``nutation_longitude`` and ``nutation_obliquity`` (the amplitudes sqrt(c^2 + s^2) of the
        first frequency, rad), and ``residual_longitude``, ``residual_obliquity`` (rms, rad).
    """
    t = np.asarray(t, dtype=float)
    scale = t[-1] - t[0]
    columns = [np.ones_like(t), (t - t[0]) / scale]
    for f in frequencies:
        columns += [np.cos(f * t), np.sin(f * t)]
    design = np.column_stack(columns)
    out = {}
    for name, y, sign in (("longitude", phi, -1.0), ("obliquity", eps, 1.0)):
        coef, *_ = np.linalg.lstsq(design, y, rcond=None)
        rate = sign * coef[1] / scale
        out["precession_rate" if name == "longitude" else "obliquity_rate"] = rate
        out[f"nutation_{name}"] = math.hypot(coef[2], coef[3])
        out[f"residual_{name}"] = float(np.sqrt(np.mean((design @ coef - y) ** 2)))
    return out


def arcsec_per_year(rate):
    """A rate in rad s-1 as arcsec per Julian year.

    Parameters
    ----------
    rate : float or array_like
        Rate, rad s-1.

    Returns
    -------
    ndarray
        The rate in arcsec per Julian year, same shape.
    """
    return np.asarray(rate) * YEAR / ARCSEC


#: Dimension and coordinate names of the Dataset.
MODEL, TORQUE, MEMBER = "model", "torque", "member"
SERIES_TIME, CYCLE_TIME = "full_time", "cycle_time"


def _switched(orbits, torque):
    """The (sun, moon) elements of one member for ``torque`` ("sun", "moon" or "both")."""
    sun, moon = orbits
    return (sun if torque != "moon" else _off(sun), moon if torque != "sun" else _off(moon))


def _off(elements):
    out = elements.copy()
    out[O_K] = 0.0
    return out


def measure_equinoxes(*, years=100.0, members=4, steps_per_day=4, method="lp4",
                      averaged_step_days=5.0, cycle_years=30000.0, seed=0,
                      options=None):
    """Precession and nutation of the Earth's axis, full and orbit-averaged, with the shares.

    Parameters
    ----------
    years : float, default 100.0
        Run length, Julian years (at least a century for the 18.6-year terms to separate).
    members : int, default 4
        Members per torque: member 0 starts at J2000, the others at random orbital phases.
    steps_per_day : int, default 4
        Steps of the full model per day; the error is estimated from a second run of the
        "both" members at half as many (Richardson, the method's order).
    method : str, default "lp4"
        A method of scene ``lunisolar_earth``.
    averaged_step_days : float, default 5.0
        Step of the averaged model, days.
    cycle_years : float, default 30000.0
        Length of the averaged model's long run (member 0, both bodies) for the full turn of
        the axis about the ecliptic pole, Julian years; 0 to skip it.
    seed : int, default 0
        Seed of the members' orbital phases (:func:`member_orbits`) and spin phases
        (:func:`full_start`); member 0 starts at the J2000 phases whatever the seed.
    options : RunOptions, optional
        How and where the members run (:class:`~stability.ensemble.options.RunOptions`): by
        default in one piece here; with a ``store``, chunk by chunk into it, resumable and on
        dask. The result is the same, bitwise.

    Returns
    -------
    xarray.Dataset
        Dims (model, torque, member), the series of member 0 (time) and the long run
        (cycle_time); see :data:`stability.earth.schema.EQUINOXES`.
    """
    import time as _time

    import xarray as xr

    options = run_options(options)
    orbits = member_orbits(members, seed)
    full, averaged = LUNISOLAR_EARTH, PRECESSING_AXIS
    spec, avg_spec = full.method(method), averaged.method("rk4")
    h = DAY / steps_per_day
    n_steps = int(round(years * 365.25 * steps_per_day))
    # Full model: the three torques at h, and "both" at 2h for the error estimate.
    groups = [(torque, h) for torque in TORQUES] + [("both", 2.0 * h)]
    # Members of a group differ in their orbital phases: one group per (torque, member).
    x0 = full_start(members, seed=seed)
    rows, p_rows, h_rows, n_rows = [], [], [], []
    for torque, step in groups:
        for k in range(members):
            rows.append(x0[k])
            p_rows.append(spec.params(earth_parameters(*_switched(orbits[k], torque)), step))
            h_rows.append(step)
            n_rows.append(n_steps if step == h else n_steps // 2)
    t0 = _time.perf_counter()
    run = run_plan(
        Plan(full, spec.name, np.array(rows), np.array(p_rows), np.ones(len(rows)),
             np.array(h_rows), np.array(n_rows), save_every=steps_per_day,
             label=f"Earth under Sun and Moon ({method})"),
        options.within("full"))
    wall = _time.perf_counter() - t0
    samples = np.concatenate([np.array(rows)[:, None, :], run.saved], axis=1)
    t_full = np.arange(samples.shape[1]) * DAY
    phi, eps = equinox_angles(figure_axes(samples))

    # Averaged model: the three torques, every member, same length; then the long run.
    ha = averaged_step_days * DAY
    na = int(round(years * 365.25 / averaged_step_days))
    xa = averaged_start(members * len(TORQUES))
    pa = [avg_spec.params(averaged_parameters(*_switched(orbits[k], torque)), ha)
          for torque in TORQUES for k in range(members)]
    t1 = _time.perf_counter()
    run_a = run_plan(
        Plan(averaged, avg_spec.name, xa, np.array(pa), np.ones(len(pa)), ha, na,
             save_every=1, label="orbit-averaged Earth (rk4)"),
        options.within("averaged"))
    wall_averaged = _time.perf_counter() - t1
    samples_a = np.concatenate([xa[:, None, :], run_a.saved], axis=1)
    t_avg = np.arange(samples_a.shape[1]) * ha
    phi_a, eps_a = equinox_angles(samples_a[..., :3])

    shape = (len(MODELS), len(TORQUES), members)
    fits = {key: np.full(shape, np.nan) for key in
            ("precession_rate", "nutation_longitude", "nutation_obliquity", "obliquity_rate",
             "residual_longitude")}
    for i, torque in enumerate(TORQUES):
        for k in range(members):
            r = i * members + k
            for m, (t, ph, ep, model) in enumerate(((t_full, phi[r], eps[r], "full"),
                                                    (t_avg, phi_a[r], eps_a[r], "averaged"))):
                keep = np.isfinite(ph)
                fit = fit_precession(t[keep], ph[keep], ep[keep], nutation_frequencies(model))
                for key in fits:
                    fits[key][m, i, k] = fit[key]
    coarse = []
    for r in range(3 * members, 4 * members):  # sampled every 2 days
        keep = np.isfinite(phi[r])
        coarse.append(fit_precession(2.0 * t_full[keep], phi[r][keep], eps[r][keep],
                                     nutation_frequencies("full"))["precession_rate"])
    coarse = np.array(coarse)
    fine = fits["precession_rate"][0, TORQUES.index("both")]
    step_error = np.abs(coarse - fine) / (2.0 ** spec.order - 1.0)

    cycle = None
    if cycle_years > 0:
        nc = int(round(cycle_years * 365.25 / averaged_step_days))
        every = max(1, int(round(365.25 / averaged_step_days)))
        run_c = run_plan(
            Plan(averaged, avg_spec.name, xa[:1],
                 np.array(pa[2 * members:2 * members + 1]), [1], ha, nc,
                 save_every=every, label="orbit-averaged Earth, full cycle (rk4)"),
            options.within("cycle"))
        cycle = np.concatenate([xa[:1, None, :], run_c.saved], axis=1)[0]
        t_cycle = np.arange(cycle.shape[0]) * every * ha

    formula = np.array([precession_formula("sun"), precession_formula("moon"), 0.0])
    formula[2] = formula[0] + formula[1]
    arcsec = 1.0 / ARCSEC
    data = {
        "precession_rate": arcsec_per_year(fits["precession_rate"]),
        "nutation_longitude": fits["nutation_longitude"] * arcsec,
        "nutation_obliquity": fits["nutation_obliquity"] * arcsec,
        "obliquity_rate": arcsec_per_year(fits["obliquity_rate"]),
        "fit_residual": fits["residual_longitude"] * arcsec,
        "precession_rate_formula": arcsec_per_year(formula),
        "step_error": arcsec_per_year(step_error),
        "longitude": (phi[[i * members for i in range(3)]] - phi[0, 0]) * arcsec,
        "obliquity": eps[[i * members for i in range(3)]] * arcsec,
        "longitude_averaged": (phi_a[[i * members for i in range(3)]] - phi_a[0, 0]) * arcsec,
        "obliquity_averaged": eps_a[[i * members for i in range(3)]] * arcsec,
    }
    coords = {
        MODEL: list(MODELS),
        TORQUE: list(TORQUES),
        MEMBER: np.arange(members),
        SERIES_TIME: t_full / YEAR,
        "averaged_time": t_avg / YEAR,
    }
    if cycle is not None:
        cphi, ceps = equinox_angles(cycle[None, :, :3])
        data["cycle_longitude"] = np.degrees(cphi[0] - cphi[0, 0])
        data["cycle_obliquity"] = np.degrees(ceps[0])
        coords[CYCLE_TIME] = t_cycle / YEAR
    ds = xr.Dataset(EQUINOXES.entries(data), coords=EQUINOXES.entries(coords))
    if cycle is not None:
        turn = 2.0 * np.pi / (fits["precession_rate"][1, 2, 0]) / YEAR
        ds.attrs["precession_period_years"] = float(turn)
        ds.attrs["cycle_wall_time"] = float(run_c.wall_time)
    ds.attrs.update({
        "method": spec.name, "steps_per_day": steps_per_day, "years": years,
        "averaged_step_days": averaged_step_days, "members": members,
        "obliquity": OBLIQUITY / ARCSEC, "spin": NOMINAL_SPIN,
        "dynamical_ellipticity": DYNAMICAL_ELLIPTICITY,
        "published_precession": PUBLISHED_PRECESSION,
        "published_nutation_longitude": PUBLISHED_NUTATION_LONGITUDE,
        "published_nutation_obliquity": PUBLISHED_NUTATION_OBLIQUITY,
        "wall_time": wall, "averaged_wall_time": wall_averaged,
        "member_steps": int(np.sum(n_rows)), "averaged_member_steps": int(na * len(pa)),
    })
    return ds

