"""A round body rolling or slipping along a track of straight sections (planar).

The state is ``(x, v, w, t, mode, switches, t_roll, x_roll, heat)``: the distance along the
track, the speed of the centre, the spin (positive rolling forward), the time, the regime (0
rolling, +1 or -1 slipping with the contact point moving forward or back), the switches of
regime so far, the time and place the body last started to roll (the start's own if it has not
switched), and the work done by kinetic friction. Parameters per group:
:func:`stability.rolling.methods.track_row`. Equations, events and the exact step:
:mod:`stability.rolling.methods`. Invariant: the energy with the friction's work added back.
"""

import numpy as np
from numba import njit

from ..util import conventions as cv
from .methods import (
    HEAT, MAX_SECTIONS, METHODS, P_G, P_K, P_MASS, P_R, P_SECTIONS, P_TRACK, V, W, X, track_row,
)
from ..engine.scene import Scene


@njit(inline="always")
def observe(x, v, w, t, mode, switches, t_roll, x_roll, heat, p, ia, ib, ic):
    """``(u, v, 0)``: the slip speed, which changes sign when the slip reverses, and the speed."""
    return v - p[P_R] * w, v, 0.0


def tracked(x, p, axes):
    """:func:`observe` in NumPy over states ``x`` (N, 9)."""
    return x[:, V] - p[P_R] * x[:, W], x[:, V], np.zeros(x.shape[0])


def height(x, p):
    """Height of the centre above its height at ``x = 0`` (m), the track's sections joined."""
    x = np.asarray(x, dtype=float)
    z = np.zeros_like(x)
    for j in range(int(p[P_SECTIONS])):
        lo = p[P_TRACK + 3 * j]
        hi = p[P_TRACK + 3 * (j + 1)] if j + 1 < MAX_SECTIONS else np.inf
        # the part of [0, x] (or [x, 0]) inside section j, signed, times its drop per metre
        inside = np.clip(x, lo, hi) - np.clip(0.0, lo, hi)
        z -= inside * p[P_TRACK + 3 * j + 1]
    return z


def energy(x, p):
    """``M v^2 / 2 + k M R^2 w^2 / 2 + M g z(x) + heat`` (J): kept to round-off."""
    p = np.asarray(p, dtype=float)
    mass, k, radius = p[P_MASS], p[P_K], p[P_R]
    return (0.5 * mass * x[:, V] ** 2 + 0.5 * k * mass * radius**2 * x[:, W] ** 2
            + mass * p[P_G] * height(x[:, X], p) + x[:, HEAT])


def example(n, seed=0):
    """Starts and tracks for generic tests: launches with random slip on three tracks."""
    rng = np.random.default_rng(seed)
    x = np.zeros((n, 9))
    x[:, V] = 0.5 + rng.random(n)
    x[:, W] = (rng.random(n) * 3.0 - 1.0) / 0.1
    u = x[:, V] - 0.1 * x[:, W]
    x[:, 4] = np.sign(u)
    tracks = [
        track_row(0.4, 0.1, 0.3, 0.2),  # level floor
        track_row(0.5, 0.1, 0.2, 0.15, angles=(0.3,)),  # rolls or slips down a slope
        track_row(1.0, 0.1, 0.25, 0.2, angles=(0.1, 0.6, 0.0), starts=(0.3, 0.6)),
    ]
    return x, tracks


ROLLING_BODY = Scene(
    name="rolling_body",
    module=__name__,
    title="round body rolling or slipping along straight sections (Coulomb friction)",
    equations="rolling: v' = g sin(theta) / (1 + k); slipping: v' = g (sin(theta) - s mu_k "
              "cos(theta)), w' = s mu_k g cos(theta) / (k R)",
    latex=(r"\text{rolling: } \dot v = \frac{g \sin\theta}{1 + k}; \qquad"
           r" \text{slipping: } \dot v = g\, (\sin\theta - s\, \mu_k \cos\theta), \quad"
           r" \dot w = \frac{s\, \mu_k\, g \cos\theta}{k R}"),
    components=("x", "v", "w", "t", "mode", "switches", "t_roll", "x_roll", "heat"),
    units=("m", "m s-1", cv.UNITS_ANGULAR_VELOCITY, cv.UNITS_TIME, cv.UNITS_DIMENSIONLESS,
           cv.UNITS_DIMENSIONLESS, cv.UNITS_TIME, "m", cv.UNITS_ENERGY),
    methods=METHODS,
    observe=observe,
    tracked=tracked,
    invariants={"energy": energy},
    kept_by={"energy": "preserves_energy"},
    example=example,
    tracked_units="m s-1",
)
