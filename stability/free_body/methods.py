"""The free body's methods: :data:`METHODS`, the integrators of Euler's equations
(:mod:`stability.integrators`, one module per method family) and the free body's own exact flow,
``exact``; :func:`method_spec` looks one up by name. ``stability.METHODS`` is this table.

To add a method: write its step kernel and spec in the module of its family in
:mod:`stability.integrators`, then add the spec to :data:`METHODS` below. Tests parametrized over
``METHODS`` (order, invariants) cover it from then on.

**The exact flow as a one-step method.** Each step maps m to the exact solution at time h by
Jacobi elliptic functions (Landau & Lifshitz, *Mechanics*, section 37; the formulas, regimes and
accuracy are in :mod:`stability.free_body.exact`), so its only error is rounding: |L| and the
energy are kept to round-off, with no truncation error at any h. It is the exact free flow that
Celledoni, Fasso, Safstrom & Zanna (SIAM J. Sci. Comput. 30, 2084 (2008)) use inside splittings.
The increment is formed without cancellation, so with the driver's compensated sum 2000 steps
stay within ~4e-15 of one evaluation of :func:`stability.exact_omega`. Near the separatrix the
state's own rounding (1 ulp per step) moves k'^2 and hence the flip times, as it would for any
method: that is the problem's conditioning, not the method's error. Cost: one elliptic set-up and
one sn/cn/dn evaluation per step (~1 microsecond), scalar code that does not vectorize across
members, so per step it is two to three orders of magnitude slower than ``rk4``; it wins when h
can be as large as the output spacing. Use it as the reference in ensembles and to separate
integrator error from the dynamics.
"""

import math

from numba import njit

from ..integrators.composition import LP4, LP6, LP8
from ..integrators.lgvi import LGVI
from ..integrators.lie_poisson import LP2
from ..integrators.midpoint import MIDPOINT
from ..integrators.moser_veselov import DMV, DMV4
from ..integrators.munthe_kaas import RKMK4
from ..integrators.rk4 import RK4
from ..integrators.spec import P_I1, P_I2, P_I3, MethodSpec, body_params
from ..util.checks import registered
from .exact import flow_increment


@njit(inline="always")
def exact_step(m1, m2, m3, h, p, s):
    """Exact flow over time h from m (canonical frame); returns the increment and 0 iterations.

    The increment is formed without cancellation
    (:func:`stability.free_body.exact.flow_increment`), to a relative error of a few ulp, so the
    driver's compensated sum keeps the state as accurate as an exact evaluation from t = 0.
    Never raises and never allocates.

    Parameters
    ----------
    m1, m2, m3 : float
        The body angular momentum (kg m^2/s), canonical frame (I1 <= I2 <= I3).
    h : float
        The step (s).
    p : ndarray
        The body's parameters (:func:`stability.integrators.spec.body_params`).
    s : ndarray
        The method's scratch (unused).

    Returns
    -------
    d1, d2, d3 : float
        The increment of m over h.
    iterations : int
        0: the flow is explicit.
    """
    I1 = p[P_I1]
    I2 = p[P_I2]
    I3 = p[P_I3]
    d1, d2, d3 = flow_increment(I1, I2, I3, m1 / I1, m2 / I2, m3 / I3, h)
    return I1 * d1, I2 * d2, I3 * d3, 0


EXACT = MethodSpec(
    name="exact",
    title="exact elliptic flow",
    order=math.inf,
    step=exact_step,
    params=body_params,
    family="exact flow",
    poisson=True,
    preserves_casimir=True,
    preserves_energy=True,
    symmetric=True,
    implicit=False,
    evaluations=1,
    reference=(
        "Landau & Lifshitz, Mechanics, section 37; Celledoni, Fasso, Safstrom & Zanna, "
        "SIAM J. Sci. Comput. 30, 2084 (2008)"
    ),
    stages=1,
    note="no truncation error at any h; the reference for ensembles, ~1 us per member-step",
    # w is exact at any step, but flips and crossings are found by sign changes between steps:
    # flip counts right at 3 rad, off by 2 at 3.5.
    max_step_angle=3.0,
)


#: Every method of the free body by name, in the order the tables and studies list them.
METHODS: dict[str, MethodSpec] = {
    spec.name: spec for spec in (RK4, LP2, LP4, LP6, LP8, EXACT, DMV, DMV4, LGVI, RKMK4, MIDPOINT)}


def method_spec(name) -> MethodSpec:
    """Return the spec registered under ``name``; ``ValueError`` listing the known names if none.

    Parameters
    ----------
    name : str or MethodSpec
        A key of :data:`METHODS` (``"rk4"``, ``"lp2"``, ...); a spec is returned as it is.

    Returns
    -------
    MethodSpec
    """
    if isinstance(name, MethodSpec):
        return name
    return registered(METHODS, name, "method")


def method_names() -> tuple:
    """The names of the registered methods (``stability methods``), for a method key's
    choices in a study file."""
    return tuple(METHODS)
