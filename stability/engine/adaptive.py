r"""Adaptive steps for any scene with a vector field: the Dormand-Prince 5(4) pair.

The explicit embedded pair of Dormand & Prince (J. Comput. Appl. Math. 6, 19 (1980)), order 5
propagated, order 4 for the error estimate, 7 stages of which the last is the next step's first
(FSAL: 6 evaluations of ``f`` per step). Each member is integrated to its own end time with its
own steps, chosen by the PI controller of Hairer, Norsett & Wanner (*Solving ODEs I*, II.4,
Eq. (4.13) and the code DOPRI5: ``h_new = h err^{-0.17} err_old^{0.04} / 0.9``, bounded to
``[h / 10, 5 h]``, no growth right after a rejection); a step with

.. math::

    \mathrm{err} = \Big(\frac1n \sum_i \Big(\frac{h \sum_j e_j k_{ji}}
    {\mathrm{atol} + \mathrm{rtol} \max(|y_i|, |\hat y_i|)}\Big)^2\Big)^{1/2} > 1

is rejected and redone with a smaller step. The first step is the rule of II.4 (p. 169): an
explicit Euler probe of the second derivative. Dense output: the method's own continuous
extension of order 4 (II.6, DOPRI5's ``CONTD5``), which the events (:mod:`stability.engine.events`)
are located on.

The state is updated with a compensated sum (Kahan; TwoSum of Knuth, *TAOCP* 2, 4.2.2): each
member carries what the rounding of ``y + increment`` left out into its next step, so a long
run does not take one rounding of the whole state per step. Near the separatrix that rounding
sets the flip times' error (the flip interval goes as ``ln(4/k')``): on members with
``k' ~ 1e-4`` it cut the largest error of the second flip from 1.0e-8 to 1.0e-9 at rtol 1e-12,
and from 2.4e-8 to 2.4e-10 at rtol 1e-14, where without it more steps had made it worse.

The loop is written once, as the template below, and rendered for each scene (its vector field
``rhs(x_0, ..., x_{n-1}, p)``, the scene's :class:`~stability.engine.tangent.Linearisation`) and
events (their ``g``), then kept in the disk cache (:func:`stability.engine.cache.load_module`).
Members run in tasks of ``BLOCK`` members, the tasks shared among threads as the fixed-step
loop's blocks are (:func:`stability.engine.driver.run_blocks`: the loop releases the GIL, so no
``prange``, whose parallel lowering took 4 s of each compile), ``LANES`` of them in step:
one member's step is a chain of seven dependent evaluations, which alone leaves the processor
waiting on each; the stages of eight members are computed together, and a lane whose member ends
takes the next. Each member depends on nothing but its own start, row, end time and the
tolerances (its arithmetic is the same on any lane), so the results are bitwise the same for any
threads and any chunks. A member that
needs more than ``max_steps`` steps (accepted and rejected) stops there with a status, and so does
one whose step falls below round-off in ``t`` (non-finite where its error estimate had become
NaN or inf): nothing hangs.
"""

from __future__ import annotations

import functools
import math
import sys
import time
from dataclasses import dataclass

import numba
import numpy as np

from ..util import conventions as cv
from .cache import compiling, load_module
from .driver import run_blocks
from .events import ACTIONS, DIRECTIONS, bracketed_root, checked_events, located
from .scene import Scene, checked_scene

# Dormand & Prince (1980), Table 2 (DOPRI5): nodes c, stages a, weights b (= a7, FSAL), and the
# error weights e = b - b_hat of the embedded order-4 solution.
C2, C3, C4, C5 = 1 / 5, 3 / 10, 4 / 5, 8 / 9
A21 = 1 / 5
A31, A32 = 3 / 40, 9 / 40
A41, A42, A43 = 44 / 45, -56 / 15, 32 / 9
A51, A52, A53, A54 = 19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729
A61, A62, A63, A64, A65 = 9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656
B1, B3, B4, B5, B6 = 35 / 384, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84
E1, E3, E4, E5, E6, E7 = (71 / 57600, -71 / 16695, 71 / 1920, -17253 / 339200, 22 / 525,
                          -1 / 40)
