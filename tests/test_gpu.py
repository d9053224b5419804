"""The GPU kernels (stability.engine.gpu), checked on numba-cuda's CUDA simulator against the CPU.

The simulator (``NUMBA_ENABLE_CUDASIM=1``) runs every kernel as Python on the CPU, one thread
after another: it checks the kernels' logic (indexing, layout, tracking, chunks, groups, frame
conversions), not their speed or the device's arithmetic. It is switched on in a subprocess
(``tests/gpu_simulated.py``, which prints its results as JSON): numba reads the variable once,
when ``numba.cuda`` is first imported, and pytest-xdist runs several test modules in one worker
process, so setting it here would turn the simulator on for whichever module came next.

Why a real GPU agrees with the CPU to round-off and not bitwise: NVVM contracts a * b + c into
fused multiply-adds (one rounding instead of two) wherever it can, the device's libm (``log``
of the level passages, ``cosh``, ``asinh``, ``sqrt`` of the exact flow) is not glibc's, and
every contracted or reassociated expression rounds differently. Each is an ulp per operation;
over a run they add up like the method's own round-off, far below the 1e-12 asked here. Python
rounds every operation once, as the CPU loop does, so under the simulator the results are in
fact bitwise the CPU's (asserted to 1e-12 all the same, which is what a GPU must meet).
"""

import importlib.util
import json
import os
import pathlib
import subprocess
import sys

import pytest

from stability.engine.gpu import NO_GPU_MESSAGE, NOT_ON_GPU, gpu_method, gpu_methods
from stability.free_body.propagate_gpu import GPU_METHODS
from stability.heavy_top.scene import HEAVY_TOP

from .helpers import once_per_run

ROOT = pathlib.Path(__file__).resolve().parents[1]
SCRIPT = ROOT / "tests" / "gpu_simulated.py"
TOLERANCE = 1e-12

needs_numba_cuda = pytest.mark.skipif(
    importlib.util.find_spec("numba_cuda") is None, reason="numba-cuda is not installed"
)


def _run(simulator, *args):
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_ENABLE_CUDASIM"}
    if simulator:
        env["NUMBA_ENABLE_CUDASIM"] = "1"
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT), env.get("PYTHONPATH")]))
    done = subprocess.run([sys.executable, str(SCRIPT), *args], env=env, cwd=ROOT,
                          capture_output=True, text=True, timeout=900)
    assert done.returncode == 0, done.stderr[-4000:]
    return json.loads(done.stdout.strip().splitlines()[-1])


@pytest.fixture(scope="module")
def simulated(tmp_path_factory):
    """The simulator's results (about 25 CPU s), made once in a run of the suite."""
    folder = once_per_run(tmp_path_factory, "gpu_simulated", lambda folder: (
        folder / "results.json").write_text(json.dumps(_run(True))))
    return json.loads((folder / "results.json").read_text())


@needs_numba_cuda
@pytest.mark.parametrize("method", GPU_METHODS)
def test_agrees_with_cpu(simulated, method):
    r = simulated[method]
    assert r["final"] <= TOLERANCE
    assert r["saved_shape"][0] == r["saved_shape"][1] and r["saved"] <= TOLERANCE
    assert r["flips_gpu"] == r["flips_cpu"] and max(r["flips_cpu"]) >= 2
    assert r["perp_equal"] and r["nan_equal"] and r["status_equal"]
    assert r["max_amplitude"] <= TOLERANCE
    for key in ("first_axis_crossing", "last_axis_crossing", "first_perp_crossing",
                "last_perp_crossing", "passage_time"):
        assert r[key] <= TOLERANCE, key
    assert r["steps_done"][0] == r["steps_done"][1]


@needs_numba_cuda
def test_exact_kernel_against_elliptic_solution(simulated):
    r = simulated["exact_vs_elliptic"]
    assert r["one_step"] <= TOLERANCE and r["fifty_steps"] <= TOLERANCE


@needs_numba_cuda
def test_chunks_and_groups_change_nothing(simulated):
    r = simulated["chunks_and_groups"]
    assert r["chunked"] and r["group0"] and r["group1"]
    assert r["steps_done"] == [200, 100]


@needs_numba_cuda
def test_a_method_the_scene_has_not_is_named_with_those_it_has(simulated, monkeypatch):
    assert "'no_such_method' does not run scene 'free_body'" in simulated["no_kernel_error"]
    assert "rk4, lp2" in simulated["no_kernel_error"]
    monkeypatch.setitem(NOT_ON_GPU, ("heavy_top", "lp4"), "a reason")
    with pytest.raises(ValueError, match=r"'lp4' of scene 'heavy_top' has no GPU kernel "
                                         r"\(a reason\); methods with one: rk4, lp2$"):
        gpu_method("lp4", HEAVY_TOP)
    assert gpu_methods(HEAVY_TOP) == ("rk4", "lp2")
    assert set(GPU_METHODS) >= {"rk4", "lp2", "exact"}


