r"""The Earth's two scenes: the oblate Earth torqued by the Sun and the Moon, and its figure
axis averaged over their orbits.

``lunisolar_earth``, angular momentum, attitude and time: the state is ``(m1, m2, m3, q0, q1,
q2, q3, t)``, the body angular momentum, the body-to-space unit quaternion (scalar first; space
is the ecliptic frame of the epoch) and the time, which the prescribed orbits of the Sun and the
Moon depend on. Parameters: ``(A, C)`` and the two orbits' elements
(:func:`stability.earth.precession.earth_parameters`). Equations, methods and references:
:mod:`stability.earth.methods`. Invariants: :math:`|q| = 1` and :math:`m_3` (the torque of
either body on an oblate Earth has no component along its figure axis). Tracking: the figure
axis :math:`k = R(q)\, e_3` in space, its component :math:`k_a` along space axis :math:`a` and
:math:`\sqrt{k_b^2 + k_c^2}` across it (with :math:`a = 3`: the cosine and sine of the
obliquity).

``precessing_axis``, the orbit-averaged Earth, its figure axis in space under the rings of the
Sun and the Moon: the state is ``(k1, k2, k3, t)``, the unit figure axis in the ecliptic frame of
the epoch and the time (the Moon's ring turns with its node). The spin is averaged into the
angular momentum :math:`C W k` and each orbit into its ring; what is left is the slow precession
and the 18.6-year nutation (:mod:`stability.earth.methods`, the averaged model). Parameters:
``(H / W, Sun's orbit, Moon's orbit)``. Invariant: :math:`|k| = 1`. Its kernels are named
``axis_*``.
"""

import math

import numpy as np
from numba import njit

from ..util import conventions as cv
from .methods import AVERAGED_METHODS, METHODS
from ..engine.scene import Scene, component


@njit(forceinline=True, error_model="numpy")
def figure_axis(q0, q1, q2, q3):
    """``R(q) e3``: the body's axis 3 in space."""
    return (2.0 * (q1 * q3 + q0 * q2), 2.0 * (q2 * q3 - q0 * q1),
            1.0 - 2.0 * (q1 * q1 + q2 * q2))


@njit(inline="always")
def observe(m1, m2, m3, q0, q1, q2, q3, t, p, ia, ib, ic):
    """``(k_a, sqrt(k_b^2 + k_c^2), 0)`` of the figure axis k in space."""
    k1, k2, k3 = figure_axis(q0, q1, q2, q3)
    kb = component(k1, k2, k3, ib)
    kc = component(k1, k2, k3, ic)
    return component(k1, k2, k3, ia), math.sqrt(kb * kb + kc * kc), 0.0


def figure_axes(x):
    """The figure axis in space of states ``x`` (N, 8) or (N, T, 8): shape (..., 3)."""
    q0, q1, q2, q3 = (x[..., 3 + i] for i in range(4))
    return np.stack([2.0 * (q1 * q3 + q0 * q2), 2.0 * (q2 * q3 - q0 * q1),
                     1.0 - 2.0 * (q1 * q1 + q2 * q2)], axis=-1)


def tracked(x, p, axes):
    """:func:`observe` in NumPy over states ``x`` (N, 8)."""
    k = figure_axes(x)
    return k[:, axes[0]], np.hypot(k[:, axes[1]], k[:, axes[2]]), np.zeros(x.shape[0])


def quaternion_norm(x, earth):
    """``|q|`` (1)."""
    return np.linalg.norm(x[:, 3:7], axis=-1)


def axial_momentum(x, earth):
    """``m3`` (kg m2 s-1): kept exactly by an oblate Earth under any external torque whose
    line of action passes through its centre (gravity gradient)."""
    return x[:, 2].copy()


def example(n, seed=0):
    """Starts and parameter sets for generic tests, in scaled units (A = 1, spin ~ 1 rad/s,
    orbits of periods ~ 10 to 60 s), so a few dozen steps show every term."""
    rng = np.random.default_rng(seed)
    tilt = 0.4 + 0.05 * rng.random(n)
    spin = rng.random(n) * 2.0 * np.pi
    # q = Rx(tilt) Rz(spin): figure axis at obliquity ``tilt``, spin phase ``spin``.
    q = np.column_stack([np.cos(tilt / 2) * np.cos(spin / 2), np.sin(tilt / 2) * np.cos(spin / 2),
                         np.sin(tilt / 2) * np.sin(spin / 2), np.cos(tilt / 2) * np.sin(spin / 2)])
    m = np.column_stack([0.01 * rng.standard_normal(n), 0.01 * rng.standard_normal(n),
                         1.0 + 0.1 * rng.random(n)])
    x = np.concatenate([m, q, np.zeros((n, 1))], axis=1)
    sun = [0.04, 0.017, 0.1, 0.3, 1.2, 0.0, 0.0, 0.0, 0.0]
    moon = [0.08, 0.055, 0.6, 2.0, 0.7, 0.01, 0.0898, 2.2, -0.02]
    earths = [np.array([1.0, 1.1, *sun, *moon]), np.array([1.0, 1.05, *sun, *moon]),
              np.array([2.0, 2.3, *sun, 0.0, *moon[1:]])]
    return x, earths


