"""Timed sweeps: one method over a ladder of step sizes, or an adaptive one over tolerances
(the member loop's Dormand-Prince 5(4), SciPy's DOP853).

Each point of a sweep runs the whole ensemble once and records the kernel's wall time (compilation
excluded; short runs repeated, :func:`timed_propagate`), the work (right-hand-side evaluations or
exact sub-flows, ``spec.evaluations`` x steps, and nonlinear-solver iterations per step), the
members that failed, and the (max, p99, median) over members of the relative errors of w, the
energy and |L| at the end against a reference (:func:`stability.free_body.accuracy.final_errors`);
for the methods that carry the attitude, the first members' attitude errors against a reference
attitude as well. A sweep is a list of such points (dicts), coarsest first;
:func:`stability.free_body.work_precision.measure.work_precision_dataset` stacks them.
"""

from __future__ import annotations

import math
import time

import numpy as np

from ...engine.adaptive import integrate_adaptive
from ..model import euler_system
from ..attitude import propagate_attitude
from ...core.quaternions import IDENTITY, attitude_error
from ..propagate import propagate
from ..accuracy import METRICS, error_statistics, final_errors
from ..scene import FREE_BODY
from ...util import conventions as cv

#: Kernel runs shorter than MIN_TIMING seconds are repeated up to REPEATS times and the fastest
#: time is kept (:func:`timed_propagate`).
MIN_TIMING = 0.2
REPEATS = 5


def step_grid(t_end: float, h_max: float, h_min: float, per_octave: int) -> np.ndarray:
    """Step counts n (ascending, distinct) with h = t_end / n from about h_max down to h_min.

    Parameters
    ----------
    t_end : float
        Run length, s.
    h_max, h_min : float
        Coarsest and finest step, s; the first count is ``ceil(t_end / h_max)``, and counts
        whose step would go below ``h_min`` are left out.
    per_octave : int
        Counts per doubling of n (geometric spacing ``2 ** (1 / per_octave)``, rounded).

    Returns
    -------
    ndarray of int64, shape (K,)
        ``per_octave`` counts per doubling, the first ``ceil(t_end / h_max)``.
    """
    n0 = max(1, math.ceil(t_end / h_max - 1e-9))
    n_last = t_end / h_min
    counts = []
    k = 0
    while True:
        n = round(n0 * 2.0 ** (k / per_octave))
        if n > n_last * (1 + 1e-9):
            break
        if not counts or n > counts[-1]:
            counts.append(n)
        k += 1
    return np.array(counts or [n0], dtype=np.int64)


def jittered_starts(w0, members: int, seed: int) -> np.ndarray:
    """``members`` starts (members, 3): w0 perturbed by a random relative 1e-3 (member 0 is w0).

    Parameters
    ----------
    w0 : array_like, shape (3,)
        The central start, rad/s.
    members : int
        Number of starts.
    seed : int
        Seed of the normal jitter (standard deviation ``1e-3 |w0|`` per component).

    Returns
    -------
    ndarray, shape (members, 3)
        The starts, rad/s.
    """
    rng = np.random.default_rng(np.random.SeedSequence(seed))
    jitter = 1e-3 * np.linalg.norm(w0) * rng.standard_normal((members, 3))
    jitter[0] = 0.0
    return w0 + jitter


