"""Running the GPU kernels from the host: ``propagate_gpu`` and ``propagate_many_gpu``.

The GPU twins of :func:`stability.driver.propagate` and :func:`~stability.driver.propagate_many`:
the same arguments (bar the progress bar), the same frame conversions, tracking set-up and
final checks, and a :class:`stability.engine.Propagation` with arrays of the same shapes. The
host copies the starts in (structure of arrays, members last), launches one thread per member
in blocks of :data:`~stability.gpu.kernels.THREADS_PER_BLOCK`, once per chunk of steps (the
whole run by default; the state stays on the device between chunks, and chunking never changes
a result), and copies the results out.
"""

from __future__ import annotations

import time

import numpy as np

from ..driver import CanonicalGroups, group_levels
from ..engine.loop import N_TRACK, level_thresholds
from ..engine.run import Propagation, deferred_interrupt, initial_tracking, tracking_results
from ..scenes import SCENES
from .device import cuda_module
from .methods import THREADS_PER_BLOCK, gpu_method


def propagate_gpu(method, moments, m0, h, n_steps, axis=None, *, levels=None, save_every=0,
                  chunk_steps=None, threads_per_block=THREADS_PER_BLOCK):
    """Advance an ensemble of body angular momenta on the GPU (one member per thread).

    Parameters
    ----------
    method : str or MethodSpec
        One of :data:`stability.gpu.GPU_METHODS` (``"rk4"``, ``"lp2"``, ``"exact"``, ...).
    moments : array_like, shape (3,)
        Principal moments (I1, I2, I3) in kg m^2, any order.
    m0 : array_like, shape (N, 3)
        Initial body angular momenta m = I w, body frame.
    h : float
        Step in s.
    n_steps : int
        Number of steps.
    axis : int, optional
        Body axis (0-based) of the spin: turns tracking on, as ``track_axis`` of
        :func:`stability.driver.propagate` (the same ``extras``).
    levels : array_like, optional
        Ascending perpendicular-amplitude levels (rad/s) for ``passage_time``.
    save_every : int, default 0
        Store the state every ``save_every`` steps (0: only the final state).
    chunk_steps : int, optional
        Steps per kernel launch (a multiple of ``save_every``); default: all in one launch.
    threads_per_block : int
        CUDA block size.

    Returns
    -------
    Propagation
        Body frame: ``m_final`` (N, 3), ``saved`` (N, n_saved, 3), ``status``, ``fail_step``,
        ``iterations`` (zeros: no GPU method iterates) (N,), ``steps_done`` an int,
        ``wall_time`` (kernel seconds, copies excluded), ``compile_time`` and, with ``axis``,
        the tracking results in ``extras``.

    Raises
    ------
    ValueError
        For a method without a GPU kernel, or bad shapes.
    stability.gpu.NoGPUError
        When neither a CUDA GPU nor the simulator (``NUMBA_ENABLE_CUDASIM=1``) is available.
    """
    m0 = np.atleast_2d(np.asarray(m0, dtype=float))
    run = propagate_many_gpu(
        method, np.asarray(moments, dtype=float)[None, :], m0, [m0.shape[0]], h, n_steps,
        save_every=save_every, track_axes=None if axis is None else [axis],
        levels=None if levels is None else np.asarray(levels, dtype=float)[None, :],
        chunk_steps=chunk_steps, threads_per_block=threads_per_block,
    )
    run.steps_done = int(run.steps_done[0])
    return run


