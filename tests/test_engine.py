"""The engine: one member loop for every scene and method, cached on disk, grouped ensembles."""

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

from stability.engine import BLOCK, compiled_loop, propagate_groups
from stability.engine.loop import level_thresholds
from stability.registry import SCENES
from stability.util.threads import numba_threads

ROOT = Path(__file__).resolve().parents[1]

MOMENTS = np.array([1.0, 2.0, 3.0])  # canonical already


def starts(scene, n, seed=0):
    """n starts of the scene's own example (for the free body: near the intermediate axis)."""
    return scene.example(n, seed)[0]


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


def test_every_scene_method_pair_compiles_to_one_signature():
    """A second run of any kind (saving, tracking, groups) reuses the compiled loop."""
    scene = SCENES["free_body_attitude"]
    spec = scene.method("lp2")
    x0 = starts(scene, 3)
    p = spec.params(MOMENTS, 0.1)[None, :]
    propagate_groups(scene, spec, x0, p, [3], 0.1, 20, save_every=5, progress=False)
    propagate_groups(scene, spec, x0, p, [3], 0.1, 20, axes=[[1, 0, 2]], levels=[[0.1]],
                     progress=False)
    assert len(compiled_loop(scene, spec).signatures) == 1


def test_bad_shapes_are_refused_with_the_expected_shape():
    scene = SCENES["free_body"]
    p = scene.method("rk4").params(MOMENTS, 0.1)[None, :]
    with pytest.raises(ValueError, match=r"shape \(sum\(sizes\), 3\)"):
        propagate_groups(scene, "rk4", np.zeros((4, 7)), p, [4], 0.1, 5)
    with pytest.raises(ValueError, match="method 'exact' does not run scene"):
        propagate_groups(SCENES["free_body_attitude"], "exact", np.zeros((1, 7)), p, [1], 0.1, 5)


@pytest.mark.parametrize("level", [1e-300, 3e-7, 0.1, 1.0, 2.0 ** 0.5, 7.3e12, 1e150])
def test_level_thresholds_are_the_exact_square_boundaries(level):
    """sqrt(x) >= level exactly when x >= threshold: no square root per step is needed."""
    x = float(level_thresholds([level])[0])
    assert np.sqrt(x) >= level
    assert np.sqrt(np.nextafter(x, 0.0)) < level


# --- the disk cache ----------------------------------------------------------------------------

KERNEL = '''
from numba import njit

@njit(inline="always")
def decay_step(x1, x2, x3, h, p, s):
    """Explicit Euler on x' = -k x (k = p[0]), each component."""
    return -h * {factor} * p[0] * x1, -h * p[0] * x2, -h * p[0] * x3, 0

@njit(inline="always")
def observe(x1, x2, x3, p, ia, ib, ic):
    return x1, x2, x3
'''

SCRIPT = '''
import json, sys
import numpy as np
sys.path.insert(0, sys.argv[1])
import decay
from stability.engine import compiled_loop, propagate_groups
from stability.integrators.spec import MethodSpec
from stability.engine.scene import Scene

spec = MethodSpec(name="euler", title="explicit Euler", order=1, step=decay.decay_step,
                  params=lambda k, h: np.array([k]))
scene = Scene(name="decay", title="decay", equations="x' = -k x", components=("a", "b", "c"),
              units=("1", "1", "1"), methods={"euler": spec}, observe=decay.observe,
              tracked=lambda x, p, axes: (x[:, 0], x[:, 1], x[:, 2]))
run = propagate_groups(scene, spec, np.ones((3, 3)), [[0.5]], [3], 0.1, 10, progress=False)
stats = compiled_loop(scene, spec).stats
print(json.dumps({"x": run.x_final[0].tolist(), "hits": sum(stats.cache_hits.values()),
                  "misses": sum(stats.cache_misses.values())}))
'''