# Dense output of order 4 (Hairer, Norsett & Wanner, II.6; DOPRI5's CONTD5).
D1, D3, D4, D5, D6, D7 = (-12715105075 / 11282082432, 87487479700 / 32700410799,
                          -10690763975 / 1880347072, 701980252875 / 199316789632,
                          -1453857185 / 822651844, 69997945 / 29380423)
# PI step control (II.4; DOPRI5's defaults): exponents, safety factor, step ratio bounds.
BETA = 0.04
EXPO1 = 0.2 - 0.75 * BETA
SAFE = 0.9
FAC_MIN = 0.2  # h_new >= h / 5 after a rejection ...
FAC_MAX = 10.0  # ... and h_new <= 10 h
LOG_FLOOR = math.log(1e-4)  # the error's floor in the controller's memory, as its logarithm
#: Steps (accepted and rejected) a member may take by default.
MAX_STEPS = 100_000
#: Members a thread integrates in step (their stages computed together), and members per task
#: of the parallel loop (a lane whose member ends takes the next of its task).
LANES = 8
BLOCK = 64
#: Which scenes have adaptive steps, for the refusals of those that have none.
WITH_VECTOR_FIELD = ("scenes that declare a vector field have them: every scene of define_scene, "
                     "free_body, heavy_top, sphere_damper and gyrostat")

#: Statuses of an adaptive member (:data:`stability.util.conventions`).
STATUS_FLAGS = (cv.STATUS_OK, cv.STATUS_NONFINITE, cv.STATUS_MAX_STEPS,
                cv.STATUS_STEP_TOO_SMALL)
STATUS_MEANINGS = "ok non_finite max_steps step_too_small"

