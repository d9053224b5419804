"""The speed-against-error study: which integrator to use, at which accuracy, in numbers.

Every registered method (``stability.METHODS``, so methods added later join by themselves) runs
the same two ensembles over a sweep of step sizes h, and scipy's DOP853 runs them as one system
over a sweep of tolerances, in the same process:

- **tennis**: spin about the intermediate axis, each member nudged by ``epsilon`` in a random
  perpendicular direction, over a horizon of a few flips; the hard, ill-conditioned workload;
- **stable**: spin about a stable axis (largest or smallest moment), nudged the same way.

For each (workload, method, h) it records the wall time of the kernel (``Propagation.wall_time``,
compilation excluded) for the whole ensemble and per member-step, the work (right-hand-side
evaluations or exactly solved sub-flows, ``spec.evaluations`` x steps, and nonlinear-solver
iterations per step), and errors at the end against the exact solution: the max, 99th
percentile and median over members of the relative error of w, and of the relative energy and
|L| errors; for the methods that carry the attitude (``stability.attitude``), the first
``[attitude] members`` also run with it, and their attitude error (the angle between the
method's rotation and a DOP853 reference on (w, q) at rtol = 1e-13, the exact attitude not
being in the package) gets the same statistics. A third workload, the **long horizon** (``>= 1e6`` steps of a few members at a fixed
h), records the energy and |L| error against time, whose log-log slope says whether a method's
invariant error is bounded (0), a round-off random walk (1/2, Brouwer's law) or a linear drift
(1).

Near the separatrix the final error has a floor set by conditioning, not by the method: the
flip time depends on D2 = L^2 - 2 E I2 (literature notes 1.5, 2.2), and members whose D2 is
close to zero (random directions near the separatrix's) amplify one rounding of D2 (u L^2,
u = 2^-53) into an error of 1e-9 or more in w(T). The study measures that floor: D2 of every
start is moved by one rounding (along the sphere |m| = L) and the spread of the exact solution
at T is reported with the same statistics as the errors. It is the error of a method that
rounds its whole state once, at the level of ulp(|m|), somewhere along the run; a composition
does that at every stage, and its max error over the tennis ensemble stalls near the floor,
while a compensated one-stage update (rk4: only the small increment is rounded) can go below
it. The members near the separatrix set the max, which is why the p99 and the median are
reported beside it.

The outputs: a Dataset (``work_precision.nc``; dims ``workload``, ``method``, ``sweep``,
``metric``, and ``long_time`` for the long horizon), the work-precision figure, the
invariant-drift figure, and ``work_precision.md``, the Markdown tables that say which method is
fastest at each accuracy (quoted in the README under "How to choose an integrator").
"""

from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np
import xarray as xr

from .. import conventions as cv
from ..body import RigidBody
from ..dataset import CONVENTIONS, history_line, software_attrs
from ..driver import propagate
from ..ensemble import perturbed_starts
from ..exact import exact_omega
from ..integrators import METHODS, method_spec
from ..io import save
from ..threads import numba_threads
from .config import ConfigError, Key, Schema, Section, StudyKind, StudySummary, to_toml

NAME = "work_precision"

#: Name of scipy's DOP853 in the ``method`` dimension (run as one system over all members).
SCIPY = "dop853"

#: Workloads in the order of the ``workload`` dimension.
WORKLOADS = ("tennis", "stable")

#: Statistics over members, in the order of the ``metric`` dimension.
METRICS = ("max", "p99", "median")

#: Accuracy targets of the tables (relative w error reached by the p99 member).
TARGETS = (1e-2, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12)

#: Long-horizon log-log slopes that separate the three behaviours of an invariant's error:
#: below BOUNDED_SLOPE "bounded", above DRIFT_SLOPE "linear drift", between them "random walk".
BOUNDED_SLOPE = 0.25
DRIFT_SLOPE = 0.75
#: Relative invariant errors below this are round-off (~1e4 ulps), whatever their slope.
ROUNDOFF_LEVEL = 1e-12

#: Kernel runs shorter than MIN_TIMING seconds are repeated up to REPEATS times and the fastest
#: time is kept (``timed_propagate``).
MIN_TIMING = 0.2
REPEATS = 5

#: Figure stems.
FIGURES = ("work_precision", "invariant_drift")


def _method_names() -> tuple:
    return tuple(METHODS)


