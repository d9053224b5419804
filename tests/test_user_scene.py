"""Scenes from the user's own code: a module outside the package defines a harmonic oscillator
with stability.define_scene, and it runs as a registered scene does (groups, a store in chunks,
resume, dask workers that import the module, the disk cache across processes); each mistake in
a definition is one line."""

import importlib
import json
import os
import pickle
import subprocess
import sys
import textwrap

from pathlib import Path

import numpy as np
import pytest

import stability
from stability import define_scene
from stability.engine import propagate_groups
from stability import RunOptions
from stability.ensemble.chunks import run_plan
from stability.ensemble.plan import Plan
from stability.output.store import status_lines

from .helpers import assert_cf_compliant, assert_declared

ROOT = Path(__file__).resolve().parents[1]

#: The user's module: x' = v, v' = -(f omega)^2 x, exactly solvable (f = 1 unless edited).
MODULE = '''
"""A harmonic oscillator, defined outside the package."""
import numpy as np
from numba import njit
from stability import MethodSpec, define_scene


def rhs(x, v, p):
    """x' = v, v' = -omega^2 x"""
    return v, -({factor} * p[0]) ** 2 * x


@njit(inline="always")
def euler_step(x, v, h, p, s):
    """Explicit Euler: the increment h f(x)."""
    return h * v, -h * ({factor} * p[0]) ** 2 * x, 0


def energy(x, values):
    return 0.5 * (x[:, 1] ** 2 + (values[0] * x[:, 0]) ** 2)


def exact(x0, values, t):
    w = values[0]
    c, s = np.cos(w * t), np.sin(w * t)
    return np.column_stack([x0[:, 0] * c + x0[:, 1] / w * s, x0[:, 1] * c - x0[:, 0] * w * s])


def example(n, seed=0):
    return np.random.default_rng(seed).standard_normal((n, 2)), [{{"omega": 1.0}}, [2.5]]


OSCILLATOR = define_scene("user_oscillator", ["x", "v"], ["m", "m s-1"], rhs, ["omega"],
                          parameter_units=["rad s-1"],
                          invariants={{"energy": energy}}, exact=exact, example=example,
                          methods=[MethodSpec(name="euler", title="explicit Euler", order=1,
                                              step=euler_step)])
'''

#: A new process: imports the module from the folder argv[1], runs it, reports the cache.
SCRIPT = '''
import json, sys, time
t0 = time.perf_counter()
sys.path.insert(0, sys.argv[1])
from user_oscillator import OSCILLATOR
from stability.engine import compiled_loop, propagate_groups
spec = OSCILLATOR.method("rk4")
x0 = OSCILLATOR.example(5)[0]
run = propagate_groups(OSCILLATOR, spec, x0, [spec.params([1.5])], [5], 0.05, 40,
                       progress=False)
seconds = time.perf_counter() - t0
stats = compiled_loop(OSCILLATOR, spec).stats
print(json.dumps({"x": run.x_final.tolist(), "seconds": seconds,
                  "hits": sum(stats.cache_hits.values()),
                  "misses": sum(stats.cache_misses.values())}))
'''


def write_module(folder, factor="1.0"):
    folder.mkdir(exist_ok=True)
    (folder / "user_oscillator.py").write_text(MODULE.format(factor=factor))
    return folder


@pytest.fixture(scope="module")
def home(tmp_path_factory):
    """The user's folder on the path and their scene imported from it."""
    folder = write_module(tmp_path_factory.mktemp("user") / "mine")
    sys.path.insert(0, str(folder))
    try:
        yield folder, importlib.import_module("user_oscillator").OSCILLATOR
    finally:
        sys.path.remove(str(folder))
        sys.modules.pop("user_oscillator", None)


def oscillator_run(scene) -> Plan:
    """Three groups of unequal sizes, steps and horizons, saving samples and tracking v."""
    spec = scene.method("rk4")
    sizes, hs = [7, 5, 4], [0.05, 0.02, 0.04]
    x0 = np.concatenate([scene.example(n, seed=k)[0] for k, n in enumerate(sizes)])
    params = [spec.params(values, h) for values, h in zip([[1.0], [2.5], {"omega": 0.7}], hs)]
    return Plan(scene, "rk4", x0, params, sizes, hs, [40, 60, 25], save_every=10,
                axes=[[1, 0, 1]] * 3, levels=[[0.5, 1.0]] * 3)