LUNISOLAR_EARTH = Scene(
    name="lunisolar_earth",
    module=__name__,
    title="oblate Earth torqued by the Sun and the Moon (angular momentum, attitude, time)",
    equations="m' = m x I^-1 m + sum_j 3 G M_j / r_j^3 s_j x I s_j, q' = q (0, I^-1 m) / 2, t' = 1",
    latex=(r"\dot m = m \times I^{-1} m + \sum_j \frac{3 G M_j}{r_j^3}\, s_j \times I s_j, \qquad"
           r" \dot q = \tfrac12\, q\, (0, I^{-1} m), \qquad \dot t = 1"),
    components=("m1", "m2", "m3", "q0", "q1", "q2", "q3", "t"),
    units=(cv.UNITS_ANGULAR_MOMENTUM,) * 3 + (cv.UNITS_DIMENSIONLESS,) * 4 + (cv.UNITS_TIME,),
    methods=METHODS,
    observe=observe,
    tracked=tracked,
    invariants={"quaternion_norm": quaternion_norm, "axial_momentum": axial_momentum},
    # q is turned by rotations; no term of the equations changes m3.
    kept_by={"quaternion_norm": True, "axial_momentum": True},
    example=example,
    tracked_units=cv.UNITS_DIMENSIONLESS,
)


# The orbit-averaged figure axis ------------------------------------------------------------------

@njit(inline="always")
def axis_observe(k1, k2, k3, t, p, ia, ib, ic):
    """``(k_a, sqrt(k_b^2 + k_c^2), 0)``."""
    kb = component(k1, k2, k3, ib)
    kc = component(k1, k2, k3, ic)
    return component(k1, k2, k3, ia), math.sqrt(kb * kb + kc * kc), 0.0


def axis_tracked(x, p, axes):
    """:func:`axis_observe` in NumPy over states ``x`` (N, 4)."""
    return x[:, axes[0]], np.hypot(x[:, axes[1]], x[:, axes[2]]), np.zeros(x.shape[0])


def axis_norm(x, earth):
    """``|k|`` (1)."""
    return np.linalg.norm(x[:, :3], axis=-1)


def axis_example(n, seed=0):
    """Starts and parameter sets for generic tests in scaled units (periods of ~10 to 100 s)."""
    rng = np.random.default_rng(seed)
    tilt = 0.4 + 0.05 * rng.random(n)
    phase = 2.0 * np.pi * rng.random(n)
    x = np.column_stack([np.sin(tilt) * np.sin(phase), -np.sin(tilt) * np.cos(phase),
                         np.cos(tilt), np.zeros(n)])
    sun = [0.04, 0.017, 0.1, 0.3, 1.2, 0.0, 0.0, 0.0, 0.0]
    moon = [0.08, 0.055, 0.6, 2.0, 0.7, 0.01, 0.0898, 2.2, -0.05]
    return x, [np.array([h, *sun, *moon]) for h in (1.0, 3.0, 0.5)]


PRECESSING_AXIS = Scene(
    name="precessing_axis",
    module=__name__,
    title="orbit-averaged figure axis of the Earth (precession and nutation)",
    equations="k' = sum_j 3 k_j / (2 (1 - e_j^2)^(3/2)) (H / W) (n_j . k) (k x n_j), t' = 1",
    latex=(r"\dot k = \sum_j \frac{3 k_j}{2 (1 - e_j^2)^{3/2}}\, \frac{H}{W}\, (n_j \cdot k)\,"
           r" (k \times n_j), \qquad \dot t = 1"),
    components=("k1", "k2", "k3", "t"),
    units=(cv.UNITS_DIMENSIONLESS,) * 3 + (cv.UNITS_TIME,),
    methods=AVERAGED_METHODS,
    observe=axis_observe,
    tracked=axis_tracked,
    invariants={"axis_norm": axis_norm},
    kept_by={"axis_norm": False},  # RK4 keeps |k| to its order
    example=axis_example,
    tracked_units=cv.UNITS_DIMENSIONLESS,
)
