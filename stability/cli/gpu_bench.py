"""Member-steps per second of the GPU kernels, and how far they are from the hardware's bounds.

``python -m stability.cli.gpu_bench [--members N ...] [--steps N] [--methods NAME ...]
[--scenes]`` times the free-body kernels of ``rk4`` and ``lp2`` (with and without tracking) on the
CUDA GPU, and with ``--scenes`` every scene's every method, with CUDA events around launches made
after a warm-up launch, and prints member-steps/s, the fraction of the issue's target for RK4 on
one H100 (1e11 member-steps/s) and two bounds, compute and memory (the timing and the bounds
are :mod:`stability.engine.gpu.throughput`'s).

Without a GPU (or under the simulator, which measures nothing useful) it prints
``no CUDA GPU: skipped`` and exits 0.
"""

from __future__ import annotations

import argparse
import sys

import numpy as np

from ..engine.gpu.throughput import (BYTES_PER_MEMBER, FP64_PER_STEP, TARGET_RK4_H100,
                                     device_bounds, scene_table, time_kernel)
from ..engine.gpu.device import cuda_module, real_gpu
from ..free_body.scene import FREE_BODY
from ..registry import SCENES


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m stability.cli.gpu_bench", description=__doc__
                                     .split("\n")[0])
    parser.add_argument("--members", type=float, nargs="+", default=[1e6, 1e7])
    parser.add_argument("--steps", type=int, default=1000)
    parser.add_argument("--methods", nargs="+", default=["rk4", "lp2"])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--scenes", action="store_true",
                        help="also time every scene and method (1e6 members, 200 steps)")
    args = parser.parse_args(argv)

    if not real_gpu():
        print("no CUDA GPU: skipped")
        return 0
    cuda = cuda_module()

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
                rate = time_kernel(cuda, FREE_BODY, method, members, args.steps, tracked,
                                   args.repeat)
                print(f"{method:<6} {str(tracked):<8} {members:>9.0e} {rate:>15.3e} "
                      f"{rate / TARGET_RK4_H100:>8.2f} {compute:>14.3e} {rate / compute:>9.2f} "
                      f"{memory:>13.3e}", flush=True)
    if args.scenes:
        scene_table(cuda, SCENES.values(), 10**6, 200)
    return 0


if __name__ == "__main__":
    sys.exit(main())