def sweep_point(h=np.nan, rtol=np.nan, steps=np.nan, wall=np.nan, evaluations=np.nan,
                iterations=np.nan, failed=0, members=1, errors=None) -> dict:
    """One point of a sweep: scalars, and (max, p99, median) of each error (NaN if not run).

    Parameters
    ----------
    h : float, default NaN
        Step, s (NaN for scipy's adaptive runs).
    rtol : float, default NaN
        scipy's relative tolerance (NaN for the fixed-step methods).
    steps : int or float, default NaN
        Steps per member; NaN leaves ``member_step_time`` NaN.
    wall : float, default NaN
        Kernel wall time for the whole ensemble, s.
    evaluations : float, default NaN
        Right-hand-side evaluations or exact sub-flows per member.
    iterations : float, default NaN
        Nonlinear-solver iterations per step, mean over members.
    failed : int, default 0
        Members whose run failed.
    members : int, default 1
        Ensemble size, for the time per member-step.
    errors : dict, optional
        :func:`stability.free_body.accuracy.final_errors` of the run (``w``, ``energy``, ``momentum``,
        each of shape (N,)); None leaves the error statistics NaN.

    Returns
    -------
    dict
        ``h``, ``rtol``, ``steps``, ``wall_time``, ``member_step_time`` (s), ``evaluations``,
        ``iterations``, ``failed``, and ``w_error``, ``energy_error``, ``momentum_error``,
        ``attitude_error`` (ndarray, shape (3,), in the order of
        :data:`stability.free_body.accuracy.METRICS`; the attitude one NaN, filled in by the caller).
    """
    point = {
        "h": h, "rtol": rtol, "steps": steps, "wall_time": wall,
        "member_step_time": wall / (members * steps) if steps == steps else np.nan,
        "evaluations": evaluations, "iterations": iterations, "failed": failed,
    }
    for key in ("w", "energy", "momentum"):
        point[f"{key}_error"] = (error_statistics(errors[key]) if errors is not None
                                 else np.full(3, np.nan))
    point["attitude_error"] = np.full(len(METRICS), np.nan)
    return point


def timed_propagate(spec, moments, m0, h, n_steps):
    """``propagate`` once, repeated while short: returns the run and its fastest wall time.

    A run shorter than ``MIN_TIMING`` seconds is repeated (at most ``REPEATS`` times in all,
    or until the repeats add up to ``MIN_TIMING``) and the minimum kept, the usual defence of
    a benchmark against a busy machine; the results are identical (the loop is deterministic).

    Parameters
    ----------
    spec : MethodSpec or str
        The method (registry name or spec).
    moments : array_like, shape (3,)
        Principal moments, kg m^2.
    m0 : ndarray, shape (N, 3)
        Initial body angular momenta m = I w, body frame, kg m^2/s.
    h : float
        Step, s.
    n_steps : int
        Number of steps.

    Returns
    -------
    run : Propagation
        The first run (:func:`stability.free_body.propagate.propagate`, no progress bar).
    wall : float
        Fastest kernel wall time over the repeats, s.
    """
    return fastest_of(lambda: propagate(spec, moments, m0, h, n_steps, progress=False))


def fastest_of(run_once):
    """``run_once()`` (a run with a ``wall_time``), repeated while short as
    :func:`timed_propagate` says: the first run and the fastest wall time.

    Parameters
    ----------
    run_once : callable
        Runs the kernel once; returns an object with ``wall_time`` (s).

    Returns
    -------
    run : object
        The first run.
    wall : float
        Fastest wall time over the repeats, s.
    """
    run = run_once()
    best, total, repeats = run.wall_time, run.wall_time, 1
    while total < MIN_TIMING and repeats < REPEATS:
        again = run_once()
        best, total, repeats = min(best, again.wall_time), total + again.wall_time, repeats + 1
    return run, best


def attitude_errors(spec, body, w0, q_ref, h, n_steps) -> np.ndarray:
    """Rotation angle (rad) between each member's attitude after n_steps and ``q_ref``; (N,).

    NaN for a member whose run failed; all NaN when the method cannot carry the attitude.

    Parameters
    ----------
    spec : MethodSpec
        The method; ``spec.attitude`` says whether it carries the attitude.
    body : RigidBody
        The body (its ``moments``, kg m^2).
    w0 : ndarray, shape (N, 3)
        Starts, rad/s; every member starts at the identity attitude.
    q_ref : array_like, shape (N, 4)
        Reference attitudes after ``n_steps`` (unit quaternions, scalar first, body to space),
        from :func:`stability.free_body.accuracy.attitude_reference`.
    h : float
        Step, s.
    n_steps : int
        Number of steps.

    Returns
    -------
    ndarray, shape (N,)
        Rotation angles, rad.
    """

    if not spec.attitude:
        return np.full(len(w0), np.nan)
    moments = body.moments
    run = propagate_attitude(spec, moments, moments * w0, IDENTITY, h, n_steps, progress=False)
    error = attitude_error(run.extras["q_final"], q_ref)
    return np.where(run.status == cv.STATUS_OK, error, np.nan)


