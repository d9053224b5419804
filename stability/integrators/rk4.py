"""Classical fourth-order Runge-Kutta on Euler's equations in momentum form.

Explicit, order 4, 4 right-hand-side evaluations and no transcendental functions per step, so it
is the cheapest method per step. It preserves neither |L| nor the energy: both drift linearly in
time (dissipative sign, relative energy drift ~ 5e-6 per unit time at h = 0.1 for I = (1, 2, 3)).
Use it for short and medium horizons at h up to ~0.1 / |w|; prefer a Lie-Poisson method for
long runs or when invariants matter.
"""

from numba import njit

from .spec import P_A1, P_A2, P_A3, MethodSpec, body_params


@njit(inline="always")
def euler_rhs(m1, m2, m3, p):
    """Euler's equations m' = m x I^-1 m: ``(A1 m2 m3, A2 m3 m1, A3 m1 m2)``."""
    return p[P_A1] * m2 * m3, p[P_A2] * m3 * m1, p[P_A3] * m1 * m2


@njit(inline="always")
def rk4_step(m1, m2, m3, h, p, s):
    """One RK4 step (a single stage); returns the increment of m and 0 solver iterations."""
    a1, a2, a3 = euler_rhs(m1, m2, m3, p)
    hh = 0.5 * h
    b1, b2, b3 = euler_rhs(m1 + hh * a1, m2 + hh * a2, m3 + hh * a3, p)
    c1, c2, c3 = euler_rhs(m1 + hh * b1, m2 + hh * b2, m3 + hh * b3, p)
    d1, d2, d3 = euler_rhs(m1 + h * c1, m2 + h * c2, m3 + h * c3, p)
    s = h / 6.0
    return (
        s * (a1 + 2.0 * (b1 + c1) + d1),
        s * (a2 + 2.0 * (b2 + c2) + d2),
        s * (a3 + 2.0 * (b3 + c3) + d3),
        0,
    )


RK4 = MethodSpec(
    name="rk4",
    title="classical Runge-Kutta",
    order=4,
    step=rk4_step,
    params=body_params,
    family="Runge-Kutta",
    symmetric=False,
    evaluations=4,
    attitude=True,  # through its twin kernel in integrators/kinematics.py
    reference="Kutta (1901); Hairer, Norsett & Wanner, Solving ODEs I, Table II.1.2",
    note="cheapest per step and most accurate per unit work on short horizons; energy drifts linearly",
)
