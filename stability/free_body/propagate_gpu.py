"""The free body on the GPU: ``propagate_gpu`` and ``propagate_many_gpu``.

The GPU twins of :func:`stability.free_body.propagate.propagate` and
:func:`~stability.free_body.propagate.propagate_many`: the same arguments, the same frame
conversions, tracking set-up and final checks (they are
:func:`~stability.free_body.propagate.propagate_many` with
:func:`stability.engine.gpu.driver.propagate_groups_gpu` as its propagator), and a
:class:`stability.engine.Propagation` with arrays of the same shapes.
"""

from __future__ import annotations

import functools

import numpy as np

from .propagate import propagate_many
from .scene import FREE_BODY
from .scene_attitude import FREE_BODY_ATTITUDE
from ..engine.gpu.support import gpu_method, gpu_methods
from ..engine.gpu.driver import propagate_groups_gpu

#: Methods with a GPU kernel for the free body.
GPU_METHODS = gpu_methods(FREE_BODY)


def propagate_gpu(method, moments, m0, h, n_steps, axis=None, *, levels=None, save_every=0,
                  chunk_steps=None, threads_per_block=None):
    """Advance an ensemble of body angular momenta on the GPU (one member per thread).

    Parameters
    ----------
    method : str or MethodSpec
        One of :data:`GPU_METHODS` (``"rk4"``, ``"lp2"``, ``"exact"``, ...).
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
        :func:`stability.free_body.propagate.propagate` (the same ``extras``).
    levels : array_like, optional
        Ascending perpendicular-amplitude levels (rad/s) for ``passage_time``.
    save_every : int, default 0
        Store the state every ``save_every`` steps (0: only the final state).
    chunk_steps : int, optional
        Steps per kernel launch (a multiple of ``save_every``); by default chosen so a launch
        takes about 0.25 s. Never changes the result.
    threads_per_block : int, optional
        CUDA block size (default: as :func:`stability.engine.gpu.propagate_groups_gpu` chooses).

    Returns
    -------
    Propagation
        Body frame: ``m_final`` (N, 3), ``saved`` (N, n_saved, 3), ``status``, ``fail_step``,
        ``iterations`` (N,), ``steps_done`` an int,
        ``wall_time`` (kernel seconds, copies excluded), ``compile_time`` and, with ``axis``,
        the tracking results in ``extras``.

    Raises
    ------
    ValueError
        For a method without a GPU kernel, or bad shapes.
    stability.engine.gpu.NoGPUError
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
                       levels=None, chunk_steps=None, threads_per_block=None,
                       progress=None, q0=None, partial=False):
    """Several ensembles (groups), each of its own body, step and length, in one launch.

    The arguments are those of :func:`stability.free_body.propagate.propagate_many` (``moments``
    (G, 3), ``m0`` (N, 3) with group 0's members first, ``sizes`` (G,), ``h`` and ``n_steps`` (G,)
    or scalars, ``track_axes`` (G,), ``levels`` (G, L), ``q0`` (N, 4) to carry the attitude), plus
    ``chunk_steps`` and ``threads_per_block`` of :func:`propagate_gpu`. Returns a
    body-frame :class:`~stability.engine.Propagation` with ``steps_done`` per group.
    """
    gpu_method(method, FREE_BODY if q0 is None else FREE_BODY_ATTITUDE)
    return propagate_many(
        method, moments, m0, sizes, h, n_steps, save_every=save_every, progress=progress,
        chunk_steps=chunk_steps, track_axes=track_axes, levels=levels, q0=q0, partial=partial,
        propagator=functools.partial(propagate_groups_gpu, threads_per_block=threads_per_block),
    )