_TEMPLATE = '''\
"""Dormand-Prince 5(4) member loop of scene {scene!r}, {m} event(s).

Rendered from the template in stability/engine/adaptive.py; do not edit (sources {{digest}}).
"""

import math

import numpy as np
from numba import njit

from stability.engine.adaptive import (
    A21, A31, A32, A41, A42, A43, A51, A52, A53, A54, A61, A62, A63, A64, A65, B1, B3, B4, B5,
    B6, BETA, BLOCK, C2, C3, C4, C5, D1, D3, D4, D5, D6, D7, E1, E3, E4, E5, E6, E7, EXPO1,
    FAC_MAX, FAC_MIN, LANES, LOG_FLOOR, SAFE,
)
from stability.engine.events import taken_in_order
from stability.util.conventions import (
    STATUS_MAX_STEPS, STATUS_NONFINITE, STATUS_OK, STATUS_STEP_TOO_SMALL,
)
from {rhs_module} import {rhs_name} as rhs
{g_imports}


@njit(forceinline=True, error_model="numpy")
def _f(y, p, out):
    {fs}, = rhs({ys}, p)
{stores}


@njit(forceinline=True, error_model="numpy")
def _f_lanes(s, rows, row, out):
    """The vector field on every lane: s and out (n, LANES), lane l's parameters rows[row[l]]."""
    for l in range(LANES):
        {lane_fs}, = rhs({lane_ss}, rows[row[l]])
{lane_stores}


@njit(forceinline=True, error_model="numpy")
def _g(k, y, t, p):
{g_calls}
    return 0.0


@njit(forceinline=True, error_model="numpy")
def _dense(r, theta, out):
    """y(t_old + theta h) = r0 + theta (r1 + (1 - theta) (r2 + theta (r3 + (1 - theta) r4)))."""
    u = 1.0 - theta
    for i in range(out.shape[0]):
        out[i] = r[0, i] + theta * (r[1, i] + u * (r[2, i] + theta * (r[3, i] + u * r[4, i])))


@njit(forceinline=True, error_model="numpy")
def _coefficients(r, y, z, h, k1, k3, k4, k5, k6, k7, l):
    """The continuous extension of lane l's step h from y to z (DOPRI5's CONTD5
    coefficients)."""
    for j in range(y.shape[0]):
        r[0, j] = y[j, l]
        r[1, j] = z[j, l] - y[j, l]
        r[2, j] = h * k1[j, l] - r[1, j]
        r[3, j] = r[1, j] - h * k7[j, l] - r[2, j]
        r[4, j] = h * (D1 * k1[j, l] + D3 * k3[j, l] + D4 * k4[j, l] + D5 * k5[j, l]
                       + D6 * k6[j, l] + D7 * k7[j, l])


{root}


@njit(forceinline=True, error_model="numpy")
def _rms(v, y, z, rtol, atol, l):
    total = 0.0
    for i in range(v.shape[0]):
        s = v[i, l] / (atol + rtol * max(abs(y[i, l]), abs(z[i, l])))
        total += s * s
    return math.sqrt(total / v.shape[0])


@njit(error_model="numpy")
def _finish(i, l, y, t, nacc, nrej, err, esum, used, code, stopped, x, t_final, accepted,
            rejected, error, error_sum, h_last, status, stop_event, lane):
    """Member i's results, from lane l, which it leaves free."""
    for j in range(x.shape[1]):
        x[i, j] = y[j, l]
    t_final[i] = t[l]
    accepted[i] = nacc[l]
    rejected[i] = nrej[l]
    error[i] = err[l]
    error_sum[i] = esum[l]
    h_last[i] = used[l]
    status[i] = code
    stop_event[i] = stopped
    lane[l] = -1


@njit(error_model="numpy")
def _block(first, last, x, rows, group, t_end, rtol, atol, max_steps, directions, stops, keep,
           samples, t_final, accepted, rejected, error, error_sum, h_last, status, counts, times,
           stop_event, x_sample):
    """Members first to last - 1 on LANES lanes in step: the stages of all lanes are computed
    together (independent chains the processor overlaps), the rest lane by lane; a lane whose
    member ends takes the next. A member's arithmetic does not depend on its lane or on the
    other members, so neither do its results."""
    n = x.shape[1]
    m = directions.shape[0]
    n_samples = samples.shape[0]
    y = np.zeros((n, LANES))
    z = np.zeros((n, LANES))
    c = np.zeros((n, LANES))  # each state's compensation: what its rounding left out
    cz = np.zeros((n, LANES))  # the compensation of z, taken with the step
    s = np.zeros((n, LANES))
    k1 = np.zeros((n, LANES))
    k2 = np.zeros((n, LANES))
    k3 = np.zeros((n, LANES))
    k4 = np.zeros((n, LANES))
    k5 = np.zeros((n, LANES))
    k6 = np.zeros((n, LANES))
    k7 = np.zeros((n, LANES))
    r = np.empty((LANES, 5, n))
    g_old = np.empty((LANES, max(m, 1)))
    g_new = np.empty((LANES, max(m, 1)))
    t_hit = np.empty(max(m, 1))
    order = np.empty(max(m, 1), dtype=np.int64)
    a1 = np.empty(n)
    a2 = np.empty(n)
    a3 = np.empty(n)
    a4 = np.empty(n)
    lane = np.full(LANES, -1, dtype=np.int64)  # the member on each lane, -1 for none
    row = np.zeros(LANES, dtype=np.int64)
    t = np.zeros(LANES)
    h = np.zeros(LANES)
    tend = np.zeros(LANES)
    log_fac_old = np.zeros(LANES)
    was_rejected = np.zeros(LANES, dtype=np.bool_)
    bad = np.zeros(LANES, dtype=np.bool_)
    last_step = np.zeros(LANES, dtype=np.bool_)
    nacc = np.zeros(LANES, dtype=np.int64)
    nrej = np.zeros(LANES, dtype=np.int64)
    err = np.zeros(LANES)
    esum = np.zeros(LANES)
    used = np.zeros(LANES)
    si = np.zeros(LANES, dtype=np.int64)
    # the codes _finish takes, as int64 variables: literals would compile it once per value
    no_event = np.int64(-1)
    ok = np.int64(STATUS_OK)
    too_many = np.int64(STATUS_MAX_STEPS)
    following = first
    while True:
        busy = 0
        for l in range(LANES):  # each lane: its member's next step, or the next member
            while True:
                if lane[l] < 0:
                    if following >= last:
                        break
                    i = following
                    following += 1
                    lane[l] = i
                    row[l] = group[i]
                    p = rows[row[l]]
                    for j in range(n):
                        y[j, l] = x[i, j]
                        c[j, l] = 0.0
                        a1[j] = x[i, j]
                    tend[l] = t_end[i]
                    t[l] = 0.0
                    si[l] = 0
                    # samples at the start; element by element, as below: the two slices' shape
                    # checks (and their messages) cost 2 s of every compile
                    while si[l] < n_samples and samples[si[l]] <= 0.0:
                        for j in range(n):
                            x_sample[i, si[l], j] = x[i, j]
                        si[l] += 1
                    _f(a1, p, a2)
                    for j in range(n):
                        k1[j, l] = a2[j]
                    for k in range(m):
                        g_old[l, k] = _g(k, a1, 0.0, p)
                    # the first step: Hairer, Norsett & Wanner, II.4, p. 169
                    d0 = 0.0
                    d1 = 0.0
                    for j in range(n):
                        a3[j] = atol + rtol * abs(a1[j])
                        d0 += (a1[j] / a3[j]) ** 2
                        d1 += (a2[j] / a3[j]) ** 2
                    d0 = math.sqrt(d0 / n)
                    d1 = math.sqrt(d1 / n)
                    h0 = 1e-6 if (d0 < 1e-5 or d1 < 1e-5) else 0.01 * d0 / d1
                    h0 = min(h0, tend[l])
                    for j in range(n):
                        a4[j] = a1[j] + h0 * a2[j]
                    _f(a4, p, a1)
                    d2 = 0.0
                    for j in range(n):
                        d2 += ((a1[j] - a2[j]) / a3[j]) ** 2
                    d2 = math.sqrt(d2 / n) / h0
                    top = max(d1, d2)
                    h1 = max(1e-6, 1e-3 * h0) if top <= 1e-15 else (0.01 / top) ** 0.2
                    h[l] = min(100.0 * h0, h1, tend[l])
                    log_fac_old[l] = LOG_FLOOR
                    was_rejected[l] = False
                    bad[l] = False
                    nacc[l] = 0
                    nrej[l] = 0
                    err[l] = np.nan
                    esum[l] = 0.0
                    used[l] = np.nan
                i = lane[l]
                if nacc[l] + nrej[l] >= max_steps:
                    _finish(i, l, y, t, nacc, nrej, err, esum, used, too_many, no_event, x,
                            t_final, accepted, rejected, error, error_sum, h_last, status,
                            stop_event, lane)
                    continue
                if not (t[l] + h[l] > t[l]):
                    _finish(i, l, y, t, nacc, nrej, err, esum, used,
                            STATUS_NONFINITE if bad[l] else STATUS_STEP_TOO_SMALL, no_event, x,
                            t_final, accepted, rejected, error, error_sum, h_last, status,
                            stop_event, lane)
                    continue
                last_step[l] = t[l] + 1.01 * h[l] >= tend[l]
                if last_step[l]:
                    h[l] = tend[l] - t[l]
                busy += 1
                break
        if busy == 0:
            return
        for j in range(n):  # the stages, all lanes together
            for l in range(LANES):
                s[j, l] = y[j, l] + h[l] * A21 * k1[j, l]
        _f_lanes(s, rows, row, k2)
        for j in range(n):
            for l in range(LANES):
                s[j, l] = y[j, l] + h[l] * (A31 * k1[j, l] + A32 * k2[j, l])
        _f_lanes(s, rows, row, k3)
        for j in range(n):
            for l in range(LANES):
                s[j, l] = y[j, l] + h[l] * (A41 * k1[j, l] + A42 * k2[j, l] + A43 * k3[j, l])
        _f_lanes(s, rows, row, k4)
        for j in range(n):
            for l in range(LANES):
                s[j, l] = y[j, l] + h[l] * (A51 * k1[j, l] + A52 * k2[j, l] + A53 * k3[j, l]
                                            + A54 * k4[j, l])
        _f_lanes(s, rows, row, k5)
        for j in range(n):
            for l in range(LANES):
                s[j, l] = y[j, l] + h[l] * (A61 * k1[j, l] + A62 * k2[j, l] + A63 * k3[j, l]
                                            + A64 * k4[j, l] + A65 * k5[j, l])
        _f_lanes(s, rows, row, k6)
        for j in range(n):  # z = y + (increment + compensation), and what z rounds off
            for l in range(LANES):
                d = h[l] * (B1 * k1[j, l] + B3 * k3[j, l] + B4 * k4[j, l] + B5 * k5[j, l]
                            + B6 * k6[j, l]) + c[j, l]
                zj = y[j, l] + d
                back = zj - y[j, l]
                cz[j, l] = (y[j, l] - (zj - back)) + (d - back)
                z[j, l] = zj
        _f_lanes(z, rows, row, k7)
        for j in range(n):
            for l in range(LANES):
                s[j, l] = h[l] * (E1 * k1[j, l] + E3 * k3[j, l] + E4 * k4[j, l]
                                  + E5 * k5[j, l] + E6 * k6[j, l] + E7 * k7[j, l])
        for l in range(LANES):  # each lane's error, step control, events and samples
            i = lane[l]
            if i < 0:
                continue
            p = rows[row[l]]
            e = _rms(s, y, z, rtol, atol, l)
            if not (e < math.inf):  # NaN or inf: a much shorter step
                bad[l] = True
                nrej[l] += 1
                h[l] *= FAC_MIN
                was_rejected[l] = True
                continue
            bad[l] = False
            log_e = math.log(e)  # e^EXPO1 / fac_old^BETA as one exponential
            fac = max(1.0 / FAC_MAX, min(1.0 / FAC_MIN,
                                         math.exp(EXPO1 * log_e - BETA * log_fac_old[l]) / SAFE))
            h_new = h[l] / fac
            if e > 1.0:
                nrej[l] += 1
                h[l] = h[l] / min(1.0 / FAC_MIN, math.exp(EXPO1 * log_e) / SAFE)
                was_rejected[l] = True
                continue
            log_fac_old[l] = log_e if e > 1e-4 else LOG_FLOOR  # log(max(e, 1e-4))
            if was_rejected[l]:
                h_new = min(h_new, h[l])
            was_rejected[l] = False
            nacc[l] += 1
            err[l] = e
            local = 0.0  # the local error estimate's Euclidean norm, summed over the steps
            for j in range(n):
                local += s[j, l] * s[j, l]
            esum[l] += math.sqrt(local)
            used[l] = h[l]
            t0 = t[l]
            t_new = tend[l] if last_step[l] else t0 + h[l]
            for j in range(n):
                a1[j] = z[j, l]
            hits = 0
            for k in range(m):
                g_new[l, k] = _g(k, a1, t_new, p)
                up = g_old[l, k] < 0.0 and g_new[l, k] >= 0.0
                down = g_old[l, k] >= 0.0 and g_new[l, k] < 0.0
                if (up and directions[k] >= 0) or (down and directions[k] <= 0):
                    order[hits] = k
                    hits += 1
            if hits > 0 or (si[l] < n_samples and samples[si[l]] < t_new):
                _coefficients(r[l], y, z, h[l], k1, k3, k4, k5, k6, k7, l)  # the extension
            stopped = -1
            if hits > 0:
                for q in range(hits):
                    k = order[q]
                    t_hit[k] = _root(k, r[l], t0, t_new - t0, g_old[l, k], g_new[l, k], p, a2)
                stopped = taken_in_order(order, hits, t_hit, counts[i], times[i], keep, stops)
            t_upto = t_hit[stopped] if stopped >= 0 else t_new
            while si[l] < n_samples and samples[si[l]] <= t_upto:  # samples within the step
                if samples[si[l]] == t_new:
                    for j in range(n):
                        x_sample[i, si[l], j] = a1[j]
                else:
                    _dense(r[l], (samples[si[l]] - t0) / (t_new - t0), x_sample[i, si[l]])
                si[l] += 1
            if stopped >= 0:  # the state at the located time, from the continuous extension
                _dense(r[l], (t_hit[stopped] - t0) / (t_new - t0), a2)
                for j in range(n):
                    y[j, l] = a2[j]
                t[l] = t_hit[stopped]
                _finish(i, l, y, t, nacc, nrej, err, esum, used, ok, stopped, x,
                        t_final, accepted, rejected, error, error_sum, h_last, status,
                        stop_event, lane)
                continue
            for j in range(n):
                y[j, l] = z[j, l]
                c[j, l] = cz[j, l]
                k1[j, l] = k7[j, l]
            for k in range(m):
                g_old[l, k] = g_new[l, k]
            t[l] = t_new
            h[l] = h_new
            if t[l] >= tend[l]:
                _finish(i, l, y, t, nacc, nrej, err, esum, used, ok, no_event, x, t_final,
                        accepted, rejected, error, error_sum, h_last, status, stop_event, lane)


@njit(nogil=True, error_model="numpy")
def integrate(blocks, x, rows, group, t_end, rtol, atol, max_steps, directions, stops, keep,
              samples, t_final, accepted, rejected, error, error_sum, h_last, status, counts,
              times, stop_event, x_sample):
    """The tasks ``blocks`` (of BLOCK members each), one after another: a thread's share."""
    for q in range(blocks.shape[0]):
        b = blocks[q]
        _block(b * BLOCK, min(x.shape[0], (b + 1) * BLOCK), x, rows, group, t_end, rtol, atol,
               max_steps, directions, stops, keep, samples, t_final, accepted, rejected, error,
               error_sum, h_last, status, counts, times, stop_event, x_sample)
'''


