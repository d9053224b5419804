"""The Earth as a rigid body: published moments, its spin, and the free (Euler) wobble.

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
"""

from __future__ import annotations

import math

import numpy as np

from ..free_body.model import oscillation_frequency
from ..core.body import RigidBody

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
