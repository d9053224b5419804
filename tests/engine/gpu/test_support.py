"""Which scenes and methods the GPU runs (stability.engine.gpu.support): a method without a GPU
kernel is refused, naming those with one."""

import pytest

from stability.engine.gpu import NOT_ON_GPU, gpu_method, gpu_methods
from stability.free_body.propagate_gpu import GPU_METHODS
from stability.heavy_top.scene import HEAVY_TOP

from ...helpers import needs_numba_cuda


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
