"""Which methods have a GPU kernel, and the launch shape (no CUDA import here)."""

from __future__ import annotations

from ..integrators import method_spec

#: Methods with a GPU kernel (free-body scene): each one's stage kernel has a device twin
#: (rk4: ``rk4_step``; lp2 and the compositions lp4, lp6, lp8: ``rotation_stage``; exact:
#: ``exact_step``). Implicit methods are left out: their solver counts and failures would
#: need the CPU loop's bookkeeping, and they are the slow ones anyway.
GPU_METHODS = ("rk4", "lp2", "lp4", "lp6", "lp8", "exact")

#: Threads per block: 128 keeps 16 resident blocks per SM within the register file at up to
#: 128 registers a thread (FP64 state, tracking and stage temporaries).
THREADS_PER_BLOCK = 128


def gpu_method(method):
    """The spec of ``method`` if it has a GPU kernel, else ValueError naming those that do."""
    spec = method_spec(method)
    if spec.name not in GPU_METHODS:
        raise ValueError(
            f"method {spec.name!r} has no GPU kernel; methods with one: {', '.join(GPU_METHODS)}"
        )
    return spec