@needs_numba_cuda
def test_every_scene_and_method_runs_on_the_gpu(simulated):
    """Each registered scene's every method, and a scene of the user's own, in two groups,
    tracked, saved and in chunks: the CPU loop's result (bitwise under the simulator, which
    rounds as the CPU does)."""
    from stability.registry import SCENES

    runs = simulated["every_scene"]
    assert set(runs) == {f"{s.name}/{m}" for s in SCENES.values()
                         for m in gpu_methods(s)} | {"gpu_damped_body/rk4"}
    assert len(runs) > len(SCENES)
    for case, r in runs.items():
        assert r["shapes"] and r["status_equal"] and r["counts_equal"], case
        assert r["iterations_equal"] and r["steps_done"][0] == r["steps_done"][1], case
        assert max(r["final"], r["saved"], r["times"]) <= TOLERANCE, case
        assert r["bitwise"], case


@needs_numba_cuda
def test_the_tangent_scenes_run_on_the_gpu_as_on_the_cpu(simulated):
    """The state with two tangents of the free body, the heavy top and the sphere damper,
    saved and in chunked launches: the CPU loop's result, bitwise under the simulator."""
    runs = simulated["tangents"]
    assert {case.split("_tangent")[0] for case in runs} == {
        "free_body", "heavy_top", "sphere_damper"}
    for case, r in runs.items():
        assert r["shapes"] and r["status_equal"] and r["bitwise"], case
        assert r["steps_done"][0] == r["steps_done"][1], case


@needs_numba_cuda
def test_no_gpu_and_no_simulator_says_what_to_do():
    r = _run(False, "--no-device")
    if r["real_gpu"]:
        pytest.skip("a CUDA GPU is present")
    assert r["message"] == NO_GPU_MESSAGE
    assert "NUMBA_ENABLE_CUDASIM=1" in r["message"]


def test_bench_without_gpu_skips():
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_ENABLE_CUDASIM"}
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT), env.get("PYTHONPATH")]))
    done = subprocess.run([sys.executable, "-m", "stability.cli.gpu_bench"], env=env, cwd=ROOT,
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr[-4000:]
    if "member-steps/s" in done.stdout:
        pytest.skip("a CUDA GPU is present (the benchmark ran)")
    assert done.stdout.strip() == "no CUDA GPU: skipped"


@needs_numba_cuda
def test_run_ensemble_on_the_gpu_gives_the_cpu_members(simulated):
    r = simulated["ensemble"]
    assert r["worst"] <= TOLERANCE and r["flips"] > 0
    assert r["device"] == 1  # recorded in the Dataset's configuration


def test_gpu_device_refuses_a_method_it_has_not():
    import stability

    body = stability.RigidBody(1.0, 2.0, 3.0)
    with pytest.raises(ValueError, match="device must be 'cpu' or 'gpu', got 'tpu'"):
        stability.run_ensemble(body, 2, 1.0, 0.01, 4, h=0.1, t_end=1.0,
                               options=stability.RunOptions(device="tpu"))
    NOT_ON_GPU["free_body", "midpoint"] = "a reason"
    try:
        with pytest.raises(ValueError, match="'midpoint' of scene 'free_body' has no GPU"):
            stability.run_ensemble(body, 2, 1.0, 0.01, 4, h=0.1, t_end=1.0, method="midpoint",
                                   options=stability.RunOptions(device="gpu"))
    finally:
        del NOT_ON_GPU["free_body", "midpoint"]


@needs_numba_cuda
def test_a_stored_run_on_the_gpu_in_chunks_is_the_cpu_run(simulated):
    r = simulated["stored"]
    assert r["bitwise"]  # under the simulator; to round-off on a GPU
    assert r["identity_differs"]  # a store written on one device is not resumed on the other


@needs_numba_cuda
def test_the_tennis_studys_measurement_of_gpu_chunks_is_the_cpus(simulated):
    """Chunks run on the GPU come back as the loop's canonical series, which the tennis study
    measures without building every member's w: the same rates, flips, histograms and sample."""
    r = simulated["tennis"]
    assert r["worst"] <= TOLERANCE and r["rates"] == 10 and r["kept"] == 3


def test_grouped_run_refuses_an_unknown_device():
    from stability.ensemble.plan import Plan
    from stability.free_body.scene import FREE_BODY

    with pytest.raises(ValueError, match="device must be 'cpu' or 'gpu', got 'tpu'"):
        Plan(FREE_BODY, "rk4", [[0.0, 1.0, 0.0]], [[1.0] * 9], [1], 0.1, 1,
             device="tpu")
