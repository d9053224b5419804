"""What an integrator is: its step kernel and the facts it declares about itself.

Every method registers one :class:`MethodSpec`. Its kernel has one signature::

    step(m1, m2, m3, h, p, s) -> (d1, d2, d3, iterations)

It takes the body angular momentum ``m = I w`` in the *canonical frame* (moments sorted
ascending, ``I1 <= I2 <= I3``), the step ``h`` in s, the float64 parameter array ``p`` made by
``spec.params(moments, h)`` and the stage index ``s`` (0 <= s < ``spec.stages``), and returns the
*increment* of ``m`` made by that stage (so the driver can add the step's total with compensated
summation) and the number of nonlinear-solver iterations it used (0 for explicit methods, -1
when an implicit solve failed to converge). A one-stage method does the whole step at s = 0; a
composition runs its sub-flows as stages, each applied to ``m`` plus the increments of the
earlier stages, so the driver's loop over members stays innermost and vectorizes for every
stage. Kernels are ``njit(inline="always")`` so that the loop inlines them; the helpers they
call are ``njit(forceinline=True, error_model="numpy")`` where they are short
(:mod:`stability.engine.loop`, "Inlining").

Checklist for a new method (see :mod:`stability.free_body.methods`):

1. Write the step kernel in a module of its family, with the equation it implements tagged.
2. Declare a ``MethodSpec`` beside it: order, what it preserves, cost, reference.
3. Measure its ``max_step_angle`` (below) and declare it on the spec.
4. Add it to ``METHODS`` of :mod:`stability.free_body.methods`; the generic order, invariant and step-bound tests pick it up from there
   (``tests/test_registry.py`` for every scene it runs).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

# Layout of the common parameter array (canonical frame, I1 <= I2 <= I3).
P_I1, P_I2, P_I3 = 0, 1, 2  #: moments of inertia
P_INV1, P_INV2, P_INV3 = 3, 4, 5  #: 1 / I_i
#: Coefficients of m' = m x w written without cancellation:
#: m1' = A1 m2 m3, m2' = A2 m3 m1, m3' = A3 m1 m2 with
#: A1 = (I2 - I3) / (I2 I3), A2 = (I3 - I1) / (I3 I1), A3 = (I1 - I2) / (I1 I2).
P_A1, P_A2, P_A3 = 6, 7, 8
N_BODY_PARAMS = 9


def body_params(moments, h: float = 0.0) -> np.ndarray:
    """Common kernel parameters for canonical moments ``(I1, I2, I3)``; see the layout above.

    Differences of inverse moments are formed as (I_j - I_k) / (I_j I_k), which is exact to a
    rounding for nearly symmetric bodies, where 1/I_k - 1/I_j would cancel.

    Parameters
    ----------
    moments : array_like, shape (3,)
        Canonical (ascending) principal moments (I1, I2, I3), kg m^2.
    h : float, default 0.0
        Step in s; not used by these parameters, taken so that ``body_params`` can serve as a
        spec's ``params(moments, h)``.

    Returns
    -------
    ndarray, shape (N_BODY_PARAMS,)
        I1, I2, I3 (kg m^2), their inverses (kg^-1 m^-2) and A1, A2, A3 (kg^-1 m^-2), at the
        indices ``P_I1 ... P_A3``.
    """
    I1, I2, I3 = (float(x) for x in moments)
    p = np.empty(N_BODY_PARAMS)
    p[P_I1], p[P_I2], p[P_I3] = I1, I2, I3
    p[P_INV1], p[P_INV2], p[P_INV3] = 1.0 / I1, 1.0 / I2, 1.0 / I3
    p[P_A1] = (I2 - I3) / (I2 * I3)
    p[P_A2] = (I3 - I1) / (I3 * I1)
    p[P_A3] = (I1 - I2) / (I1 * I2)
    return p


@dataclass(frozen=True)
class MethodSpec:
    """A registered integrator: its kernel and what it declares about itself.

    The fields are the constructor's parameters and the instance's attributes.

    Parameters
    ----------
    name : str
        Short lowercase registry key (``"rk4"``, ``"lp2"``...).
    title : str
        Human name, e.g. "classical Runge-Kutta".
    order : float
        Global order of accuracy; ``math.inf`` for the exact flow.
    step : numba dispatcher
        The step kernel, signature in the module docstring.
    params : callable
        ``params(moments, h) -> float64 array`` for the kernel (canonical moments).
    family : str
        Method family ("Runge-Kutta", "Lie-Poisson splitting", ...).
    poisson : bool
        Symplectic / Poisson map of the free-body Lie-Poisson structure.
    preserves_casimir : bool
        Keeps the Casimirs of the scene's Lie-Poisson structure to round-off: |L| = |m| for the
        free body, |g| and g . m for the heavy top (a scene's ``kept_by`` names the invariants
        this flag stands for).
    preserves_energy : bool
        Keeps the energy to round-off (or solver tolerance).
    symmetric : bool
        Time-reversible (self-adjoint) one-step map.
    implicit : bool
        Needs a nonlinear solve per step.
    evaluations : int
        Cost unit per step: right-hand-side evaluations, or exactly solved sub-flows (rotations).
    reference : str
        Where the method comes from.
    stages : int
        Stages per step (kernel calls with s = 0 .. stages - 1).
    attitude_step : numba dispatcher or None
        The kernel that advances (m, q) together (scene ``free_body_attitude``, see
        ``stability.free_body.attitude``); the one fact that says whether the method carries the
        attitude::

            attitude_step(m1, m2, m3, q0, q1, q2, q3, h, p, s)
                -> (d1, d2, d3, e0, e1, e2, e3, iterations)

        returning the increments of m (identical to ``step``'s) and of the body-to-space unit
        quaternion q (scalar first). ``None`` when the method cannot carry the attitude.
    note : str
        One sentence on when to use it.
    max_step_angle : float
        The largest step angle ``h max|w|`` in rad (``max|w|``: the largest angular speed the
        exact motion from the member's start reaches, bounded by its energy and |L|) at which
        the method's results are still trustworthy. ``run_ensemble`` labels a member whose step
        angle exceeds it ``step_too_large`` instead of ok. Measured so: ensembles of 32 starts
        (24 random, 8 near the intermediate axis) on four bodies (I = (1, 2, 3), the tennis
        racket, a rod (0.1, 1, 1.05) and a nearly symmetric top (1, 1.02, 2)), run for at least
        40 rad of rotation; the bound is the largest angle of the grid 0.2, 0.3, 0.4, 0.5, 0.6, 0.7,
        0.85, 1, 1.2, 1.4, 1.7, 2, 2.5, 3, 3.5, 4, 5 at which, on every body, the median
        relative error of w at the end is below 0.3 and no member's flip count is off by more
        than one from the exact flow's. Beyond it the errors saturate at O(1), flips are
        missed or invented, or the method blows up. Even the exact flow has a bound: flips and
        crossings are located by sign changes between steps.
    """

    name: str
    title: str
    order: float
    step: object = field(repr=False)
    params: Callable = field(repr=False, default=body_params)
    family: str = ""
    poisson: bool = False
    preserves_casimir: bool = False
    preserves_energy: bool = False
    symmetric: bool = False
    implicit: bool = False
    evaluations: int = 1
    reference: str = ""
    stages: int = 1
    note: str = ""
    attitude_step: object = field(repr=False, default=None)
    max_step_angle: float | None = None

    @property
    def explicit(self) -> bool:
        return not self.implicit

    @property
    def attitude(self) -> bool:
        """Can carry the attitude (has an ``attitude_step``)."""
        return self.attitude_step is not None

    @property
    def is_exact(self) -> bool:
        return math.isinf(self.order)

    def describe(self) -> dict:
        """The declared facts as a plain dict (for tables and Dataset attributes)."""
        return {
            "name": self.name,
            "title": self.title,
            "order": "exact" if self.is_exact else int(self.order),
            "family": self.family,
            "poisson": self.poisson,
            "preserves_casimir": self.preserves_casimir,
            "preserves_energy": self.preserves_energy,
            "symmetric": self.symmetric,
            "implicit": self.implicit,
            "evaluations": self.evaluations,
            "attitude": self.attitude,
            "max_step_angle": self.max_step_angle,
            "reference": self.reference,
        }