def assert_bitwise(a, b):
    for name in ("x_final", "saved", "status", "fail_step", "iterations", "steps_done"):
        assert np.array_equal(getattr(a, name), getattr(b, name), equal_nan=True), name
    for name, value in a.extras.items():
        assert np.array_equal(value, b.extras[name], equal_nan=True), name


def test_the_scenes_rk4_has_order_four_against_its_exact_solution(home):
    """Groups at h, h/2 and h/4 to the same time: each halving divides the error by 2^4."""
    _, scene = home
    spec = scene.method("rk4")
    x0 = scene.example(20, seed=3)[0]
    hs = np.array([0.2, 0.1, 0.05])
    run = propagate_groups(scene, spec, np.tile(x0, (3, 1)), [spec.params([1.3])] * 3,
                           [20] * 3, hs, np.rint(4.0 / hs).astype(int), progress=False)
    exact = scene.exact(x0, {"omega": 1.3}, 4.0)
    errors = [np.abs(part - exact).max() for part in np.split(run.x_final, 3)]
    assert np.log2(errors[0] / errors[1]) == pytest.approx(4.0, abs=0.15)
    assert np.log2(errors[1] / errors[2]) == pytest.approx(4.0, abs=0.15)
    energy = scene.invariants["energy"]
    assert np.allclose(energy(run.x_final[40:], [1.3]), energy(x0, [1.3]), rtol=1e-6)
    assert scene.equations == "x' = v, v' = -omega^2 x"
    assert scene.parameters == ("omega",) and scene.units == ("m", "m s-1")


def test_a_method_of_the_users_own_runs_with_the_scenes_parameters(home):
    """A MethodSpec given to define_scene runs its own kernel, with the scene's parameter row
    (its params left at the default, a body's, are the scene's)."""
    _, scene = home
    assert list(scene.methods) == ["rk4", "euler"]
    spec = scene.method("euler")
    p = spec.params({"omega": 2.0}, 0.1)
    assert p.tolist() == [2.0]
    run = propagate_groups(scene, spec, [[1.0, 0.5]], [p], [1], 0.1, 1, progress=False)
    assert run.x_final.tolist() == [[1.0 + 0.1 * 0.5, 0.5 + -0.1 * (1.0 * 2.0) ** 2 * 1.0]]


def test_a_stored_run_in_chunks_and_resumed_is_bitwise_the_run_in_one_piece(home, tmp_path):
    _, scene = home
    run = oscillator_run(scene)
    whole = run_plan(run, RunOptions(progress=False))
    store = tmp_path / "store"
    assert_bitwise(run_plan(run, RunOptions(store=store, chunk_members=3, progress=False)), whole)
    for name in ("chunk-000002.nc", "chunk-000002.nc.sha256"):  # as a stopped run leaves it
        (store / name).unlink()
    again = run_plan(run, RunOptions(store=store, chunk_members=3, resume=True, progress=False))
    assert_bitwise(again, whole)
    assert whole.saved.shape == (16, 6, 2)
    assert any("complete" in line for line in status_lines(store))


def test_the_chunks_run_on_dask_workers_that_import_the_users_module(home, tmp_path):
    """The run is pickled with its scene by reference; each worker imports the user's module
    (its folder on their path) and loads the compiled loop from the shared disk cache."""
    distributed = pytest.importorskip("distributed")
    folder, scene = home
    assert pickle.loads(pickle.dumps(scene)) is scene
    run = oscillator_run(scene)
    whole = run_plan(run, RunOptions(progress=False))
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        client.run(sys.path.insert, 0, str(folder))  # what a user's remote workers need too
        there = run_plan(run,
                         RunOptions(store=tmp_path / "store", chunk_members=6, scheduler=client,
                                    progress=False))
    assert_bitwise(there, whole)


def leave_path(folder):
    """Take ``folder`` off this process's path (run on a worker: ``sys.path.remove`` itself
    would be pickled with a copy of the caller's list)."""
    sys.path.remove(folder)