SCHEMA = Schema(
    top=(
        Key("title", "str", "Speed against error of every integrator on the free rigid body",
            "one line describing the run (the Dataset's title)"),
    ),
    sections=(
        Section("body", "the rigid body, by its principal moments", (
            Key("moments", "floats", [1.0, 2.0, 3.0], "principal moments I1, I2, I3 (distinct)",
                unit="kg m2", minimum=0.0, exclusive_minimum=True, length=3),
            Key("physical", "bool", True,
                "require the triangle inequality of real bodies (false: mathematical body)"),
            Key("name", "str", "body", "label of the body"),
        )),
        Section("tennis", "ensemble spun about the intermediate axis (the hard workload)", (
            Key("members", "int", 10_000, "number of members", minimum=1),
            Key("spin", "float", 1.0, "spin rate W", unit="rad s-1", minimum=0.0,
                exclusive_minimum=True),
            Key("epsilon", "float", 1e-2,
                "perturbation relative to the spin, random perpendicular direction",
                minimum=0.0, exclusive_minimum=True, maximum=1.0),
            Key("t_end", "float", 50.0, "horizon (a few flip intervals)", unit="s",
                minimum=0.0, exclusive_minimum=True),
            Key("seed", "int", 1, "seed of the random directions", minimum=0),
        )),
        Section("stable", "ensemble spun about a stable axis", (
            Key("axis", "str", "largest", "the stable axis: the one with this moment",
                choices=("smallest", "largest")),
            Key("members", "int", 10_000, "number of members", minimum=1),
            Key("spin", "float", 1.0, "spin rate W", unit="rad s-1", minimum=0.0,
                exclusive_minimum=True),
            Key("epsilon", "float", 0.1, "perturbation relative to the spin",
                minimum=0.0, exclusive_minimum=True, maximum=1.0),
            Key("t_end", "float", 50.0, "horizon", unit="s", minimum=0.0,
                exclusive_minimum=True),
            Key("seed", "int", 2, "seed of the random directions", minimum=0),
        )),
        Section("sweep", "the step sizes tried per method", (
            Key("methods", "strs", [], "methods to run; empty: every registered method",
                choices=_method_names),
            Key("h_max", "float", 0.5, "largest step (times spin: the step's rotation angle)",
                unit="s", minimum=0.0, exclusive_minimum=True),
            Key("h_min", "float", 1e-4, "smallest step tried", unit="s", minimum=0.0,
                exclusive_minimum=True),
            Key("per_octave", "int", 2, "step sizes per halving of h", minimum=1),
            Key("budget", "float", 12.0,
                "kernel seconds per method and workload; a step size whose predicted time "
                "would exceed it is not run", unit="s", minimum=0.0, exclusive_minimum=True),
            Key("stop_error", "float", 1e-13,
                "stop refining a method once its median relative w error is below this",
                minimum=0.0, exclusive_minimum=True),
        )),
        Section("scipy", "scipy's DOP853 on each ensemble as one system", (
            Key("enabled", "bool", True, "run it"),
            Key("rtols", "floats", [1e-3, 1e-5, 1e-7, 1e-9, 1e-11, 1e-13],
                "relative tolerances (atol = rtol x spin)", minimum=1e-15, maximum=0.1),
        )),
        Section("attitude", "attitude errors, for the methods that carry the attitude", (
            Key("members", "int", 1000,
                "members of each ensemble (the first ones) also run with their attitude; 0: "
                "no attitude", minimum=0),
        )),
        Section("long", "the long-horizon run for invariant behaviour", (
            Key("steps", "int", 1_000_000, "steps per method", minimum=100),
            Key("h", "float", 0.1, "step", unit="s", minimum=0.0, exclusive_minimum=True),
            Key("members", "int", 8, "members (starts jittered around w0); errors are RMS over "
                "them", minimum=1),
            Key("w0", "floats", [0.3, 1.0, 0.9], "central start", unit="rad s-1", length=3),
            Key("samples", "int", 10_000, "states kept per member (evenly spaced)", minimum=10),
            Key("seed", "int", 3, "seed of the jitter", minimum=0),
        )),
        Section("output", "where the results go", (
            Key("dir", "str", "results/work_precision", "output folder"),
            Key("dataset", "str", "work_precision.nc", "file name of the Dataset (netCDF)"),
            Key("table", "str", "work_precision.md", "file name of the Markdown tables"),
            Key("figures", "bool", True, "draw the two figures"),
            Key("formats", "strs", ["png", "pdf"], "figure formats",
                choices=("png", "pdf", "svg")),
        )),
    ),
)

#: ``--quick``: small ensembles, a few step sizes, a short long-horizon run (used by the tests).
QUICK = {
    "tennis": {"members": 256, "t_end": 30.0},
    "stable": {"members": 256, "t_end": 30.0},
    "sweep": {"h_max": 0.5, "h_min": 0.03, "per_octave": 1, "budget": 2.0},
    "scipy": {"rtols": [1e-4, 1e-8]},
    "attitude": {"members": 32},
    "long": {"steps": 20_000, "members": 4, "samples": 1000},
}


def check(config: dict, source: str) -> dict:
    """Checks across keys: distinct moments, h_min < h_max, the long run's samples fit."""
    try:
        _body(config)
    except ValueError as exc:
        raise ConfigError(str(exc), source, "body") from None
    moments = sorted(config["body"]["moments"])
    if moments[0] == moments[1] or moments[1] == moments[2]:
        raise ConfigError(
            f"must be three distinct moments (the study needs an intermediate axis), got "
            f"{config['body']['moments']}", source, "body", "moments",
        )
    sweep = config["sweep"]
    if sweep["h_min"] > sweep["h_max"]:
        raise ConfigError(f"must be <= h_max = {sweep['h_max']}, got {sweep['h_min']}",
                          source, "sweep", "h_min")
    long = config["long"]
    if long["samples"] > long["steps"]:
        raise ConfigError(f"must be <= steps = {long['steps']}, got {long['samples']}",
                          source, "long", "samples")
    if not all(math.isfinite(x) for x in long["w0"]) or not any(long["w0"]):
        raise ConfigError(f"must be finite and not zero, got {long['w0']}", source, "long", "w0")
    return config


def outputs(config: dict) -> list[str]:
    """Files a run writes into the output folder."""
    out = config["output"]
    names = [out["dataset"], out["table"], "config.toml"]
    if out["figures"]:
        names += [f"{stem}.{fmt}" for stem in FIGURES for fmt in out["formats"]]
    return names


def _body(config: dict) -> RigidBody:
    b = config["body"]
    return RigidBody(*b["moments"], physical=b["physical"], name=b["name"])


# --------------------------------------------------------------------------- starts and reference


def spin_axis(body: RigidBody, which: str) -> int:
    """Body axis (1, 2 or 3) with the ``"smallest"``, ``"intermediate"`` or ``"largest"`` moment."""
    order = np.argsort(body.moments, kind="stable")
    return int(order[{"smallest": 0, "intermediate": 1, "largest": 2}[which]]) + 1


def ensemble_starts(axis: int, spin: float, epsilon: float, members: int, seed: int):
    """Starts ``spin e_axis + epsilon spin (cos phi e_b + sin phi e_c)``, phi uniform; (N, 3).

    The draws of :func:`stability.ensemble.perturbed_starts`, so a member here starts where
    the same member of ``run_ensemble`` with the same seed does.
    """
    return perturbed_starts(axis, spin, epsilon, members, seed=seed)


def exact_final_w(body: RigidBody, w0, t_end: float) -> np.ndarray:
    """w(t_end) of the torque-free body for each start: the reference of the study.

    Parameters
    ----------
    body : RigidBody
    w0 : ndarray, shape (N, 3)
        Starts, rad/s.
    t_end : float
        Time, s.

    Returns
    -------
    ndarray, shape (N, 3)
        The exact solution (:func:`stability.exact_omega`, ~1e-14 relative) at ``t_end``.
    """
    w0 = np.atleast_2d(np.asarray(w0, dtype=float))
    t = float(t_end)
    return np.array([exact_omega(body, w, t) for w in w0]).reshape(w0.shape)


