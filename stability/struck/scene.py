"""A bat or racket struck across its axis, held at the hands or free (planar motion).

The state is ``(x, y, phi, vx, vy, w, j_along, j_across, t)``: the centre of mass, the angle of
the body's axis, the velocity of the centre, the angular velocity, the reaction impulse at the
hands along and across the body, and the time; the hands (the pivot) start at the origin with
the body along +x. Parameters per group: a strike ``(M, d, I_cm, s, J, tau, held)``
(:func:`stability.struck.methods.strike_params`). Equations: :mod:`stability.struck.methods`.
Invariants: after the contact, the angular momentum about the hands (held) or about the centre
(free); exact solution, held, from rest: :func:`stability.struck.methods.held_exact`
(:func:`exact` here).
"""

import numpy as np
from numba import njit

from ..util import conventions as cv
from .methods import (
    J_ACROSS, J_ALONG, METHODS, P_HELD, P_I_CM, P_MASS, PHI, T, W, X, Y, VX, VY, held_exact,
)
from ..engine.scene import Scene


@njit(inline="always")
def observe(x, y, phi, vx, vy, w, j_along, j_across, t, p, ia, ib, ic):
    """``(j_across, w, 0)``: the sting across the hands and the angular velocity."""
    return j_across, w, 0.0


def tracked(x, p, axes):
    """:func:`observe` in NumPy over states ``x`` (N, 9)."""
    return x[:, J_ACROSS], x[:, W], np.zeros(x.shape[0])


def angular_momentum(x, strike):
    """Angular momentum about the start of the hands (kg m2 s-1): ``I_cm w + M (r x v)``;
    constant after the contact when free, and while held (the reaction acts at the origin)
    kept by the force's torque only."""
    strike = np.asarray(strike, dtype=float)
    mass, i_cm = strike[P_MASS], strike[P_I_CM]
    return i_cm * x[:, W] + mass * (x[:, X] * x[:, VY] - x[:, Y] * x[:, VX])


def exact(x0, strike, t):
    """The exact states (N, 9) at time ``t`` of a held strike (:func:`held_exact`) from starts
    ``x0`` (N, 9) at rest along +x at time 0; None for a free strike or a start not at rest.

    The equations involve neither x, y nor the impulses, so a start's offsets in them from the
    held body's own ``(d, 0, 0, 0)`` (the example's starts have some) are carried along.
    """
    x0 = np.asarray(x0, dtype=float)
    strike = np.asarray(strike, dtype=float)
    if strike[P_HELD] == 0.0 or np.any(x0[:, [PHI, VX, VY, W, T]] != 0.0):
        return None
    offsets = x0 - held_exact(np.zeros(1), strike)
    return held_exact(np.full(len(x0), float(t)), strike) + offsets * _CARRIED


#: The components whose start offsets a held strike carries along unchanged.
_CARRIED = np.isin(np.arange(9), [X, Y, J_ALONG, J_ACROSS]).astype(float)


def example(n, seed=0):
    """Starts and strikes for generic tests: bodies at rest; held and free strikes. The
    contacts end on dyadic times (the force's kink there costs RK4 its order unless a step
    ends on it), so that steps of ``2^-k`` s meet them."""
    rng = np.random.default_rng(seed)
    x = np.zeros((n, 9))
    x[:, X] = 0.4 + 0.01 * rng.random(n)
    strikes = [np.array([0.85, 0.4, 0.04, 0.6, 10.0, 0.5, 1.0]),
               np.array([0.30, 0.25, 0.015, 0.5, 5.0, 0.25, 0.0]),
               np.array([0.85, 0.4, 0.04, 0.52, 10.0, 0.125, 1.0])]
    return x, strikes


STRUCK_BODY = Scene(
    name="struck_body",
    module=__name__,
    title="bat or racket struck across its axis, held at the hands or free (planar)",
    equations="held: I_P w' = s F, R = M d (w' n - w^2 e) - F n; free: I_cm w' = (s - d) F, "
              "M v' = F n",
    latex=(r"\text{held: } I_P \dot w = s F, \quad R = M d\, (\dot w\, n - w^2 e) - F n; \qquad"
           r" \text{free: } I_{cm} \dot w = (s - d) F, \quad M \dot v = F n"),
    components=("x", "y", "phi", "vx", "vy", "w", "j_along", "j_across", "t"),
    units=("m", "m", "rad", "m s-1", "m s-1", cv.UNITS_ANGULAR_VELOCITY, "N s", "N s",
           cv.UNITS_TIME),
    methods=METHODS,
    observe=observe,
    tracked=tracked,
    invariants={"angular_momentum": angular_momentum},
    kept_by={"angular_momentum": None},  # not during the contact
    exact=exact,
    example=example,
    tracked_units=cv.UNITS_ANGULAR_VELOCITY,
)
