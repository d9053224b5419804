"""Heavy tops: the body on its pivot, its linear theory, and its ensembles.

:class:`HeavyTop` describes a top by what one can measure: its mass M, the distance l from the
pivot to the centre of mass (on body axis 3), its principal moments about the centre of mass
and the gravity g. The kernels (scene ``heavy_top``) take its moments about the pivot,
``I1 = I1cm + M l^2``, ``I2 = I2cm + M l^2``, ``I3 = I3cm`` (parallel-axis theorem), and
``c = (0, 0, M g l)``.

Linear theory of the symmetric top (``I1 = I2 = A`` about the pivot, ``I3 = C``) spun at w3 about
its upright symmetry axis (the *sleeping* top): the complex tilt ``xi = theta e^{i phi}`` obeys ``A
xi'' - i C w3 xi' - M g l xi = 0`` [Goldstein, Poole & Safko, *Classical Mechanics*, 3rd ed.,
section 5.7; Klein & Sommerfeld, *Theorie des Kreisels*], with roots ``s = (i C w3 +- sqrt(4 A M g
l - C^2 w3^2)) / (2 A)``. The top is stable when ``C^2 w3^2 > 4 A M g l``, that is above the
critical spin ``w_c = 2 sqrt(A M g l) / C``; below it a small tilt grows at ``lambda = sqrt(4 A M g
l - C^2 w3^2) / (2 A)`` (:func:`sleeping_growth_rate`); above it the tilt nutates at ``|Im s|``
(:func:`sleeping_frequencies`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..core.body import RigidBody
from ..util.checks import real_number
from ..analysis.members import tracked_members

#: Standard gravity (m s-2), the default g.
STANDARD_GRAVITY = 9.80665


@dataclass(frozen=True)
class HeavyTop:
    """A top on a fixed pivot in uniform gravity.

    Parameters
    ----------
    mass : float
        M in kg, > 0.
    length : float
        l in m, >= 0: the distance from the pivot to the centre of mass, which lies on body
        axis 3 (l = 0: a body pivoted at its centre of mass, torque-free).
    central_moments : sequence of 3 floats
        Principal moments about the centre of mass, kg m2, for body axes 1, 2, 3; they obey
        the triangle inequality of real bodies.
    gravity : float, default :data:`STANDARD_GRAVITY`
        g in m s-2, >= 0.
    name : str
        Label for Datasets and figures.

    Raises
    ------
    ValueError
        One line saying which number is unphysical and why.
    """

    mass: float
    length: float
    central_moments: tuple
    gravity: float = STANDARD_GRAVITY
    name: str = field(default="top", compare=False)

    def __post_init__(self):
        mass = real_number("mass", self.mass, "kg")
        if not (math.isfinite(mass) and mass > 0.0):
            raise ValueError(f"mass must be a finite number > 0 kg, got {mass}")
        length = real_number("length", self.length, "m")
        if not (math.isfinite(length) and length >= 0.0):
            raise ValueError(
                f"length (pivot to centre of mass) must be a finite number >= 0 m, got {length}; "
                "a top whose centre of mass is below the pivot is the same top turned over: "
                "give l >= 0 and start it upside down"
            )
        gravity = real_number("gravity", self.gravity, "m s-2")
        if not (math.isfinite(gravity) and gravity >= 0.0):
            raise ValueError(f"gravity must be a finite number >= 0 m s-2, got {gravity}")
        moments = tuple(self.central_moments) if np.ndim(self.central_moments) == 1 else ()
        if len(moments) != 3:
            raise ValueError(
                f"central_moments must be 3 principal moments (kg m2) about the centre of mass, "
                f"got {self.central_moments!r}"
            )
        body = RigidBody(*moments)  # positive, finite, triangle inequality: its own messages
        object.__setattr__(self, "mass", mass)
        object.__setattr__(self, "length", length)
        object.__setattr__(self, "gravity", gravity)
        object.__setattr__(self, "central_moments", tuple(float(x) for x in body.moments))

    @classmethod
    def from_pivot_moments(cls, pivot_moments, mass, length, gravity=STANDARD_GRAVITY,
                           name="top"):
        """The top whose principal moments about the pivot are ``pivot_moments`` (kg m2).

        The moments about the centre of mass follow by the parallel-axis theorem; a moment
        about a transverse axis smaller than M l^2 is impossible and is refused.
        """
        moments = [real_number(f"I{i + 1} (about the pivot)", x, "kg m2")
                   for i, x in enumerate(pivot_moments)]
        mass = real_number("mass", mass, "kg")
        length = real_number("length", length, "m")
        shift = mass * length * length
        for i in (0, 1):
            if moments[i] < shift:
                raise ValueError(
                    f"I{i + 1} about the pivot ({moments[i]:g} kg m2) is smaller than M l^2 = "
                    f"{shift:g} kg m2, the least a body of mass {mass:g} kg with its centre of "
                    f"mass {length:g} m from the pivot can have (parallel-axis theorem)"
                )
        central = (moments[0] - shift, moments[1] - shift, moments[2])
        return cls(mass, length, central, gravity, name)

    @classmethod
    def disk(cls, mass, radius, length, gravity=STANDARD_GRAVITY, name="disk top"):
        """A thin uniform disk on a massless axle, its centre ``length`` from the pivot."""
        r2 = real_number("radius", radius, "m") ** 2
        m = real_number("mass", mass, "kg")
        return cls(mass, length, (m * r2 / 4.0, m * r2 / 4.0, m * r2 / 2.0), gravity, name)

    @property
    def pivot_moments(self) -> np.ndarray:
        """Principal moments about the pivot ``(I1, I2, I3)``, kg m2."""
        shift = self.mass * self.length**2
        I1, I2, I3 = self.central_moments
        return np.array([I1 + shift, I2 + shift, I3])

    @property
    def mgl(self) -> float:
        """M g l, N m: the largest gravity torque."""
        return self.mass * self.gravity * self.length

    @property
    def symmetric(self) -> bool:
        """Equal transverse moments (I1 = I2): a Lagrange top."""
        return self.central_moments[0] == self.central_moments[1]

    @property
    def parameters(self) -> np.ndarray:
        """What the kernels take: ``(I1, I2, I3, 0, 0, M g l)`` about the pivot."""
        return np.concatenate([self.pivot_moments, [0.0, 0.0, self.mgl]])

    def describe(self) -> dict:
        """Numbers and arrays for Dataset attributes (netCDF takes no lists)."""
        return {"top_name": self.name, "mass": self.mass, "length": self.length,
                "gravity": self.gravity, "central_moments": np.array(self.central_moments),
                "pivot_moments": self.pivot_moments, "mgl": self.mgl}


def _symmetric(top: HeavyTop, what: str):
    if not top.symmetric:
        raise ValueError(f"{what} is the symmetric top's (I1 = I2); this top has central "
                         f"moments {top.central_moments}")
    A, _, C = top.pivot_moments
    return A, C, top.mgl


def critical_spin(top: HeavyTop) -> float:
    """``w_c = 2 sqrt(A M g l) / C`` (rad s-1): a sleeping top is stable above it.

    Parameters
    ----------
    top : HeavyTop
        A symmetric top (``top.symmetric``); otherwise ValueError.

    Returns
    -------
    float
        w_c, rad s-1.
    """
    A, C, mgl = _symmetric(top, "the critical spin")
    return 2.0 * math.sqrt(A * mgl) / C


def sleeping_growth_rate(top: HeavyTop, spin):
    """Growth rate of a sleeping top's tilt, ``sqrt(4 A M g l - C^2 w3^2) / (2 A)`` (s-1);
    0 at and above the critical spin. ``spin`` (rad s-1) may be an array.

    Parameters
    ----------
    top : HeavyTop
        A symmetric top (``top.symmetric``); otherwise ValueError.
    spin : float or array_like
        Spin w3 about the symmetry axis, rad s-1.

    Returns
    -------
    ndarray
        Growth rate, s-1, the shape of ``spin``.
    """
    A, C, mgl = _symmetric(top, "the sleeping-top growth rate")
    w = np.asarray(spin, dtype=float)
    return np.sqrt(np.maximum(4.0 * A * mgl - (C * w) ** 2, 0.0)) / (2.0 * A)


def sleeping_frequencies(top: HeavyTop, spin):
    """Angular frequencies ``(C w3 -+ sqrt(C^2 w3^2 - 4 A M g l)) / (2 A)`` (rad s-1) of a
    stable sleeping top's small tilt (slow and fast precession of the tilt); NaN below the
    critical spin.

    Parameters
    ----------
    top : HeavyTop
        A symmetric top (``top.symmetric``); otherwise ValueError.
    spin : float or array_like
        Spin w3 about the symmetry axis, rad s-1.

    Returns
    -------
    slow, fast : ndarray
        The two frequencies, rad s-1, the shape of ``spin``.
    """
    A, C, mgl = _symmetric(top, "the sleeping-top frequencies")
    w = np.asarray(spin, dtype=float)
    with np.errstate(invalid="ignore"):
        root = np.sqrt((C * w) ** 2 - 4.0 * A * mgl)
    return (C * w - root) / (2.0 * A), (C * w + root) / (2.0 * A)


def gyroscopic_precession_rate(top: HeavyTop, spin):
    """Mean precession rate of a fast top, ``M g l / (C w3)`` (rad s-1): the leading term of
    the slow root of steady precession, ``A W^2 cos(theta) - C w3 W + M g l = 0``, for
    ``C^2 w3^2 >> 4 A M g l cos(theta)`` (Goldstein, section 5.7).

    Parameters
    ----------
    top : HeavyTop
        A symmetric top (``top.symmetric``); otherwise ValueError.
    spin : float or array_like
        Spin w3 about the symmetry axis, rad s-1.

    Returns
    -------
    ndarray
        Precession rate, rad s-1, the shape of ``spin``.
    """
    A, C, mgl = _symmetric(top, "the gyroscopic precession rate")
    return mgl / (C * np.asarray(spin, dtype=float))


def gyroscopic_nutation_frequency(top: HeavyTop, spin):
    """Nutation frequency of a fast top, ``C w3 / A`` (rad s-1).

    Parameters
    ----------
    top : HeavyTop
        A symmetric top (``top.symmetric``); otherwise ValueError.
    spin : float or array_like
        Spin w3 about the symmetry axis, rad s-1.

    Returns
    -------
    ndarray
        Nutation frequency, rad s-1, the shape of ``spin``.
    """
    A, C, _ = _symmetric(top, "the gyroscopic nutation frequency")
    return C * np.asarray(spin, dtype=float) / A


def gyroscopic_nutation_amplitude(top: HeavyTop, spin, tilt, release=0.0):
    """Peak-to-peak nutation of a fast top released at ``tilt`` (rad), rad.

    To leading order the figure axis runs round a small circle whose centre precesses at
    ``W = M g l / (C w3)`` with the nutation frequency ``C w3 / A``; released with
    ``phi' = release W`` it starts off the centre's velocity by ``(1 - release) W sin(tilt)``,
    so the circle's diameter is ``2 |1 - release| A M g l sin(tilt) / (C w3)^2`` (for a release
    at rest, the cusped case, it follows from ``p_phi`` and the energy: Goldstein, section 5.7).

    Parameters
    ----------
    top : HeavyTop
        A symmetric top (``top.symmetric``); otherwise ValueError.
    spin : float or array_like
        Spin w3 about the symmetry axis, rad s-1.
    tilt : float or array_like
        Angle of the symmetry axis from the vertical at release, rad.
    release : float or array_like, default 0.0
        Precession rate phi' at release in units of ``W = M g l / (C w3)``: 0 at rest (the
        cusped path), 1 the steady precession (no nutation).

    Returns
    -------
    ndarray
        Peak-to-peak nutation, rad, the broadcast shape of ``spin``, ``tilt`` and ``release``.
    """
    A, C, mgl = _symmetric(top, "the gyroscopic nutation amplitude")
    w = np.asarray(spin, dtype=float)
    return (2.0 * np.abs(1.0 - np.asarray(release, dtype=float)) * A * mgl
            * np.sin(np.asarray(tilt, dtype=float)) / (C * w) ** 2)


def tilted_starts(spin, tilt, members, *, top: HeavyTop, seed=0, tilt_rate=0.0,
                  precession_rate=0.0):
    """Starts of tops tilted by ``tilt`` (rad) from the vertical, spinning at ``spin`` about
    their axis 3, at random azimuths of the vertical in the body frame.

    The body frame turns with the spin, so only the tilt and its rates are physical; the random
    azimuth decorrelates the members. With z-x-z Euler angles the body angular velocity is
    ``w = phi' g + theta' n + psi' e3`` (g the vertical, n the line of nodes, both in the body
    frame); ``spin`` is its component w3 (``psi' + phi' cos(theta)``), ``tilt_rate`` (rad s-1)
    sets theta' and ``precession_rate`` (rad s-1, scalar or one per member) phi' at the start.
    ``theta' = phi' = 0`` (the default) is the top released with no transverse angular
    velocity: the cusped path of the figure axis.

    Parameters
    ----------
    spin : float
        w3, rad s-1.
    tilt : float or array_like, shape (members,)
        Angle of body axis 3 from the vertical, rad.
    members : int
        Number of starts.
    top : HeavyTop
        The top; its moments about the pivot turn the angular velocity into ``m``.
    seed : int, default 0
        Seed of the azimuths.
    tilt_rate : float, default 0.0
        theta', rad s-1.
    precession_rate : float or array_like, shape (members,), default 0.0
        phi', rad s-1.

    Returns
    -------
    ndarray, shape (members, 6)
        ``(m1, m2, m3, g1, g2, g3)``: the angular momentum about the pivot in the body frame
        (kg m2 s-1) and the unit upward vertical in the body frame.
    """
    rng = np.random.default_rng(seed)
    azimuth = 2.0 * np.pi * rng.random(members)
    tilt = np.broadcast_to(np.asarray(tilt, dtype=float), (members,))
    s = np.sin(tilt)
    g = np.column_stack([s * np.sin(azimuth), s * np.cos(azimuth), np.cos(tilt)])
    A, B, C = top.pivot_moments
    phi_rate = np.broadcast_to(np.asarray(precession_rate, dtype=float), (members,))
    # Line of nodes in the body frame: (cos psi, -sin psi, 0) for g = (s sin psi, s cos psi, c).
    w1 = tilt_rate * np.cos(azimuth) + phi_rate * g[:, 0]
    w2 = -tilt_rate * np.sin(azimuth) + phi_rate * g[:, 1]
    m = np.column_stack([A * w1, B * w2, np.full(members, C * float(spin))])
    return np.concatenate([m, g], axis=1)


def tilt_members(extras, x0, status, levels):
    """The estimators' :class:`~stability.analysis.members.Members` of tracked top runs.

    The tracked amplitude is ``sin(tilt)`` of body axis 3 (scene ``heavy_top``), so the
    estimators fit its growth exactly as they fit the perpendicular angular velocity of a
    free body; the "spin" that scales the window's upper edge is 1 (``sin`` of the largest
    tilt).

    Parameters
    ----------
    extras : dict
        ``Propagation.extras`` of these runs' rows, as
        :func:`stability.analysis.members.tracked_members` takes them (crossings,
        ``max_perp_amplitude`` (N,), ``passage_time`` (N, n_levels)).
    x0 : ndarray, shape (N, 6)
        Starts ``(m1, m2, m3, g1, g2, g3)`` (:func:`tilted_starts`).
    status : array_like, shape (N,)
        Per-member status codes; members not ``STATUS_OK`` are left out of every estimate.
    levels : array_like, shape (n_levels,)
        The ascending levels of ``passage_time``, in ``sin(tilt)`` (dimensionless).

    Returns
    -------
    Members
    """

    return tracked_members(extras, x0[:, 3:6], 3, 1.0, levels, status=status)
