"""Numba's thread count for the length of a run, restored afterwards.

One helper for every place that runs kernels with a caller-chosen number of threads
(:func:`stability.run_ensemble`, the studies). Results never depend on it: members are
independent and each member's start depends only on the seed and its index.
"""

from __future__ import annotations

import contextlib

import numba


@contextlib.contextmanager
def numba_threads(threads):
    """Run the block with ``threads`` Numba threads, then restore the previous number.

    Parameters
    ----------
    threads : int or None
        Threads to use; ``None`` leaves Numba's setting alone. More than the
        ``NUMBA_NUM_THREADS`` Numba was started with are clamped to that number.
    """
    if threads is None:
        yield
        return
    previous = numba.get_num_threads()
    numba.set_num_threads(min(int(threads), numba.config.NUMBA_NUM_THREADS))
    try:
        yield
    finally:
        numba.set_num_threads(previous)

