"""Numba's thread count for the length of a run, restored afterwards.

One helper for every place that runs kernels with a caller-chosen number of threads
(:func:`stability.run_ensemble`, the studies). Results never depend on it: members are
independent and each member's start depends only on the seed and its index.
"""

from __future__ import annotations

import contextlib

import numba

from .checks import positive_int
from .numba_env import check_threads_variable


def checked_threads(threads):
    """``threads`` checked against the cores Numba started with.

    Parameters
    ----------
    threads : int or None
        Numba threads a caller asks for; ``None`` leaves Numba's setting as it is.

    Returns
    -------
    int or None
        ``threads`` as an int, or None.

    Raises
    ------
    ValueError
        Unless ``threads`` is a whole number from 1 to ``NUMBA_NUM_THREADS`` (the cores Numba
        was started with), or None; or where ``NUMBA_NUM_THREADS`` itself is not a whole
        number >= 1.
    """
    check_threads_variable()
    if threads is None:
        return None
    threads = positive_int("threads", threads)
    if threads > numba.config.NUMBA_NUM_THREADS:
        raise ValueError(
            f"threads must be between 1 and {numba.config.NUMBA_NUM_THREADS} "
            f"(NUMBA_NUM_THREADS, set before numba is imported), got {threads}"
        )
    return threads


@contextlib.contextmanager
def numba_threads(threads):
    """Run the block with ``threads`` Numba threads, then restore the previous number.

    Parameters
    ----------
    threads : int or None
        Threads to use; ``None`` leaves Numba's setting alone. More than the
        ``NUMBA_NUM_THREADS`` Numba was started with are clamped to that number.

    Raises
    ------
    ValueError
        Where ``NUMBA_NUM_THREADS`` is not a whole number >= 1.
    """
    check_threads_variable()
    if threads is None:
        yield
        return
    previous = numba.get_num_threads()
    numba.set_num_threads(min(int(threads), numba.config.NUMBA_NUM_THREADS))
    try:
        yield
    finally:
        numba.set_num_threads(previous)