def propagate_many_gpu(method, moments, m0, sizes, h, n_steps, save_every=0, track_axes=None,
                       levels=None, chunk_steps=None, threads_per_block=THREADS_PER_BLOCK):
    """Several ensembles (groups), each of its own body, step and length, in one launch.

    The arguments are those of :func:`stability.driver.propagate_many` (``moments`` (G, 3),
    ``m0`` (N, 3) with group 0's members first, ``sizes`` (G,), ``h`` and ``n_steps`` (G,) or
    scalars, ``track_axes`` (G,), ``levels`` (G, L)), plus ``chunk_steps`` and
    ``threads_per_block`` of :func:`propagate_gpu`. Returns a body-frame
    :class:`~stability.engine.Propagation` with ``steps_done`` per group.
    """
    spec = gpu_method(method)
    scene = SCENES["free_body"]
    moments = np.atleast_2d(np.asarray(moments, dtype=float))
    sizes = np.asarray(sizes, dtype=np.int64).reshape(-1)
    n_groups = sizes.size
    m0 = np.atleast_2d(np.asarray(m0, dtype=float))
    n_members = m0.shape[0]
    if m0.ndim != 2 or m0.shape[1] != 3 or sizes.sum() != n_members or np.any(sizes < 0):
        raise ValueError(
            f"m0 must have shape (sum(sizes), 3), got {m0.shape} with sizes summing to "
            f"{int(sizes.sum())}"
        )
    if moments.shape != (n_groups, 3):
        raise ValueError(f"moments must have shape ({n_groups}, 3), got {moments.shape}")
    hs = np.array(np.broadcast_to(np.asarray(h, dtype=float), (n_groups,)))
    total = np.array(np.broadcast_to(np.asarray(n_steps, dtype=np.int64), (n_groups,)))
    if np.any(total < 0):
        raise ValueError(f"n_steps must be >= 0, got {n_steps}")
    save_every = int(save_every)
    cuda = cuda_module()

    groups = CanonicalGroups(spec, moments, sizes, hs)
    bounds, params = groups.bounds, groups.params
    x = groups.to_canonical(m0)
    tracked = track_axes is not None
    if tracked:
        axes = groups.tracking_axes(track_axes)
        levels = group_levels(np.zeros((n_groups, 0)) if levels is None else levels, n_groups)
        start = np.empty((3, n_members))
        for g in range(n_groups):
            rows = slice(bounds[g], bounds[g + 1])
            start[:, rows] = scene.tracked(x[rows], params[g], axes[g])
        track, passage = initial_tracking(*start, np.repeat(levels, sizes, axis=0))
    else:
        axes = np.zeros((n_groups, 3), dtype=np.int64)
        levels = np.zeros((n_groups, 0))
        track, passage = np.zeros((1, N_TRACK)), np.zeros((1, 0))
    thresholds = np.full((n_groups, levels.shape[1] + 1), np.inf)  # inf past the last level
    thresholds[:, :-1] = level_thresholds(levels)
    n_saved = int(total.max(initial=0)) // save_every if save_every > 0 else 0

    from .kernels import member_kernel  # imports numba.cuda: only once a device is found

    kernel = member_kernel(spec, tracked)
    compile_time = _ready(cuda, kernel, params.shape[1], levels.shape[1])

    d = cuda.to_device
    x_d = d(np.ascontiguousarray(x.T))
    comp_d = d(np.zeros((3, n_members)))
    params_d = d(np.ascontiguousarray(params))
    group_d = d(np.repeat(np.arange(n_groups, dtype=np.int32), sizes))
    hs_d = d(hs)
    axes_d = d(np.ascontiguousarray(axes, dtype=np.int64))
    track_d = d(np.ascontiguousarray(track.T))
    thresholds_d = d(thresholds)
    levels_d = d(np.ascontiguousarray(levels))
    passage_d = d(np.ascontiguousarray(passage.T))
    status_d = d(np.zeros(n_members, dtype=np.int8))
    fail_d = d(np.full(n_members, -1, dtype=np.int64))
    saved_d = d(np.full((max(n_saved, 1), 3, n_members if n_saved else 1), np.nan))
    blocks = max(1, -(-n_members // threads_per_block))

    done = np.zeros(n_groups, dtype=np.int64)
    k_saved = np.zeros(n_groups, dtype=np.int64)
    unit = save_every if save_every > 0 else 1
    chunk = int(total.max(initial=0)) if chunk_steps is None else int(chunk_steps)
    chunk = max(unit, (chunk // unit) * unit)
    wall = 0.0
    with deferred_interrupt() as interrupt:
        while n_members and np.any(done < total) and not interrupt.requested:
            this = np.minimum(total - done, chunk)
            t0 = time.perf_counter()
            kernel[blocks, threads_per_block](
                x_d, comp_d, params_d, group_d, hs_d, d(this), d(done), axes_d, track_d,
                thresholds_d, levels_d, passage_d, status_d, fail_d, saved_d, save_every,
                d(k_saved),
            )
            cuda.synchronize()
            wall += time.perf_counter() - t0
            done += this
            if save_every > 0:
                k_saved += this // save_every
        interrupted = interrupt.requested
    done[sizes == 0] = total[sizes == 0]

    x = np.ascontiguousarray(x_d.copy_to_host().T)
    status = status_d.copy_to_host()
    fail_step = fail_d.copy_to_host()
    # The last check, as on the CPU: a state that stopped being finite after the last multiple
    # of CHECK_EVERY.
    lost = (status == 0) & ~np.all(np.isfinite(x), axis=1)
    status[lost] = 1
    fail_step[lost] = np.repeat(done, sizes)[lost]
    kept = int(k_saved.max(initial=0))
    if n_saved:
        saved = np.ascontiguousarray(saved_d.copy_to_host()[:kept].transpose(2, 0, 1))
        if n_groups > 1 and kept:
            short = np.repeat(k_saved, sizes)
            saved[np.arange(kept)[None, :] >= short[:, None]] = np.nan
        saved = groups.from_canonical(saved)
    else:
        saved = np.empty((n_members, 0, 3))
    extras = {}
    if tracked:
        extras = tracking_results(np.ascontiguousarray(track_d.copy_to_host().T),
                                  np.ascontiguousarray(passage_d.copy_to_host().T))
    return Propagation(
        x_final=groups.from_canonical(x), saved=saved, status=status,
        fail_step=fail_step, iterations=np.zeros(n_members, dtype=np.int64), steps_done=done,
        interrupted=interrupted, wall_time=wall, compile_time=compile_time, extras=extras,
    )


_READY: set = set()


def _ready(cuda, kernel, n_params, n_levels) -> float:
    """Compile ``kernel`` for the standard argument types (one idle member); seconds it took."""
    key = (id(kernel), n_params, n_levels)
    if key in _READY:
        return 0.0
    t0 = time.perf_counter()
    i64 = np.int64
    kernel[1, 1](
        np.zeros((3, 1)), np.zeros((3, 1)), np.zeros((1, n_params)), np.zeros(1, np.int32),
        np.zeros(1), np.zeros(1, i64), np.zeros(1, i64), np.zeros((1, 3), i64),
        np.zeros((N_TRACK, 1)), np.full((1, n_levels + 1), np.inf), np.zeros((1, n_levels)),
        np.zeros((n_levels, 1)), np.zeros(1, np.int8), np.full(1, -1, i64),
        np.zeros((1, 3, 1)), 0, np.zeros(1, i64),
    )
    cuda.synchronize()
    _READY.add(key)
    return time.perf_counter() - t0
