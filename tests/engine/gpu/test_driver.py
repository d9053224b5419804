"""Running the CUDA member loop from the host (stability.engine.gpu.driver) under the simulator: the
tangent scenes in chunked launches, ensembles, stored runs and the tennis study's chunks, as on
the CPU."""

from ...helpers import GPU_TOLERANCE as TOLERANCE
from ...helpers import needs_numba_cuda


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
def test_run_ensemble_on_the_gpu_gives_the_cpu_members(simulated):
    r = simulated["ensemble"]
    assert r["worst"] <= TOLERANCE and r["flips"] > 0
    assert r["device"] == 1  # recorded in the Dataset's configuration


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
