"""Running the CUDA member loop from the host, for any scene: ``propagate_groups_gpu``.

The GPU twin of :func:`stability.engine.propagate_groups`: the same arguments, the same checks of
shapes and tracking set-up (:func:`stability.engine.driver.member_arrays`), the same chunks in time
with their progress bar and Ctrl-C (:func:`stability.engine.driver.run_in_chunks`), and a
:class:`~stability.engine.Propagation` with arrays of the same shapes, in the kernels' frame. The
host copies the members in (structure of arrays, members last), launches one thread per member in
blocks of :data:`~stability.engine.gpu.support.THREADS_PER_BLOCK` (or of the whole warps fewer
members need) once per chunk (the state stays on the device between chunks, and chunking never
changes a result), and copies the results out.
"""

from __future__ import annotations

import time

import numpy as np

from ..loop import N_TRACK
from ..driver import idle_event_arrays, member_arrays, run_in_chunks
from ..scene import checked_scene
from .device import cuda_module
from .support import THREADS_PER_BLOCK, gpu_method

#: Threads of a CUDA warp: a block of fewer members than THREADS_PER_BLOCK is this many times
#: the warps they need.
WARP = 32


def propagate_groups_gpu(
    scene, method, x0, params, sizes, h, n_steps, *, save_every=0, axes=None, levels=None,
    progress=None, chunk_steps=None, label=None, partial=False, threads_per_block=None,
    events=(),
):
    """Advance groups of members of ``scene`` with ``method`` on a CUDA GPU (one per thread).

    Parameters
    ----------
    scene, method, x0, params, sizes, h, n_steps, save_every, axes, levels, progress, label,
    partial, events
        As :func:`stability.engine.propagate_groups` takes them.
    chunk_steps : int, optional
        Steps per kernel launch (rounded to a multiple of ``save_every``); by default chosen so
        a launch takes about 0.25 s. Never changes the result.
    threads_per_block : int, optional
        CUDA block size; default :data:`~stability.engine.gpu.support.THREADS_PER_BLOCK`, or
        fewer for fewer members: whole warps of 32, as many as the members need (the same
        results; under the CUDA simulator, where each thread is a Python thread, a 21-member
        run starts 32 threads per launch instead of 128).

    Returns
    -------
    Propagation
        In the kernels' frame, ``steps_done`` per group; ``wall_time`` counts the launches and
        their synchronisation, not the copies.

    Raises
    ------
    ValueError
        For a method without a GPU kernel (:func:`stability.engine.gpu.gpu_method`) or bad shapes.
    stability.engine.gpu.NoGPUError
        When neither a CUDA GPU nor the simulator (``NUMBA_ENABLE_CUDASIM=1``) is available.
    KeyboardInterrupt
        When Ctrl-C stopped the run (without ``partial``).
    """
    scene = checked_scene(scene, "propagate_groups_gpu")
    spec = gpu_method(method, scene)
    events = tuple(events)
    a = member_arrays(scene, x0, params, sizes, h, n_steps, save_every, axes, levels, events)
    cuda = cuda_module()
    tracked = a.track.shape[0] > 0
    n_members, width = a.x.shape

    from .kernels import member_kernel  # imports numba.cuda: only once a device is found

    kernel = member_kernel(scene, spec, tracked, events)
    compile_time = _ready(cuda, kernel, width, a.params.shape[1], a.levels.shape[1],
                          len(events))

    members = DeviceMembers(cuda, a)
    if threads_per_block is None:
        threads_per_block = min(THREADS_PER_BLOCK, WARP * max(1, -(-n_members // WARP)))
    blocks = max(1, -(-n_members // threads_per_block))
    done = np.zeros(a.sizes.size, dtype=np.int64)
    k_saved = np.zeros(a.sizes.size, dtype=np.int64)

    def run_chunk(this):
        kernel[blocks, threads_per_block](*members.arguments(this, done, k_saved, save_every))
        cuda.synchronize()

    wall, interrupted = (0.0, False) if n_members == 0 else run_in_chunks(
        run_chunk, a.sizes, a.total, done, k_saved, save_every, chunk_steps, progress,
        label or f"{spec.name} (GPU)",
    )
    if n_members == 0:
        done[:] = a.total
    if interrupted and not partial:
        raise KeyboardInterrupt
    saved = members.copy_back(a)
    return a.propagation(saved, done, k_saved, interrupted, wall, compile_time)


class DeviceMembers:
    """The arrays of :class:`~stability.engine.driver.MemberArrays` on the device, laid out for
    the kernel (:mod:`stability.engine.gpu.kernels`): structure of arrays, members last.

    Parameters
    ----------
    cuda : module
        ``numba.cuda`` (a device or the simulator).
    a : MemberArrays
        The members, on the host.
    """

    def __init__(self, cuda, a):
        self._cuda = cuda
        tracked = a.track.shape[0] > 0
        n_members, width = a.x.shape
        put = self._put
        self.x, self.comp, self.params = put(a.x.T), put(a.comp.T), put(a.params)
        self.group = put(np.repeat(np.arange(a.sizes.size, dtype=np.int32), a.sizes))
        self.hs, self.axes = put(a.hs), put(a.axes)
        self.track = put(a.track.T if tracked else np.zeros((N_TRACK, 1)))
        self.thresholds, self.levels = put(a.thresholds), put(a.levels)
        self.passage = put(a.passage.T if tracked else np.zeros((0, 1)))
        self.status, self.fail_step = put(a.status), put(a.fail_step)
        self.iterations = put(a.iterations)
        self.saved = put(np.full((max(a.n_saved, 1), width, n_members if a.n_saved else 1),
                                 np.nan))
        self.events = tuple(put(array) for array in a.event_arrays)  # members first

    def _put(self, array):
        return self._cuda.to_device(np.ascontiguousarray(array))

    def arguments(self, steps, done, k0, save_every) -> tuple:
        """The kernel's arguments (:data:`stability.engine.gpu.kernels.ARGUMENTS`) for a launch of
        ``steps`` per group after ``done`` steps and ``k0`` saved samples."""
        return (self.x, self.comp, self.params, self.group, self.hs, self._put(steps),
                self._put(done), self.axes, self.track, self.thresholds, self.levels,
                self.passage, self.status, self.fail_step, self.iterations, self.saved,
                save_every, self._put(k0), *self.events)

    def copy_back(self, a) -> np.ndarray:
        """Copy the members' state, status and tracking into ``a``; the saved samples
        (N, n_saved, n)."""
        a.x[:] = self.x.copy_to_host().T
        a.comp[:] = self.comp.copy_to_host().T
        a.status[:] = self.status.copy_to_host()
        a.fail_step[:] = self.fail_step.copy_to_host()
        a.iterations[:] = self.iterations.copy_to_host()
        if a.track.shape[0] > 0:
            a.track[:] = self.track.copy_to_host().T
            a.passage[:] = self.passage.copy_to_host().T
        for host, device in zip(a.event_arrays, self.events):
            host[...] = device.copy_to_host()
        saved = np.empty((a.x.shape[0], a.n_saved, a.x.shape[1]))
        if a.n_saved:
            saved[:] = self.saved.copy_to_host().transpose(2, 0, 1)
        return saved


_READY: set = set()


def _ready(cuda, kernel, width, n_params, n_levels, n_events=0) -> float:
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
        *idle_event_arrays(width, n_events),
    )
    cuda.synchronize()
    _READY.add(key)
    return time.perf_counter() - t0