@dataclass
class AdaptiveRun:
    """What :func:`integrate_adaptive` returns, members as rows.

    Parameters
    ----------
    x_final : ndarray, shape (N, n)
        State at ``t_final``.
    t_final : ndarray, shape (N,)
        The end time reached: the member's ``t_end``, a stop event's located time, or where a
        failure stopped it.
    accepted, rejected : ndarray of int, shape (N,)
        Steps accepted and rejected (redone shorter).
    error : ndarray, shape (N,)
        The last accepted step's error estimate, in units of the tolerance (<= 1).
    error_sum : ndarray, shape (N,)
        The Euclidean norms of the accepted steps' local error estimates, summed (the
        components' numbers in their own units): an estimate of the Euclidean norm of the
        global error at ``t_final``, a bound where the flow does not stretch the steps' errors
        (a rotation, a contraction).
    h_last : ndarray, shape (N,)
        The last accepted step.
    status : ndarray of int8, shape (N,)
        :data:`STATUS_FLAGS` (``ok``, ``non_finite``, ``max_steps``, ``step_too_small``).
    event_count : ndarray of int, shape (N, m)
        Crossings of each event (up to the stop).
    event_time : ndarray, shape (N, m, k)
        The first ``count`` crossing times of each event (NaN past those found), ``k`` the
        largest count.
    stop_event : ndarray of int, shape (N,)
        The event that stopped the member, -1 for none.
    x_sample : ndarray, shape (N, S, n)
        The state at each of the ``samples`` asked for, from the continuous extension (NaN past
        ``t_final``).
    wall_time, compile_time : float
        Seconds in the loop, and compiling or loading it.
    """

    x_final: np.ndarray
    t_final: np.ndarray
    accepted: np.ndarray
    rejected: np.ndarray
    error: np.ndarray
    h_last: np.ndarray
    status: np.ndarray
    event_count: np.ndarray
    event_time: np.ndarray
    stop_event: np.ndarray
    error_sum: np.ndarray
    x_sample: np.ndarray
    wall_time: float = 0.0
    compile_time: float = 0.0


