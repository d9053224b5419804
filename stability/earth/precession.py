"""The precession of the equinoxes: a rigid, oblate Earth under the Sun's and the Moon's torques.

The Earth (the moments of :mod:`stability.earth.model`, made oblate: A = B their mean) spins at the
IERS nominal rate W with its figure axis at the obliquity eps0 of J2000 from the ecliptic pole.
The Sun (its apparent orbit) and the Moon move on Kepler ellipses with the mean elements of
J2000 [Simon et al., A&A 282, 663 (1994); Meeus, *Astronomical Algorithms*, 2nd ed., ch. 22 and
47]: the Moon inclined 5.145 degrees, its node regressing in 18.6 years and its perigee advancing
in 8.85 (the elements' rates of date; the ~50"/yr they include is 7e-4 of the node's rate). Their
strengths are ``G M_j / a_j^3 = n_j^2 M_j / (M_j + M_other)`` with the sidereal periods and the
published mass ratios.

What is measured: the figure axis k in the ecliptic frame of the epoch gives the longitude of the
equinox ``phi = atan2(k1, -k2)`` and the obliquity ``eps = angle(k, Z)``; a least-squares fit of a
line plus the nutation terms (:func:`fit_precession`) gives the precession rate ``-phi'`` and the
amplitudes of the 18.6-year nutation in longitude (``Delta psi = -Delta phi``) and obliquity.
They are set beside the averaged (gyroscopic) formula

    p_j = (3/2) H cos(eps0) / W  G M_j / (a_j^3 (1 - e_j^2)^(3/2))  f_j,
    f_sun = 1,  f_moon = 1 - (3/2) sin^2(i_moon)

(:func:`precession_formula`; derived in :mod:`stability.earth.methods`; e.g. Lambeck,
*The Earth's Variable Rotation* (1980), ch. 2) and the published values: the lunisolar precession
50.385"/yr of IAU 2006 [Capitaine, Wallace & Chapront, A&A 412, 567 (2003)], and the IAU 1980
nutation's 18.6-year terms 17.1996" and 9.2025" [Seidelmann, Celest. Mech. 27, 79 (1982)].
"""

from __future__ import annotations

import math

import numpy as np

from .model import ARCSEC, DAY, DYNAMICAL_ELLIPTICITY, EQUATORIAL_RADIUS, MASS, POLAR_MOMENT_FACTOR
from .methods import N_ORBIT, O_E, O_I, O_K, O_M0, O_N, O_NODE0, O_NODEDOT, O_W0, O_WDOT
from ..ensemble.chunks import run_plan
from ..ensemble.options import run_options
from ..ensemble.plan import Plan
from .scene import LUNISOLAR_EARTH, PRECESSING_AXIS, figure_axes
from .schema import EQUINOXES

#: The Julian year (s) and century, the units of the rates.
YEAR = 365.25 * DAY
#: IERS nominal mean angular velocity of the Earth (rad s-1) [IERS Conventions (2010), 1.2].
NOMINAL_SPIN = 7.292115e-5
#: Obliquity of the ecliptic at J2000, IAU 2006: 84381.406" [Capitaine et al. (2003)].
OBLIQUITY = 84381.406 * ARCSEC
#: Sidereal year and month, days; the node's regression and the perigee's advance, days per turn.
SIDEREAL_YEAR_DAYS = 365.256363
SIDEREAL_MONTH_DAYS = 27.321661
ANOMALISTIC_MONTH_DAYS = 27.554550
NODE_PERIOD_DAYS = 36525.0 * 360.0 / 1934.1362891
PERIGEE_PERIOD_DAYS = 36525.0 * 360.0 / 4069.0137287
#: Eccentricities, the Moon's inclination to the ecliptic (rad) and the mass ratios.
SUN_ECCENTRICITY = 0.016708634
MOON_ECCENTRICITY = 0.0549
MOON_INCLINATION = math.radians(5.145)
EARTH_MOON_MASS_RATIO = 81.300568
SUN_EARTH_MOON_MASS_RATIO = 328900.56
#: Mean elements at J2000 (degrees): the Sun's mean longitude and perigee, the Moon's mean
#: longitude, node and perigee (Meeus, eq. 22.2 and 47.1-47.7).
SUN_MEAN_LONGITUDE = 280.46646
SUN_PERIGEE = 282.93735
MOON_MEAN_LONGITUDE = 218.3164477
MOON_NODE = 125.0445479
MOON_PERIGEE = 83.3532465
#: Published values ("/yr and "): IAU 2006 lunisolar precession, IAU 1980 18.6-year nutation.
PUBLISHED_PRECESSION = 5038.481507 / 100.0
PUBLISHED_NUTATION_LONGITUDE = 17.1996
PUBLISHED_NUTATION_OBLIQUITY = 9.2025
#: The perturbers, in the order of the kernels' parameters.
BODIES = ("sun", "moon")


