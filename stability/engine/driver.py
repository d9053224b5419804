"""Running the member loop: groups of members, chunks in time, Ctrl-C, progress.

:func:`propagate_groups` is the one Python driver of :mod:`stability.engine.loop` for every
scene: it loads (or compiles, once per process and then from the disk cache) the loop of a scene
and a method, lays the members out in blocks, and calls the loop in chunks of steps, so a progress
bar can advance and Ctrl-C can end the run cleanly after the chunk in flight (the state then
matches the steps done). It works in the kernels' frame; the scenes' own layers convert
(``stability.free_body.propagate`` for the free body, ``stability.free_body.attitude`` for the body
with attitude).

Reproducibility: each member's arithmetic depends on nothing but its own state, its group's
parameters and step, so results are bitwise the same for any number of threads, any chunking in
time and any grouping of ensembles into calls.
"""

from __future__ import annotations

import os
import sys
import threading
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field

import numba
import numpy as np

from ..util.interrupts import deferred_interrupt
from .cache import compiling, load_module
from .loop import BLOCK, CHECK_EVERY, N_TRACK, T_FIRST_A, T_FIRST_B, T_LAST_A, T_LAST_B
from .loop import T_MAX_AMP2, T_NEXT_LEVEL, T_PREV_A, T_PREV_AMP2, T_PREV_B, T_COUNT_A
from .loop import T_COUNT_B, level_thresholds, render
from .events import ACTIONS, DIRECTIONS, located
from .scene import checked_scene

#: Wall time a chunk of steps aims at (s): short enough for a live progress bar and a prompt
#: Ctrl-C, long enough that the call overhead is negligible.
CHUNK_SECONDS = 0.25
#: Steps of the first, calibrating chunk.
FIRST_CHUNK = 64

_LOOPS: dict = {}


def compiled_loop(scene, spec, compensated=True, events=()):
    """The member loop of ``scene`` with method ``spec`` (a Numba dispatcher), made once.

    Rendered and imported through the disk cache (:mod:`stability.engine.cache`); compiled on
    its first call in the first process, loaded from disk after that.

    Parameters
    ----------
    scene : Scene
        A scene: a family's, or one of the user's own.
    spec : MethodSpec
        A method of the scene.
    compensated : bool, default True
        Kahan-compensated update; False only to measure what compensation costs.
    events : tuple of Event, optional
        Events the loop locates (:mod:`stability.engine.events`): a loop of its own, which
        takes the event arrays of :class:`MemberArrays` too.

    Returns
    -------
    numba dispatcher
        The loop's ``advance`` function, kept for the rest of the process.

    Raises
    ------
    ValueError
        If the scene's kernel or its ``observe`` is not a module-level ``@njit`` function
        bound to its own name, so the rendered loop cannot import it.
    """
    kernel = scene.kernel(spec)
    gs = tuple((*located(event.g), hasattr(event.g, "py_func")) for event in events)
    key = (scene.name, spec.name, kernel, compensated, gs)
    if key not in _LOOPS:
        source = render(scene.name, spec.name, scene.width, spec.stages, spec.implicit, kernel,
                        scene.observe, compensated, gs)
        stem = f"{scene.name}__{spec.name}" + ("" if compensated else "__plain") + (
            f"__events{len(gs)}" if gs else "")
        for function in (kernel, scene.observe):
            home = sys.modules.get(function.py_func.__module__)
            if getattr(home, function.py_func.__name__, None) is not function:
                raise ValueError(
                    f"the kernel {function.py_func.__qualname__} of scene {scene.name!r}, "
                    f"method {spec.name!r} must be a module-level @njit function bound to its "
                    f"own name in {function.py_func.__module__}, so the compiled loop can "
                    "import it"
                )
        functions = [event.python for event in events]
        roots = tuple(dict.fromkeys([kernel.py_func.__module__, scene.observe.py_func.__module__,
                                     "stability.engine.loop"]
                                    + (["stability.engine.events"] if events else [])
                                    + [f.__module__ for f in functions]))
        code = (kernel.py_func, scene.observe.py_func, *functions)
        _LOOPS[key] = load_module(stem, source, roots, code).advance
    return _LOOPS[key]


