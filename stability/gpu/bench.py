"""Member-steps per second of the GPU kernels, and how far they are from the hardware's bounds.

``python -m stability.gpu.bench [--members N ...] [--steps N] [--methods NAME ...]`` times the
free-body kernels of ``rk4`` and ``lp2`` (with and without tracking) on the CUDA GPU, with
CUDA events around launches made after a warm-up launch, and prints member-steps/s, the
fraction of the issue's target for RK4 on one H100 (1e11 member-steps/s) and two bounds:

- compute: the device's FP64 instruction rate (SMs x clock x FP64 lanes per SM) over the FP64
  instructions one step issues (a fused multiply-add counts once), counted in the PTX of the
  untracked kernel's step loop (:data:`FP64_PER_STEP`, NVVM 13.5 for sm_90);
- memory: the state (x and its Kahan compensation, 3 + 3 doubles) is read once and written
  once per launch and lives in registers in between, so the traffic per member is
  :data:`BYTES_PER_MEMBER` whatever the number of steps, and the bound is bandwidth x steps /
  bytes; at 1000 steps it is two orders of magnitude above the compute bound.

Without a GPU (or under the simulator, which measures nothing useful) it prints
``no CUDA GPU: skipped`` and exits 0.
"""

from __future__ import annotations

import argparse
import sys

import numpy as np

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


def time_kernel(cuda, method, members, steps, tracked, repeat=3):
    """Best member-steps/s of ``repeat`` timed launches (after one warm-up launch)."""
    from ..engine.loop import N_TRACK
    from ..integrators import method_spec
    from .kernels import member_kernel
    from .methods import THREADS_PER_BLOCK

    spec = method_spec(method)
    moments = np.array([1.0, 2.0, 3.0])
    rng = np.random.default_rng(0)
    w = np.zeros((3, members))
    w[1] = 1.0
    w[0], w[2] = 1e-4 * rng.standard_normal((2, members))
    x = cuda.to_device(w * moments[:, None])
    comp = cuda.to_device(np.zeros((3, members)))
    params = cuda.to_device(spec.params(moments, 0.01)[None, :])
    group = cuda.to_device(np.zeros(members, dtype=np.int32))
    hs = cuda.to_device(np.array([0.01]))
    n = cuda.to_device(np.array([steps], dtype=np.int64))
    zero = cuda.to_device(np.zeros(1, dtype=np.int64))
    axes = cuda.to_device(np.array([[1, 0, 2]], dtype=np.int64))
    track = np.zeros((N_TRACK, members if tracked else 1))
    if tracked:
        track[0], track[1] = w[1], w[0]
        track[2] = track[9] = w[0] ** 2 + w[2] ** 2
        track[[4, 5, 7, 8]] = np.nan
    track = cuda.to_device(track)
    thresholds = cuda.to_device(np.full((1, 1), np.inf))
    levels = cuda.to_device(np.zeros((1, 0)))
    passage = cuda.to_device(np.zeros((0, members if tracked else 1)))
    status = cuda.to_device(np.zeros(members, dtype=np.int8))
    fail = cuda.to_device(np.full(members, -1, dtype=np.int64))
    saved = cuda.to_device(np.zeros((1, 3, 1)))
    kernel = member_kernel(spec, tracked)
    blocks = -(-members // THREADS_PER_BLOCK)

    def launch():
        kernel[blocks, THREADS_PER_BLOCK](x, comp, params, group, hs, n, zero, axes, track,
                                          thresholds, levels, passage, status, fail, saved, 0,
                                          zero)

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


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m stability.gpu.bench", description=__doc__
                                     .split("\n")[0])
    parser.add_argument("--members", type=float, nargs="+", default=[1e6, 1e7])
    parser.add_argument("--steps", type=int, default=1000)
    parser.add_argument("--methods", nargs="+", default=["rk4", "lp2"])
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args(argv)
    from .device import real_gpu

    if not real_gpu():
        print("no CUDA GPU: skipped")
        return 0
    from numba import cuda

    name, fp64_rate, bandwidth = device_bounds(cuda)
    print(f"{name}: FP64 {fp64_rate:.3g} instructions/s, memory {bandwidth / 1e9:.0f} GB/s, "
          f"{args.steps} steps")
    print(f"{'method':<6} {'tracked':<8} {'members':>9} {'member-steps/s':>15} "
          f"{'of 1e11':>8} {'compute bound':>14} {'of bound':>9} {'memory bound':>13}")
    for method in args.methods:
        compute = fp64_rate / FP64_PER_STEP.get(method, np.nan)
        memory = bandwidth * args.steps / BYTES_PER_MEMBER
        for tracked in (False, True):
            for members in (int(m) for m in args.members):
                rate = time_kernel(cuda, method, members, args.steps, tracked, args.repeat)
                print(f"{method:<6} {str(tracked):<8} {members:>9.0e} {rate:>15.3e} "
                      f"{rate / TARGET_RK4_H100:>8.2f} {compute:>14.3e} {rate / compute:>9.2f} "
                      f"{memory:>13.3e}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
