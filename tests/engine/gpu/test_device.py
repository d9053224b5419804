"""Finding a CUDA device (stability.engine.gpu.device): without a GPU and without the simulator,
the error says what to do."""

import pytest

from stability.engine.gpu import NO_GPU_MESSAGE

from ...helpers import needs_numba_cuda, run_gpu_script


@needs_numba_cuda
def test_no_gpu_and_no_simulator_says_what_to_do():
    r = run_gpu_script(False, "--no-device")
    if r["real_gpu"]:
        pytest.skip("a CUDA GPU is present")
    assert r["message"] == NO_GPU_MESSAGE
    assert r["adaptive_message"] == NO_GPU_MESSAGE  # run_adaptive(device="gpu") too
    assert "NUMBA_ENABLE_CUDASIM=1" in r["message"]