def loop_ready(advance, width, n_params, n_events=0) -> float:
    """Compile or load ``advance`` for the standard argument types; the seconds it took.

    Ctrl-C (or SIGTERM, through :func:`~stability.util.interrupts.request_stop`) during the
    compilation takes effect when it ends, as KeyboardInterrupt: raised in the middle of
    Numba's and LLVM's work it can leave their objects half built (a run stopped that way once
    ended in a segmentation fault at the interpreter's exit, after its clean message). The
    compiled loop is cached all the same.
    """
    t0 = time.perf_counter()
    if advance.signatures:
        return time.perf_counter() - t0
    with compiling(advance):  # one process compiles; the others then load its machine code
        with deferred_interrupt() as interrupt:
            i64 = np.int64
            one = np.zeros((1, width))
            advance(
                np.zeros(1, i64), one, one.copy(), np.zeros((1, n_params)), np.zeros(1, i64),
                np.zeros(1, i64), np.zeros(1, i64), np.zeros(1), np.zeros(1, i64),
                np.zeros(1, i64), 0,
                np.zeros((1, 0, width)), np.zeros(1, i64), np.zeros(1, np.int8),
                np.full(1, -1, i64), np.zeros(1, i64), np.zeros((1, 3), i64),
                np.zeros((0, N_TRACK)), np.zeros((1, 0)), np.full((1, 1), np.inf),
                np.zeros((1, 0)), *idle_event_arrays(width, n_events),
            )
    if interrupt.requested:
        raise KeyboardInterrupt
    return time.perf_counter() - t0


def idle_event_arrays(width, n_events) -> tuple:
    """Arrays of the types the loop with ``n_events`` events takes for them (none without),
    for one idle member: what the CPU and the GPU loops are compiled for."""
    if not n_events:
        return ()
    i64 = np.int64
    return (np.zeros(n_events, i64), np.zeros(n_events, i64), np.ones(n_events, i64),
            np.zeros((1, n_events)), np.zeros((1, n_events), i64), np.zeros((1, n_events, 1)),
            np.zeros((1, width)), np.zeros(1), np.zeros(1, i64))


@dataclass
class Propagation:
    """What a propagation returns.

    The fields are the constructor's parameters and the instance's attributes.

    Parameters
    ----------
    x_final : ndarray, shape (N, n)
        State after the last completed step.
    saved : ndarray, shape (N, n_saved, n)
        State after steps ``save_every, 2 save_every, ...`` (initial excluded; NaN past a
        group's own last sample).
    status, fail_step, iterations : ndarray, shape (N,)
        Per-member status code (``stability.util.conventions``), the step count at which the failure
        was detected (-1 if none; see :func:`untrusted`), and the nonlinear-solver iterations.
    steps_done : int or ndarray of int, shape (G,)
        Steps completed (fewer than asked if the run was interrupted); per group for groups.
    interrupted : bool, default False
        True if Ctrl-C ended the run early (a run asked for its ``partial`` result).
    wall_time : float, default 0.0
        Seconds spent in the loop, compilation excluded.
    compile_time : float, default 0.0
        Seconds spent compiling or loading the loop from the disk cache.
    extras : dict, optional
        Tracking results (:func:`tracking_results`) and scene-specific outputs; empty by
        default.
    """

    x_final: np.ndarray
    saved: np.ndarray
    status: np.ndarray
    fail_step: np.ndarray
    iterations: np.ndarray
    steps_done: object
    interrupted: bool = False
    wall_time: float = 0.0
    compile_time: float = 0.0
    extras: dict = field(default_factory=dict)

    @property
    def m_final(self) -> np.ndarray:
        """Body angular momentum after the last step (the first three components)."""
        return self.x_final[..., :3]