def run_in_new_process(tmp_path):
    env = dict(os.environ, STABILITY_CACHE_DIR=str(tmp_path / "cache"))
    done = subprocess.run([sys.executable, str(tmp_path / "script.py"), str(tmp_path)],
                          capture_output=True, text=True, env=env, check=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def test_loops_load_from_disk_and_compile_again_when_a_kernel_changes(tmp_path):
    """The second process loads the compiled loop from the disk cache; after an edit of the
    kernel's module the next process compiles it again, and runs the edited kernel."""
    (tmp_path / "decay.py").write_text(textwrap.dedent(KERNEL.format(factor="1.0")))
    (tmp_path / "script.py").write_text(SCRIPT)
    first = run_in_new_process(tmp_path)
    second = run_in_new_process(tmp_path)
    assert (first["misses"], first["hits"]) == (1, 0)
    assert (second["misses"], second["hits"]) == (0, 1)
    assert second["x"] == first["x"] == pytest.approx([0.95 ** 10] * 3, rel=1e-14)

    (tmp_path / "decay.py").write_text(textwrap.dedent(KERNEL.format(factor="2.0")))
    edited = run_in_new_process(tmp_path)
    assert (edited["misses"], edited["hits"]) == (1, 0)
    assert edited["x"][0] == pytest.approx(0.9 ** 10, rel=1e-14)
    assert edited["x"][1:] == first["x"][1:]


def _loop_digests():
    """The digest naming each registered (scene, method) loop, as compiled_loop computes it."""
    from stability.engine.sources import digest

    out = {}
    for scene in SCENES.values():
        for spec in scene.methods.values():
            kernel = scene.kernel(spec)
            roots = (kernel.py_func.__module__, scene.observe.py_func.__module__,
                     "stability.engine.loop")
            out[f"{scene.name}/{spec.name}"] = digest(
                "", roots, (kernel.py_func, scene.observe.py_func))
    return out


def test_a_loops_name_does_not_depend_on_what_the_process_holds():
    """The digest in a loop's file name is the same whatever else refers to its kernels'
    constants, and under another string hash seed (in a new process): with marshal's bytes
    it was not, and the lp4/6/8 attitude loops and the engine rules were compiled twice in
    one test run, under two names."""
    before = _loop_digests()
    held = [const for scene in SCENES.values() for spec in scene.methods.values()
            for function in (scene.kernel(spec), scene.observe)
            for const in function.py_func.__code__.co_consts]
    assert held and _loop_digests() == before
    script = ("import json; from tests.test_engine import _loop_digests; "
              "print(json.dumps(_loop_digests()))")
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                          check=True, cwd=ROOT, env=dict(os.environ, PYTHONHASHSEED="12345"))
    assert json.loads(done.stdout.strip().splitlines()[-1]) == before


def test_processes_that_need_one_loop_at_once_compile_it_once(tmp_path):
    """Two processes start together on an empty cache: one compiles the loop while the other
    waits on the loop's lock file, then loads that compile from disk."""
    (tmp_path / "decay.py").write_text(textwrap.dedent(KERNEL.format(factor="1.0")))
    (tmp_path / "script.py").write_text(SCRIPT)
    env = dict(os.environ, STABILITY_CACHE_DIR=str(tmp_path / "cache"))
    both = [subprocess.Popen([sys.executable, str(tmp_path / "script.py"), str(tmp_path)],
                             stdout=subprocess.PIPE, text=True, env=env) for _ in range(2)]
    outputs = [json.loads(p.communicate()[0].strip().splitlines()[-1]) for p in both]
    assert all(p.returncode == 0 for p in both)
    assert sorted((o["misses"], o["hits"]) for o in outputs) == [(0, 1), (1, 0)]
    assert outputs[0]["x"] == outputs[1]["x"]


def test_block_table_covers_every_active_member_once_and_splits_the_last_groups():
    from stability.engine.run import MIN_BLOCK, block_table

    sizes = [70, 64, 5, 300]
    lo, size, group = block_table(sizes)
    covered = np.concatenate([np.arange(a, a + n) for a, n in zip(lo, size)])
    assert np.array_equal(np.sort(covered), np.arange(sum(sizes)))
    assert np.all(size <= BLOCK) and np.all(size >= 1)
    starts = np.cumsum(sizes) - sizes
    assert np.all((lo >= starts[group]) & (lo + size <= starts[group] + np.array(sizes)[group]))
    # Only the active groups; fewer members than blocks for every thread: smaller blocks.
    from stability.engine.run import BLOCKS_PER_THREAD

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
    from stability.engine.run import LPT_BLOCKS, thread_shares

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


def test_the_speed_reference_loop_is_rk4_on_every_member():
    """``stability bench``'s plain loop (:mod:`stability.engine.reference`) does the engine's
    RK4 on every member, the last partial block included: it differs from the engine's
    compensated loop by rounding only (1e-12 of |m| after 200 steps), so the bench's ratio of
    the two rates compares the same arithmetic."""
    from stability.engine.reference import plain_rk4
    from stability.integrators.spec import body_params

    scene = SCENES["free_body"]
    m0 = starts(scene, BLOCK + 37)  # one whole block and a partial one
    h, steps = 0.01, 200
    m = m0.copy()
    plain_rk4(m, body_params(MOMENTS), h, steps)
    spec = scene.method("rk4")
    engine = propagate_groups(scene, spec, m0, spec.params(MOMENTS, h)[None], [len(m0)], h,
                              steps, progress=False)
    scale = np.abs(m0).max()
    assert np.abs(m - engine.x_final).max() < 1e-12 * scale
    assert np.abs(m - m0).max() > 1e-3 * scale  # the members changed