def test_a_worker_that_cannot_import_the_users_module_is_named_in_one_line(home, tmp_path):
    """The module is on this process's path, not on the worker's: the worker failed to read
    each task, died and was started again, and the run waited for good. One line now, naming
    the module, the worker and where it must be importable, before any task is sent."""
    distributed = pytest.importorskip("distributed")
    folder, scene = home
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        # the worker inherited this process's path; client.run answers by worker address
        # (the client's scheduler_info can still be empty under load, before its first refresh)
        (worker,) = client.run(leave_path, str(folder))
        with pytest.raises(ValueError) as info:
            run_plan(oscillator_run(scene),
                     RunOptions(store=tmp_path / "store", chunk_members=6, scheduler=client,
                                progress=False))
    assert str(info.value) == (
        f"the dask worker {worker} cannot import module 'user_oscillator' (No module named "
        "'user_oscillator'), which the run needs: it must be importable on the scheduler and "
        "on every worker; put its folder on their PYTHONPATH, or install it there")
    assert not list((tmp_path / "store").glob("chunk-*"))


#: A script that defines its scene in itself (``__main__``) and runs it on a local cluster.
MAIN_SCRIPT = """
import sys
import numpy as np
from stability import define_scene
from stability import RunOptions
from stability.ensemble.chunks import run_plan
from stability.ensemble.plan import Plan


def rhs(x, v, p):
    return v, -p[0] ** 2 * x


SCENE = define_scene("script_oscillator", ["x", "v"], ["m", "m s-1"], rhs, ["omega"])

if __name__ == "__main__":
    spec = SCENE.method("rk4")
    run = Plan(SCENE, "rk4", np.ones((8, 2)), [spec.params([1.0], 0.05)], [8], [0.05],
               [40])
    run_plan(run, RunOptions(store=sys.argv[1], chunk_members=4, scheduler="dask",
                             progress=False))
"""


def test_a_scene_of_the_script_itself_is_refused_before_a_cluster_starts(tmp_path):
    """Workers cannot import ``__main__``: the run ended in dask's "Could not serialize object
    of type LLGExpr" after the cluster had started; now one line up front, no store made."""
    script = tmp_path / "mine.py"
    script.write_text(MAIN_SCRIPT)
    store = tmp_path / "store"
    done = subprocess.run([sys.executable, str(script), str(store)], capture_output=True,
                          text=True, cwd=tmp_path, timeout=300,
                          env={**os.environ, "PYTHONPATH": str(ROOT)})
    assert done.returncode == 1
    assert done.stderr.strip().splitlines()[-1] == (
        "ValueError: scene 'script_oscillator' cannot be sent to another process: it is "
        "defined in __main__ (the script being run), which "
        "other processes cannot import; move define_scene and the scene's functions into a "
        "module of their own and import the scene from there"), done.stderr
    assert "distributed" not in done.stderr and not store.exists()


def test_a_run_of_the_users_scene_is_a_dataset_named_and_labelled_from_it(home, tmp_path):
    """run_scene gives one variable per component, in the scene's units, the parameters by
    name, each member's status and drift; in one piece or stored in chunks, bitwise alike; the
    file written is as the register declares it for this scene, and CF-compliant."""
    _, scene = home
    spec = scene.method("rk4")
    x0 = scene.example(9, seed=2)[0]
    sets, steps = [[1.0], {"omega": 2.5}], [40, 60]
    kwargs = dict(sizes=[5, 4], h=0.05, n_steps=steps, save_every=10, axes=[0, 1, 1],
                  levels=[0.5, 1.0], options=stability.RunOptions(progress=False))
    ds = stability.run_scene(scene, "rk4", x0, sets, **kwargs)
    for name, unit in zip(scene.components, scene.units):
        assert ds[name].dims == ("member", "time") and ds[name].attrs["units"] == unit
        assert ds[f"{name}_start"].attrs["units"] == ds[f"{name}_final"].attrs["units"] == unit
    assert ds.omega.attrs["units"] == "rad s-1" and ds.omega.values.tolist() == [1.0, 2.5]
    assert ds.time.attrs["units"].startswith("s since") and ds.time.values[-1] == 3.0
    assert ds.status.attrs["flag_meanings"].split()[0] == "ok" and (ds.status == 0).all()
    assert ds.max_perp_amplitude.attrs["units"] == "m s-1" and ds.passage_time.shape == (9, 2)
    assert float(np.abs(ds.energy_drift).max()) < 1e-5
    # the numbers are the loop's: the same groups through run_plan
    rows = [spec.params(values, 0.05) for values in sets]
    raw = run_plan(Plan(scene, "rk4", x0, rows, [5, 4], 0.05, steps,
                                      save_every=10), RunOptions(progress=False))
    assert np.array_equal(np.column_stack([ds.x_final, ds.v_final]), raw.x_final)
    assert np.array_equal(ds.x.values[:, 1:], raw.saved[:, :, 0], equal_nan=True)
    assert np.isnan(ds.x.values[:5, -2:]).all()  # past the end of the shorter group
    stored = stability.run_scene(scene, "rk4", x0, sets, **{**kwargs, "options": RunOptions(
        store=tmp_path / "store", chunk_members=2, progress=False)})
    assert set(stored.variables) == set(ds.variables)
    for name in ds.variables:
        assert np.array_equal(stored[name].values, ds[name].values, equal_nan=True), name
    path = stability.save(stored, tmp_path / "oscillator.nc")
    assert_declared(path, "scene_run")
    assert_cf_compliant(path)


