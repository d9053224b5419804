"""The Earth as a rigid body: published moments, its spin, the free (Euler) wobble, and the
Sun's and the Moon's orbits that torque it.

The principal moments follow from published ratios (each with its source):

- ``C / (M a^2) = 0.3307`` [Yoder, *Astrometric and geodetic properties of Earth and the Solar
  System*, AGU Reference Shelf 1 (1995), Table 2 (0.3307007)];
- the dynamical ellipticity ``H = (C - (A + B) / 2) / C = 3.27379448e-3`` [Capitaine, Wallace &
  Chapront, A&A 412, 567 (2003); the IAU 2006 value], defined with the mean equatorial moment;
- ``B - A = 7.260e-6 M a^2`` [Liu & Chao, Geophys. J. Int. 106, 699 (1991)];
- ``M = 5.9722e24 kg``, ``a = 6378136.6 m`` [IERS Conventions (2010), Table 1.1; IAU 2015
  nominal GM / G], and the sidereal day 86164.0905 s (IERS).

A rigid Earth spinning at ``W = 2 pi / sidereal day`` about its figure axis C, with its rotation
axis a little off that axis, wobbles: in the body frame the rotation axis circles the figure axis
at ``Omega = W sqrt((C - A)(C - B) / (A B))`` (Euler's free precession; for A = B the familiar ``A
/ (C - A) = (1 - H) / H`` sidereal days, 304.5, or 303.6 days), while in space it circles the fixed
angular momentum once a day on a cone ~H times narrower. The observed Chandler wobble has a period
of about 433 days: the Earth is not rigid (elastic mantle, oceans and fluid core lengthen it; Smith
& Dahlen, Geophys. J. R. Astr. Soc. 64, 223 (1981)).

**The Earth under the Sun and the Moon** (scenes ``lunisolar_earth`` and ``precessing_axis``):
the Earth (these moments made oblate: A = B their mean, :func:`oblate_earth_moments`) spins at the
IERS nominal rate W with its figure axis at the obliquity eps0 of J2000 from the ecliptic pole.
The Sun (its apparent orbit) and the Moon move on Kepler ellipses with the mean elements of
J2000 [Simon et al., A&A 282, 663 (1994); Meeus, *Astronomical Algorithms*, 2nd ed., ch. 22 and
47]: the Moon inclined 5.145 degrees, its node regressing in 18.6 years and its perigee advancing
in 8.85 (the elements' rates of date; the ~50"/yr they include is 7e-4 of the node's rate). Their
strengths are ``G M_j / a_j^3 = n_j^2 M_j / (M_j + M_other)`` with the sidereal periods and the
published mass ratios (:func:`orbit_elements`). The averaged (gyroscopic) precession rate is

    p_j = (3/2) H cos(eps0) / W  G M_j / (a_j^3 (1 - e_j^2)^(3/2))  f_j,
    f_sun = 1,  f_moon = 1 - (3/2) sin^2(i_moon)

(:func:`precession_formula`; derived in :mod:`stability.earth.methods`; e.g. Lambeck,
*The Earth's Variable Rotation* (1980), ch. 2), set beside the published values: the lunisolar
precession 50.385"/yr of IAU 2006 [Capitaine, Wallace & Chapront, A&A 412, 567 (2003)], and the
IAU 1980 nutation's 18.6-year terms 17.1996" and 9.2025" [Seidelmann, Celest. Mech. 27, 79
(1982)].
"""

from __future__ import annotations

import math

import numpy as np

from ..free_body.model import oscillation_frequency
from ..core.body import RigidBody
from .methods import N_ORBIT, O_E, O_I, O_K, O_M0, O_N, O_NODE0, O_NODEDOT, O_W0, O_WDOT

#: Published numbers (module docstring), SI units.
MASS = 5.9722e24
EQUATORIAL_RADIUS = 6378136.6
POLAR_MOMENT_FACTOR = 0.3307
DYNAMICAL_ELLIPTICITY = 3.27379448e-3
EQUATORIAL_ASYMMETRY = 7.260e-6
SIDEREAL_DAY = 86164.0905
#: The observed Chandler period, days (Malkin & Miller, Earth Planets Space 62, 943 (2010)).
CHANDLER_PERIOD_DAYS = 433.0
#: Seconds per day (the unit "d").
DAY = 86400.0
#: Radians per arcsecond.
ARCSEC = math.pi / (180.0 * 3600.0)


def earth_moments(mass=MASS, radius=EQUATORIAL_RADIUS, polar_factor=POLAR_MOMENT_FACTOR,
                  ellipticity=DYNAMICAL_ELLIPTICITY, asymmetry=EQUATORIAL_ASYMMETRY):
    """Principal moments ``(A, B, C)`` (kg m2) from ``C / (M a^2)``, the dynamical ellipticity
    ``H = (C - (A + B) / 2) / C`` and ``(B - A) / (M a^2)``.

    Parameters
    ----------
    mass : float, default :data:`MASS`
        M, kg.
    radius : float, default :data:`EQUATORIAL_RADIUS`
        Equatorial radius a, m.
    polar_factor : float, default :data:`POLAR_MOMENT_FACTOR`
        ``C / (M a^2)``.
    ellipticity : float, default :data:`DYNAMICAL_ELLIPTICITY`
        Dynamical ellipticity H.
    asymmetry : float, default :data:`EQUATORIAL_ASYMMETRY`
        ``(B - A) / (M a^2)``.

    Returns
    -------
    ndarray, shape (3,)
        ``(A, B, C)``, kg m2.
    """
    ma2 = mass * radius * radius
    C = polar_factor * ma2
    mean = C * (1.0 - ellipticity)
    half = 0.5 * asymmetry * ma2
    return np.array([mean - half, mean + half, C])


def earth(**kwargs) -> RigidBody:
    """The rigid Earth (:func:`earth_moments`; its keyword arguments) as a RigidBody."""
    return RigidBody(*earth_moments(**kwargs), name="Earth")


def euler_period(moments, spin) -> float:
    """Period (s) of the free wobble about the figure axis: ``2 pi / (W sqrt((C - A)(C - B)
    / (A B)))`` [Landau & Lifshitz, *Mechanics*, section 36], the small-offset limit: 2 pi
    over :func:`stability.free_body.model.oscillation_frequency` about axis 3.

    Parameters
    ----------
    moments : array_like, shape (3,)
        Principal moments ``(A, B, C)``, kg m2; C, the figure axis, the largest or the
        smallest.
    spin : float
        W, rad s-1.

    Returns
    -------
    float
        Period, s.
    """
    return 2.0 * math.pi / float(oscillation_frequency(moments, 3, spin))


def oblate_euler_period(moments, spin) -> float:
    """``A / (C - A)`` turns (s), A the mean equatorial moment: ``(1 - H) / H`` sidereal days.

    Parameters
    ----------
    moments : array_like, shape (3,)
        Principal moments ``(A, B, C)``, kg m2, C the polar moment.
    spin : float
        W, rad s-1 (its sign is ignored).

    Returns
    -------
    float
        Period, s.
    """
    A, B, C = (float(x) for x in moments)
    mean = 0.5 * (A + B)
    return mean / (C - mean) * 2.0 * math.pi / abs(spin)


# --- The Earth under the Sun and the Moon -------------------------------------------------------

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


#: The models and the torques measured.
MODELS = ("full", "averaged")
TORQUES = ("sun", "moon", "both")


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