def sweep_method(spec, body, w0, w_ref, t_end, counts, budget, stop_error,
                 attitude=None) -> list[dict]:
    """Run one method over the step counts ``counts`` (exact methods: one step of t_end).

    ``attitude = (n, q_ref)``: the first n members are also run with their attitude from the
    identity, and their attitude errors against ``q_ref`` (n, 4) are recorded.

    A step count whose predicted kernel time (the last point's time scaled by the step ratio)
    would take the method's total (of the w runs' timed kernels) past ``budget`` seconds is
    not run; the sweep also stops once the median relative w error is below ``stop_error`` or
    has not improved for three points (the conditioning floor).

    Parameters
    ----------
    spec : MethodSpec
        The method.
    body : RigidBody
        The body (its ``moments``, kg m^2).
    w0 : ndarray, shape (N, 3)
        Starts, rad/s.
    w_ref : ndarray, shape (N, 3)
        Reference w at ``t_end``, rad/s (:func:`stability.free_body.accuracy.exact_final_w`).
    t_end : float
        Run length, s.
    counts : array_like of int, shape (K,)
        Step counts, ascending (:func:`step_grid`); the step is ``t_end / n``.
    budget : float
        Most kernel seconds the method may spend on the sweep, s.
    stop_error : float
        The sweep stops once the median relative w error is below this.
    attitude : tuple of (int, ndarray), optional
        ``(n, q_ref)``: run the first n members' attitude as well, against ``q_ref``, shape
        (n, 4); None or n = 0 runs no attitude.

    Returns
    -------
    list of dict
        :func:`sweep_point` per step count run, coarsest first.
    """
    moments = body.moments
    m0 = moments * w0
    members = w0.shape[0]
    if spec.is_exact:
        counts = np.array([1], dtype=np.int64)
    points, spent, stalled = [], 0.0, 0
    for n in counts:
        n = int(n)
        if points and spent + points[-1]["wall_time"] * n / points[-1]["steps"] > budget:
            break
        run, wall = timed_propagate(spec, moments, m0, t_end / n, n)
        ok = run.status == cv.STATUS_OK
        w_end = np.where(ok[:, None], run.m_final / moments, np.nan)
        errors = final_errors(moments, w0, w_end, w_ref)
        point = sweep_point(
            h=t_end / n, steps=n, wall=wall, evaluations=spec.evaluations * n,
            iterations=float(np.mean(run.iterations)) / n, failed=int(np.sum(~ok)),
            members=members, errors=errors,
        )
        if attitude is not None and attitude[0] > 0:
            k, q_ref = attitude
            point["attitude_error"] = error_statistics(
                attitude_errors(spec, body, w0[:k], q_ref, t_end / n, n))
        spent += wall
        if points:
            previous = points[-1]["w_error"][2]
            stalled = stalled + 1 if point["w_error"][2] > 0.8 * previous else 0
        points.append(point)
        if point["w_error"][2] < stop_error or stalled >= 3:
            break
    return points


