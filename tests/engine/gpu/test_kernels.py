"""The member loop as a CUDA kernel (stability.engine.gpu.kernels) under the simulator: every
registered scene's every method, and a scene of the user's own, give the CPU loop's result."""

from stability.engine.gpu import gpu_methods

from ...helpers import GPU_TOLERANCE as TOLERANCE
from ...helpers import needs_numba_cuda


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
def test_events_on_the_gpus_fixed_steps_give_the_cpus_dataset(simulated):
    """run_scene with events on the GPU: the free body's flips recorded and a stop at the second,
    a user's scene's crossings; every variable agrees with the CPU's to 1e-12 and is NaN at the
    same places (bitwise under the simulator, which rounds as the CPU loop does)."""
    runs = simulated["fixed_step_events"]
    assert set(runs) == {"free_body", "user_scene"}
    for case, r in runs.items():
        assert r["same_nan"] and r["worst"] <= TOLERANCE, case
        assert r["bitwise"], case
        assert r["events"] > 0, case
    assert runs["free_body"]["stopped"] > 0  # measured: 2 of the 3 reach their second flip