def conditioning_floor(body: RigidBody, w0, t_end: float, w_ref, seed: int = 0) -> np.ndarray:
    """Relative change of the exact w(t_end) when D2 of each start moves by one rounding; (N,).

    D2 = L^2 - 2 E I2 sets the flip times (literature notes 1.5, 2.2). A method rounds its state
    at every step, by about one ulp of |m| in each component; far from the saddle (during a
    flip) that changes D2 by about u L^2, u = 2^-53, and the flip times by u L^2 / (nu |D2|).
    Here each start m0 is moved along the sphere |m| = L, in the direction of the tangential
    energy gradient, by just enough to change D2 by u L^2 (random sign), and the exact solution
    from there is compared with ``w_ref``, the exact solution from the unmoved start: the error
    one rounding of the whole state at the level of ulp(|m|) causes (each stage of a composition
    makes one; the driver's compensated update of a one-stage method rounds only the increment).
    """
    moments = body.moments
    w0 = np.asarray(w0, dtype=float)
    m0 = moments * w0
    L2 = np.sum(m0 * m0, axis=1)
    unit = m0 / np.sqrt(L2)[:, None]
    g = w0 - np.sum(w0 * unit, axis=1)[:, None] * unit  # grad_m E, tangential to the sphere
    g2 = np.sum(g * g, axis=1)
    signs = np.random.default_rng(np.random.SeedSequence(seed)).choice([-1.0, 1.0], len(w0))
    intermediate = np.sort(moments)[1]
    d_energy = -signs * 2.0**-53 * L2 / (2.0 * intermediate)  # dD2 = -2 I2 dE at fixed L
    moved = m0 + np.where(g2 > 0, d_energy / np.where(g2 > 0, g2, 1.0), 0.0)[:, None] * g
    w_moved = exact_final_w(body, moved / moments, t_end)
    return np.linalg.norm(w_moved - w_ref, axis=1) / np.linalg.norm(w_ref, axis=1)


def attitude_reference(body: RigidBody, w0, t_end: float):
    """Attitude at t_end of each start, from the identity: scipy DOP853 on (w, q), one system.

    The exact attitude (Celledoni, Fasso, Safstrom & Zanna 2008) is not in the package; the
    reference is DOP853 at rtol = atol = 1e-13 on Euler's equations and ``q' = q (0, w) / 2``
    (``stability.attitude``'s convention: body-to-space, scalar first) for all members as one
    system. Its accuracy is measured on its w part against the exact solution.

    Returns
    -------
    q_ref : ndarray, shape (N, 4)
        Unit quaternions at t_end.
    w_error : ndarray, shape (N,)
        Relative error of the reference's w(t_end) against :func:`exact_final_w`, per member:
        attitude errors below about this are not resolved.
    """
    from scipy.integrate import solve_ivp

    w0 = np.atleast_2d(np.asarray(w0, dtype=float))
    n = w0.shape[0]
    rhs_w = _euler_rhs(body.moments, n)

    def rhs(t, y):
        w1, w2, w3 = y[:n], y[n : 2 * n], y[2 * n : 3 * n]
        q0, q1, q2, q3 = y[3 * n : 4 * n], y[4 * n : 5 * n], y[5 * n : 6 * n], y[6 * n :]
        dq = 0.5 * np.concatenate((
            -(q1 * w1 + q2 * w2 + q3 * w3),  # q (0, w): scalar part -q_v . w
            q0 * w1 + q2 * w3 - q3 * w2,  # vector part q0 w + q_v x w
            q0 * w2 + q3 * w1 - q1 * w3,
            q0 * w3 + q1 * w2 - q2 * w1,
        ))
        return np.concatenate((rhs_w(t, y[: 3 * n]), dq))

    y0 = np.concatenate((np.ascontiguousarray(w0.T).ravel(), np.repeat([1.0, 0.0, 0.0, 0.0], n)))
    sol = solve_ivp(rhs, (0.0, t_end), y0, method="DOP853", rtol=1e-13, atol=1e-13,
                    t_eval=[t_end])
    y = sol.y[:, -1]
    w_end = y[: 3 * n].reshape(3, n).T
    q = y[3 * n :].reshape(4, n).T
    w_error = (np.linalg.norm(w_end - exact_final_w(body, w0, t_end), axis=1)
               / np.linalg.norm(w_end, axis=1))
    return q / np.linalg.norm(q, axis=1, keepdims=True), w_error


def attitude_errors(spec, body, w0, q_ref, h, n_steps) -> np.ndarray:
    """Rotation angle (rad) between each member's attitude after n_steps and ``q_ref``; (N,).

    NaN for a member whose run failed; all NaN when the method cannot carry the attitude.
    """
    from ..attitude import IDENTITY, attitude_error, attitude_methods, propagate_attitude

    if spec.name not in attitude_methods():
        return np.full(len(w0), np.nan)
    moments = body.moments
    run = propagate_attitude(spec, moments, moments * w0, IDENTITY, h, n_steps, progress=False)
    error = attitude_error(run.extras["q_final"], q_ref)
    return np.where(run.status == cv.STATUS_OK, error, np.nan)


# ------------------------------------------------------------------------------- measurements


def _stats(values) -> np.ndarray:
    """(max, p99, median) of the finite ``values``; NaN if there are none."""
    values = np.asarray(values, dtype=float)
    values = values[np.isfinite(values)]
    if values.size == 0:
        return np.full(len(METRICS), np.nan)
    return np.array([values.max(), np.percentile(values, 99.0), np.median(values)])


def final_errors(moments, w0, w_end, w_ref) -> dict:
    """Per-member relative errors at the end: w against the reference, energy and |L| drift.

    Returns a dict of arrays of shape (N,): ``w`` = |w - w_ref| / |w_ref|, ``energy`` =
    |E / E0 - 1|, ``momentum`` = | |L| / |L0| - 1 |.
    """
    moments = np.asarray(moments, dtype=float)
    m0, m1 = moments * w0, moments * w_end
    e0 = np.sum(m0 * w0, axis=1)
    e1 = np.sum(m1 * w_end, axis=1)
    l0 = np.linalg.norm(m0, axis=1)
    l1 = np.linalg.norm(m1, axis=1)
    return {
        "w": np.linalg.norm(w_end - w_ref, axis=1) / np.linalg.norm(w_ref, axis=1),
        "energy": np.abs(e1 / e0 - 1.0),
        "momentum": np.abs(l1 / l0 - 1.0),
    }


