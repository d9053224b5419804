r"""The free rigid body in its principal frame: the state is the body angular momentum only.

Euler's equations :math:`\dot m = m \times I^{-1} m` with :math:`m = I w`
(:math:`I_1 \dot w_1 = (I_2 - I_3)\, w_2 w_3` and cyclic), in the canonical frame
:math:`I_1 \le I_2 \le I_3` (:func:`stability.core.body.canonical_frame`); three numbers per
member, no attitude (that is scene ``free_body_attitude``). Invariants: the kinetic energy
:math:`E = m \cdot I^{-1} m / 2` and :math:`|m| = |L|`; exact solution: Jacobi elliptic
functions (:func:`stability.exact_omega`, here as :func:`exact`). Every registered method runs
it.
"""

import numpy as np
from numba import njit

from ..util import conventions as cv
from ..core.body import RigidBody
from .exact import exact_omega_of_starts
from .methods import METHODS
from ..integrators.rk4 import euler_jvp, euler_rhs
from ..integrators.spec import body_params
from ..engine.scene import Scene, angular_velocity_components, angular_velocity_tracked
from ..engine.tangent import Linearisation


@njit
def flip_event(x, t, p):
    """The g of an event (:class:`stability.Event`) at the free body's flips: ``m2``, the
    component along the intermediate axis (canonical frame), changes sign at each one.

    Parameters
    ----------
    x : ndarray
        A member's state ``(m1, m2, m3)`` (kg m^2/s).
    t : float
        The time (s).
    p : ndarray
        The member's parameter row.

    Returns
    -------
    float
        ``m2``.
    """
    return x[1]


@njit(inline="always")
def observe(m1, m2, m3, p, ia, ib, ic):
    """Angular velocity along the spin axis ``ia`` and the perpendicular axes ``ib``, ``ic``."""
    return angular_velocity_components(m1, m2, m3, p, ia, ib, ic)


def tracked(m, p, axes):
    """:func:`observe` in NumPy at the start: ``(w_a, w_b, w_c)`` of states ``m`` (N, 3), ``w``
    as the caller's ``w0`` was made (:func:`~stability.engine.scene.angular_velocity_tracked`)."""
    return angular_velocity_tracked(m, p, axes)


def energy(m, moments):
    """Kinetic energy ``m . I^-1 m / 2`` (J) of body angular momenta ``m`` (N, 3)."""
    return 0.5 * np.sum(m * m / np.asarray(moments, dtype=float), axis=-1)


def angular_momentum(m, moments):
    """``|m| = |L|`` (kg m2 s-1)."""
    return np.linalg.norm(m, axis=-1)


def exact(m, moments, t):
    """The exact ``m(t) = I w(t)`` (N, 3) of starts ``m`` (N, 3): the Jacobi elliptic solution
    (:func:`stability.free_body.exact.exact_omega_of_starts`) of ``w = m / I``."""
    moments = np.asarray(moments, dtype=float)
    body = RigidBody(*moments, physical=False)
    return exact_omega_of_starts(body, np.asarray(m, dtype=float) / moments, t) * moments


def example(n, seed=0):
    """Starts near a spin about the intermediate axis, and three bodies (generic tests)."""
    rng = np.random.default_rng(seed)
    m = np.column_stack([1e-2 * rng.standard_normal(n), np.full(n, 2.0),
                         1e-2 * rng.standard_normal(n)])
    return m, [np.array([1.0, 2.0, 3.0]), np.array([1.0, 1.5, 2.2]), np.array([0.5, 2.0, 2.1])]


FREE_BODY = Scene(
    name="free_body",
    module=__name__,
    title="free rigid body (angular velocity only)",
    equations="I1 w1' = (I2 - I3) w2 w3 and cyclic (m' = m x I^-1 m)",
    latex=(r"I_1 \dot w_1 = (I_2 - I_3)\, w_2 w_3 \text{ and cyclic}, \qquad"
           r" \dot m = m \times I^{-1} m"),
    components=("m1", "m2", "m3"),
    units=(cv.UNITS_ANGULAR_MOMENTUM,) * 3,
    methods=METHODS,
    observe=observe,
    tracked=tracked,
    invariants={"energy": energy, "angular_momentum": angular_momentum},
    kept_by={"energy": "preserves_energy", "angular_momentum": "preserves_casimir"},
    exact=exact,
    example=example,
    tracked_units=cv.UNITS_ANGULAR_VELOCITY,
    linearisation=Linearisation(euler_rhs, euler_jvp, body_params),
)

