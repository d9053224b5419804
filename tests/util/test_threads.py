"""Numba's thread count is set for a block and restored after it, even on an error."""

import numba
import pytest

from stability.util.threads import numba_threads


def test_threads_are_set_clamped_and_restored():
    before = numba.get_num_threads()
    with numba_threads(1):
        assert numba.get_num_threads() == 1
    assert numba.get_num_threads() == before
    with numba_threads(10 * numba.config.NUMBA_NUM_THREADS):
        assert numba.get_num_threads() == numba.config.NUMBA_NUM_THREADS
    with numba_threads(None):
        assert numba.get_num_threads() == before
    with pytest.raises(RuntimeError), numba_threads(1):
        raise RuntimeError
    assert numba.get_num_threads() == before
