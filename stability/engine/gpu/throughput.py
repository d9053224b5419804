"""Member-steps per second of the GPU kernels, and how far they are from the hardware's bounds:
the timing behind ``python -m stability.cli.gpu_bench`` (:mod:`stability.cli.gpu_bench`).

:func:`time_kernel` times one scene's method with CUDA events around launches made after a
warm-up launch; :func:`device_bounds` gives two bounds to compare with:

- compute: the device's FP64 instruction rate (SMs x clock x FP64 lanes per SM) over the FP64
  instructions one step issues (a fused multiply-add counts once), counted in the PTX of the
  untracked kernel's step loop (:data:`FP64_PER_STEP`, NVVM 13.5 for sm_90);
- memory: the state (x and its Kahan compensation, 3 + 3 doubles) is read once and written
  once per launch and lives in registers in between, so the traffic per member is
  :data:`BYTES_PER_MEMBER` whatever the number of steps, and the bound is bandwidth x steps /
  bytes; at 1000 steps it is two orders of magnitude above the compute bound.
"""

from __future__ import annotations

import time

import numpy as np

from ..driver import member_arrays
from .kernels import member_kernel
from .support import THREADS_PER_BLOCK, gpu_method, gpu_methods
from .driver import DeviceMembers

#: The issue's target for RK4 on one H100 (member-steps/s).
TARGET_RK4_H100 = 1e11
#: FP64 instructions (fma, mul, add, sub, neg, floor) and flops (an fma is 2) of one step of
#: the untracked kernel, Kahan commit included, counted in its PTX (NVVM 13.5, sm_90). RK4's
#: own arithmetic is 4 evaluations of 6 products, 3 stage points of 3 fma each and the
#: weighted sum; Kahan adds 4 additions per component.
FP64_PER_STEP = {"rk4": 57, "lp2": 147}
FLOPS_PER_STEP = {"rk4": 72, "lp2": 183}
#: Global-memory bytes per member and launch: x and comp read and written (48 B each way) and
#: the member's group index (4 B); parameters are shared by all members (cached).
BYTES_PER_MEMBER = 2 * 48 + 4
#: FP64 results per SM per clock by compute capability (the data-centre parts; consumer GPUs
#: run FP64 at 1/64 of FP32: 2 per SM per clock).
FP64_PER_SM_CLOCK = {(6, 0): 32, (7, 0): 32, (8, 0): 32, (9, 0): 64, (10, 0): 64}


def device_bounds(cuda):
    """(name, FP64 instructions/s, bytes/s) of the current device, from its attributes."""
    dev = cuda.get_current_device()
    name = dev.name.decode() if isinstance(dev.name, bytes) else str(dev.name)
    sms = dev.MULTIPROCESSOR_COUNT
    clock = dev.CLOCK_RATE * 1e3  # kHz -> Hz
    lanes = FP64_PER_SM_CLOCK.get(tuple(dev.compute_capability), 2)
    bandwidth = 2.0 * dev.MEMORY_CLOCK_RATE * 1e3 * dev.GLOBAL_MEMORY_BUS_WIDTH / 8.0
    return name, sms * clock * lanes, bandwidth


#: Step (s) of every timed run, and the spin axis and its perpendiculars tracked (the free
#: body's example spins about its middle axis, body axis 1).
STEP = 0.01
TRACK_AXES = {"free_body": (1, 0, 2)}


def time_kernel(cuda, scene, method, members, steps, tracked, repeat=3):
    """Best member-steps/s of ``repeat`` timed launches of ``method`` on ``scene`` (a Scene),
    after one warm-up launch.

    The members are ``scene.example``'s starts (for the free body: near a spin about the middle
    axis of I = 1, 2, 3) with its first parameter set, step :data:`STEP`.
    """
    spec = gpu_method(method, scene)
    x0, parameter_sets = scene.example(members, seed=0)
    params = spec.params(parameter_sets[0], STEP)[None, :]
    axes = [TRACK_AXES.get(scene.name, (2, 0, 1))] if tracked else None
    a = member_arrays(scene, x0, params, [members], STEP, steps, 0, axes, None)

    zero = np.zeros(1, dtype=np.int64)
    args = DeviceMembers(cuda, a).arguments(a.total, zero, zero, 0)
    kernel = member_kernel(scene, spec, tracked)
    blocks = -(-members // THREADS_PER_BLOCK)

    def launch():
        kernel[blocks, THREADS_PER_BLOCK](*args)

    launch()  # warm-up: compiles and loads the kernel
    cuda.synchronize()
    best = 0.0
    for _ in range(repeat):
        start, end = cuda.event(), cuda.event()
        start.record()
        launch()
        end.record()
        end.synchronize()
        seconds = start.elapsed_time(end) * 1e-3  # ms
        if seconds > 0.0:
            best = max(best, members * steps / seconds)
    return best


def scene_table(cuda, scenes, members, steps):
    """Print member-steps/s (untracked and tracked) and compile seconds of each of ``scenes``
    and each of its methods with a GPU kernel."""
    print(f"\nevery scene, {members:.0e} members, {steps} steps (member-steps/s)")
    print(f"{'scene':<20} {'method':<20} {'width':>5} {'compile s':>10} {'untracked':>11} "
          f"{'tracked':>11}")
    for scene in scenes:
        for method in gpu_methods(scene):
            t0 = time.perf_counter()
            try:
                plain = time_kernel(cuda, scene, method, members, steps, False, 2)
            except Exception as error:  # a kernel the device compiler refuses: say which
                print(f"{scene.name:<20} {method:<20} failed: {type(error).__name__}: "
                      f"{str(error).splitlines()[0][:200]}")
                continue
            compile_s = time.perf_counter() - t0
            tracked = time_kernel(cuda, scene, method, members, steps, True, 2)
            print(f"{scene.name:<20} {method:<20} {scene.width:>5} {compile_s:>10.2f} "
                  f"{plain:>11.3e} {tracked:>11.3e}", flush=True)