def sweep_adaptive(body, w0, w_ref, t_end, rtols, atols) -> list[dict]:
    """The member loop's adaptive Dormand-Prince 5(4) (:mod:`stability.engine.adaptive`), each
    member with its own steps, per pair of tolerances.

    ``wall_time`` is the loop's (compilation excluded), repeated while short like
    :func:`timed_propagate`; ``steps`` and ``evaluations`` are means over members (6 per
    step tried, accepted or rejected, the last stage of each being the next one's first, and 2
    for the first step's choice).

    Parameters
    ----------
    body : RigidBody
        The body.
    w0 : ndarray, shape (N, 3)
        Starts, rad/s.
    w_ref : ndarray, shape (N, 3)
        Reference w at ``t_end``, rad/s.
    t_end : float
        Run length, s.
    rtols, atols : sequence of float
        Relative tolerances and absolute ones (kg m2 s-1, on m = I w), pairwise, one sweep
        point each.

    Returns
    -------
    list of dict
        :func:`sweep_point` per pair, in their order.
    """
    moments = body.moments
    m0 = moments * w0
    members = w0.shape[0]
    rows = np.atleast_2d(FREE_BODY.linearisation.params(moments, 0.0))
    group = np.zeros(members, dtype=np.int64)
    points = []
    for rtol, atol in zip(rtols, atols):
        run, best = fastest_of(lambda: integrate_adaptive(FREE_BODY, m0, rows, group, t_end,
                                                          rtol=rtol, atol=atol))
        ok = run.status == cv.STATUS_OK
        w_end = np.where(ok[:, None], run.x_final / moments, np.nan)
        tried = run.accepted + run.rejected
        points.append(sweep_point(
            rtol=rtol, steps=float(np.mean(tried)), wall=best,
            evaluations=float(np.mean(6 * tried + 2)), iterations=0.0,
            failed=int(np.sum(~ok)), members=members,
            errors=final_errors(moments, w0, w_end, w_ref)))
    return points


def sweep_scipy(body, w0, w_ref, t_end, rtols, scale) -> list[dict]:
    """scipy ``solve_ivp`` DOP853 on the whole ensemble as one system, per tolerance.

    The right-hand side is vectorized over members (:func:`stability.free_body.model.euler_system`);
    ``atol = rtol * scale``. ``evaluations`` is scipy's ``nfev`` (each call evaluates every
    member once); ``wall_time`` is the whole call, Python overhead included.

    Parameters
    ----------
    body : RigidBody
        The body.
    w0 : ndarray, shape (N, 3)
        Starts, rad/s.
    w_ref : ndarray, shape (N, 3)
        Reference w at ``t_end``, rad/s (:func:`stability.free_body.accuracy.exact_final_w`).
    t_end : float
        Run length, s.
    rtols : sequence of float
        Relative tolerances, one sweep point each.
    scale : float
        Typical size of w (the spin), rad/s: ``atol = rtol * scale``.

    Returns
    -------
    list of dict
        :func:`sweep_point` per tolerance, in the order of ``rtols``; a call that fails
        (``sol.status != 0``) gives a point with every member failed and NaN errors.
    """
    from scipy.integrate import solve_ivp

    moments = body.moments
    members = w0.shape[0]
    rhs = euler_system(body, members)
    y0 = np.ascontiguousarray(w0.T).ravel()
    points = []
    for rtol in rtols:
        t0 = time.perf_counter()
        sol = solve_ivp(rhs, (0.0, t_end), y0, method="DOP853", rtol=rtol, atol=rtol * scale,
                        t_eval=[t_end])
        wall = time.perf_counter() - t0
        if sol.status != 0:
            points.append(sweep_point(rtol=rtol, wall=wall, evaluations=sol.nfev,
                                      failed=members, members=members))
            continue
        w_end = sol.y[:, -1].reshape(3, members).T
        ok = np.all(np.isfinite(w_end), axis=1)
        errors = final_errors(moments, w0, np.where(ok[:, None], w_end, np.nan), w_ref)
        points.append(sweep_point(rtol=rtol, wall=wall, evaluations=float(sol.nfev),
                                  iterations=0.0, failed=int(np.sum(~ok)), members=members,
                                  errors=errors))
    return points