def run_in_new_process(folder, env=None):
    """SCRIPT's report from a new process, with this checkout's package."""
    path = os.pathsep.join(filter(None, [str(ROOT), os.environ.get("PYTHONPATH")]))
    done = subprocess.run([sys.executable, "-c", SCRIPT, str(folder)], capture_output=True,
                          text=True, check=True,
                          env=dict(os.environ, PYTHONPATH=path, **(env or {})))
    return json.loads(done.stdout.strip().splitlines()[-1])


@pytest.mark.parametrize("change, message", [
    (dict(parameters={"omega": float("nan")}),
     "scene 'user_oscillator': parameter omega must be finite, got nan"),
    (dict(parameters=[float("inf")]),
     "scene 'user_oscillator': parameter omega must be finite, got inf"),
    (dict(parameters={"omega": "one"}),
     "scene 'user_oscillator': parameter omega must be a number, got 'one'"),
    (dict(save_every=100), "save_every = 100 is more than the 10 steps of the longest "
                           "group, so the series would hold the start alone"),
    (dict(x0=np.ones((0, 2))), "x0 has no rows: give at least one member, a row of 2 numbers"),
    (dict(label=5), "label must be a string"),
])
def test_a_run_of_the_users_scene_refuses_nonsense_in_one_line(home, change, message):
    _, scene = home
    args = dict(x0=np.ones((3, 2)), parameters={"omega": 1.0}, h=0.01, n_steps=10,
                options=stability.RunOptions(progress=False))
    args.update(change)
    with pytest.raises(ValueError, match=message.replace("(", r"\(")) as caught:
        stability.run_scene(scene, "rk4", args.pop("x0"), args.pop("parameters"), **args)
    assert "\n" not in str(caught.value)


def test_invariants_may_be_given_as_name_function_pairs(home):
    module = importlib.import_module("user_oscillator")
    pairs = define_scene("paired_oscillator", ["x", "v"], ["m", "m s-1"], module.rhs,
                         ["omega"], invariants=[("energy", module.energy)])
    assert list(pairs.invariants) == ["energy"]


def test_a_new_process_loads_the_scene_from_disk_and_an_edit_compiles_again(home, tmp_path):
    """A new process finds the loop compiled here in the disk cache; an edited copy of the
    module (another cache: it must compile, whatever earlier runs left) compiles and runs the
    edited right-hand side."""
    folder, scene = home
    spec = scene.method("rk4")
    x0 = scene.example(5)[0]
    here = propagate_groups(scene, spec, x0, [spec.params([1.5])], [5], 0.05, 40,
                            progress=False)
    loaded = run_in_new_process(folder)
    assert (loaded["misses"], loaded["hits"]) == (0, 1)
    assert np.array_equal(loaded["x"], here.x_final)

    edited = run_in_new_process(write_module(tmp_path / "edited", factor="2.0"),
                                {"STABILITY_CACHE_DIR": str(tmp_path / "cache")})
    assert (edited["misses"], edited["hits"]) == (1, 0)
    exact = scene.exact(x0, [3.0], 2.0)  # omega 1.5 doubled
    assert np.allclose(edited["x"], exact, atol=1e-3)
    assert not np.allclose(edited["x"], here.x_final, atol=1e-2)


