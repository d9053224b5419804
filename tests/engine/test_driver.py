"""Running the member loop (stability.engine.driver): grouped ensembles bitwise the runs alone, the
shapes it refuses, the blocks and thread shares it cuts the members into, a forked child's pool."""

import subprocess
import sys
import textwrap

import numpy as np
import pytest

from stability.engine import BLOCK, propagate_groups
from stability.registry import SCENES
from stability.util.threads import numba_threads

from ..helpers import starts

MOMENTS = np.array([1.0, 2.0, 3.0])  # canonical already


CASES = [(scene, name) for scene in SCENES.values() for name in scene.methods]


@pytest.mark.parametrize("scene,name", CASES, ids=[f"{s.name}-{n}" for s, n in CASES])
def test_groups_are_bitwise_the_runs_alone(scene, name):
    """Ensembles grouped in one call (other bodies, steps and horizons beside them), in chunks
    and on two threads, give every member bitwise what a run of its ensemble alone, in one
    chunk on one thread, gives, saved samples and tracking included (the thread count sets
    the blocks the members are cut into)."""
    spec = scene.method(name)
    bodies = scene.example(1)[1]
    sizes = [70, BLOCK, 5]  # a partial block, a whole one, a tiny one
    hs = [0.05, 0.02, 0.04]
    steps = [40, 60, 20]
    x0 = np.concatenate([starts(scene, n, seed=k) for k, n in enumerate(sizes)])
    params = np.array([spec.params(I, h) for I, h in zip(bodies, hs)])
    levels = np.array([[1e-2, 5e-2, 0.3]] * 3)
    axes = np.array([[1, 0, 2]] * 3)
    with numba_threads(2):
        together = propagate_groups(scene, spec, x0, params, sizes, hs, steps, save_every=10,
                                    axes=axes, levels=levels, chunk_steps=30, progress=False)
    lo = 0
    for g, n in enumerate(sizes):
        with numba_threads(1):
            alone = propagate_groups(scene, spec, x0[lo:lo + n], params[g:g + 1], [n], hs[g],
                                     steps[g], save_every=10, axes=axes[g:g + 1],
                                     levels=levels[g:g + 1], progress=False)
        rows = slice(lo, lo + n)
        assert np.array_equal(together.x_final[rows], alone.x_final)
        k = steps[g] // 10
        assert np.array_equal(together.saved[rows, :k], alone.saved)
        assert np.all(np.isnan(together.saved[rows, k:]))
        for key, value in alone.extras.items():
            assert np.array_equal(together.extras[key][rows], value, equal_nan=True), key
        assert together.steps_done[g] == steps[g]
        lo += n


def test_bad_shapes_are_refused_with_the_expected_shape():
    scene = SCENES["free_body"]
    p = scene.method("rk4").params(MOMENTS, 0.1)[None, :]
    with pytest.raises(ValueError, match=r"shape \(sum\(sizes\), 3\)"):
        propagate_groups(scene, "rk4", np.zeros((4, 7)), p, [4], 0.1, 5)
    with pytest.raises(ValueError, match="method 'exact' does not run scene"):
        propagate_groups(SCENES["free_body_attitude"], "exact", np.zeros((1, 7)), p, [1], 0.1, 5)


# --- the disk cache ----------------------------------------------------------------------------


def test_block_table_covers_every_active_member_once_and_splits_the_last_groups():
    from stability.engine.driver import MIN_BLOCK, block_table

    sizes = [70, 64, 5, 300]
    lo, size, group = block_table(sizes)
    covered = np.concatenate([np.arange(a, a + n) for a, n in zip(lo, size)])
    assert np.array_equal(np.sort(covered), np.arange(sum(sizes)))
    assert np.all(size <= BLOCK) and np.all(size >= 1)
    starts = np.cumsum(sizes) - sizes
    assert np.all((lo >= starts[group]) & (lo + size <= starts[group] + np.array(sizes)[group]))
    # Only the active groups; fewer members than blocks for every thread: smaller blocks.
    from stability.engine.driver import BLOCKS_PER_THREAD

    for active in ([False, True, False, False], [False, False, True, False]):
        lo, size, group = block_table(sizes, active, threads=2)
        assert set(group) == {active.index(True)} and size.sum() == sizes[active.index(True)]
        assert len(size) >= BLOCKS_PER_THREAD * 2 or np.all(size[:-1] == MIN_BLOCK)
        assert np.all(size <= BLOCK // 8)  # 64 and 5 members: blocks of 8 and of 4


def test_thread_shares_give_every_block_once_and_balance_the_work():
    """Every block in exactly one share, ascending. Up to LPT_BLOCKS blocks no share exceeds
    4/3 of the best possible largest share (Graham 1969; checked against the lower bound
    max(total / threads, largest block)); above, they are runs of consecutive blocks (made
    without a loop over them) and none exceeds total / threads by more than the largest block."""
    from stability.engine.driver import LPT_BLOCKS, thread_shares

    rng = np.random.default_rng(3)
    for threads in (1, 2, 3, 8):
        for work in (np.full(157, 64.0 * 100), rng.integers(1, 50, 40) * 1000.0, np.ones(2),
                     rng.integers(1, 50, 3 * LPT_BLOCKS) * 1000.0):
            shares = thread_shares(work, threads)
            assert 1 <= len(shares) <= min(threads, work.size)
            joined = np.concatenate(shares)
            assert np.array_equal(np.sort(joined), np.arange(work.size))
            assert all(np.all(np.diff(share) > 0) for share in shares)
            largest = max(work[share].sum() for share in shares)
            if work.size <= LPT_BLOCKS:
                assert largest <= 4 / 3 * max(work.sum() / len(shares), work.max())
            else:  # runs of consecutive blocks, cut where the running sum passes k / threads
                assert largest <= work.sum() / threads + work.max()
                assert all(np.all(np.diff(share) == 1) for share in shares)


def test_a_forked_child_runs_the_loop_on_threads_of_its_own():
    """A process forked after the loop ran on a thread pool (multiprocessing's fork, a forking
    server) cannot use the parent's pool, whose threads did not come with it: the child makes its
    own and gets the parent's result, where it would otherwise wait for ever."""
    code = textwrap.dedent("""
        import os, sys
        import numpy as np
        import stability
        body = stability.RigidBody(1.0, 2.0, 3.0)
        run = dict(axis=2, spin=1.0, members=500, h=0.01, t_end=2.0,
                   keep=stability.Keep(save_every=0),
                   options=stability.RunOptions(threads=2, progress=False))
        parent = stability.run_ensemble(body, **run)
        pid = os.fork()
        if pid == 0:
            child = stability.run_ensemble(body, **run)
            same = all(np.array_equal(parent[k].values, child[k].values, equal_nan=True)
                       for k in parent.data_vars)
            os._exit(0 if same else 3)
        sys.exit(os.waitstatus_to_exitcode(os.waitpid(pid, 0)[1]))
    """)
    done = subprocess.run([sys.executable, "-W", "ignore", "-c", code], capture_output=True,
                          text=True, timeout=120)
    assert done.returncode == 0, done.stderr[-2000:]

