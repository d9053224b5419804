"""CUDA device twins of the CPU kernels: the same Python source, compiled for the GPU.

The integrators' step kernels, the exact solution and the loop's helpers are ``@njit``
functions. :func:`device_twin` compiles the Python function behind one of them with
``cuda.jit(device=True)``, after replacing every ``@njit`` function it calls (a global of its
module) by that function's own twin, recursively. So a GPU step runs the very formulas of the
CPU step, in the same order: the only differences are the code generator's (see
:mod:`stability.engine.gpu`), never a second copy of the mathematics to keep in step.

``OVERRIDES`` names the few CPU functions that get a device-specific body instead: Dekker's
exact product by Veltkamp splitting assumes that a * b + c is rounded twice, which NVVM's
contraction to fused multiply-adds breaks; on the device the exact product is one FMA
(Ogita, Rump & Oishi, SIAM J. Sci. Comput. 26, 1955 (2005), TwoProductFMA). The simulator
runs Python, which rounds twice, so it keeps the CPU body.
"""

from __future__ import annotations

import types

from numba.core.registry import CPUDispatcher

from ...core.compensated import two_prod
from .device import simulated

_TWINS: dict = {}


def _two_prod_fma(a, b):
    """p + e = a b exactly: p = fl(a b), e = fma(a, b, -p) (TwoProductFMA)."""
    p = a * b
    return p, cuda.fma(a, b, -p)  # noqa: F821 (``cuda`` is put in its namespace by device_twin)


def _overrides(cuda):
    """CPU function (py_func) -> device body, for the real GPU only."""
    if simulated(cuda):
        return {}
    return {two_prod.py_func: _two_prod_fma}


def device_twin(cuda, dispatcher):
    """The ``cuda.jit(device=True)`` twin of the ``@njit`` function ``dispatcher``.

    Parameters
    ----------
    cuda : module
        ``numba.cuda`` (a real device or the simulator).
    dispatcher : numba CPUDispatcher or function
        An ``@njit`` function (its ``py_func`` is recompiled), or a plain Python function.

    Returns
    -------
    device function
        Made once per process and function; every ``@njit`` global it calls is twinned too.
    """
    py_func = getattr(dispatcher, "py_func", dispatcher)
    key = (py_func, simulated(cuda))
    if key in _TWINS:
        return _TWINS[key]
    body = _overrides(cuda).get(py_func, py_func)
    namespace = dict(body.__globals__)
    for name in body.__code__.co_names:
        value = namespace.get(name)
        if isinstance(value, CPUDispatcher):
            namespace[name] = device_twin(cuda, value)
    if body is _two_prod_fma:
        namespace["cuda"] = cuda
    clone = types.FunctionType(body.__code__, namespace, body.__name__, body.__defaults__,
                               body.__closure__)
    clone.__qualname__ = body.__qualname__
    clone.__module__ = body.__module__
    clone.__doc__ = body.__doc__
    twin = cuda.jit(device=True)(clone)
    _TWINS[key] = twin
    return twin