def test_a_scene_not_bound_at_the_top_of_a_module_says_so_when_pickled(home):
    _, scene = home
    from dataclasses import replace

    inner = replace(scene, module="__main__")
    with pytest.raises(pickle.PicklingError, match="cannot be sent to another process"):
        pickle.dumps(inner)


# --- mistakes: one line each -------------------------------------------------------------------

MISTAKES = '''
import fractions
import math
import numpy as np


def rhs(x, v, p):
    return v, -p[0] * x


def rhs_two(x, p):
    return (x,)


def rhs_one_value(x, v, p):
    return v


def rhs_misspelt(x, v, p):
    return v, -p[0] * math.sine(x)


def rhs_second_parameter(x, v, p):
    return v, -p[1] * x


def rhs_numba_cannot(x, v, p):
    return v, -p[0] * float(fractions.Fraction(1, 3)) * x


def rhs_divides_by_zero(x, v, p):
    return v, -p[0] / (x - 1.0)


def rhs_dict(x, v, p):
    return {"a": x}, v


def energy_scalar(x, values):
    return 0.0


def example_three(n, seed=0):
    return np.ones((n, 2)), [[1.0, 2.0, 3.0]]


lam = lambda x, v, p: (v, x)
'''

CASES = {
    "capital name": (dict(name="Spring"), ValueError, "lowercase letters"),
    "registered name": (dict(name="free_body"), ValueError, "a registered scene's name"),
    "bad component": (dict(components=["x", "2v"]), ValueError, "identifiers.*'2v'"),
    "component twice": (dict(components=["x", "x"]), ValueError, "x comes twice"),
    "units missing": (dict(units=["m"]), ValueError, "1 units for 2 components"),
    "units a string": (dict(units="m"), TypeError, "units must be a list"),
    "rhs not a function": (dict(rhs=3.0), TypeError, "rhs must be a function"),
    "rhs a lambda": (dict(rhs="lam"), ValueError, "top level of its module"),
    "rhs arguments": (dict(rhs="rhs_two"), TypeError, r"takes 2 arguments.*rhs\(x, v, p\)"),
    "rhs one value": (dict(rhs="rhs_one_value"), ValueError, "returned float.*tuple of 2"),
    "rhs raises": (dict(rhs="rhs_misspelt"), ValueError, "rhs raised AttributeError.*sine"),
    "rhs reads a missing parameter": (dict(rhs="rhs_second_parameter"), ValueError,
                                      "IndexError.*p has 1 number"),
    "example's parameters": (dict(example="example_three"), ValueError,
                             "a parameter set has 1 number .k., got 3"),
    "observe alone": (dict(observe="rhs"), ValueError, "observe and tracked together"),
    "tracked units a number": (dict(tracked_units=5), TypeError,
                               "tracked_units must be a UDUNITS string such as 'rad s-1' or "
                               "'1', got 5"),
    "rhs returns a dict among its numbers": (dict(rhs="rhs_dict"), ValueError,
                                             "rhs returned dict .* as its number 0; it must "
                                             "return a tuple of 2 numbers"),
    "invariants a list": (dict(invariants=["energy_scalar"]), TypeError,
                          "invariants must be a dict of name: function"),
    "invariant shape": (dict(invariants={"energy": "energy_scalar"}), ValueError,
                        r"invariant 'energy' returned shape \(\)"),
    "rhs raises only when compiled": (  # it was "Numba cannot compile"
        dict(rhs="rhs_divides_by_zero"), ValueError,
        r"rhs rhs_divides_by_zero raised ZeroDivisionError: division by zero when compiled "
        r"\(compiled code raises on a division by zero.*tried on a state and parameters of ones"),
    "numba cannot compile": (dict(rhs="rhs_numba_cannot"), TypeError,
                             r"Numba cannot compile rhs rhs_numba_cannot: "
                             r"Unknown attribute 'Fraction'.*user_mistakes.py, line \d+\)"),
}


