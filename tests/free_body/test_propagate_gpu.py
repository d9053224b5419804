"""The free body on the GPU (stability.free_body.propagate_gpu) under the CUDA simulator, against
the CPU: every GPU method, the exact kernel against the elliptic solution, chunks and groups
(tests/engine/gpu/__init__.py says how)."""

import pytest

from stability.free_body.propagate_gpu import GPU_METHODS

from ..helpers import GPU_TOLERANCE as TOLERANCE
from ..helpers import needs_numba_cuda


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