def _rate(period_days):
    return 2.0 * math.pi / (period_days * DAY)


def orbit_elements(body, *, mean_anomaly=None, node=None, strength=1.0) -> np.ndarray:
    """The kernels' elements of ``body`` ("sun" or "moon") at J2000, times ``strength``.

    ``mean_anomaly`` and ``node`` (rad) replace the epoch's (for members started at other
    phases); ``strength = 0`` switches the body off.

    Parameters
    ----------
    body : {"sun", "moon"}
        The perturber (the Sun's apparent orbit about the Earth, or the Moon's).
    mean_anomaly : float, optional
        Mean anomaly at the epoch, rad; default the J2000 value.
    node : float, optional
        Longitude of the Moon's ascending node on the ecliptic at the epoch, rad; default the
        J2000 value. Ignored for the Sun.
    strength : float, default 1.0
        Factor on ``G M / a^3``.

    Returns
    -------
    ndarray, shape (9,)
        ``(G M / a^3, e, n, M0, w0, w', i, node0, node')`` (indices ``O_K`` ... ``O_NODEDOT`` of
        :mod:`stability.earth.methods`): ``G M / a^3`` in s-2, the eccentricity, the
        mean motion of the mean anomaly, the mean anomaly and argument of perigee at the epoch
        and the perigee's rate, the inclination, the node at the epoch and its rate; angles in
        rad, rates in rad s-1.
    """
    p = np.zeros(N_ORBIT)
    if body == "sun":
        n = _rate(SIDEREAL_YEAR_DAYS)
        p[O_K] = n * n / (1.0 + 1.0 / SUN_EARTH_MOON_MASS_RATIO)
        p[O_E] = SUN_ECCENTRICITY
        p[O_N] = n
        p[O_M0] = math.radians(SUN_MEAN_LONGITUDE - SUN_PERIGEE)
        p[O_W0] = math.radians(SUN_PERIGEE)  # from the equinox: the node of an orbit with i = 0
    elif body == "moon":
        n = _rate(SIDEREAL_MONTH_DAYS)
        p[O_K] = n * n / (1.0 + EARTH_MOON_MASS_RATIO)
        p[O_E] = MOON_ECCENTRICITY
        p[O_N] = _rate(ANOMALISTIC_MONTH_DAYS)
        p[O_M0] = math.radians(MOON_MEAN_LONGITUDE - MOON_PERIGEE)
        p[O_W0] = math.radians(MOON_PERIGEE - MOON_NODE)
        p[O_WDOT] = _rate(PERIGEE_PERIOD_DAYS) + _rate(NODE_PERIOD_DAYS)
        p[O_I] = MOON_INCLINATION
        p[O_NODE0] = math.radians(MOON_NODE)
        p[O_NODEDOT] = -_rate(NODE_PERIOD_DAYS)
    else:
        raise ValueError(f"body must be 'sun' or 'moon', got {body!r}")
    if mean_anomaly is not None:
        p[O_M0] = float(mean_anomaly)
    if node is not None and body == "moon":
        p[O_NODE0] = float(node)
    p[O_K] *= strength
    return p