def untrusted(steps, fail_step):
    """Mask of samples that may be past a failure.

    Parameters
    ----------
    steps : ndarray of int, shape (n,)
        Step count of each sample (0 for the initial state).
    fail_step : ndarray of int, shape (N,)
        ``Propagation.fail_step``.

    Returns
    -------
    ndarray of bool, shape (N, n)
        True where the sample must be masked: at or after the last check that could have
        missed the failure (``CHECK_EVERY`` steps before its detection).
    """
    fail = np.asarray(fail_step)[:, None]
    return (fail >= 0) & (np.asarray(steps)[None, :] > fail - CHECK_EVERY)


#: Up to this many blocks the shares are made longest-processing-time first, a loop in Python of
#: about 1 us a block; above, by cutting the blocks in order into runs of nearly equal work.
LPT_BLOCKS = 512


def thread_shares(work, threads: int) -> list:
    """The blocks each thread runs: ``work`` (member-steps of each block) spread over at most
    ``threads`` shares of nearly equal work, each an int64 array of block indices, ascending.

    Up to :data:`LPT_BLOCKS` blocks, the largest are placed first, each on the share with the
    least work so far (longest-processing-time first; Graham 1969: within 4/3 of the best
    largest share). Above, the blocks in order are cut where the running sum of their work
    passes k / threads of the whole: no share exceeds its equal part by more than one block's
    work."""
    work = np.asarray(work, dtype=float)
    n = max(1, min(int(threads), work.size))
    if n == 1:
        return [np.arange(work.size, dtype=np.int64)]
    if work.size > LPT_BLOCKS:
        ends = np.cumsum(work)
        cuts = np.searchsorted(ends, ends[-1] * np.arange(1, n) / n, side="right")
        shares = np.split(np.arange(work.size, dtype=np.int64), cuts)
        return [share for share in shares if share.size]
    load = np.zeros(n)
    owner = np.empty(work.size, dtype=np.int64)
    for b in np.argsort(-work, kind="stable"):
        k = int(np.argmin(load))
        owner[b] = k
        load[k] += work[b]
    return [np.flatnonzero(owner == k).astype(np.int64) for k in range(n)]


#: The thread pools of :func:`run_blocks`, by size, with the process that made them.
_POOLS: dict = {}
_POOLS_LOCK = threading.Lock()


def _pool(size: int) -> ThreadPoolExecutor:
    """A pool of ``size`` threads kept for the process. A forked child makes its own: a pool's
    threads do not survive a fork, and one copied into the child would never run its work."""
    with _POOLS_LOCK:
        pid, pool = _POOLS.get(size, (None, None))
        if pid != os.getpid():
            pool = ThreadPoolExecutor(size, thread_name_prefix="stability-loop")
            _POOLS[size] = (os.getpid(), pool)
        return pool


def run_blocks(advance, work, threads: int, arguments: tuple) -> None:
    """``advance(blocks, *arguments)`` for every block, on ``threads`` threads at most.

    The loop releases the GIL, so the shares of :func:`thread_shares` run at the same time: one
    in this thread, the others on a pool kept for the process. Members are independent, so who
    runs a block never changes a result."""
    shares = thread_shares(work, threads)
    if len(shares) == 1:
        advance(shares[0], *arguments)
        return
    others = [_pool(len(shares) - 1).submit(advance, share, *arguments) for share in shares[1:]]
    try:
        advance(shares[0], *arguments)
    finally:
        for future in others:  # every share finishes before the arrays are read
            future.result()


#: Smallest block the table splits groups into: half an AVX-512 vector, so that even an
#: ensemble of 8 members (the work-precision study's long runs) keeps two cores busy.
MIN_BLOCK = 4
#: Blocks per thread the table aims at, so that threads finishing early find work.
BLOCKS_PER_THREAD = 4