def step_grid(t_end: float, h_max: float, h_min: float, per_octave: int) -> np.ndarray:
    """Step counts n (ascending, distinct) with h = t_end / n from about h_max down to h_min."""
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


def _point(h=np.nan, rtol=np.nan, steps=np.nan, wall=np.nan, evaluations=np.nan,
           iterations=np.nan, failed=0, members=1, errors=None) -> dict:
    point = {
        "h": h, "rtol": rtol, "steps": steps, "wall_time": wall,
        "member_step_time": wall / (members * steps) if steps == steps else np.nan,
        "evaluations": evaluations, "iterations": iterations, "failed": failed,
    }
    for key in ("w", "energy", "momentum"):
        point[f"{key}_error"] = _stats(errors[key]) if errors is not None else np.full(3, np.nan)
    point["attitude_error"] = np.full(len(METRICS), np.nan)
    return point


def timed_propagate(spec, moments, m0, h, n_steps):
    """``propagate`` once, repeated while short: returns the run and its fastest wall time.

    A run shorter than ``MIN_TIMING`` seconds is repeated (at most ``REPEATS`` times in all,
    or until the repeats add up to ``MIN_TIMING``) and the minimum kept, the usual defence of
    a benchmark against a busy machine; the results are identical (the loop is deterministic).
    """
    run = propagate(spec, moments, m0, h, n_steps, progress=False)
    best, total, repeats = run.wall_time, run.wall_time, 1
    while total < MIN_TIMING and repeats < REPEATS:
        again = propagate(spec, moments, m0, h, n_steps, progress=False)
        best, total, repeats = min(best, again.wall_time), total + again.wall_time, repeats + 1
    return run, best


def sweep_method(spec, body, w0, w_ref, t_end, counts, budget, stop_error,
                 attitude=None) -> list[dict]:
    """Run one method over the step counts ``counts`` (exact methods: one step of t_end).

    ``attitude = (n, q_ref)``: the first n members are also run with their attitude from the
    identity, and their attitude errors against ``q_ref`` (n, 4) are recorded.

    A step count whose predicted kernel time (the last point's time scaled by the step ratio)
    would take the method's total (of the w runs' timed kernels) past ``budget`` seconds is
    not run; the sweep also stops once
    the median relative w error is below ``stop_error`` or has not improved for three points
    (the conditioning floor).
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
        point = _point(
            h=t_end / n, steps=n, wall=wall, evaluations=spec.evaluations * n,
            iterations=float(np.mean(run.iterations)) / n, failed=int(np.sum(~ok)),
            members=members, errors=errors,
        )
        if attitude is not None and attitude[0] > 0:
            k, q_ref = attitude
            point["attitude_error"] = _stats(attitude_errors(spec, body, w0[:k], q_ref,
                                                             t_end / n, n))
        spent += wall
        if points:
            previous = points[-1]["w_error"][2]
            stalled = stalled + 1 if point["w_error"][2] > 0.8 * previous else 0
        points.append(point)
        if point["w_error"][2] < stop_error or stalled >= 3:
            break
    return points


def _euler_rhs(moments, members):
    """Euler's equations in w for scipy, on the stacked state (w1[:], w2[:], w3[:])."""
    I1, I2, I3 = (float(x) for x in moments)
    a1, a2, a3 = (I2 - I3) / I1, (I3 - I1) / I2, (I1 - I2) / I3

    def rhs(t, y):
        w1, w2, w3 = y[:members], y[members : 2 * members], y[2 * members :]
        return np.concatenate((a1 * w2 * w3, a2 * w3 * w1, a3 * w1 * w2))

    return rhs


def sweep_scipy(body, w0, w_ref, t_end, rtols, scale) -> list[dict]:
    """scipy ``solve_ivp`` DOP853 on the whole ensemble as one system, per tolerance.

    The right-hand side is vectorized over members (one NumPy expression for all of them);
    ``atol = rtol * scale``. ``evaluations`` is scipy's ``nfev`` (each call evaluates every
    member once); ``wall_time`` is the whole call, Python overhead included.
    """
    from scipy.integrate import solve_ivp

    moments = body.moments
    members = w0.shape[0]
    rhs = _euler_rhs(moments, members)
    y0 = np.ascontiguousarray(w0.T).ravel()
    points = []
    for rtol in rtols:
        t0 = time.perf_counter()
        sol = solve_ivp(rhs, (0.0, t_end), y0, method="DOP853", rtol=rtol, atol=rtol * scale,
                        t_eval=[t_end])
        wall = time.perf_counter() - t0
        if sol.status != 0:
            points.append(_point(rtol=rtol, wall=wall, evaluations=sol.nfev, failed=members,
                                 members=members))
            continue
        w_end = sol.y[:, -1].reshape(3, members).T
        ok = np.all(np.isfinite(w_end), axis=1)
        errors = final_errors(moments, w0, np.where(ok[:, None], w_end, np.nan), w_ref)
        points.append(_point(rtol=rtol, wall=wall, evaluations=float(sol.nfev), iterations=0.0,
                             failed=int(np.sum(~ok)), members=members, errors=errors))
    return points


def long_horizon(spec, body, w0, h, steps, samples):
    """Energy and |L| error against time over ``steps`` steps: RMS over the members.

    Returns
    -------
    t : ndarray, shape (S,)
        Times of the kept states, s.
    energy, momentum : ndarray, shape (S,)
        RMS over members of E / E0 - 1 and |L| / |L0| - 1 (NaN once a member failed).
    wall : float
        Kernel seconds.
    """
    moments = body.moments
    m0 = moments * w0
    save_every = steps // samples
    run = propagate(spec, moments, m0, h, steps, save_every=save_every, progress=False)
    m = run.saved  # (N, S, 3)
    e0 = np.sum(m0 * m0 / moments, axis=1)
    l0 = np.linalg.norm(m0, axis=1)
    de = np.sum(m * m / moments, axis=2) / e0[:, None] - 1.0
    dl = np.linalg.norm(m, axis=2) / l0[:, None] - 1.0
    t = h * save_every * np.arange(1, m.shape[1] + 1)
    rms = lambda x: np.sqrt(np.mean(x * x, axis=0))  # noqa: E731 - NaN propagates on purpose
    return t, rms(de), rms(dl), run.wall_time


