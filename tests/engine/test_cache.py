"""The loops' disk cache (stability.engine.cache): loaded by the next process, compiled again when a
kernel changes, named the same in every process, compiled once by processes that start together."""

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from stability.registry import SCENES

ROOT = Path(__file__).resolve().parents[2]

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
    script = ("import json; from tests.engine.test_cache import _loop_digests; "
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
