"""The centre of percussion: a bat or racket struck across its axis, held at the hands or free.

A struck body is described by what its planar motion needs: mass M, length, the distance of its
centre of mass from the end held (the knob or butt) and its moment of inertia I_cm about a
transverse axis through that centre (:class:`StruckBody`; :func:`baseball_bat` builds a tapered
wooden bat from cylinders and truncated cones, :func:`tennis_racket` takes the package's racket
preset). Hit with impulse J at distance s from the hands (the pivot P, d from the centre):

- held (the hands a hinge), the body turns about P at w = s J / I_P and the hands take the
  reaction impulse across the body ``J (M d s / I_P - 1)`` (:func:`reaction_impulse`);
- free, the centre moves off at J / M and the body spins at (s - d) J / I_cm, so the point at
  the hands moves across at ``J / M - d (s - d) J / I_cm`` (:func:`hand_velocity`).

Both vanish at the centre of percussion ``q = I_P / (M d)`` from the hands, where
``(q - d) d = I_cm / M`` [the course notes' "baseball bat theorem"; Cross, Am. J. Phys. 72, 622
(2004)]. :func:`stability.struck.measure.measure_strikes` runs ensembles of strikes (scene
``struck_body``, the contact a short half-sine force) and finds q and the sweet zone from the
runs.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..core.body import PRESETS, Part, RigidBody
from ..util.checks import positive_float, real_number

INCH = 0.0254
#: A 33-inch wooden baseball bat, stations (distance from the knob end, radius) in inches; two
#: stations at one distance are a step. Knob 1.5 in across, handle 0.92 in, a taper over 10 in
#: to a 2.44 in barrel, a rounded end. At 0.85 kg (30 oz) its balance point is 22.2 in from the
#: knob and its moment about the pivot 6 in from the knob 0.176 kg m^2, in the range of the WSU
#: Sports Science Lab's measurements of wood bats (0.146 to 0.183 kg m^2).
BAT_PROFILE = ((0.0, 0.75), (0.5, 0.75), (0.5, 0.46), (11.0, 0.46), (21.0, 1.22),
               (31.5, 1.22), (33.0, 0.85))

#: Dimension names.
HOLD = "hold"
PIVOT = "pivot"
STRIKE = "strike"


@dataclass(frozen=True)
class StruckBody:
    """What the planar strike needs of a body.

    The fields are the constructor's parameters and the instance's attributes.

    Parameters
    ----------
    name : str
        Name of the body, for labels and messages.
    mass : float
        M (kg).
    length : float
        From the end held (x = 0) to the tip (m).
    centre : float
        The centre of mass, from the end held (m).
    inertia : float
        I_cm about a transverse axis through the centre (kg m2).
    outline : ndarray, shape (n, 2)
        Stations (x, half-width) in m along the body, for drawing it to scale.
    """

    name: str
    mass: float
    length: float
    centre: float
    inertia: float
    outline: np.ndarray = field(repr=False)

    def moment_about(self, pivot) -> np.ndarray:
        """I_P = I_cm + M d^2 about a transverse axis at ``pivot`` (m from the end)."""
        return self.inertia + self.mass * (self.centre - np.asarray(pivot, dtype=float)) ** 2

    def describe(self) -> dict:
        return {"body": self.name, "mass": self.mass, "length": self.length,
                "centre_of_mass": self.centre, "inertia_cm": self.inertia}


def baseball_bat(mass=0.850, profile=BAT_PROFILE, unit=INCH, name="baseball bat"):
    """A wooden bat of uniform density: one truncated cone (``Part.frustum``) per section of
    ``profile``, the stations ``(x, radius)`` in ``unit`` (m per unit), scaled to ``mass``.

    Parameters
    ----------
    mass : float, default 0.850
        Mass of the bat in kg.
    profile : array_like, shape (n, 2), default BAT_PROFILE
        Stations ``(x, radius)`` from the knob end, x non-decreasing; two stations at one x
        are a step.
    unit : float, default INCH
        Length of one profile unit in m.
    name : str, default "baseball bat"
        Name of the body.

    Returns
    -------
    StruckBody
        The bat, held at its knob end (x = 0); ``outline`` is the stations in m.
    """

    mass = positive_float("mass of the bat", mass, "kg")
    stations = np.asarray(profile, dtype=float) * unit
    parts = []
    volumes = []
    for (x0, r0), (x1, r1) in zip(stations[:-1], stations[1:]):
        if x1 > x0:
            volumes.append(math.pi * (x1 - x0) * (r0 * r0 + r0 * r1 + r1 * r1) / 3.0)
            parts.append((x0, x1, r0, r1))
    density = mass / sum(volumes)
    pieces = [Part.frustum(density * v, r0, r1, x1 - x0, base=(x0, 0.0, 0.0), axis=(1, 0, 0),
                           name=f"section {k}")
              for k, ((x0, x1, r0, r1), v) in enumerate(zip(parts, volumes))]
    bat = RigidBody.composite(pieces, name=name)
    return StruckBody(name, bat.mass, float(stations[-1, 0]), float(bat.centre_of_mass[0]),
                      float(bat.inertia[1, 1]), stations)


def tennis_racket():
    """The package's tennis-racket preset (``RigidBody.preset("tennis_racket")``), struck on
    its strings: the rotation is about the axis across the head in the string plane."""

    racket = RigidBody.composite(PRESETS["tennis_racket"].parts(), name="tennis racket")
    x = np.linspace(0.0, 0.69, 139)
    head = np.clip(1.0 - ((x - 0.525) / 0.165) ** 2, 0.0, None)
    throat = 0.015 + (0.095 - 0.015) * np.clip((x - 0.19) / (0.40 - 0.19), 0.0, 1.0)
    half_width = np.where(x < 0.19, 0.015, np.maximum(0.14 * np.sqrt(head), throat * (x < 0.40)))
    return StruckBody("tennis racket", racket.mass, 0.69, float(racket.centre_of_mass[0]),
                      float(racket.inertia[1, 1]), np.column_stack([x, half_width]))


BODIES = {"baseball_bat": baseball_bat, "tennis_racket": tennis_racket}


def check_pivot(body: StruckBody, pivot) -> float:
    """``pivot`` (m from the end) as a float on the body and off its centre, else ValueError.

    Parameters
    ----------
    body : StruckBody
        The body struck.
    pivot : float
        Position of the hands in m from the end held.

    Returns
    -------
    float
        ``pivot``.

    Raises
    ------
    ValueError
        If ``pivot`` is not a real number, is off the body (outside 0 to ``body.length``), or
        lies within ``1e-3 body.length`` of the centre of mass.
    """
    pivot = real_number("pivot", pivot, "m")
    if not 0.0 <= pivot <= body.length:
        raise ValueError(f"pivot {pivot:g} m is off the {body.name} (0 to {body.length:g} m "
                         "from the end held)")
    if abs(pivot - body.centre) <= 1e-3 * body.length:
        raise ValueError(f"a pivot at the centre of mass ({body.centre:.4g} m) has no centre "
                         "of percussion: any strike there pushes on the hands; hold the "
                         f"{body.name} elsewhere")
    return pivot


def centre_of_percussion(body: StruckBody, pivot) -> float:
    """The centre of percussion for hands at ``pivot``: ``pivot + I_P / (M d)`` (m from the
    end held; it lies beyond the centre of mass, on the far side from the hands).

    Parameters
    ----------
    body : StruckBody
        The body struck.
    pivot : float
        Position of the hands in m from the end held (checked by :func:`check_pivot`).

    Returns
    -------
    float
        The centre of percussion in m from the end held.
    """
    pivot = check_pivot(body, pivot)
    d = body.centre - pivot
    return pivot + body.moment_about(pivot) / (body.mass * d)


def reaction_impulse(body: StruckBody, pivot, strike, impulse):
    """Reaction impulse across the body at hands holding it at ``pivot``, for an impulse hit
    at ``strike`` (m from the end): ``J (M d s / I_P - 1)`` with s = strike - pivot (N s).

    Parameters
    ----------
    body : StruckBody
        The body struck.
    pivot : float or array_like
        Position of the hands in m from the end held (not checked).
    strike : float or array_like
        Strike point in m from the end held; broadcast against ``pivot``.
    impulse : float
        Impulse J of the strike in N s.

    Returns
    -------
    ndarray or float
        Reaction impulse across the body at the hands in N s, for an instantaneous strike;
        0 at the centre of percussion.
    """
    d = body.centre - pivot
    s = np.asarray(strike, dtype=float) - pivot
    return impulse * (body.mass * d * s / body.moment_about(pivot) - 1.0)


def hand_velocity(body: StruckBody, pivot, strike, impulse):
    """Velocity across the body of the point at ``pivot`` of a free body just after an impulse
    at ``strike``: ``J / M - d (s - d) J / I_cm`` (m s-1).

    Parameters
    ----------
    body : StruckBody
        The body struck.
    pivot : float or array_like
        Position of the hands in m from the end held (not checked).
    strike : float or array_like
        Strike point in m from the end held; broadcast against ``pivot``.
    impulse : float
        Impulse J of the strike in N s.

    Returns
    -------
    ndarray or float
        Velocity across the body of the point at the hands in m s-1, for an instantaneous
        strike; 0 at the centre of percussion.
    """
    d = body.centre - pivot
    lever = np.asarray(strike, dtype=float) - body.centre
    return impulse / body.mass - d * lever * impulse / body.inertia