def oblate_earth_moments(mass=MASS, radius=EQUATORIAL_RADIUS, polar_factor=POLAR_MOMENT_FACTOR,
                         ellipticity=DYNAMICAL_ELLIPTICITY):
    """``(A, C)`` (kg m2) of the oblate Earth: C = polar_factor M a^2, A = C (1 - H).

    Parameters
    ----------
    mass : float, default :data:`~stability.earth.model.MASS`
        M, kg.
    radius : float, default :data:`~stability.earth.model.EQUATORIAL_RADIUS`
        Equatorial radius a, m.
    polar_factor : float, default :data:`~stability.earth.model.POLAR_MOMENT_FACTOR`
        ``C / (M a^2)``.
    ellipticity : float, default :data:`~stability.earth.model.DYNAMICAL_ELLIPTICITY`
        Dynamical ellipticity ``H = (C - A) / C``.

    Returns
    -------
    A, C : float
        Equatorial and polar moments, kg m2.
    """
    C = polar_factor * mass * radius * radius
    return C * (1.0 - ellipticity), C


def earth_parameters(sun, moon, moments=None) -> np.ndarray:
    """Parameters of scene ``lunisolar_earth``: ``(A, C, sun's elements, moon's elements)``.

    Parameters
    ----------
    sun, moon : array_like, shape (9,)
        Elements of the Sun and the Moon (:func:`orbit_elements`).
    moments : tuple of 2 floats, optional
        ``(A, C)``, kg m2; default :func:`oblate_earth_moments`.

    Returns
    -------
    ndarray, shape (20,)
    """
    A, C = oblate_earth_moments() if moments is None else moments
    return np.concatenate([[A, C], sun, moon])


def averaged_parameters(sun, moon, *, ellipticity=DYNAMICAL_ELLIPTICITY,
                        spin=NOMINAL_SPIN) -> np.ndarray:
    """Parameters of scene ``precessing_axis``: ``(H / W, sun's elements, moon's elements)``.

    Parameters
    ----------
    sun, moon : array_like, shape (9,)
        Elements of the Sun and the Moon (:func:`orbit_elements`).
    ellipticity : float, default :data:`~stability.earth.model.DYNAMICAL_ELLIPTICITY`
        Dynamical ellipticity H.
    spin : float, default :data:`NOMINAL_SPIN`
        The Earth's spin W, rad s-1.

    Returns
    -------
    ndarray, shape (19,)
        ``H / W`` in s, then the elements.
    """
    return np.concatenate([[ellipticity / spin], sun, moon])


def precession_formula(body, *, ellipticity=DYNAMICAL_ELLIPTICITY, spin=NOMINAL_SPIN,
                       obliquity=OBLIQUITY) -> float:
    """The averaged precession rate (rad s-1) caused by ``body`` (module docstring).

    Parameters
    ----------
    body : {"sun", "moon"}
        The perturber; its J2000 elements (:func:`orbit_elements`) are used.
    ellipticity : float, default :data:`~stability.earth.model.DYNAMICAL_ELLIPTICITY`
        Dynamical ellipticity H.
    spin : float, default :data:`NOMINAL_SPIN`
        The Earth's spin W, rad s-1.
    obliquity : float, default :data:`OBLIQUITY`
        eps0, rad.

    Returns
    -------
    float
        ``p_j``, rad s-1.
    """
    p = orbit_elements(body)
    factor = 1.0 - 1.5 * math.sin(p[O_I]) ** 2
    return (1.5 * ellipticity * math.cos(obliquity) / spin * p[O_K]
            / (1.0 - p[O_E] ** 2) ** 1.5 * factor)


