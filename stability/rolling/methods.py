"""The exact step of a round body rolling or slipping along a track of straight sections.

A body of mass M, radius R and moment of inertia I = k M R^2 about its axis (k = 2/5 a solid
sphere, 1/2 a solid cylinder, 1 a hoop) moves along a track of straight sections, section j
inclined at theta_j (positive: downhill in the direction of travel x). With v the speed of the
centre, w the spin (positive when it rolls forward, v = R w) and u = v - R w the speed of the
contact point (the slip), Coulomb friction with static and kinetic coefficients mu_s >= mu_k
gives two regimes [Goldstein, Poole & Safko, *Classical Mechanics* (2002), 1.6; Cross, Am. J.
Phys. 73, 914 (2005)]::

    rolling (u = 0):   v' = g sin(theta) / (1 + k),    w' = v' / R,
                       needs |f| = k M g |sin(theta)| / (1 + k) <= mu_s M g cos(theta),
                       that is tan|theta| <= mu_s (1 + 1 / k);                            (1)
    slipping (s = sign u):
                       v' = g (sin(theta) - s mu_k cos(theta)),
                       w' = s mu_k g cos(theta) / (k R),
                       u' = g sin(theta) - s mu_k g cos(theta) (1 + 1 / k).              (2)

Within a section both are motions at constant accelerations, so the step is exact: it advances
in closed form to the first event inside the step, applies it, and goes on with the rest of the
step. The events, each located in closed form (to a rounding):

- the slip ends, u = 0 at tau = -u / u': the body rolls if (1) allows it, or else slips on with
  the friction reversed;
- a section boundary, x(tau) = x_b, the smaller positive root of a quadratic, taken in its
  cancellation-free form: a rolling body that reaches a section too steep for (1) starts to slip.

The friction's work while slipping, mu_k M g cos(theta) |u|, is integrated exactly too (state
``heat``), so the energy ``M v^2 / 2 + I w^2 / 2 + M g z(x) + heat`` is kept to round-off. The
state also records the number of switches, the time and place the body last started to roll.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..integrators.spec import MethodSpec

# Parameter layout: one row per group.
P_G, P_K, P_R, P_MU_S, P_MU_K, P_MASS, P_SECTIONS = 0, 1, 2, 3, 4, 5, 6
#: Section j: its start x_j at P_TRACK + 3 j (x_0 = -inf), then sin(theta_j) and cos(theta_j).
P_TRACK = 7
#: At most this many sections.
MAX_SECTIONS = 4
N_ROLLING_PARAMS = P_TRACK + 3 * MAX_SECTIONS
#: Events handled inside one step; more (a step longer than many bounces in a valley) leaves the
#: rest of the step undone and returns a non-finite time, so the member is labelled non-finite.
MAX_EVENTS = 64
#: State layout.
X, V, W, T, MODE, SWITCHES, T_ROLL, X_ROLL, HEAT = range(9)
N_STATE = 9


def rolling_params(row, h: float = 0.0) -> np.ndarray:
    """The kernel parameters: ``row`` as :func:`track_row` made it, the same for every step."""
    row = np.asarray(row, dtype=float).reshape(-1)
    if row.size != N_ROLLING_PARAMS:
        raise ValueError(f"a rolling body and its track are {N_ROLLING_PARAMS} numbers "
                         f"(stability.rolling.methods.track_row), got {row.size}")
    return row.copy()


def track_row(k, radius, mu_s, mu_k, *, angles=(0.0,), starts=(), mass=1.0, g=9.80665):
    """One group's parameters: a body ``I = k M R^2`` on a track of straight sections.

    Parameters
    ----------
    k : float
        I / (M R^2) (1).
    radius : float
        R (m).
    mu_s, mu_k : float
        Static and kinetic friction coefficients (1).
    angles : sequence of float
        Inclination of each section in rad, positive downhill in the direction of +x.
    starts : sequence of float
        Where sections 1, 2, ... start (m), ascending; section 0 runs from -inf.
    mass : float
        M (kg), for the energies.
    g : float
        Gravity (m s-2).
    """
    angles = np.atleast_1d(np.asarray(angles, dtype=float))
    starts = np.atleast_1d(np.asarray(starts, dtype=float))
    if not 1 <= angles.size <= MAX_SECTIONS or starts.size != angles.size - 1:
        raise ValueError(f"a track has 1 to {MAX_SECTIONS} sections and one start fewer than "
                         f"angles; got {angles.size} angles and {starts.size} starts")
    if starts.size > 1 and np.any(np.diff(starts) <= 0):
        raise ValueError(f"section starts must ascend, got {starts.tolist()}")
    row = np.zeros(N_ROLLING_PARAMS)
    row[[P_G, P_K, P_R, P_MU_S, P_MU_K, P_MASS, P_SECTIONS]] = (
        g, k, radius, mu_s, mu_k, mass, angles.size)
    for j, angle in enumerate(angles):
        row[P_TRACK + 3 * j] = -np.inf if j == 0 else starts[j - 1]
        row[P_TRACK + 3 * j + 1] = math.sin(angle)
        row[P_TRACK + 3 * j + 2] = math.cos(angle)
    for j in range(angles.size, MAX_SECTIONS):  # unused sections start at +inf
        row[P_TRACK + 3 * j] = np.inf
        row[P_TRACK + 3 * j + 2] = 1.0
    return row


@njit(inline="always")
def section_of(x, v, p):
    """The section the body is in: the last whose start it has passed (moving back from a
    start it has just reached, the one before)."""
    j = 0
    for i in range(1, int(p[P_SECTIONS])):
        xb = p[P_TRACK + 3 * i]
        if x > xb or (x == xb and v >= 0.0):
            j = i
    return j


@njit(forceinline=True, error_model="numpy")
def can_roll(sn, cs, p):
    """Condition (1): the static friction rolling needs is available."""
    k = p[P_K]
    return k * abs(sn) <= p[P_MU_S] * cs * (1.0 + k)


@njit(forceinline=True, error_model="numpy")
def time_to(distance, v, a):
    """Smallest tau > 0 with v tau + a tau^2 / 2 = distance, inf if none (no cancellation)."""
    if a == 0.0:
        tau = distance / v if v != 0.0 else math.inf
        return tau if tau > 0.0 else math.inf
    disc = v * v + 2.0 * a * distance
    if disc < 0.0:
        return math.inf
    q = -(v + math.copysign(math.sqrt(disc), v))  # roots q / a and -2 distance / q
    best = math.inf
    if q != 0.0:
        r1 = q / a
        r2 = -2.0 * distance / q
        if r1 > 0.0:
            best = r1
        if 0.0 < r2 < best:
            best = r2
    return best


@njit(inline="always")
def exact_step(x, v, w, t, mode, switches, t_roll, x_roll, heat, h, p, s):
    """Advance (1)-(2) exactly by h through every event in the step; the increments."""
    g, k, radius, mu_k, mass = p[P_G], p[P_K], p[P_R], p[P_MU_K], p[P_MASS]
    x1, v1, w1, t1, m1, n1, tr1, xr1, q1 = x, v, w, t, mode, switches, t_roll, x_roll, heat
    left = h
    for _ in range(MAX_EVENTS):
        if left <= 0.0:
            break
        j = section_of(x1, v1, p)
        sn, cs = p[P_TRACK + 3 * j + 1], p[P_TRACK + 3 * j + 2]
        if m1 == 0.0 and not can_roll(sn, cs, p):
            m1 = 1.0 if sn > 0.0 else -1.0  # the rolling motion would outrun the contact
            n1 += 1.0
        u = v1 - radius * w1
        if m1 == 0.0:
            a = g * sn / (1.0 + k)
            alpha = a / radius
            du = 0.0
            tau_stop = math.inf
        else:
            a = g * (sn - m1 * mu_k * cs)
            alpha = m1 * mu_k * g * cs / (k * radius)
            du = a - radius * alpha
            tau_stop = max(-u / du, 0.0) if m1 * du < 0.0 else math.inf
        tau_ahead = time_to(p[P_TRACK + 3 * (j + 1)] - x1, v1, a) if j + 1 < MAX_SECTIONS \
            else math.inf
        tau_back = time_to(p[P_TRACK + 3 * j] - x1, v1, a) if j > 0 else math.inf
        tau = min(left, tau_stop, tau_ahead, tau_back)
        if m1 != 0.0:
            q1 += mu_k * mass * g * cs * m1 * (u * tau + 0.5 * du * tau * tau)
        x1 += (v1 + 0.5 * a * tau) * tau
        v1 += a * tau
        w1 += alpha * tau
        t1 += tau
        left -= tau
        if tau == tau_stop:
            w1 = v1 / radius  # u = 0
            n1 += 1.0
            if can_roll(sn, cs, p):
                m1 = 0.0
                tr1, xr1 = t1, x1
            else:
                m1 = -m1
        elif tau == tau_ahead:
            x1 = p[P_TRACK + 3 * (j + 1)]
        elif tau == tau_back:
            x1 = p[P_TRACK + 3 * j]
    if left > 0.0:
        t1 = math.nan
    return (x1 - x, v1 - v, w1 - w, t1 - t, m1 - mode, n1 - switches, tr1 - t_roll,
            xr1 - x_roll, q1 - heat, 0)


EXACT = MethodSpec(
    name="exact",
    title="exact flow with events located in closed form",
    order=math.inf,
    step=exact_step,
    params=rolling_params,
    family="exact flow",
    preserves_energy=True,
    reference="constant accelerations between events; Cross, Am. J. Phys. 73, 914 (2005)",
    note="the only method needed: the motion between events is a polynomial in time",
)

METHODS = {EXACT.name: EXACT}
