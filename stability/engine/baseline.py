"""The speed baseline: plain RK4 on the free body, blocked for SIMD, nothing else.

``stability bench`` times the package's member loop against this loop in the same process: the
same block layout (time outside, members innermost over blocks of ``BLOCK`` in ``prange``) and
the same arithmetic as ``rk4_step``, but an uncompensated ``m += dm``, no finiteness checks, no
status, no tracking and nothing saved. It is what the hardware does with RK4 alone, so the ratio
of the two rates is the price of everything the engine adds.
"""

import numpy as np
from numba import njit, prange

from ..integrators.rk4 import rk4_step
from .loop import BLOCK


@njit(parallel=True, cache=True, error_model="numpy")
def plain_rk4(m, p, h, n_steps):
    """Advance ``m`` (N, 3) in place by ``n_steps`` RK4 steps; ``p`` from ``body_params``."""
    n = m.shape[0]
    for b in prange((n + BLOCK - 1) // BLOCK):
        lo = b * BLOCK
        size = min(BLOCK, n - lo)
        x1 = np.empty(BLOCK)
        x2 = np.empty(BLOCK)
        x3 = np.empty(BLOCK)
        for j in range(size):
            x1[j] = m[lo + j, 0]
            x2[j] = m[lo + j, 1]
            x3[j] = m[lo + j, 2]
        for _ in range(n_steps):
            for j in range(size):
                e1, e2, e3, _it = rk4_step(x1[j], x2[j], x3[j], h, p, 0)
                x1[j] += e1
                x2[j] += e2
                x3[j] += e3
        for j in range(size):
            m[lo + j, 0] = x1[j]
            m[lo + j, 1] = x2[j]
            m[lo + j, 2] = x3[j]