def full_start(members, *, obliquity=OBLIQUITY, spin=NOMINAL_SPIN, moments=None, seed=0):
    """Starts ``(m, q, t = 0)`` of the full model: the figure axis at ``obliquity`` toward the
    ecliptic longitude -90 degrees (the equinox on +X), spinning at ``spin`` about it, the spin
    phase random (member 0: zero).

    Parameters
    ----------
    members : int
        Number of starts.
    obliquity : float, default :data:`OBLIQUITY`
        Angle of the figure axis from the ecliptic pole, rad.
    spin : float, default :data:`NOMINAL_SPIN`
        Spin W about the figure axis, rad s-1.
    moments : tuple of 2 floats, optional
        ``(A, C)``, kg m2 (only C is used); default :func:`oblate_earth_moments`.
    seed : int, default 0
        Seed of the spin phases.

    Returns
    -------
    ndarray, shape (members, 8)
        ``(m1, m2, m3, q0, q1, q2, q3, t)``: the body-frame angular momentum ``(0, 0, C W)``
        (kg m2 s-1), the attitude quaternion and t = 0 (s).
    """
    rng = np.random.default_rng(seed)
    _, C = oblate_earth_moments() if moments is None else moments
    phase = rng.random(members) * 2.0 * np.pi
    phase[0] = 0.0
    c, s = math.cos(0.5 * obliquity), math.sin(0.5 * obliquity)
    # q = Rx(obliquity) Rz(phase): figure axis (0, -sin eps, cos eps).
    q = np.column_stack([c * np.cos(phase / 2), s * np.cos(phase / 2), s * np.sin(phase / 2),
                         c * np.sin(phase / 2)])
    m = np.column_stack([np.zeros(members), np.zeros(members), np.full(members, C * spin)])
    return np.concatenate([m, q, np.zeros((members, 1))], axis=1)


def averaged_start(members, *, obliquity=OBLIQUITY):
    """Starts ``(k, t = 0)`` of the averaged model, the figure axis as in :func:`full_start`.

    Parameters
    ----------
    members : int
        Number of starts (all the same).
    obliquity : float, default :data:`OBLIQUITY`
        Angle of the figure axis from the ecliptic pole, rad.

    Returns
    -------
    ndarray, shape (members, 4)
        ``(k1, k2, k3, t)``: the unit figure axis in the ecliptic frame and t = 0 (s).
    """
    k = np.array([0.0, -math.sin(obliquity), math.cos(obliquity), 0.0])
    return np.tile(k, (members, 1))


def member_orbits(members, seed=0):
    """The Sun's and Moon's elements of each member: member 0 at J2000, the others with random
    mean anomalies and Moon's node (the phases of every periodic term), as (members, 2, 9).

    Parameters
    ----------
    members : int
        Number of members.
    seed : int, default 0
        Seed of the random phases.

    Returns
    -------
    ndarray, shape (members, 2, 9)
        The Sun's (index 0) and the Moon's (index 1) elements (:func:`orbit_elements`).
    """
    rng = np.random.default_rng(seed)
    out = np.empty((members, 2, N_ORBIT))
    for k in range(members):
        if k == 0:
            out[k] = orbit_elements("sun"), orbit_elements("moon")
        else:
            a_sun, a_moon, node = rng.random(3) * 2.0 * np.pi
            out[k] = (orbit_elements("sun", mean_anomaly=a_sun),
                      orbit_elements("moon", mean_anomaly=a_moon, node=node))
    return out


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
MODELS = ("full", "averaged")
TORQUES = ("sun", "moon", "both")
SERIES_TIME, CYCLE_TIME = "full_time", "cycle_time"


def _switched(orbits, torque):
    """The (sun, moon) elements of one member for ``torque`` ("sun", "moon" or "both")."""
    sun, moon = orbits
    return (sun if torque != "moon" else _off(sun), moon if torque != "sun" else _off(moon))


def _off(elements):
    out = elements.copy()
    out[O_K] = 0.0
    return out


def nutation_frequencies(model):
    """Angular frequencies (rad s-1) fitted beside the line: the node's 18.6 years and its
    half; for the full model also the semi-annual, fortnightly, annual and monthly terms (the
    averaged model has none of these).

    Parameters
    ----------
    model : {"full", "averaged"}
        The model whose fit they are for.

    Returns
    -------
    list of float
        Angular frequencies, rad s-1; the node's first.
    """
    node = _rate(NODE_PERIOD_DAYS)
    if model == "averaged":
        return [node, 2.0 * node]
    year, month = _rate(SIDEREAL_YEAR_DAYS), _rate(SIDEREAL_MONTH_DAYS)
    return [node, 2.0 * node, 2.0 * year, 2.0 * month, year, _rate(ANOMALISTIC_MONTH_DAYS)]


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