def checked_tolerances(rtol, atol, max_steps=MAX_STEPS) -> tuple[float, float, int]:
    """``(rtol, atol, max_steps)`` as numbers; a one-line ValueError where ``rtol`` is not a
    finite number > 0, ``atol`` not a finite number >= 0, or ``max_steps`` not a whole number
    >= 1."""
    for name, value, low in (("rtol", rtol, "> 0"), ("atol", atol, ">= 0")):
        ok = isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(
            value, bool) and math.isfinite(value) and (value > 0 if name == "rtol" else
                                                      value >= 0)
        if not ok:
            raise ValueError(f"{name} must be a finite number {low}, got {value!r}")
    if isinstance(max_steps, bool) or not isinstance(max_steps, (int, np.integer)) or \
            max_steps < 1:
        raise ValueError(f"max_steps must be a whole number >= 1, got {max_steps!r}")
    return float(rtol), float(atol), int(max_steps)


def adaptive_scene(scene, caller: str) -> Scene:
    """``scene`` checked (:func:`~stability.engine.scene.checked_scene`) and with a vector field
    to take adaptive steps on; a one-line ValueError naming the scenes that have one."""
    scene = checked_scene(scene, caller)
    if scene.linearisation is None:
        raise ValueError(f"scene {scene.name!r} declares no vector field (a linearisation), so "
                         f"it has no adaptive steps; {WITH_VECTOR_FIELD}")
    return scene


