r"""The free rigid body with its attitude: body angular momentum and a unit quaternion.

The state is ``(m1, m2, m3, q0, q1, q2, q3)``: :math:`\dot m = m \times I^{-1} m` and
:math:`\dot q = \tfrac12\, q\, (0, w)` with :math:`q` the body-to-space rotation, scalar first
(:mod:`stability.free_body.attitude`), canonical frame as for ``free_body``. Each method advances
:math:`q` by its own rule (``MethodSpec.attitude_step``); the methods that have none (the exact
elliptic flow) do not run this scene. Invariants: those of the free body, :math:`|q| = 1` and
the spatial angular momentum :math:`R(q)\, m`.
"""

import numpy as np
from numba import njit

from ..util import conventions as cv
from .methods import METHODS
from ..engine.scene import Scene
from .scene import angular_momentum, energy, example as example_m, observe as observe_m
from .scene import tracked as tracked_m


@njit(inline="always")
def observe(m1, m2, m3, q0, q1, q2, q3, p, ia, ib, ic):
    """As the free body's: angular velocity along the spin axis and across it."""
    return observe_m(m1, m2, m3, p, ia, ib, ic)


def tracked(x, p, axes):
    """:func:`observe` in NumPy over states ``x`` (N, 7)."""
    return tracked_m(x[:, :3], p, axes)


def _attitude_step(spec):
    return spec.attitude_step


def quaternion_norm(x, moments):
    """``|q|`` of states ``x`` (N, 7)."""
    return np.linalg.norm(x[:, 3:], axis=-1)


def example(n, seed=0):
    """The free body's starts with the identity attitude, and its bodies."""
    m, bodies = example_m(n, seed)
    return np.concatenate([m, np.tile([1.0, 0.0, 0.0, 0.0], (n, 1))], axis=1), bodies


FREE_BODY_ATTITUDE = Scene(
    name="free_body_attitude",
    module=__name__,
    title="free rigid body with attitude",
    equations="m' = m x I^-1 m, q' = q (0, I^-1 m) / 2",
    latex=r"\dot m = m \times I^{-1} m, \qquad \dot q = \tfrac12\, q\, (0, I^{-1} m)",
    components=("m1", "m2", "m3", "q0", "q1", "q2", "q3"),
    units=(cv.UNITS_ANGULAR_MOMENTUM,) * 3 + (cv.UNITS_DIMENSIONLESS,) * 4,
    methods={name: spec for name, spec in METHODS.items() if spec.attitude},
    observe=observe,
    tracked=tracked,
    kernel=_attitude_step,
    invariants={
        "energy": lambda x, moments: energy(x[:, :3], moments),
        "angular_momentum": lambda x, moments: angular_momentum(x[:, :3], moments),
        "quaternion_norm": quaternion_norm,
    },
    # Every method but RK4 turns q by rotations; RK4 integrates q' = q (0, w) / 2 as it is.
    kept_by={"energy": "preserves_energy", "angular_momentum": "preserves_casimir",
             "quaternion_norm": frozenset(n for n, s in METHODS.items()
                                          if s.attitude and n != "rk4")},
    example=example,
    tracked_units=cv.UNITS_ANGULAR_VELOCITY,
)
