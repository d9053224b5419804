"""The adaptive Dormand-Prince 5(4) loop on the GPU (stability.engine.gpu.adaptive) under the
simulator: run_adaptive(device="gpu") gives the CPU's Dataset, events (recorded, and one that
stops its members) and samples included, for the free body and for a scene of the user's own."""

from ...helpers import GPU_TOLERANCE as TOLERANCE
from ...helpers import needs_numba_cuda


@needs_numba_cuda
def test_the_adaptive_loop_on_the_gpu_gives_the_cpus_dataset(simulated):
    """Every variable of both Datasets (final states, steps, error estimates, event times,
    stops, samples) agrees to 1e-12 and is NaN at the same places; bitwise, in fact, under the
    simulator (measured: both cases bitwise)."""
    runs = simulated["adaptive"]
    assert set(runs) == {"free_body", "user_scene"}
    for case, r in runs.items():
        assert r["same_nan"] and r["worst"] <= TOLERANCE, case
        assert r["bitwise"], case  # Python rounds as the CPU loop does
        assert r["events"] > 0, case
    assert runs["free_body"]["stopped"] > 0