def envelope(err) -> np.ndarray:
    """Running maximum of |err| over time: the error reached so far (NaN stays NaN)."""
    err = np.abs(np.asarray(err, dtype=float))
    return np.fmax.accumulate(err) if err.size else err


def log_slope(t, err, decades=2.0) -> float:
    """Least-squares slope of log(envelope(err)) against log(t) over the last ``decades`` of t.

    The envelope (running maximum) turns an oscillating but bounded error into a plateau
    (slope 0), so the slope separates bounded, random-walk (1/2) and drifting (1) errors.
    """
    t, err = np.asarray(t), envelope(err)
    keep = (t >= t[-1] * 10.0**-decades) & np.isfinite(err) & (err > 0)
    if np.count_nonzero(keep) < 3:
        return np.nan
    return float(np.polyfit(np.log(t[keep]), np.log(err[keep]), 1)[0])


def drift_kind(slope: float, size: float = math.inf) -> str:
    """In words, the behaviour of an invariant's error from its long-run log-log slope and size.

    "bounded" (slope < BOUNDED_SLOPE), "linear drift" (slope > DRIFT_SLOPE) or "random walk"
    in between; an error that stays below ROUNDOFF_LEVEL is "round-off", and its slope then
    tells an unbiased random walk (t^(1/2), Brouwer's law) from a biased one (closer to t).
    """
    if not np.isfinite(slope):
        return "n/a"
    if size <= ROUNDOFF_LEVEL:
        if slope < BOUNDED_SLOPE:
            return "round-off, bounded"
        return f"round-off, grows like t^{slope:.2f}"
    if slope < BOUNDED_SLOPE:
        return "bounded"
    if slope > DRIFT_SLOPE:
        return "linear drift"
    return "random walk"


# ------------------------------------------------------------------------------------ dataset


def _sweep_arrays(results, methods, n_sweep):
    """Stack per-point dicts into arrays (workload, method, sweep[, metric]), NaN-padded."""
    shape = (len(WORKLOADS), len(methods), n_sweep)
    scalars = ("h", "rtol", "steps", "wall_time", "member_step_time", "evaluations",
               "iterations", "failed")
    vectors = ("w_error", "energy_error", "momentum_error", "attitude_error")
    out = {k: np.full(shape, np.nan) for k in scalars}
    out.update({k: np.full(shape + (len(METRICS),), np.nan) for k in vectors})
    for i, workload in enumerate(WORKLOADS):
        for j, method in enumerate(methods):
            for k, point in enumerate(results.get((workload, method), [])):
                for key in scalars + vectors:
                    out[key][i, j, k] = point[key]
    return out


_VARIABLES = {
    "w_error": ("relative error of w at the end, |w - w_exact| / |w_exact|",
                cv.UNITS_DIMENSIONLESS),
    "energy_error": ("relative kinetic-energy error at the end, |E / E0 - 1|",
                     cv.UNITS_DIMENSIONLESS),
    "momentum_error": ("relative angular-momentum error at the end, | |L| / |L0| - 1 |",
                       cv.UNITS_DIMENSIONLESS),
    "attitude_error": ("attitude error at the end: angle of the rotation from the reference "
                       "attitude (DOP853) to the method's, over the first [attitude] members",
                       "rad"),
    "wall_time": ("kernel wall time for the whole ensemble (compilation excluded)",
                  cv.UNITS_TIME),
    "member_step_time": ("wall time per member and step", cv.UNITS_TIME),
    "steps": ("steps per member", cv.UNITS_DIMENSIONLESS),
    "evaluations": ("right-hand-side evaluations or exact sub-flows per member",
                    cv.UNITS_DIMENSIONLESS),
    "iterations": ("nonlinear-solver iterations per step, mean over members",
                   cv.UNITS_DIMENSIONLESS),
    "failed": ("members flagged non-finite, diverged or not converged", cv.UNITS_DIMENSIONLESS),
}


