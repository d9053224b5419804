"""The member loop on a CUDA GPU, for every scene whose kernels can be compiled for it.

One member per thread, its state in registers, members coalesced (structure of arrays,
``(n, N)``): :func:`propagate_groups_gpu` is :func:`stability.engine.propagate_groups` on the
GPU, for any scene and method (:func:`gpu_methods`), the user's own scenes included, and
:func:`integrate_adaptive_gpu` is :func:`stability.engine.adaptive.integrate_adaptive` on it;
the free body's :func:`~stability.free_body.propagate_gpu.propagate_gpu` is
:func:`stability.free_body.propagate.propagate` on the GPU, with the same tracking of flips,
crossings, amplitudes and levels. The kernels run the CPU's own step kernels, compiled for the
device (:mod:`stability.engine.gpu.retarget`), inside a twin of the CPU member loop rendered for
the scene's width (:mod:`stability.engine.gpu.kernels`). Needs the ``gpu`` extra (``numba-cuda``)
and a CUDA GPU, or ``NUMBA_ENABLE_CUDASIM=1`` to run the kernels as Python on the CPU (slow: tests
only).

Why results agree with the CPU to round-off but not bitwise: NVVM contracts a * b + c into fused
multiply-adds (one rounding instead of two), the device's libm (``log``, ``sqrt`` rounding modes
aside, ``cosh``, ``asinh`` of the exact flow) is not glibc's, and a reassociated or contracted
expression rounds differently. The sine and cosine of the Lie-Poisson rotations are the
package's own polynomials (:mod:`stability.core.trig`), so they differ only by contraction. Each
difference is an ulp per step; over n steps they add up like the method's own round-off
(a few 1e-15 relative for ``rk4`` and ``lp2`` over hundreds of steps,
``tests/free_body/test_propagate_gpu.py``).
"""

from .adaptive import integrate_adaptive_gpu
from .device import NO_GPU_MESSAGE, NoGPUError, cuda_module, real_gpu
from .support import NOT_ON_GPU, THREADS_PER_BLOCK, gpu_method, gpu_methods
from .driver import propagate_groups_gpu

__all__ = ["NOT_ON_GPU", "NO_GPU_MESSAGE", "NoGPUError", "THREADS_PER_BLOCK", "cuda_module",
           "gpu_method", "gpu_methods", "integrate_adaptive_gpu", "propagate_groups_gpu",
           "real_gpu"]
