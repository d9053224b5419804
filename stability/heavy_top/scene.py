r"""The heavy top on a fixed pivot in uniform gravity: body angular momentum and the vertical.

The state is ``(m1, m2, m3, g1, g2, g3)``: :math:`m` the angular momentum about the pivot and
:math:`g` the upward vertical, both in the principal frame of the moments about the pivot; six
numbers per member and no attitude (the tilt of any body axis is read from :math:`g`).
Parameters per top: ``(I1, I2, I3, c1, c2, c3)``, the moments about the pivot and
:math:`c = M g\, l\, \chi` with :math:`\chi` the unit vector from the pivot to the centre of mass
(:class:`stability.heavy_top.model.HeavyTop` makes them).
Equations, methods and references: :mod:`stability.heavy_top.methods`. Invariants: the
energy :math:`m \cdot I^{-1} m / 2 + c \cdot g` and the Casimirs :math:`|g|` and
:math:`g \cdot m` (the angular momentum about the vertical); exact solution for a symmetric top
(:func:`exact`, from :func:`stability.heavy_top.exact.body_states`): the example's second top is
one.
Tangent equations: the exact product ``J v`` of equations (1) (:func:`~.methods.top_jvp`), for
:func:`stability.engine.tangent.tangent_scene`.

Tracking: the spin-axis component is :math:`g_a` (the cosine of the tilt of body axis :math:`a`
from the vertical: it changes sign when that axis passes the horizontal) and the amplitude
across it is :math:`\sqrt{g_b^2 + g_c^2}`, the sine of the tilt, returned as ``b`` with
``c = 0``: the components :math:`g_b, g_c` themselves turn with the spin, and would count the
spin's turns as oscillations.
"""

import math

import numpy as np
from numba import njit

from ..util import conventions as cv
from .exact import body_states
from .methods import METHODS, N_TOP, top_jvp, top_params, top_rhs
from ..engine.scene import Scene, component
from ..engine.tangent import Linearisation


@njit(inline="always")
def observe(m1, m2, m3, g1, g2, g3, p, ia, ib, ic):
    """``(g_a, sqrt(g_b^2 + g_c^2), 0)``: cosine and sine of body axis a's tilt."""
    gb = component(g1, g2, g3, ib)
    gc = component(g1, g2, g3, ic)
    return component(g1, g2, g3, ia), math.sqrt(gb * gb + gc * gc), 0.0


def tracked(x, p, axes):
    """:func:`observe` in NumPy over states ``x`` (N, 6)."""
    g = x[:, 3:6]
    return g[:, axes[0]], np.hypot(g[:, axes[1]], g[:, axes[2]]), np.zeros(x.shape[0])


def _top(top):
    top = np.asarray(top, dtype=float).reshape(-1)
    if top.size < N_TOP:
        raise ValueError(f"a top is described by {N_TOP} numbers, got {top.size}")
    return top[:3], top[3:6]


def energy(x, top):
    """``H = m . I^-1 m / 2 + c . g`` (J) of states ``x`` (N, 6) of ``top``."""
    moments, c = _top(top)
    return 0.5 * np.sum(x[:, :3] ** 2 / moments, axis=-1) + x[:, 3:6] @ c


def vertical_norm(x, top):
    """``|g|`` (1), a Casimir."""
    return np.linalg.norm(x[:, 3:6], axis=-1)


def vertical_momentum(x, top):
    """``g . m`` (kg m2 s-1), the angular momentum about the vertical: a Casimir."""
    return np.sum(x[:, :3] * x[:, 3:6], axis=-1)


def exact(x0, top, t):
    """The exact states (N, 6) at time ``t`` of starts ``x0`` (N, 6) of a symmetric top: the
    Lagrange top, ``I1 = I2`` with the centre of mass on axis 3 above the pivot (``c1 = c2 =
    0 <= c3``), by :func:`stability.heavy_top.exact.body_states`; None for any other top."""
    moments, c = _top(top)
    if moments[0] != moments[1] or c[0] != 0.0 or c[1] != 0.0 or not c[2] >= 0.0:
        return None
    return body_states(float(t), x0, moments[0], moments[2], c[2])


def example(n, seed=0):
    """Starts and tops for generic tests: ``n`` states of a tilted, spinning top; the first and
    the last top are asymmetric, the second symmetric (the one :func:`exact` covers)."""
    rng = np.random.default_rng(seed)
    tilt = 0.3 + 0.1 * rng.random(n)
    g = np.column_stack([np.sin(tilt) * 0.6, np.sin(tilt) * 0.8, np.cos(tilt)])
    m = np.column_stack([0.1 * rng.standard_normal(n), 0.1 * rng.standard_normal(n),
                         4.0 + rng.random(n)])
    tops = [np.array([1.0, 1.2, 0.5, 0.0, 0.0, 1.5]), np.array([2.0, 2.0, 0.8, 0.0, 0.0, 3.0]),
            np.array([1.0, 1.3, 0.9, 0.1, 0.0, 2.0])]
    return np.concatenate([m, g], axis=1), tops


HEAVY_TOP = Scene(
    name="heavy_top",
    module=__name__,
    title="heavy top on a fixed pivot (angular momentum and vertical)",
    equations="m' = m x I^-1 m + g x c, g' = g x I^-1 m (c = M g l chi)",
    latex=(r"\dot m = m \times I^{-1} m + g \times c, \qquad \dot g = g \times I^{-1} m"
           r" \qquad (c = M g\, l\, \chi)"),
    components=("m1", "m2", "m3", "g1", "g2", "g3"),
    units=(cv.UNITS_ANGULAR_MOMENTUM,) * 3 + (cv.UNITS_DIMENSIONLESS,) * 3,
    methods=METHODS,
    observe=observe,
    tracked=tracked,
    invariants={"energy": energy, "vertical_norm": vertical_norm,
                "vertical_momentum": vertical_momentum},
    kept_by={"energy": "preserves_energy", "vertical_norm": "preserves_casimir",
             "vertical_momentum": "preserves_casimir"},
    exact=exact,
    example=example,
    tracked_units=cv.UNITS_DIMENSIONLESS,
    linearisation=Linearisation(top_rhs, top_jvp, top_params),
)
