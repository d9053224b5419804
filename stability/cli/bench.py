"""``stability bench``: member-steps per second of every integrator, against SciPy and NumPy,
and the heavy top's work and precision against its exact motion.

The free body (``--scene free_body``, the default). One workload for everyone: the
tennis-racket preset spun at 10 rad/s about its intermediate axis, each of ``members`` members
nudged by 1e-4 of the spin in a random perpendicular direction, ``steps`` steps of h = 2 ms (the
default tennis-racket study's step). Timed on it, in one run:

- every registered method through the parallel member loop (:func:`stability.free_body.propagate.propagate`,
  nothing saved), with 1 and 2 threads (compile time excluded and reported apart);
- the member loop's adaptive Dormand-Prince 5(4) (:mod:`stability.engine.adaptive`), each
  member with its own steps, at SciPy's tolerance, with the most threads; quoted as the
  equivalent member-steps/s like SciPy's, with its mean steps per member; and again with one
  event, the sign changes of w2 (the flips), to show what locating events costs; and RK4 with
  the same event on the fixed-step loop, beside RK4 without it;
- SciPy's ``solve_ivp`` with DOP853 on the whole ensemble as one system of 3N equations (a
  vectorized right-hand side over the members), at a tolerance that gives an error comparable
  to RK4's at this h; its speed is quoted as the equivalent member-steps/s, members x steps /
  wall time, since it chooses its own steps;
- a plain NumPy RK4 on the same arrays of members (no Numba): what vectorizing over members
  without compiling buys.

Each of these rows also gives the largest error of w at the end over members, against the exact
solution, so that speeds are compared at a known accuracy.

Then, on workload W1 (:data:`W1`: I = (1, 2, 3), 10,000 members near the intermediate axis,
T = 100 s, h = 0.01), what the engine costs (:func:`engine_costs`): a plain uncompensated RK4
loop blocked for SIMD (:mod:`stability.engine.baseline`), the engine's RK4 loop without and
with compensated summation, and ``run_ensemble(keep=Keep(save_every=0))`` (the loop with its
tracking), each as member-steps/s and as a fraction of the plain loop, all in one process.

The heavy top (``--scene heavy_top``; :func:`top_work_precision`): a 0.1 kg disk of radius 3 cm
4 cm from the pivot, ``members`` tops released at rest at a tilt of 60 degrees with spin
300 rad/s at random azimuths, run for 5.25 nutation periods. Every method of scene ``heavy_top``
runs at a ladder of steps h = step_angle / spin (:data:`STEP_ANGLES`); per (method, h): the loop's
wall time, member-steps/s and the largest error over members of cos(theta) = g3 at the end
against the exact solution (:func:`stability.heavy_top.exact.cos_theta`), which makes the table a
work-precision diagram; per method, the measured order (:func:`measured_order`). Steps at which a
method is unstable are reported as such.

Each timing is the best of ``repeat`` runs. Timings depend on the machine and its load; this
module prints numbers and asserts nothing about them.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from ..core.axes import intermediate_axis
from ..free_body.model import euler_system
from ..core.body import RigidBody
from ..free_body.propagate import propagate
from ..engine import propagate_groups
from ..engine.baseline import plain_rk4
from ..engine.adaptive import integrate_adaptive
from ..engine.events import Event
from ..engine.tangent import tangent_scene
from ..free_body.spin_ensembles import run_ensemble
from ..free_body.keep import Keep
from ..ensemble.options import RunOptions
from ..ensemble.starts import perturbed_starts
from ..free_body.exact import exact_omega_of_starts
from ..free_body.scene import FREE_BODY, flip_event
from ..heavy_top.exact import cos_theta, nutation_period
from ..heavy_top.model import HeavyTop, tilted_starts
from ..free_body.methods import METHODS, method_spec
from ..integrators.spec import body_params
from ..registry import SCENES
from ..util.checks import positive_float, positive_int

#: The workload: body preset, spin (rad/s), perturbation, step (s).
BODY_PRESET = "tennis_racket"
SPIN = 10.0
EPSILON = 1e-4
H = 2e-3
#: DOP853 tolerances: relative, and absolute in units of the spin.
SCIPY_RTOL = 1e-10
SCIPY_ATOL = 1e-10


@dataclass
class BenchRow:
    """One timed solver.

    Attributes
    ----------
    solver : str
        Method name, ``"adaptive dopri5"``, ``"scipy DOP853"`` or ``"numpy RK4"``.
    threads : int
        Threads it ran on (1 for SciPy and NumPy).
    wall : float
        Seconds for the whole workload, compilation excluded.
    rate : float
        Member-steps per second (equivalent for the adaptive ones, SciPy and dopri5).
    error : float
        Max over members of |w(T) - w_exact(T)| in rad/s (NaN if not measured).
    note : str
        Extra facts (compile time, function evaluations).
    """

    solver: str
    threads: int
    wall: float
    rate: float
    error: float = math.nan
    note: str = ""


#: Workload W1 of :func:`engine_costs`.
W1 = {"moments": (1.0, 2.0, 3.0), "axis": 2, "spin": 1.0, "epsilon": 1e-3, "members": 10_000,
      "t_end": 100.0, "h": 0.01}


@dataclass
class BenchReport:
    """What ``bench`` measured, with the workload it ran."""

    members: int
    steps: int
    h: float
    body: object
    axis: int
    repeat: int = 1
    rows: list = field(default_factory=list)
    engine_rows: list = field(default_factory=list)
    environment: dict = field(default_factory=dict)


def workload(members: int, seed: int = 0):
    """Body, spin axis (1-based) and starts ``w0`` (members, 3) in rad/s of the benchmark."""

    body = RigidBody.preset(BODY_PRESET)
    axis = int(intermediate_axis(body))
    return body, axis, perturbed_starts(axis, SPIN, EPSILON, members, seed=seed)


def bench(members=10_000, steps=1000, threads=None, methods=None, scipy=True, numpy=True,
          repeat=3, log=None, engine=True, adaptive=True) -> BenchReport:
    """Time every method (and SciPy DOP853, NumPy RK4) on one ensemble; see the module docstring.

    Parameters
    ----------
    members, steps : int
        Ensemble size and steps per member.
    threads : sequence of int, optional
        Thread counts for the Numba methods; default (1, 2), capped at the cores Numba has.
    methods : sequence of str, optional
        Registry names; default all of ``stability.METHODS``.
    scipy, numpy : bool
        Also time SciPy's DOP853 and the NumPy RK4.
    engine : bool
        Also measure what the engine costs on workload W1 (:func:`engine_costs`).
    adaptive : bool
        Also time the member loop's adaptive Dormand-Prince 5(4) (:func:`_time_adaptive`).
    repeat : int
        Runs per timing; the shortest wall time is kept (the least disturbed by other load).
    log : callable, optional
        Called with a line of text before each timing (progress).

    Returns
    -------
    BenchReport
    """
    import numba


    members = positive_int("members", members)
    steps = positive_int("steps", steps)
    repeat = positive_int("repeat", repeat)
    most = numba.config.NUMBA_NUM_THREADS
    threads = _thread_counts([t for t in (1, 2) if t <= most] if threads is None else threads)
    specs = [method_spec(name) for name in (methods or list(METHODS))]
    log = log or (lambda line: None)

    body, axis, w0 = workload(members)
    moments = body.moments
    m0 = w0 * moments
    t_end = steps * H
    reference = _exact(body, w0, t_end)
    report = BenchReport(members, steps, H, body, axis, repeat)

    before = numba.get_num_threads()
    try:
        for spec in specs:
            compile_time = None
            for n_threads in threads:
                numba.set_num_threads(n_threads)
                log(f"timing {spec.name} on {n_threads} thread(s) ...")
                runs = [propagate(spec, moments, m0, H, steps, save_every=0, progress=False)
                        for _ in range(repeat)]
                if compile_time is None:
                    compile_time = runs[0].compile_time  # or the load from the disk cache
                wall = min(run.wall_time for run in runs)
                error = _error(runs[0].m_final / moments, reference)
                report.rows.append(BenchRow(
                    spec.name, n_threads, wall, members * steps / wall, error,
                    f"compile/load {compile_time:.2f} s" if n_threads == threads[0] else "",
                ))
        if any(spec.name == "rk4" for spec in specs):
            numba.set_num_threads(threads[-1])
            log(f"timing rk4 with one event on {threads[-1]} thread(s) ...")
            plain = next(row for row in report.rows
                         if row.solver == "rk4" and row.threads == threads[-1])
            rows = [_time_fixed_step_event(moments, m0, steps, reference, threads[-1], plain)
                    for _ in range(repeat)]
            report.rows.append(min(rows, key=lambda row: row.wall))
        if adaptive:
            numba.set_num_threads(threads[-1])
            log(f"timing adaptive dopri5 on {threads[-1]} thread(s) ...")
            for events in ((), (Event(flip_event, count=4, name="flips"),)):
                rows = [_time_adaptive(moments, m0, t_end, steps, reference, threads[-1],
                                       events) for _ in range(repeat)]
                report.rows.append(min(rows, key=lambda row: row.wall))
    finally:
        numba.set_num_threads(before)
    report.environment = {
        "numba": numba.__version__,
        "threading_layer": _threading_layer(),
        "cores": most,
        "numpy": np.__version__,
    }

    if scipy:
        import scipy as sp  # here, not at the top: the command line starts faster without it
        from scipy.integrate import solve_ivp

        log("timing scipy DOP853 on the whole ensemble as one system ...")
        report.environment["scipy"] = sp.__version__
        rows = [_time_scipy(solve_ivp, moments, w0, t_end, steps, reference)
                for _ in range(repeat)]
        report.rows.append(min(rows, key=lambda row: row.wall))
    if numpy:
        log("timing the NumPy RK4 ...")
        walls = []
        for _ in range(repeat):
            t0 = time.perf_counter()
            m = numpy_rk4(moments, m0, H, steps)
            walls.append(time.perf_counter() - t0)
        wall = min(walls)
        report.rows.append(BenchRow("numpy RK4", 1, wall, members * steps / wall,
                                    _error(m / moments, reference), "NumPy arrays over members"))
    if engine:
        log("timing the engine against a plain RK4 loop on workload W1 ...")
        report.engine_rows = engine_costs(repeat=repeat)
    return report


#: Rounds of the engine-cost table at least (:func:`engine_costs`).
ENGINE_ROUNDS = 7


def engine_costs(repeat=3, workload=None) -> list[BenchRow]:
    """Member-steps/s on W1 of a plain RK4 loop and of the engine's, with all threads.

    Rows: the plain uncompensated loop (:func:`stability.engine.baseline.plain_rk4`); the
    engine's RK4 loop with an uncompensated update; the engine's loop as every run uses it
    (compensated); ``run_ensemble(keep=Keep(save_every=0))`` (compensated, with tracking; its rate
    is the loop's, from the Dataset's ``member_steps_per_second``). Each run takes about 0.1 s,
    so the four are interleaved, one of each per round, and each row keeps its best of
    ``max(repeat, ENGINE_ROUNDS)`` rounds: a change in the machine's speed during the bench
    then reaches every row alike, and the ratios between them hold (best of 3 in a row each,
    the ensemble's ratio to the plain loop ranged from 0.42 to 0.62 from one bench to the
    next; interleaved over 7 rounds, 0.61 and 0.61).
    """
    import numba


    w = dict(W1, **(workload or {}))
    moments = np.array(w["moments"], dtype=float)
    members, h = int(w["members"]), float(w["h"])
    steps = int(round(w["t_end"] / h))
    m0 = perturbed_starts(w["axis"], w["spin"], w["epsilon"], members, seed=0) * moments
    p = body_params(np.sort(moments), h)
    scene = SCENES["free_body"]
    threads = numba.get_num_threads()
    work = members * steps

    def plain():
        m = m0.copy()
        t0 = time.perf_counter()
        plain_rk4(m, p, h, steps)
        return time.perf_counter() - t0

    def engine_loop(compensated):
        return lambda: propagate_groups(
            scene, "rk4", m0, p[None, :], [members], h, steps, compensated=compensated,
            progress=False).wall_time

    def ensemble():
        ds = run_ensemble(RigidBody(*moments), w["axis"], w["spin"], w["epsilon"], members,
                          h=h, t_end=w["t_end"], method="rk4", keep=Keep(save_every=0),
                          options=RunOptions(progress=False))
        return work / ds.attrs["member_steps_per_second"]

    tangent = tangent_scene(scene, 1)
    x0 = np.hstack([m0, np.full((members, 3), 1.0 / math.sqrt(3.0))])

    def tangent_loop():
        return propagate_groups(tangent, "rk4", x0, p[None, :], [members], h, steps,
                                progress=False).wall_time

    plain_rk4(m0.copy(), p, h, 1)  # compile or load once, outside the timings
    propagate_groups(tangent, "rk4", x0[:1], p[None, :], [1], h, 1, progress=False)
    variants = (
        ("plain RK4 loop", plain, "uncompensated, no checks: the reference"),
        ("engine rk4, uncompensated", engine_loop(False), "the engine's loop, m += dm"),
        ("engine rk4", engine_loop(True), "compensated (every run)"),
        ("run_ensemble rk4, summaries only", ensemble, "compensated + tracking"),
        ("engine rk4 with one tangent", tangent_loop, "the state and v' = J v (issue bar: "
         "2.5 x the engine's rk4)"),
    )
    walls = [[] for _ in variants]
    for _ in range(max(repeat, ENGINE_ROUNDS)):
        for k, (_, run, _) in enumerate(variants):
            walls[k].append(run())
    return [BenchRow(name, threads, min(wall), work / min(wall), note=note)
            for (name, _, note), wall in zip(variants, walls)]


def euler_coefficients(moments):
    """``(A1, A2, A3)`` of m' = m x I^-1 m in the body's own axes, ``A1 = (I2 - I3) / (I2 I3)``.

    The same cancellation-free form as the kernels' ``body_params`` (cyclic in 1, 2, 3).
    """
    I1, I2, I3 = (float(x) for x in moments)
    return (I2 - I3) / (I2 * I3), (I3 - I1) / (I3 * I1), (I1 - I2) / (I1 * I2)


def numpy_rk4(moments, m0, h, steps):
    """Classical RK4 on Euler's equations with NumPy arrays over members (no Numba).

    Parameters
    ----------
    moments : array_like, shape (3,)
        Principal moments in kg m^2.
    m0 : ndarray, shape (N, 3)
        Initial body angular momenta m = I w.
    h : float
        Step in s.
    steps : int

    Returns
    -------
    ndarray, shape (N, 3)
        m after ``steps`` steps.
    """
    A1, A2, A3 = euler_coefficients(moments)
    m1, m2, m3 = (np.array(m0[:, i], dtype=float) for i in range(3))
    half, sixth = 0.5 * h, h / 6.0
    for _ in range(steps):
        a1, a2, a3 = A1 * m2 * m3, A2 * m3 * m1, A3 * m1 * m2
        p1, p2, p3 = m1 + half * a1, m2 + half * a2, m3 + half * a3
        b1, b2, b3 = A1 * p2 * p3, A2 * p3 * p1, A3 * p1 * p2
        p1, p2, p3 = m1 + half * b1, m2 + half * b2, m3 + half * b3
        c1, c2, c3 = A1 * p2 * p3, A2 * p3 * p1, A3 * p1 * p2
        p1, p2, p3 = m1 + h * c1, m2 + h * c2, m3 + h * c3
        d1, d2, d3 = A1 * p2 * p3, A2 * p3 * p1, A3 * p1 * p2
        m1 = m1 + sixth * (a1 + 2.0 * (b1 + c1) + d1)
        m2 = m2 + sixth * (a2 + 2.0 * (b2 + c2) + d2)
        m3 = m3 + sixth * (a3 + 2.0 * (b3 + c3) + d3)
    return np.stack([m1, m2, m3], axis=1)


def _time_adaptive(moments, m0, t_end, steps, reference, threads, events=()) -> BenchRow:
    """The member loop's Dormand-Prince 5(4) at SciPy's rtol, and an atol that is rtol of the
    state's small components (the nudge, EPSILON of the spin, in m = I w): those grow as
    exp(Omega t) near the intermediate axis, and so does what an atol lets through."""
    members = m0.shape[0]
    run = integrate_adaptive(FREE_BODY, m0, FREE_BODY.linearisation.params(moments, 0.0),
                             np.zeros(members, dtype=np.int64), t_end, rtol=SCIPY_RTOL,
                             atol=SCIPY_RTOL * EPSILON * SPIN * float(np.min(moments)),
                             events=events)
    return BenchRow(
        "adaptive dopri5" + (", one event" if events else ""), threads, run.wall_time,
        members * steps / run.wall_time, _error(run.x_final / moments, reference),
        f"rtol {SCIPY_RTOL:g}, {np.mean(run.accepted):.0f} steps per member "
        f"({np.mean(run.rejected):.1f} rejected)"
        + (f", {np.mean(run.event_count):.2f} crossings per member" if events else "")
        + f", compile/load {run.compile_time:.2f} s",
    )


def _time_fixed_step_event(moments, m0, steps, reference, threads, plain) -> BenchRow:
    """RK4 through the member loop with one event, the flips (w2's sign changes) located on
    the method's own step (:mod:`stability.engine.events`): what an event costs beside the
    same run without it (``plain``, the rk4 row on as many threads)."""
    members = m0.shape[0]
    rows = np.atleast_2d(FREE_BODY.method("rk4").params(moments, H))  # W0's frame is canonical
    run = propagate_groups(FREE_BODY, "rk4", m0, rows, [members], [H], [steps],
                           events=(Event(flip_event, count=4),), progress=False)
    counts = run.extras["event_count"]
    return BenchRow(
        "rk4, one event", threads, run.wall_time, members * steps / run.wall_time,
        _error(run.x_final / moments, reference),
        f"{np.mean(counts):.2f} crossings per member, {run.wall_time / plain.wall - 1:+.0%} "
        f"over rk4, compile/load {run.compile_time:.2f} s",
    )


def _time_scipy(solve_ivp, moments, w0, t_end, steps, reference) -> BenchRow:
    """DOP853 on the 3N-dimensional system, the right-hand side vectorized over members."""

    members = w0.shape[0]
    rhs = euler_system(moments, members)
    y0 = np.ascontiguousarray(w0.T).ravel()
    t0 = time.perf_counter()
    sol = solve_ivp(rhs, (0.0, t_end), y0, method="DOP853", rtol=SCIPY_RTOL,
                    atol=SCIPY_ATOL * SPIN, t_eval=[t_end])
    wall = time.perf_counter() - t0
    w = sol.y[:, -1].reshape(3, members).T
    return BenchRow(
        "scipy DOP853", 1, wall, members * steps / wall, _error(w, reference),
        f"rtol {SCIPY_RTOL:g}, {sol.nfev} evaluations of the 3N system",
    )


def _exact(body, w0, t_end):
    """Exact w at ``t_end`` for every start (rows of ``w0``)."""

    return exact_omega_of_starts(body, w0, t_end)


def _thread_counts(threads) -> list[int]:
    """``threads`` checked: whole numbers from 1 to the cores Numba started with."""
    import numba


    most = numba.config.NUMBA_NUM_THREADS
    threads = [positive_int("threads", t) for t in threads]
    too_many = [t for t in threads if t > most]
    if too_many:
        raise ValueError(
            f"threads must be <= {most}, the cores Numba started with (NUMBA_NUM_THREADS), "
            f"got {too_many[0]}"
        )
    return threads


def _threading_layer() -> str:
    import numba

    try:
        return str(numba.threading_layer())
    except ValueError:  # no parallel code has run
        return "no parallel run"


def _error(w, reference) -> float:
    return float(np.max(np.abs(w - reference)))


def format_report(report: BenchReport) -> str:
    """The measurements as a table, with speed ratios against NumPy RK4 and SciPy DOP853."""
    rows = report.rows
    by_name = {r.solver: r for r in rows}
    numpy_rate = by_name["numpy RK4"].rate if "numpy RK4" in by_name else math.nan
    scipy_rate = by_name["scipy DOP853"].rate if "scipy DOP853" in by_name else math.nan
    env = report.environment
    lines = [
        f"workload: {report.members} members x {report.steps} steps of h = {report.h:g} s "
        f"(t = {report.steps * report.h:g} s): {report.body.name} spun at {SPIN:g} rad/s about "
        f"axis {report.axis}, perturbation {EPSILON:g}",
        f"numba {env.get('numba', '?')} ({env.get('threading_layer', '?')}, "
        f"{env.get('cores', '?')} threads available), numpy {env.get('numpy', '?')}"
        + (f", scipy {env['scipy']}" if "scipy" in env else ""),
        "",
    ]
    header = ("solver", "threads", "wall (s)", "member-steps/s", "x NumPy RK4",
              "x SciPy DOP853", "max |w error| (rad/s)", "note")
    table = [header]
    for r in rows:
        table.append((
            r.solver, str(r.threads), f"{r.wall:.3g}", f"{r.rate:.3g}",
            _ratio(r.rate, numpy_rate), _ratio(r.rate, scipy_rate),
            f"{r.error:.1e}" if math.isfinite(r.error) else "-", r.note,
        ))
    lines.append(_aligned(table))
    lines.append("")
    lines.append("member-steps/s = members x steps / wall time, the best of "
                 f"{report.repeat} runs (SciPy: the same count for the same time span, with its "
                 "own adaptive steps); x A = speed relative to A.")
    if report.engine_rows:
        lines += ["", _engine_table(report.engine_rows)]
    return "\n".join(lines)


def _engine_table(rows) -> str:
    w = W1
    reference = rows[0].rate
    table = [("loop", "threads", "wall (s)", "member-steps/s", "x plain", "note")]
    for r in rows:
        table.append((r.solver, str(r.threads), f"{r.wall:.3g}", f"{r.rate:.3g}",
                      _ratio(r.rate, reference), r.note))
    return "\n".join([
        f"what the engine costs, workload W1: I = {w['moments']}, {w['members']} members near "
        f"axis {w['axis']} (perturbation {w['epsilon']:g}), T = {w['t_end']:g} s, h = {w['h']:g}",
        _aligned(table),
    ])


def _ratio(rate, reference) -> str:
    if not (math.isfinite(rate) and math.isfinite(reference)) or reference <= 0:
        return "-"
    return f"{rate / reference:.3g}"


# The heavy top: work and precision against the exact solution.

#: The heavy-top workload: a 0.1 kg disk of radius 3 cm, 4 cm from the pivot (critical spin
#: ~119 rad/s), released at rest at a tilt of 60 degrees with spin 300 rad/s about its axis.
TOP_DISK = {"mass": 0.1, "radius": 0.03, "length": 0.04}
TOP_SPIN = 300.0
TOP_TILT = math.radians(60.0)
#: Horizon in nutation periods: a quarter period past a whole number. After whole periods a top
#: released at rest is back at a turning point of cos(theta), where an error in the nutation's
#: phase enters squared: there lp2's error falls as h^4 and lp4's as ~h^7 (until round-off),
#: overstating both.
TOP_PERIODS = 5.25
#: The ladder of steps h = step_angle / spin. RK4 is unstable above a step angle of ~2.8; the
#: splittings turn with the spin exactly and stay stable.
STEP_ANGLES = (6.4, 3.2, 1.6, 0.8, 0.4, 0.2, 0.1, 0.05, 0.025, 0.0125)
#: Errors inside this window enter the measured order: above round-off, and small beside the
#: nutation's range of cos(theta) (~0.06 here), past which errors are not yet asymptotic.
ORDER_WINDOW = (1e-13, 1e-4)


@dataclass
class TopRow:
    """One heavy-top method at one step.

    Attributes
    ----------
    method : str
        Method of scene ``heavy_top``.
    step_angle : float
        Asked step in radians of spin; ``h`` is it over the spin, shortened so that ``steps``
        steps end exactly at the horizon.
    h : float
        Step in s.
    steps : int
        Steps per member.
    wall : float
        Seconds for the whole ensemble, the best of ``repeat`` runs, compilation excluded.
    rate : float
        Member-steps per second (NaN if a member failed).
    error : float
        Max over members of |g3(T) - cos(theta(T))|, against
        :func:`stability.heavy_top.exact.cos_theta` (NaN if a member failed).
    failed : int
        Members whose state stopped being finite (the method is unstable at this step).
    """

    method: str
    step_angle: float
    h: float
    steps: int
    wall: float
    rate: float
    error: float
    failed: int = 0


@dataclass
class TopReport:
    """What :func:`top_work_precision` measured, with its workload."""

    top: object
    members: int
    spin: float
    tilt: float
    periods: float
    t_end: float
    threads: int
    repeat: int
    rows: list = field(default_factory=list)
    compile_times: dict = field(default_factory=dict)


def top_workload(members: int, spin=TOP_SPIN, tilt=TOP_TILT, seed=0):
    """The disk top :data:`TOP_DISK` and ``members`` starts (members, 6) released at rest at
    ``tilt`` (rad) with spin ``spin`` (rad/s), at random azimuths."""

    top = HeavyTop.disk(**TOP_DISK)
    return top, tilted_starts(spin, tilt, members, top=top, seed=seed)


def top_work_precision(members=256, spin=TOP_SPIN, tilt=TOP_TILT, periods=TOP_PERIODS,
                       step_angles=STEP_ANGLES, methods=None, threads=None, repeat=3,
                       log=None) -> TopReport:
    """Wall time and error against the exact motion of each heavy-top method over a ladder of h.

    The workload is :func:`top_workload` run for ``periods`` exact nutation periods
    (:func:`stability.heavy_top.exact.nutation_period`). Each method runs once for one step to
    compile it or load it from the disk cache (reported apart), then ``repeat`` times at each step;
    the shortest loop time is kept. The error is that of the tilt's cosine g3 at the end against
    :func:`stability.heavy_top.exact.cos_theta`, the largest over members.

    Parameters
    ----------
    members : int
        Ensemble size.
    spin, tilt : float
        Spin about the symmetry axis (rad/s) and initial tilt from the vertical (rad).
    periods : float
        Horizon in nutation periods.
    step_angles : sequence of float
        Steps as angles of spin, h = step_angle / spin (rad).
    methods : sequence of str, optional
        Methods of scene ``heavy_top``; default all.
    threads : int, optional
        Numba threads; default those in use.
    repeat : int
        Runs per timing.
    log : callable, optional
        Called with a line of text before each method (progress).

    Returns
    -------
    TopReport
        One :class:`TopRow` per (method, step), methods in order, steps as given.
    """
    import numba


    members = positive_int("members", members)
    repeat = positive_int("repeat", repeat)
    periods = positive_float("periods", periods)
    threads = _thread_counts([threads if threads is not None else numba.get_num_threads()])[0]
    scene = SCENES["heavy_top"]
    specs = [scene.method(name) for name in (methods or list(scene.methods))]
    log = log or (lambda line: None)

    top, x0 = top_workload(members, spin, tilt)
    A, _, C = top.pivot_moments
    t_end = periods * float(np.max(nutation_period(x0, A, C, top.mgl)))
    exact = cos_theta(t_end, x0, A, C, top.mgl)
    report = TopReport(top, members, spin, tilt, periods, t_end, threads, repeat)

    def run(spec, h, steps):
        return propagate_groups(scene, spec, x0, spec.params(top.parameters, h)[None, :],
                                [members], h, steps, progress=False)

    before = numba.get_num_threads()
    numba.set_num_threads(threads)
    try:
        for spec in specs:
            log(f"timing heavy top {spec.name} at {len(step_angles)} steps ...")
            report.compile_times[spec.name] = run(spec, t_end / 1000.0, 1).compile_time
            for angle in step_angles:
                steps = max(1, math.ceil(t_end * spin / angle))
                h = t_end / steps
                runs = [run(spec, h, steps) for _ in range(repeat)]
                wall = min(r.wall_time for r in runs)
                failed = int(np.count_nonzero(runs[0].status))
                error = np.max(np.abs(runs[0].x_final[:, 5] - exact))
                report.rows.append(TopRow(
                    spec.name, angle, h, steps, wall,
                    math.nan if failed else members * steps / wall,
                    math.nan if failed else float(error), failed,
                ))
    finally:
        numba.set_num_threads(before)
    return report


def measured_order(h, error, window=ORDER_WINDOW) -> tuple[float, int]:
    """Least-squares slope of log(error) against log(h) over the errors inside ``window``.

    Returns
    -------
    slope : float
        The measured order (NaN with fewer than two points).
    points : int
        Points fitted.
    """
    h, error = np.asarray(h, dtype=float), np.asarray(error, dtype=float)
    keep = np.isfinite(error) & (error > window[0]) & (error < window[1])
    points = int(np.count_nonzero(keep))
    if points < 2:
        return math.nan, points
    return float(np.polyfit(np.log(h[keep]), np.log(error[keep]), 1)[0]), points


def format_top_report(report: TopReport) -> str:
    """The heavy-top measurements as a table per (method, step), then the measured orders."""

    top = report.top
    lines = [
        f"heavy top: {report.members} members of a {top.name} (M = {top.mass:g} kg, "
        f"l = {top.length:g} m) released at rest at a tilt of {math.degrees(report.tilt):g} deg "
        f"with spin {report.spin:g} rad/s, T = {report.periods:g} nutation periods = "
        f"{report.t_end:.4g} s, {report.threads} thread(s)",
        "",
    ]
    table = [("method", "step angle", "h (s)", "steps", "wall (s)", "member-steps/s",
              "max |cos(theta) error|")]
    for r in report.rows:
        table.append((
            r.method, f"{r.step_angle:g}", f"{r.h:.3g}", str(r.steps), f"{r.wall:.3g}",
            f"{r.rate:.3g}" if math.isfinite(r.rate) else "-",
            f"{r.error:.1e}" if not r.failed else f"unstable ({r.failed} failed)",
        ))
    orders = [("method", "declared order", "measured order", "points fitted", "compile/load (s)")]
    for name, compile_time in report.compile_times.items():
        rows = [r for r in report.rows if r.method == name]
        slope, points = measured_order([r.h for r in rows], [r.error for r in rows])
        orders.append((name, str(SCENES["heavy_top"].method(name).order),
                       f"{slope:.2f}" if math.isfinite(slope) else "-", str(points),
                       f"{compile_time:.2f}"))
    lines += [_aligned(table), "", _aligned(orders), ""]
    lines += [
        "error: max over members of |g3(T) - cos(theta(T))| against the exact motion "
        f"(stability.heavy_top.exact); wall: the best of {report.repeat} runs, "
        "compilation excluded;",
        "measured order: slope of log error against log h over the errors between "
        f"{ORDER_WINDOW[0]:g} and {ORDER_WINDOW[1]:g}.",
    ]
    return "\n".join(lines)


def _aligned(table) -> str:
    """Rows of cells as left-aligned columns under a dashed header."""
    widths = [max(len(row[i]) for row in table) for i in range(len(table[0]))]
    lines = []
    for k, row in enumerate(table):
        lines.append("  ".join(cell.ljust(n) for cell, n in zip(row, widths)).rstrip())
        if k == 0:
            lines.append("  ".join("-" * n for n in widths))
    return "\n".join(lines)
