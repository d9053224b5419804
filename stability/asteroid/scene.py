r"""A tumbler relaxing to a spin about its major axis: the scene ``relaxing_tumbler``.

The state is the body angular momentum ``(m1, m2, m3)`` in the canonical principal frame
(:math:`I_1 \le I_2 \le I_3`), as the free body's; parameters per body ``(I1, I2, I3, alpha)``.
Equation (1) of :mod:`stability.asteroid.methods`: Euler's equations with a dissipation that
keeps :math:`|m| = |L|` (the invariant) and lowers the energy until m lies along a principal
axis. Exact solution for an axisymmetric body (:func:`stability.asteroid.exact.relaxed_momentum`,
here as :func:`exact`); the linear rates about each axis:
:func:`stability.asteroid.model.wobble_rate`. With its vector field and Jacobian
(``linearisation``) it also runs with adaptive steps (:func:`stability.run_adaptive`) and with
tangents (:mod:`stability.tangents`).
"""

import numpy as np
from numba import njit

from ..util import conventions as cv
from ..engine.scene import Scene, angular_velocity_components, angular_velocity_tracked
from ..engine.tangent import Linearisation
from .exact import relaxed_momentum
from .methods import METHODS, relaxation_jvp, relaxation_params, relaxation_rhs


@njit(inline="always")
def observe(m1, m2, m3, p, ia, ib, ic):
    """Angular velocity along the spin axis ``ia`` and the perpendicular axes ``ib``, ``ic``."""
    return angular_velocity_components(m1, m2, m3, p, ia, ib, ic)


def tracked(m, p, axes):
    """:func:`observe` in NumPy at the start: ``(w_a, w_b, w_c)`` of states ``m`` (N, 3)."""
    return angular_velocity_tracked(m, p, axes)


def angular_momentum(m, parameters):
    """``|m| = |L|`` (kg m2 s-1), which (1) keeps."""
    return np.linalg.norm(m, axis=-1)


def energy(m, parameters):
    """Rotational kinetic energy ``m . I^-1 m / 2`` (J), which (1) lowers."""
    moments = np.asarray(parameters, dtype=float)[:3]
    return 0.5 * np.sum(m * m / moments, axis=-1)


def exact(m, parameters, t):
    """The exact states (N, 3) at time ``t`` of an axisymmetric body (None for a triaxial one):
    :func:`stability.asteroid.exact.relaxed_momentum`."""
    return relaxed_momentum(m, parameters, t)


def example(n, seed=0):
    """Tumbling starts, 48 to 62 degrees from the axes, and four bodies for the generic tests:
    oblate and prolate (which the exact solution covers), triaxial, and a triaxial free body."""
    rng = np.random.default_rng(seed)
    m = np.column_stack([1.0 + 0.1 * rng.standard_normal(n), np.full(n, 1.2),
                         1.4 + 0.1 * rng.standard_normal(n)])
    return m, [np.array([1.0, 1.0, 2.0, 0.1]), np.array([1.0, 2.0, 2.0, 0.1]),
               np.array([1.0, 1.5, 2.2, 0.1]), np.array([1.0, 1.5, 2.2, 0.0])]


RELAXING_TUMBLER = Scene(
    name="relaxing_tumbler",
    module=__name__,
    title="tumbler relaxing by internal dissipation (angular momentum kept)",
    equations="m' = m x w + alpha m x (m x w), w = I^-1 m",
    latex=(r"\dot m = m \times \omega + \alpha\, m \times (m \times \omega), \quad"
           r" \omega = I^{-1} m"),
    components=("m1", "m2", "m3"),
    units=(cv.UNITS_ANGULAR_MOMENTUM,) * 3,
    methods=METHODS,
    observe=observe,
    tracked=tracked,
    invariants={"angular_momentum": angular_momentum},
    exact=exact,
    example=example,
    parameters=("I1", "I2", "I3", "alpha"),
    parameter_units=("kg m2", "kg m2", "kg m2", "kg-1 m-2 s"),
    tracked_units=cv.UNITS_ANGULAR_VELOCITY,
    linearisation=Linearisation(relaxation_rhs, relaxation_jvp, relaxation_params),
)