def work_precision_dataset(config, body, results, floors, long_results, wall_total) -> xr.Dataset:
    """Assemble the study's Dataset from the measurements (see the module docstring)."""
    methods = [m for m in _selected_methods(config)] + (
        [SCIPY] if any(key[1] == SCIPY for key in results) else []
    )
    n_sweep = max((len(p) for p in results.values()), default=1)
    arrays = _sweep_arrays(results, methods, n_sweep)
    dims = ("workload", "method", "sweep")
    data = {}
    for name, (long_name, units) in _VARIABLES.items():
        values = arrays[name]
        data[name] = (dims + (("metric",) if values.ndim == 4 else ()), values,
                      {"long_name": long_name, "units": units})
    data["floor"] = (
        ("workload", "metric"), np.array([floors[w] for w in WORKLOADS]),
        {"long_name": "conditioning floor: relative change of the exact w(T) when D2 of the "
                      "start moves by one rounding", "units": cv.UNITS_DIMENSIONLESS},
    )
    long_methods = [m for m in methods if m in long_results]
    t = next(iter(long_results.values()))[0] if long_results else np.zeros(0)
    drift_e = np.array([long_results[m][1] for m in long_methods]).reshape(len(long_methods), -1)
    drift_l = np.array([long_results[m][2] for m in long_methods]).reshape(len(long_methods), -1)
    full_e = np.full((len(methods), t.size), np.nan)
    full_l = np.full((len(methods), t.size), np.nan)
    slope = np.full(len(methods), np.nan)
    for j, m in enumerate(methods):
        if m in long_results:
            k = long_methods.index(m)
            full_e[j], full_l[j] = drift_e[k], drift_l[k]
            slope[j] = log_slope(t, drift_e[k])
    data["drift_energy"] = (("method", "long_time"), full_e, {
        "long_name": "RMS over members of the relative energy error E / E0 - 1",
        "units": cv.UNITS_DIMENSIONLESS})
    data["drift_momentum"] = (("method", "long_time"), full_l, {
        "long_name": "RMS over members of the relative |L| error", "units": cv.UNITS_DIMENSIONLESS})
    data["drift_slope"] = (("method",), slope, {
        "long_name": "log-log slope of the energy error's running maximum over the last two "
                     "decades of the long run (0 bounded, 1/2 round-off random walk, 1 drift)",
        "units": cv.UNITS_DIMENSIONLESS})
    specs = {m: METHODS.get(m) for m in methods}
    coords = {
        "workload": ("workload", list(WORKLOADS), {"long_name": "workload"}),
        "method": ("method", methods, {"long_name": "integrator (registry name; dop853: scipy)"}),
        "sweep": ("sweep", np.arange(n_sweep),
                  {"long_name": "index in the step-size or tolerance sweep"}),
        "metric": ("metric", list(METRICS), {"long_name": "statistic over members"}),
        "long_time": ("long_time", t, {"long_name": "time in the long-horizon run",
                                       "units": cv.UNITS_TIME}),
        "h": (dims, arrays["h"], {"long_name": "step size", "units": cv.UNITS_TIME}),
        "rtol": (dims, arrays["rtol"], {"long_name": "scipy relative tolerance",
                                        "units": cv.UNITS_DIMENSIONLESS}),
        "order": ("method", np.array([
            (np.inf if specs[m].is_exact else float(specs[m].order)) if specs[m] else 8.0
            for m in methods]), {"long_name": "declared order (dop853: 8, adaptive)",
                                 "units": cv.UNITS_DIMENSIONLESS}),
    }
    ds = xr.Dataset(data, coords=coords)
    ds.attrs.update(_global_attrs(config, body, wall_total))
    return ds


def _global_attrs(config, body, wall_total) -> dict:
    tennis, stable, long = config["tennis"], config["stable"], config["long"]
    return {
        "Conventions": CONVENTIONS,
        "title": config["title"],
        **software_attrs(),
        "references": "literature notes (shared/notes/literature.md) sections 1.5, 3, 4; "
                      "Hairer, Lubich & Wanner, Geometric Numerical Integration (2006)",
        "body": repr(body),
        "I1": body.I1, "I2": body.I2, "I3": body.I3,
        "tennis_workload": (
            f"{tennis['members']} members, spin {tennis['spin']} rad/s about the intermediate "
            f"axis {spin_axis(body, 'intermediate')}, epsilon {tennis['epsilon']}, "
            f"t_end {tennis['t_end']} s, seed {tennis['seed']}"),
        "stable_workload": (
            f"{stable['members']} members, spin {stable['spin']} rad/s about the "
            f"{stable['axis']}-moment axis {spin_axis(body, stable['axis'])}, epsilon "
            f"{stable['epsilon']}, t_end {stable['t_end']} s, seed {stable['seed']}"),
        "long_workload": (
            f"{long['members']} members jittered by 1e-3 around w0 = {long['w0']} rad/s, "
            f"h = {long['h']} s, {long['steps']} steps"),
        "wall_time_total": float(wall_total),
        "config_toml": to_toml(config),
    }


def _selected_methods(config) -> list[str]:
    return list(config["sweep"]["methods"]) or list(METHODS)


# ----------------------------------------------------------------------------------- tables


def time_to_reach(ds: xr.Dataset, workload: str, method: str, target: float,
                  metric: str = "p99") -> float:
    """Ensemble wall time at which ``method`` reaches relative w error ``target`` (NaN: never).

    Among the sweep points without failed members, the cheapest one whose error is <= target;
    the time is interpolated in log-log between it and the costlier-error point before it
    (the next coarser step), since the sweep is a discrete ladder.
    """
    sel = ds.sel({"workload": workload, "method": method})
    err = sel.w_error.sel(metric=metric).values
    wall = sel.wall_time.values
    good = np.isfinite(err) & np.isfinite(wall) & (sel.failed.values == 0) & (wall > 0)
    err, wall = err[good], wall[good]
    if err.size == 0:
        return np.nan
    order = np.argsort(wall)
    err, wall = err[order], wall[order]
    hits = np.nonzero(err <= target)[0]
    if hits.size == 0:
        return np.nan
    k = hits[0]
    if k == 0 or err[k - 1] <= err[k]:
        return float(wall[k])
    # log-log interpolation between (wall[k-1], err[k-1] > target) and (wall[k], err[k]).
    x = (math.log(target) - math.log(err[k - 1])) / (math.log(err[k]) - math.log(err[k - 1]))
    return float(math.exp(math.log(wall[k - 1]) + x * (math.log(wall[k]) - math.log(wall[k - 1]))))


def _fmt_time(seconds: float) -> str:
    if not np.isfinite(seconds):
        return "–"
    if seconds < 1e-3:
        return f"{seconds * 1e6:.0f} µs"
    if seconds < 1.0:
        return f"{seconds * 1e3:.3g} ms"
    return f"{seconds:.3g} s"


def _is_exact_flow(name) -> bool:
    spec = METHODS.get(str(name))
    return spec is not None and spec.is_exact


def winner_table(ds: xr.Dataset, workload: str, metric: str = "p99", targets=TARGETS) -> str:
    """Markdown table: per accuracy target, the fastest method and every method's time.

    Times are kernel seconds for the whole ensemble ("–": not reached within the sweep). The
    third column leaves out the exact flow, which exists for the torque-free body only: it is
    the answer for a user who will add torques.
    """
    methods = [str(m) for m in ds.method.values]
    floor = float(ds.floor.sel(workload=workload, metric=metric))
    header = [f"w error ({metric}) <=", "fastest", "fastest integrator (exact flow aside)"]
    header += methods
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for target in targets:
        times = {m: time_to_reach(ds, workload, m, target, metric) for m in methods}
        ranked = sorted((t, m) for m, t in times.items() if np.isfinite(t))
        stepping = [(t, m) for t, m in ranked if not _is_exact_flow(m)]
        best = f"**{ranked[0][1]}**" if ranked else "none"
        integrator = (f"{stepping[0][1]} ({_fmt_time(stepping[0][0])})" if stepping else "none")
        label = f"{target:.0e}" + (" (under the floor)" if target < floor else "")
        row = [label, best, integrator] + [_fmt_time(times[m]) for m in methods]
        lines.append("| " + " | ".join(row) + " |")
    return "\n".join(lines)


