"""Running the CUDA member loop from the host, for any scene: ``propagate_groups_gpu``.

The GPU twin of :func:`stability.engine.propagate_groups`: the same arguments, the same checks of
shapes and tracking set-up (:func:`stability.engine.run.member_arrays`), the same chunks in time
with their progress bar and Ctrl-C (:func:`stability.engine.run.run_in_chunks`), and a
:class:`~stability.engine.Propagation` with arrays of the same shapes, in the kernels' frame. The
host copies the members in (structure of arrays, members last), launches one thread per member
in blocks of :data:`~stability.gpu.methods.THREADS_PER_BLOCK` once per chunk (the state stays on
the device between chunks, and chunking never changes a result), and copies the results out.
"""

from __future__ import annotations

import time

import numpy as np

from ..engine.loop import N_TRACK
from ..engine.run import member_arrays, run_in_chunks
from ..scenes import scene as registered_scene
from .device import cuda_module
from .methods import THREADS_PER_BLOCK, gpu_method


def propagate_groups_gpu(
    scene, method, x0, params, sizes, h, n_steps, *, save_every=0, axes=None, levels=None,
    progress=None, chunk_steps=None, label=None, partial=False,
    threads_per_block=THREADS_PER_BLOCK,
):
    """Advance groups of members of ``scene`` with ``method`` on a CUDA GPU (one per thread).

    Parameters
    ----------
    scene, method, x0, params, sizes, h, n_steps, save_every, axes, levels, progress, label,
    partial
        As :func:`stability.engine.propagate_groups` takes them.
    chunk_steps : int, optional
        Steps per kernel launch (rounded to a multiple of ``save_every``); by default chosen so
        a launch takes about 0.25 s. Never changes the result.
    threads_per_block : int
        CUDA block size.

    Returns
    -------
    Propagation
        In the kernels' frame, ``steps_done`` per group; ``wall_time`` counts the launches and
        their synchronisation, not the copies.

    Raises
    ------
    ValueError
        For a method without a GPU kernel (:func:`stability.gpu.gpu_method`) or bad shapes.
    stability.gpu.NoGPUError
        When neither a CUDA GPU nor the simulator (``NUMBA_ENABLE_CUDASIM=1``) is available.
    KeyboardInterrupt
        When Ctrl-C stopped the run (without ``partial``).
    """
    scene = registered_scene(scene)
    spec = gpu_method(method, scene)
    a = member_arrays(scene, x0, params, sizes, h, n_steps, save_every, axes, levels)
    cuda = cuda_module()
    tracked = a.track.shape[0] > 0
    n_members, width = a.x.shape

    from .kernels import member_kernel  # imports numba.cuda: only once a device is found

    kernel = member_kernel(scene, spec, tracked)
    compile_time = _ready(cuda, kernel, width, a.params.shape[1], a.levels.shape[1])

    def on_device(array):
        return cuda.to_device(np.ascontiguousarray(array))

    x_d = on_device(a.x.T)
    comp_d = on_device(a.comp.T)
    params_d = on_device(a.params)
    group_d = on_device(np.repeat(np.arange(a.sizes.size, dtype=np.int32), a.sizes))
    hs_d = on_device(a.hs)
    axes_d = on_device(a.axes)
    track_d = on_device(a.track.T if tracked else np.zeros((N_TRACK, 1)))
    thresholds_d = on_device(a.thresholds)
    levels_d = on_device(a.levels)
    passage_d = on_device(a.passage.T if tracked else np.zeros((0, 1)))
    status_d = on_device(a.status)
    fail_d = on_device(a.fail_step)
    iterations_d = on_device(a.iterations)
    saved_d = on_device(np.full((max(a.n_saved, 1), width, n_members if a.n_saved else 1),
                                np.nan))
    blocks = max(1, -(-n_members // threads_per_block))
    done = np.zeros(a.sizes.size, dtype=np.int64)
    k_saved = np.zeros(a.sizes.size, dtype=np.int64)

    def run_chunk(this):
        kernel[blocks, threads_per_block](
            x_d, comp_d, params_d, group_d, hs_d, on_device(this), on_device(done), axes_d,
            track_d, thresholds_d, levels_d, passage_d, status_d, fail_d, iterations_d,
            saved_d, save_every, on_device(k_saved),
        )
        cuda.synchronize()

    wall, interrupted = (0.0, False) if n_members == 0 else run_in_chunks(
        run_chunk, a.sizes, a.total, done, k_saved, save_every, chunk_steps, progress,
        label or f"{spec.name} (GPU)",
    )
    if n_members == 0:
        done[:] = a.total
    if interrupted and not partial:
        raise KeyboardInterrupt
    a.x[:] = x_d.copy_to_host().T
    a.comp[:] = comp_d.copy_to_host().T
    a.status[:] = status_d.copy_to_host()
    a.fail_step[:] = fail_d.copy_to_host()
    a.iterations[:] = iterations_d.copy_to_host()
    if tracked:
        a.track[:] = track_d.copy_to_host().T
        a.passage[:] = passage_d.copy_to_host().T
    saved = np.empty((n_members, a.n_saved, width))
    if a.n_saved:
        saved[:] = saved_d.copy_to_host().transpose(2, 0, 1)
    return a.propagation(saved, done, k_saved, interrupted, wall, compile_time)


_READY: set = set()


def _ready(cuda, kernel, width, n_params, n_levels) -> float:
    """Compile ``kernel`` for the standard argument types (one idle member); seconds it took."""
    key = (id(kernel), n_params, n_levels)
    if key in _READY:
        return 0.0
    t0 = time.perf_counter()
    i64 = np.int64
    kernel[1, 1](
        np.zeros((width, 1)), np.zeros((width, 1)), np.zeros((1, n_params)),
        np.zeros(1, np.int32), np.zeros(1), np.zeros(1, i64), np.zeros(1, i64),
        np.zeros((1, 3), i64), np.zeros((N_TRACK, 1)), np.full((1, n_levels + 1), np.inf),
        np.zeros((1, n_levels)), np.zeros((n_levels, 1)), np.zeros(1, np.int8),
        np.full(1, -1, i64), np.zeros(1, i64), np.zeros((1, width, 1)), 0, np.zeros(1, i64),
    )
    cuda.synchronize()
    _READY.add(key)
    return time.perf_counter() - t0