def checked_samples(samples) -> np.ndarray:
    """The sample times as a float64 array (S,); a one-line ValueError where they are not
    finite, >= 0 and ascending."""
    if samples is None:
        return np.zeros(0)
    try:
        times = np.ascontiguousarray(samples, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise ValueError(f"samples must be times in s, got {samples!r}") from None
    if not np.all(np.isfinite(times)) or np.any(times < 0) or np.any(np.diff(times) < 0):
        raise ValueError("samples must be finite times >= 0 in s, in ascending order")
    return times


def integrate_adaptive(scene, x0, rows, group, t_end, *, rtol, atol, events=(),
                       max_steps=MAX_STEPS, samples=None) -> AdaptiveRun:
    """Integrate each member of ``scene`` from time 0 to its own ``t_end`` with adaptive
    Dormand-Prince 5(4) steps, locating its events; see the module docstring.

    Parameters
    ----------
    scene : Scene
        A scene with a vector field: every scene of :func:`stability.define_scene` and the
        registered ones that declare a linearisation (``free_body``, ``sphere_damper``).
    x0 : array_like, shape (N, n)
        Starts, in the kernels' frame.
    rows : array_like, shape (G, p)
        Parameter rows, as the linearisation's ``params`` makes them.
    group : array_like of int, shape (N,)
        Each member's row.
    t_end : float or array_like, shape (N,)
        Each member's end time (s), > 0.
    rtol, atol : float
        Tolerances of the error per step: ``rtol > 0``, ``atol >= 0``.
    events : Event or sequence of Event, optional
        :class:`stability.engine.events.Event`.
    max_steps : int, default MAX_STEPS
        Steps a member may take (accepted and rejected) before it is flagged ``max_steps``.
    samples : array_like, shape (S,), optional
        Times (s, ascending) at which each member's state is kept, taken from the continuous
        extension of the step that holds them: the integration is the same with and without.

    Returns
    -------
    AdaptiveRun
    """
    events, out, arguments = prepared_run(scene, x0, rows, group, t_end, rtol=rtol, atol=atol,
                                          events=events, max_steps=max_steps, samples=samples)
    loop = adaptive_loop(scene, tuple((e.g, e.name) for e in events))
    t0 = time.perf_counter()
    if not loop.signatures:
        with compiling(loop):
            loop(np.zeros(0, np.int64), np.ones((0, scene.width)), *arguments)
    out.compile_time = time.perf_counter() - t0
    t0 = time.perf_counter()
    n = out.x_final.shape[0]
    tasks = -(-n // BLOCK)
    members = np.minimum(BLOCK, n - BLOCK * np.arange(tasks))  # each task's work, as members
    run_blocks(loop, members, numba.get_num_threads(), (out.x_final, *arguments))
    out.wall_time = time.perf_counter() - t0
    return out


def prepared_run(scene, x0, rows, group, t_end, *, rtol, atol, events=(), max_steps=MAX_STEPS,
                 samples=None) -> tuple:
    """The checked input of :func:`integrate_adaptive` (its parameters), as the loop takes it.

    Returns
    -------
    events : tuple of Event
        The checked events.
    out : AdaptiveRun
        The results to fill, ``x_final`` holding the starts.
    arguments : tuple
        The loop's arguments after the states (``integrate(out.x_final, *arguments)``), the
        arrays of ``out`` among them.
    """
    scene = adaptive_scene(scene, "integrate_adaptive")
    rtol, atol, max_steps = checked_tolerances(rtol, atol, max_steps)
    samples = checked_samples(samples)
    x = np.array(x0, dtype=float, ndmin=2, copy=True)
    rows = np.ascontiguousarray(np.atleast_2d(rows), dtype=float)
    group = np.ascontiguousarray(group, dtype=np.int64).reshape(-1)
    if x.shape[1:] != (scene.width,) or group.shape != (x.shape[0],):
        raise ValueError(f"scene {scene.name!r}: x0 must have shape (N, {scene.width}) and group "
                         f"(N,), got {x.shape} and {group.shape}")
    if group.size and (group.min() < 0 or group.max() >= rows.shape[0]):
        raise ValueError(f"group must number rows 0 to {rows.shape[0] - 1}")
    t_end = np.ascontiguousarray(np.broadcast_to(np.asarray(t_end, dtype=float), group.shape))
    if not np.all(np.isfinite(t_end) & (t_end > 0)):
        raise ValueError("t_end must be finite and > 0 for every member")
    events = checked_events(events, x[0] if x.shape[0] else np.ones(scene.width),
                            rows[0] if rows.shape[0] else np.ones(1))
    n, m = x.shape[0], len(events)
    kept = max([e.count for e in events], default=0)
    out = AdaptiveRun(
        x_final=x, t_final=np.zeros(n), accepted=np.zeros(n, np.int64),
        rejected=np.zeros(n, np.int64), error=np.zeros(n), h_last=np.zeros(n),
        status=np.zeros(n, np.int8), event_count=np.zeros((n, m), np.int64),
        event_time=np.full((n, m, kept), np.nan), stop_event=np.zeros(n, np.int64),
        error_sum=np.zeros(n), x_sample=np.full((n, samples.size, scene.width), np.nan))
    directions = np.array([DIRECTIONS[e.direction] for e in events], dtype=np.int64)
    stops = np.array([ACTIONS[e.action] for e in events], dtype=np.bool_)
    keep = np.array([e.count for e in events], dtype=np.int64)
    arguments = (rows, group, t_end, rtol, atol, max_steps, directions, stops, keep, samples,
                 out.t_final, out.accepted, out.rejected, out.error, out.error_sum, out.h_last,
                 out.status, out.event_count, out.event_time, out.stop_event, out.x_sample)
    return events, out, arguments


def adaptive_loop(scene: Scene, events: tuple = ()):
    """The compiled loop of ``scene`` with the events ``((g, name), ...)``, made once a
    process (from the disk cache after the first)."""
    return _loop(scene, tuple(g for g, _ in events))


@functools.lru_cache(maxsize=None)
def _loop(scene: Scene, gs: tuple):
    lin = scene.linearisation
    rhs_module, rhs_name = _bound(lin.rhs, lin.module)
    n = scene.width
    ys = ", ".join(f"y[{i}]" for i in range(n))
    fs = ", ".join(f"f{i}" for i in range(n))
    g_imports, g_calls = [], []
    for k, g in enumerate(gs):
        module, name = located(g)
        g_imports.append(f"from {module} import {name} as user_g{k}")
        wrapped = "user_g{k}" if hasattr(g, "py_func") else \
            'njit(inline="always", error_model="numpy")(user_g{k})'
        g_imports.append(f"g{k} = {wrapped.format(k=k)}")
        g_calls.append(f"    if k == {k}:\n        return float(g{k}(y, t, p))")
    source = _TEMPLATE.format(
        scene=scene.name, m=len(gs), rhs_module=rhs_module, rhs_name=rhs_name,
        g_imports="\n".join(g_imports), fs=fs, ys=ys,
        stores="\n".join(f"    out[{i}] = f{i}" for i in range(n)),
        lane_fs=fs, lane_ss=", ".join(f"s[{i}, l]" for i in range(n)),
        lane_stores="\n".join(f"        out[{i}, l] = f{i}" for i in range(n)),
        g_calls="\n".join(g_calls) or "    pass",
        root=bracketed_root("r", "y", "_dense(r, (c - t0) / h, y)", "the dense output"))
    functions = [lin.rhs.py_func] + [getattr(g, "py_func", g) for g in gs]
    roots = tuple(dict.fromkeys([rhs_module, "stability.engine.adaptive",
                                 "stability.engine.events"]
                                + [f.__module__ for f in functions]))
    stem = f"{scene.name}__dopri5" + (f"__events{len(gs)}" if gs else "")
    return load_module(stem, source, roots, tuple(functions)).integrate


def _bound(function, module: str) -> tuple[str, str]:
    """(module, name) of the ``@njit`` ``function`` at the top level of ``module`` (a user
    scene's kernels module), else of its own function's module."""
    home = module or function.py_func.__module__
    found = sys.modules.get(home)
    name = next((key for key, value in vars(found).items() if value is function), None) \
        if found is not None else None
    if name is None:
        raise ValueError(f"the vector field {function.py_func.__qualname__} must be a "
                         f"module-level @njit function bound to a name in {home}")
    return home, name


__all__ = ["AdaptiveRun", "MAX_STEPS", "STATUS_FLAGS", "STATUS_MEANINGS", "WITH_VECTOR_FIELD",
           "adaptive_loop", "adaptive_scene", "checked_samples", "checked_tolerances", "integrate_adaptive",
           "prepared_run"]
