"""The orbit-averaged Earth: its figure axis in space under the rings of the Sun and the Moon.

The state is ``(k1, k2, k3, t)``: the unit figure axis in the ecliptic frame of the epoch and the
time (the Moon's ring turns with its node). The spin is averaged into the angular momentum
``C W k`` and each orbit into its ring; what is left is the slow precession and the 18.6-year
nutation (:mod:`stability.earth.methods`, the averaged model). Parameters:
``(H / W, Sun's orbit, Moon's orbit)``. Invariant: ``|k| = 1``.
"""

import math

import numpy as np
from numba import njit

from ..util import conventions as cv
from .methods import AVERAGED_METHODS
from ..scenes.free_body import component
from ..scenes.spec import Scene


@njit(inline="always")
def observe(k1, k2, k3, t, p, ia, ib, ic):
    """``(k_a, sqrt(k_b^2 + k_c^2), 0)``."""
    kb = component(k1, k2, k3, ib)
    kc = component(k1, k2, k3, ic)
    return component(k1, k2, k3, ia), math.sqrt(kb * kb + kc * kc), 0.0


def tracked(x, p, axes):
    """:func:`observe` in NumPy over states ``x`` (N, 4)."""
    return x[:, axes[0]], np.hypot(x[:, axes[1]], x[:, axes[2]]), np.zeros(x.shape[0])


def axis_norm(x, earth):
    """``|k|`` (1)."""
    return np.linalg.norm(x[:, :3], axis=-1)


def example(n, seed=0):
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
    title="orbit-averaged figure axis of the Earth (precession and nutation)",
    equations="k' = sum_j 3 k_j / (2 (1 - e_j^2)^(3/2)) (H / W) (n_j . k) (k x n_j), t' = 1",
    components=("k1", "k2", "k3", "t"),
    units=(cv.UNITS_DIMENSIONLESS,) * 3 + (cv.UNITS_TIME,),
    methods=AVERAGED_METHODS,
    observe=observe,
    tracked=tracked,
    invariants={"axis_norm": axis_norm},
    kept_by={"axis_norm": False},  # RK4 keeps |k| to its order
    example=example,
)
