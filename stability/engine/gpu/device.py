"""Finding a CUDA device (or the CUDA simulator) for the GPU kernels.

``numba-cuda`` is an optional dependency (the ``gpu`` extra): nothing in :mod:`stability`
imports it until a GPU function is called. :func:`cuda_module` returns ``numba.cuda`` when a
real GPU or the simulator (``NUMBA_ENABLE_CUDASIM=1``, which runs kernels as Python on the CPU)
can run kernels, and raises :class:`NoGPUError` with what to do otherwise.
"""

from __future__ import annotations

import os

#: What to do when no kernel can run.
NO_GPU_MESSAGE = (
    "no CUDA GPU found; install numba-cuda and a driver, or set NUMBA_ENABLE_CUDASIM=1 to test "
    "on the simulator"
)


class NoGPUError(RuntimeError):
    """Neither a CUDA GPU nor the CUDA simulator is available."""


def simulator_requested() -> bool:
    """True when ``NUMBA_ENABLE_CUDASIM`` asks for the simulator (read as Numba reads it)."""
    return os.environ.get("NUMBA_ENABLE_CUDASIM", "0") not in ("", "0")


def _import_cuda():
    try:
        from numba import cuda
    except ImportError:  # numba-cuda missing, or built for another Numba
        return None
    return cuda


def cuda_module():
    """``numba.cuda``, ready to launch kernels on a GPU or on the simulator.

    Raises
    ------
    NoGPUError
        When numba-cuda is missing, or there is neither a usable GPU nor the simulator.
    """
    cuda = _import_cuda()
    if cuda is None:
        raise NoGPUError(NO_GPU_MESSAGE)
    if simulated(cuda):
        return cuda
    try:
        available = cuda.is_available()
    except Exception:  # a broken driver or toolkit reads as no GPU
        available = False
    if not available:
        raise NoGPUError(NO_GPU_MESSAGE)
    return cuda


def simulated(cuda) -> bool:
    """True when ``cuda`` is numba-cuda's simulator (kernels run as Python on the CPU)."""
    try:
        from numba.cuda.core import config  # numba-cuda >= 0.21 keeps its own config
    except ImportError:
        from numba.core import config
    return bool(config.ENABLE_CUDASIM)


def real_gpu() -> bool:
    """True when a real CUDA GPU (not the simulator) can run kernels."""
    cuda = _import_cuda()
    if cuda is None or simulated(cuda):
        return False
    try:
        return bool(cuda.is_available())
    except Exception:
        return False


def device_name(cuda) -> str:
    """The GPU's name, or ``"CUDA simulator"``."""
    if simulated(cuda):
        return "CUDA simulator"
    name = cuda.get_current_device().name
    return name.decode() if isinstance(name, bytes) else str(name)