def block_table(sizes, active=None, threads=1):
    """Start, size and group of every block, for groups of ``sizes`` consecutive members.

    Only the ``active`` groups (default all) get blocks. Blocks hold ``BLOCK`` members, or
    fewer (halving down to ``MIN_BLOCK``) when the active members would make fewer than
    ``BLOCKS_PER_THREAD`` blocks per thread: the last, longest ensembles of a batch then still
    spread over every core. Blocking never changes a result (members are independent).
    """
    sizes = np.asarray(sizes, dtype=np.int64)
    active = np.ones(sizes.size, dtype=bool) if active is None else np.asarray(active)
    block = BLOCK
    while block > MIN_BLOCK and sizes[active].sum() < BLOCKS_PER_THREAD * threads * block:
        block //= 2
    starts = np.cumsum(sizes) - sizes
    groups = np.flatnonzero(active)
    per_group = -(-sizes[groups] // block)  # blocks of each active group
    group = np.repeat(groups, per_group)
    k = np.arange(group.size) - np.repeat(np.cumsum(per_group) - per_group, per_group)
    lo = starts[group] + k * block
    size = np.minimum(block, sizes[group] - k * block)
    return lo.astype(np.int64), size.astype(np.int64), group.astype(np.int64)


def initial_tracking(a, b, c, levels_per_member):
    """Tracking state at the start from the tracked components ``a, b, c`` (N,) each.

    The start counts: its amplitude ``hypot(b, c)`` is the first maximum, and levels it already
    reaches are passed at time 0.
    """
    n = a.shape[0]
    amplitude = np.hypot(b, c)
    track = np.zeros((n, N_TRACK))
    track[:, T_PREV_A] = a
    track[:, T_PREV_B] = b
    track[:, T_PREV_AMP2] = amplitude * amplitude  # sqrt of it gives amplitude back exactly
    track[:, T_MAX_AMP2] = amplitude * amplitude
    for col in (T_FIRST_A, T_LAST_A, T_FIRST_B, T_LAST_B):
        track[:, col] = np.nan
    reached = levels_per_member <= amplitude[:, None]
    passage = np.where(reached, 0.0, np.nan)
    track[:, T_NEXT_LEVEL] = reached.sum(axis=1)
    return track, passage


def tracking_results(track, passage):
    """The tracked summaries by name (see :func:`propagate`)."""
    return {
        "axis_crossings": track[:, T_COUNT_A].astype(np.int64),
        "first_axis_crossing": track[:, T_FIRST_A].copy(),
        "last_axis_crossing": track[:, T_LAST_A].copy(),
        "perp_crossings": track[:, T_COUNT_B].astype(np.int64),
        "first_perp_crossing": track[:, T_FIRST_B].copy(),
        "last_perp_crossing": track[:, T_LAST_B].copy(),
        "max_perp_amplitude": np.sqrt(track[:, T_MAX_AMP2]),
        "passage_time": passage,
    }


def propagate_groups(
    scene, method, x0, params, sizes, h, n_steps, *, save_every=0, axes=None, levels=None,
    progress=None, chunk_steps=None, compensated=True, label=None, partial=False, events=(),
):
    """Advance groups of members of ``scene`` with ``method``, in the kernels' frame.

    Ctrl-C (or :func:`~stability.util.interrupts.request_stop`, which SIGTERM calls) stops the
    run after its chunk in flight and raises KeyboardInterrupt, unless ``partial``.

    Parameters
    ----------
    scene : Scene
        A family's scene (``stability.registry.scene(name)`` finds one by name) or one of the
        user's own.
    method : str or MethodSpec
        A method of the scene.
    x0 : array_like, shape (N, n)
        Initial states, the members of group 0 first, then group 1, ...
    params : array_like, shape (G, n_params)
        Kernel parameters of each group (``spec.params(...)``).
    sizes : array_like of int, shape (G,)
        Members per group (sum N).
    h : array_like, shape (G,)
        Step of each group.
    n_steps : array_like of int, shape (G,)
        Steps of each group.
    save_every : int, default 0
        Store the state every ``save_every`` steps (0: only the final state).
    axes : array_like of int, shape (G, 3), optional
        Turns tracking on: the kernel-frame indices of the spin axis and the two perpendicular
        axes of each group (``scene.observe``).
    levels : array_like, shape (G, L), optional
        Ascending amplitude levels of each group for the passage times (with ``axes``).
    progress : bool or None
        Progress bar; ``None`` shows one when the run is expected to take more than 2 s.
    chunk_steps : int, optional
        Steps per loop call (rounded to a multiple of ``save_every``); by default chosen so a
        call takes about :data:`CHUNK_SECONDS`. Never changes the result.
    compensated : bool, default True
        Kahan-compensated update; False only to measure what compensation costs.
    label : str, optional
        Progress bar label (default: the method's name).
    partial : bool, default False
        On Ctrl-C, return what was done (``interrupted`` True, ``steps_done`` short) instead
        of raising: for callers that keep the completed part of a run.
    events : tuple of Event, optional
        Events (checked, :func:`stability.engine.events.checked_events`) whose crossings the
        loop locates on each step of the method itself (:func:`stability.engine.loop.
        event_source`); a stop event ends its member at the located time and state (its
        ``x_final``; the loop's later steps of it are dropped).

    Returns
    -------
    Propagation
        In the kernels' frame; ``steps_done`` per group; tracking results in ``extras``, and
        with events ``event_count`` (N, E), ``event_time`` (N, E, K), ``stop_event`` (N,, -1:
        none) and ``t_final`` (N,, the stop's time or the end's).

    Raises
    ------
    KeyboardInterrupt
        When Ctrl-C stopped the run (without ``partial``).
    """
    scene = checked_scene(scene, "propagate_groups")
    spec = scene.method(method)
    events = tuple(events)
    advance = compiled_loop(scene, spec, compensated, events)
    arrays = member_arrays(scene, x0, params, sizes, h, n_steps, save_every, axes, levels,
                           events)
    a = arrays
    saved = np.empty((a.x.shape[0], a.n_saved, scene.width))
    compile_time = loop_ready(advance, scene.width, a.params.shape[1], len(events))
    done = np.zeros(a.sizes.size, dtype=np.int64)
    k_saved = np.zeros(a.sizes.size, dtype=np.int64)

    def run_chunk(this):
        threads = numba.get_num_threads()
        block_lo, block_size, block_group = block_table(a.sizes, this > 0, threads)
        run_blocks(advance, block_size * this[block_group], threads, (
            a.x, a.comp, a.params, block_lo, block_size, block_group, a.hs, this, done,
            save_every, saved, k_saved, a.status, a.fail_step, a.iterations, a.axes, a.track,
            a.levels, a.thresholds, a.passage, *a.event_arrays,
        ))

    wall, interrupted = run_in_chunks(
        run_chunk, a.sizes, a.total, done, k_saved, save_every, chunk_steps, progress,
        label or spec.name,
    )
    if interrupted and not partial:
        raise KeyboardInterrupt
    return arrays.propagation(saved, done, k_saved, interrupted, wall, compile_time)


@dataclass
class MemberArrays:
    """Everything the member loop reads and writes, on the host, in the kernels' frame.

    Made by :func:`member_arrays` (which checks the shapes); the loop, on the CPU or on a GPU
    (:mod:`stability.engine.gpu`), updates ``x``, ``comp``, ``status``, ``fail_step``,
    ``iterations``, ``track`` and ``passage`` in place, and :meth:`propagation` turns them into
    the result. Members are rows: ``x`` (N, n), ``track`` (N, N_TRACK) (no rows without
    tracking), ``passage`` (N, L); per group: ``params`` (G, n_params), ``sizes``, ``hs``,
    ``total`` (steps), ``axes`` (G, 3), ``levels`` (G, L) and ``thresholds`` (G, L + 1).
    """

    x: np.ndarray
    comp: np.ndarray
    params: np.ndarray
    sizes: np.ndarray
    hs: np.ndarray
    total: np.ndarray
    axes: np.ndarray
    track: np.ndarray
    levels: np.ndarray
    thresholds: np.ndarray
    passage: np.ndarray
    status: np.ndarray
    fail_step: np.ndarray
    iterations: np.ndarray
    n_saved: int
    event_arrays: tuple = ()

    def propagation(self, saved, done, k_saved, interrupted, wall, compile_time) -> Propagation:
        """The result once the loop has done ``done`` steps per group and saved ``k_saved``
        samples per group into ``saved`` (N, n_saved, n)."""
        x, status, fail_step = self.x, self.status, self.fail_step
        # The last check: a state that stopped being finite after the last multiple of
        # CHECK_EVERY.
        lost = (status == 0) & ~np.all(np.isfinite(x), axis=1)
        status[lost] = 1
        fail_step[lost] = np.repeat(done, self.sizes)[lost]
        ended = _stopped(self, status, fail_step, done)
        kept = int(k_saved.max()) if self.sizes.size else 0
        saved = saved[:, :kept]
        if self.sizes.size > 1 and kept:
            short = np.repeat(k_saved, self.sizes)
            saved[np.arange(kept)[None, :] >= short[:, None]] = np.nan
        return Propagation(
            x_final=x, saved=saved, status=status, fail_step=fail_step,
            iterations=self.iterations, steps_done=done, interrupted=interrupted,
            wall_time=wall, compile_time=compile_time,
            extras={**({} if self.track.shape[0] == 0 else
                       tracking_results(self.track, self.passage)), **ended},
        )


def _stopped(arrays, status, fail_step, done) -> dict:
    """With events: the members a stop event ended take its located state as ``x_final``
    (status ok: a state that stopped being finite later was past their end), and the event
    results by name (see :func:`propagate_groups`)."""
    if not arrays.event_arrays:
        return {}
    _, _, _, _, count, times, stop_x, stop_t, stop_event = arrays.event_arrays
    ended = stop_event >= 0
    arrays.x[ended] = stop_x[ended]
    status[ended] = 0
    fail_step[ended] = -1
    t_end = np.repeat(done * arrays.hs, arrays.sizes)
    return {"event_count": count, "event_time": times, "stop_event": stop_event,
            "t_final": np.where(ended, stop_t, t_end)}


def member_arrays(scene, x0, params, sizes, h, n_steps, save_every=0, axes=None,
                  levels=None, events=()) -> MemberArrays:
    """Lay out groups of members of ``scene`` for the loop; arguments as
    :func:`propagate_groups` takes them. ValueError for shapes that do not fit."""
    x = np.array(x0, dtype=float, order="C", copy=True)
    params = np.ascontiguousarray(np.atleast_2d(np.asarray(params, dtype=float)))
    sizes = np.asarray(sizes, dtype=np.int64).reshape(-1)
    n_groups = sizes.size
    hs = _per_group(h, float, (n_groups,))
    total = _per_group(n_steps, np.int64, (n_groups,))
    n_members = x.shape[0]
    if x.ndim != 2 or x.shape[1] != scene.width or sizes.sum() != n_members:
        raise ValueError(
            f"x0 must have shape (sum(sizes), {scene.width}) for scene {scene.name!r}, got "
            f"{x.shape} with sizes summing to {int(sizes.sum())}"
        )
    if params.shape[0] != n_groups:
        raise ValueError(f"params must have one row per group ({n_groups}), got {params.shape}")
    if axes is None:
        axes = np.zeros((n_groups, 3), dtype=np.int64)
        track = np.zeros((0, N_TRACK))
        levels = np.zeros((n_groups, 0))
        passage = np.zeros((n_members, 0))
    else:
        axes = _per_group(axes, np.int64, (n_groups, 3))
        levels = np.zeros((n_groups, 0)) if levels is None else np.atleast_2d(levels)
        levels = _per_group(levels, float, (n_groups, levels.shape[-1]))
        a, b, c = _observed(scene, x, params, axes, sizes)
        track, passage = initial_tracking(a, b, c, np.repeat(levels, sizes, axis=0))
    thresholds = np.full((n_groups, levels.shape[1] + 1), np.inf)  # inf past the last level
    thresholds[:, :-1] = level_thresholds(levels)
    return MemberArrays(
        x=x, comp=np.zeros_like(x), params=params, sizes=sizes, hs=hs, total=total, axes=axes,
        track=track, levels=levels, thresholds=thresholds, passage=passage,
        status=np.zeros(n_members, dtype=np.int8),
        fail_step=np.full(n_members, -1, dtype=np.int64),
        iterations=np.zeros(n_members, dtype=np.int64),
        n_saved=int(total.max(initial=0)) // save_every if save_every > 0 else 0,
        event_arrays=_event_arrays(events, n_members, scene.width),
    )


def _event_arrays(events, n_members, width) -> tuple:
    """The loop's event arrays (:data:`stability.engine.loop.EVENT_ARGS`) for ``events``
    before any step: nothing counted, no time kept, no member stopped (each g at the start is
    computed by the loop at its first step)."""
    if not events:
        return ()
    m = len(events)
    keep = max(event.count for event in events)
    return (np.array([DIRECTIONS[e.direction] for e in events], dtype=np.int64),
            np.array([ACTIONS[e.action] for e in events], dtype=np.int64),
            np.array([e.count for e in events], dtype=np.int64),
            np.zeros((n_members, m)), np.zeros((n_members, m), dtype=np.int64),
            np.full((n_members, m, keep), np.nan), np.full((n_members, width), np.nan),
            np.full(n_members, np.nan), np.full(n_members, -1, dtype=np.int64))


def _per_group(value, dtype, shape) -> np.ndarray:
    """``value`` broadcast to ``shape`` as a new, writable, C-ordered array (one signature)."""
    return np.array(np.broadcast_to(np.asarray(value, dtype=dtype), shape), dtype=dtype)


def _observed(scene, x, params, axes, sizes):
    """The tracked components of every member at the start (NumPy, per group)."""
    out = np.empty((3, x.shape[0]))
    lo = 0
    for g, n in enumerate(sizes):
        out[:, lo:lo + n] = scene.tracked(x[lo:lo + n], params[g], axes[g])
        lo += n
    return out


def run_in_chunks(run_chunk, sizes, total, done, k_saved, save_every, chunk_steps, progress,
                   label):
    """Call ``run_chunk(steps per group)`` until every group has done its steps.

    ``done`` and ``k_saved`` are updated in place. Chunks are whole numbers of save intervals;
    without ``chunk_steps`` the first call is short and calibrates calls of about
    :data:`CHUNK_SECONDS`. Returns the seconds spent in ``run_chunk`` and whether Ctrl-C ended
    the run.
    """
    unit = save_every if save_every > 0 else 1
    one_group = sizes.size == 1
    done[sizes == 0] = total[sizes == 0]  # nothing to advance
    work = (sizes * total).sum()  # member-steps
    wall = 0.0
    bar = None
    chunk = chunk_steps
    with deferred_interrupt() as interrupt:
        while np.any(done < total) and not interrupt.requested:
            wanted = FIRST_CHUNK if chunk is None else int(chunk)
            steps = max(unit, (wanted // unit) * unit)
            this = np.minimum(total - done, steps)
            t0 = time.perf_counter()
            run_chunk(this)
            dt = time.perf_counter() - t0
            wall += dt
            done += this
            if save_every > 0:
                k_saved += this // save_every
            member_steps = int((sizes * this).sum())
            if chunk_steps is None and member_steps > 0:
                active = max(int(sizes[done < total].sum()), 1)
                rate = member_steps / max(dt, 1e-9)
                chunk = max(unit, int(CHUNK_SECONDS * rate / active))
                if bar is None and progress is not False:
                    left = work - int((sizes * done).sum())
                    if progress or left / rate > 2.0:
                        bar = _progress_bar(
                            int(total[0]) if one_group else int(work),
                            int(done[0]) if one_group else int((sizes * done).sum()),
                            label, "step" if one_group else "member-step",
                        )
                        continue
            if bar is not None:
                bar.update(int(this[0]) if one_group else member_steps)
        interrupted = interrupt.requested
    if bar is not None:
        bar.close()
    return wall, interrupted


def _progress_bar(total, initial, label, unit):
    from tqdm.auto import tqdm

    return tqdm(total=total, initial=initial, unit=unit, desc=label, leave=False,
                unit_scale=unit != "step")