def invariants_table(ds: xr.Dataset) -> str:
    """Markdown table of the long-horizon run: final energy and |L| errors, slope, behaviour."""
    lines = ["| method | energy error at end | |L| error at end | log-log slope | behaviour |",
             "|---|---|---|---|---|"]
    for m in ds.method.values:
        e = ds.drift_energy.sel({"method": m}).values
        if e.size == 0 or not np.any(np.isfinite(e)):
            continue
        l_err = ds.drift_momentum.sel({"method": m}).values
        slope = float(ds.drift_slope.sel({"method": m}))
        kind = drift_kind(slope, float(np.nanmax(envelope(e))))
        lines.append(f"| {m} | {e[-1]:.2g} | {l_err[-1]:.2g} | {slope:.2f} | {kind} |")
    return "\n".join(lines)


def cost_table(ds: xr.Dataset, workload: str = "tennis") -> str:
    """Markdown table of the cost per member-step and the work per step, per method."""
    lines = ["| method | order | time per member-step | evaluations per step | "
             "solver iterations per step |", "|---|---|---|---|---|"]
    for m in ds.method.values:
        sel = ds.sel({"workload": workload, "method": m})
        if str(m) == SCIPY:
            continue
        per = np.nanmedian(sel.member_step_time.values) if np.any(
            np.isfinite(sel.member_step_time.values)) else np.nan
        steps = sel.steps.values
        evals = np.nanmax(sel.evaluations.values / steps) if np.any(np.isfinite(steps)) else np.nan
        iters = np.nanmedian(sel.iterations.values) if np.any(
            np.isfinite(sel.iterations.values)) else np.nan
        order = float(ds.order.sel({"method": m}))
        lines.append(f"| {m} | {'exact' if np.isinf(order) else int(order)} | "
                     f"{per * 1e9:.3g} ns | {evals:.0f} | {iters:.2g} |")
    return "\n".join(lines)