@pytest.fixture(scope="module")
def mistakes(tmp_path_factory):
    folder = tmp_path_factory.mktemp("mistakes")
    (folder / "user_mistakes.py").write_text(textwrap.dedent(MISTAKES))
    sys.path.insert(0, str(folder))
    try:
        yield importlib.import_module("user_mistakes")
    finally:
        sys.path.remove(str(folder))
        sys.modules.pop("user_mistakes", None)


@pytest.mark.parametrize("case", CASES)
def test_each_mistake_is_one_line_at_definition_time(mistakes, case):
    change, kind, message = CASES[case]

    def mine(value):  # names of the user module's functions stand for the functions
        if isinstance(value, dict):
            return {k: mine(v) for k, v in value.items()}
        return getattr(mistakes, value) if isinstance(value, str) and hasattr(
            mistakes, value) else value

    kwargs = dict(name="spring", components=["x", "v"], units=["m", "m s-1"],
                  rhs=mistakes.rhs, parameters=["k"])
    kwargs.update({key: mine(value) for key, value in change.items()})
    with pytest.raises(kind, match=message) as caught:
        define_scene(**kwargs)
    assert "\n" not in str(caught.value)
    shown = caught.value.__cause__ or (None if caught.value.__suppress_context__
                                       else caught.value.__context__)
    assert shown is None  # no traceback of ours or Numba's before the line


def test_a_scene_declares_the_units_of_what_it_tracks(home, mistakes, monkeypatch):
    """define_scene(tracked_units=) is the scene's (run_scene's default); the kernels are the
    oscillator's, not compiled again."""
    import types

    from stability.engine import user_scene

    _, oscillator = home
    kernels = types.SimpleNamespace(rk4_step=oscillator.method("rk4").step,
                                    observe=oscillator.observe, SOURCES="",
                                    rhs=oscillator.linearisation.rhs,
                                    __name__=oscillator.linearisation.module)
    monkeypatch.setattr(user_scene, "_kernels", lambda *args: kernels)
    monkeypatch.setattr(user_scene, "_compiles", lambda *args: None)
    spring = define_scene("spring", ["x", "v"], ["m", "m s-1"], mistakes.rhs, ["k"],
                          tracked_units="m")
    assert spring.tracked_units == "m"
    assert define_scene("spring", ["x", "v"], ["m", "m s-1"], mistakes.rhs,
                        ["k"]).tracked_units == ""


def test_the_users_named_parameter_dispersed_runs_each_member_with_its_own_draw(home, tmp_path):
    """omega dispersed log-uniformly over a decade (:mod:`stability.uncertainty.scenes`): the
    omega each member reports is its draw, bitwise, in one piece and in chunks resumed, and
    each end state is the exact solution of its own omega to RK4's error (h omega <= 0.05)."""
    from stability.uncertainty.designs import unit_design
    from stability.uncertainty.dispersions import dispersions
    from stability.uncertainty.scenes import nominal, run_dispersed
    _, scene = home
    disp = dispersions({"omega": {"distribution": "log-uniform", "lower": 0.5, "upper": 5.0}},
                       nominal(scene, [1.0]))
    unit = unit_design("sobol", 16, 1, 2)
    kwargs = dict(h=0.01, n_steps=200)
    draws, whole = run_dispersed(scene, "rk4", [1.0, 0.0], disp, unit, **kwargs,
                                 options=RunOptions(progress=False))
    w = draws["omega"]
    assert w.min() < 1.0 and w.max() > 3.0
    assert np.array_equal(whole.omega.values, w)
    assert np.max(np.abs(whole.x_final.values - np.cos(2.0 * w))) < 1e-6
    assert np.max(np.abs(whole.v_final.values + w * np.sin(2.0 * w))) < 1e-5
    store = tmp_path / "store"
    run_dispersed(scene, "rk4", [1.0, 0.0], disp, unit, **kwargs,
                  options=RunOptions(store=store, chunk_members=5, progress=False))
    chunks = sorted(store.rglob("*.nc"))
    assert len(chunks) >= 3
    chunks[1].unlink()
    _, resumed = run_dispersed(scene, "rk4", [1.0, 0.0], disp, unit, **kwargs,
                               options=RunOptions(store=store, chunk_members=5, resume=True,
                                                  progress=False))
    for name in ("omega", "x_final", "v_final"):
        assert np.array_equal(resumed[name].values, whole[name].values), name

