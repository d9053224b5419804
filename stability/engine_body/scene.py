r"""The free rigid body stepped as physics engines step it: space angular velocity and attitude.

The state is ``(omega_w1, omega_w2, omega_w3, q0, q1, q2, q3)``: the angular velocity in the
space frame and the body-to-space quaternion :math:`q` (scalar first), in the canonical body
frame (:math:`I_1 \le I_2 \le I_3`); parameters :func:`~stability.integrators.spec.body_params`.
The methods are the engines' update rules (:mod:`stability.engine_body.methods`), not the
package's integrators. The loop tracks the body angular velocity :math:`w = R(q)^T \omega_w`.
Invariants: the energy :math:`w \cdot I w / 2`, :math:`|I w| = |L|` and :math:`|q| = 1`.
Conversions from and to the body-frame ``(m, q)``:
:func:`~stability.engine_body.model.world_state` and ``body_state``.
"""

import numpy as np
from numba import njit

from ..util import conventions as cv
from ..engine.scene import Scene, component
from ..free_body.scene_attitude import example as example_mq
from ..free_body.scene_attitude import quaternion_norm
from .methods import ENGINE_RULES, rotate3
from .model import rotate, world_state


@njit(inline="always")
def observe(x0, x1, x2, q0, q1, q2, q3, p, ia, ib, ic):
    """Body angular velocity ``R(q / |q|)^T omega_w`` along the spin axis ``ia`` and across it."""
    w1, w2, w3 = rotate3(q0, q1, q2, q3, x0, x1, x2, -1.0)
    return component(w1, w2, w3, ia), component(w1, w2, w3, ib), component(w1, w2, w3, ic)


def body_omega(x):
    """Body angular velocity ``R(q)^T omega_w`` (N, 3) of states ``x`` (N, 7)."""
    x = np.asarray(x, dtype=float)
    return rotate(x[:, 3:], x[:, :3], transpose=True)


def tracked(x, p, axes):
    """:func:`observe` in NumPy over states ``x`` (N, 7)."""
    w = body_omega(x)
    return tuple(w[:, axes[k]] for k in range(3))


def energy(x, moments):
    """Kinetic energy ``w . I w / 2`` (J) of states ``x`` (N, 7)."""
    w = body_omega(x)
    return 0.5 * np.sum(np.asarray(moments, dtype=float) * w * w, axis=-1)


def angular_momentum(x, moments):
    """``|I w| = |L|`` (kg m2 s-1) of states ``x`` (N, 7)."""
    return np.linalg.norm(np.asarray(moments, dtype=float) * body_omega(x), axis=-1)


def example(n, seed=0):
    """The attitude scene's starts (identity attitude), as ``omega_w = I^-1 m`` for the first of
    its bodies, and its bodies."""
    x, bodies = example_mq(n, seed)
    return world_state(bodies[0], x[:, :3], x[:, 3:]), bodies


ENGINE_BODY = Scene(
    name="engine_body",
    module=__name__,
    title="free rigid body stepped as physics engines step it",
    equations="I w' = I w x w with w = R(q)^T omega_w, q' = (0, omega_w) q / 2",
    latex=(r"I \dot w = I w \times w \text{ with } w = R(q)^T \omega_w, \qquad"
           r" \dot q = \tfrac12\, (0, \omega_w)\, q"),
    components=("omega_w1", "omega_w2", "omega_w3", "q0", "q1", "q2", "q3"),
    units=(cv.UNITS_ANGULAR_VELOCITY,) * 3 + (cv.UNITS_DIMENSIONLESS,) * 4,
    methods=ENGINE_RULES,
    observe=observe,
    tracked=tracked,
    invariants={"energy": energy, "angular_momentum": angular_momentum,
                "quaternion_norm": quaternion_norm},
    kept_by={"energy": "preserves_energy", "angular_momentum": "preserves_casimir",
             "quaternion_norm": True},  # every rule normalises q
    example=example,
    tracked_units=cv.UNITS_ANGULAR_VELOCITY,
)