def attitude_table(ds: xr.Dataset) -> str:
    """Markdown table: attitude error (p99, rad) at each method's finest step, per workload."""
    header = "| method | " + " | ".join(
        f"{w}: h | {w}: attitude error p99 | {w}: w error p99" for w in WORKLOADS) + " |"
    lines = [header, "|" + "---|" * (1 + 3 * len(WORKLOADS))]
    for m in ds.method.values:
        cells = []
        for w in WORKLOADS:
            sel = ds.sel({"workload": w, "method": m})
            att = sel.attitude_error.sel(metric="p99").values
            ran = np.flatnonzero(np.isfinite(att))
            if ran.size == 0:
                cells = []
                break
            k = ran[-1]
            cells += [f"{float(sel.h.values[k]):.3g} s", f"{att[k]:.1e}",
                      f"{float(sel.w_error.sel(metric='p99').values[k]):.1e}"]
        if cells:
            lines.append(f"| {m} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def markdown_report(ds: xr.Dataset) -> str:
    """The whole Markdown report: winners per workload, the floor, costs, invariants."""
    floor = ds.floor
    parts = [
        f"# {ds.attrs.get('title', 'Work-precision study')}",
        "",
        f"Body {ds.attrs['body']}. Times are kernel wall times for the whole ensemble "
        f"(compilation excluded) with {ds.attrs.get('numba_num_threads', '?')} threads; "
        "errors are relative errors of w at the end against the exact solution; dop853 is "
        "scipy's solve_ivp on the ensemble as one vectorized system (wall time of the call).",
        "",
        f"## Tennis racket: {ds.attrs['tennis_workload']}",
        "",
        winner_table(ds, "tennis"),
        "",
        "Conditioning floor (one rounding of D2 = L^2 - 2 E I2 at each start, exact solution at "
        "the end): "
        + ", ".join(f"{m} {float(floor.sel(workload='tennis', metric=m)):.1e}" for m in METRICS)
        + ". It is the error of one rounding of the whole state (ulp of |m|) during the run: "
        "the compositions, which round the state at every stage, stall near it in the max; the "
        "members near the separatrix set the max, which is why the p99 and the median are the "
        "columns to read.",
        "",
        f"## Stable axis: {ds.attrs['stable_workload']}",
        "",
        winner_table(ds, "stable"),
        "",
        "Conditioning floor: "
        + ", ".join(f"{m} {float(floor.sel(workload='stable', metric=m)):.1e}" for m in METRICS)
        + ".",
        "",
        "## Cost per step (tennis workload)",
        "",
        cost_table(ds),
        "",
        "## Attitude (methods that carry it), at each method's finest step",
        "",
        attitude_table(ds),
        "",
        "Reference: scipy DOP853 at rtol = atol = 1e-13 on (w, q) (the exact attitude is not in "
        "the package), on the first members of each ensemble as one system; its own w error "
        "against the exact solution (p99 / max over those members) is "
        + ", ".join(
            f"{w} {float(ds.attitude_reference_error.sel(workload=w, metric='p99')):.0e} / "
            f"{float(ds.attitude_reference_error.sel(workload=w, metric='max')):.0e}"
            for w in WORKLOADS)
        + ": attitude errors below about that are not resolved.",
        "",
        f"## Invariants over the long horizon: {ds.attrs['long_workload']}",
        "",
        invariants_table(ds),
        "",
    ]
    return "\n".join(parts)


# ----------------------------------------------------------------------------------- the run


def run(config: dict, out_dir: Path, *, overwrite=False, threads=None, progress=None,
        history=None) -> StudySummary:
    """Run the study described by the resolved ``config``; write its files into ``out_dir``.

    Returns
    -------
    StudySummary
        Rows: the fastest method per accuracy target on the tennis workload, the conditioning
        floor, the long-horizon behaviour per method, and the run time.
    """
    with numba_threads(threads):
        ds, wall = measure(config, progress=progress)
    ds.attrs["history"] = history_line(history or f"stability run ({NAME})")
    out = config["output"]
    out_dir = Path(out_dir)
    files = [save(ds, out_dir / out["dataset"], overwrite=overwrite)]
    table = out_dir / out["table"]
    table.write_text(markdown_report(ds), encoding="utf-8")
    (out_dir / "config.toml").write_text(to_toml(config), encoding="utf-8")
    files += [table, out_dir / "config.toml"]
    if out["figures"]:
        from ..figures import work_precision as figures

        files += figures.draw(ds, out_dir, out["formats"])
    return summarize(ds, out_dir, files, wall)


def measure(config: dict, progress=None) -> tuple[xr.Dataset, float]:
    """Do every measurement of the study; return the Dataset and the wall time in s."""
    t_start = time.perf_counter()
    body = _body(config)
    methods = [method_spec(m) for m in _selected_methods(config)]
    sweep = config["sweep"]
    bar = _bar(progress, 2 * (len(methods) + 1) + len(methods))
    results, floors, reference_errors = {}, {}, {}
    for workload in WORKLOADS:
        section = config[workload]
        which = "intermediate" if workload == "tennis" else section["axis"]
        axis = spin_axis(body, which)
        w0 = ensemble_starts(axis, section["spin"], section["epsilon"], section["members"],
                             section["seed"])
        t_end = section["t_end"]
        w_ref = exact_final_w(body, w0, t_end)
        floors[workload] = _stats(conditioning_floor(body, w0, t_end, w_ref, section["seed"]))
        counts = step_grid(t_end, sweep["h_max"], sweep["h_min"], sweep["per_octave"])
        k = min(config["attitude"]["members"], len(w0))
        attitude = None
        if k > 0:
            q_ref, reference_error = attitude_reference(body, w0[:k], t_end)
            reference_errors[workload] = _stats(reference_error)
            attitude = (k, q_ref)
        for spec in methods:
            _describe(bar, f"{workload}: {spec.name}")
            results[(workload, spec.name)] = sweep_method(
                spec, body, w0, w_ref, t_end, counts, sweep["budget"], sweep["stop_error"],
                attitude)
            _advance(bar)
        if config["scipy"]["enabled"]:
            _describe(bar, f"{workload}: scipy {SCIPY}")
            results[(workload, SCIPY)] = sweep_scipy(
                body, w0, w_ref, t_end, config["scipy"]["rtols"], section["spin"])
        _advance(bar)
    long = config["long"]
    w0_long = _jittered(np.asarray(long["w0"], dtype=float), long["members"], long["seed"])
    long_results = {}
    for spec in methods:
        _describe(bar, f"long horizon: {spec.name}")
        long_results[spec.name] = long_horizon(
            spec, body, w0_long, long["h"], long["steps"], long["samples"])
        _advance(bar)
    if bar is not None:
        bar.close()
    wall = time.perf_counter() - t_start
    ds = work_precision_dataset(config, body, results, floors, long_results, wall)
    ds["attitude_reference_error"] = (
        ("workload", "metric"),
        np.array([reference_errors.get(w, np.full(len(METRICS), np.nan)) for w in WORKLOADS]),
        {"long_name": "relative w error of the attitude reference (DOP853, rtol = atol = 1e-13) "
                      "against the exact solution", "units": cv.UNITS_DIMENSIONLESS})
    return ds, wall


def _jittered(w0, members, seed):
    """``members`` starts: w0 moved by a random relative 1e-3 (member 0 is w0 itself)."""
    rng = np.random.default_rng(np.random.SeedSequence(seed))
    jitter = 1e-3 * np.linalg.norm(w0) * rng.standard_normal((members, 3))
    jitter[0] = 0.0
    return w0 + jitter


def _bar(progress, total):
    if progress is False:
        return None
    from tqdm.auto import tqdm

    return tqdm(total=total, desc=NAME, leave=False, disable=None if progress is None else False)


def _describe(bar, text):
    if bar is not None:
        bar.set_postfix_str(text)


def _advance(bar):
    if bar is not None:
        bar.update(1)


def summarize(ds: xr.Dataset, out_dir: Path, files, wall: float) -> StudySummary:
    """Headline numbers: fastest method per target (tennis, p99), floor, drift, run time."""
    rows, values = [], {}
    methods = [str(m) for m in ds.method.values]
    for target in TARGETS:
        times = {m: time_to_reach(ds, "tennis", m, target) for m in methods}
        ranked = sorted((t, m) for m, t in times.items() if np.isfinite(t))
        stepping = [(t, m) for t, m in ranked if not _is_exact_flow(m)]
        if ranked:
            text = f"{ranked[0][1]} {_fmt_time(ranked[0][0])}"
            if stepping and stepping[0] != ranked[0]:
                text += f"; integrator: {stepping[0][1]} {_fmt_time(stepping[0][0])}"
            rows.append((f"fastest to p99 error {target:.0e} (tennis)", text, ""))
            values[f"fastest_{target:.0e}"] = ranked[0][1]
            if stepping:
                values[f"fastest_integrator_{target:.0e}"] = stepping[0][1]
    for metric in METRICS:
        floor = float(ds.floor.sel(workload="tennis", metric=metric))
        rows.append((f"conditioning floor, {metric} (tennis)", f"{floor:.2e}", "1"))
        values[f"floor_{metric}"] = floor
    for m in methods:
        slope = float(ds.drift_slope.sel({"method": m}))
        if np.isfinite(slope):
            size = float(np.nanmax(envelope(ds.drift_energy.sel({"method": m}).values)))
            rows.append((f"long-run energy error, {m}", f"{drift_kind(slope, size)} "
                         f"(slope {slope:.2f}, max {size:.1e})", ""))
            values[f"drift_slope_{m}"] = slope
    rows.append(("run time", f"{wall:.1f}", "s"))
    values["wall_time"] = wall
    return StudySummary(study=NAME, out_dir=Path(out_dir), files=list(files), rows=rows,
                        values=values)


STUDY = StudyKind(
    name=NAME,
    title="speed against error of every integrator, and its invariants over long runs",
    schema=SCHEMA,
    run=run,
    outputs=outputs,
    check=check,
    quick=QUICK,
    members_key=("tennis", "members"),
)
