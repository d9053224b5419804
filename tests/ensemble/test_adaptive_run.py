"""run_adaptive through the one pipeline: the Dataset as declared, and bitwise the same in one
piece as chunked into a store."""

import numpy as np
import pytest

import stability
from stability.ensemble.schema import ADAPTIVE_RUN
from stability.free_body.scene import FREE_BODY, flip_event
from tests.engine.test_adaptive import MOMENTS, free_body_starts
from tests.helpers import assert_cf_compliant


SAMPLES = np.linspace(0.0, 30.0, 16)


def run(**options):
    m0 = free_body_starts(24, seed=5)
    return stability.run_adaptive(
        FREE_BODY, m0, [MOMENTS, np.array([1.0, 1.5, 2.2])],
        np.linspace(20.0, 40.0, 24), rtol=1e-10, atol=1e-13, sizes=[10, 14],
        events=stability.Event(flip_event, count=3), samples=SAMPLES,
        options=stability.RunOptions(progress=False, **options))


def test_the_dataset_is_as_declared_and_the_same_bitwise_in_one_piece_as_in_a_chunked_store(
        tmp_path):
    whole = run()
    assert ADAPTIVE_RUN.problems(whole) == []
    assert np.all(whole.status == 0) and np.array_equal(whole.t_final, whole.t_end)
    assert whole.accepted_steps.attrs["units"] == "1" and whole.t_final.attrs["units"] == "s"
    assert int(whole.event_count.min()) >= 1
    assert np.array_equal(whole.time, SAMPLES) and whole.time.attrs["standard_name"] == "time"
    assert whole.m2.dims == ("member", "time") and whole.m2.attrs["units"] == "kg m2 s-1"
    assert np.array_equal(whole.m1[:, 0], whole.m1_start)
    past = SAMPLES[None, :] > whole.t_end.values[:, None]
    assert past.any() and np.all(np.isnan(whole.m3.values[past]))
    assert whole.error_sum.attrs["units"] == "kg m2 s-1" and np.all(whole.error_sum > 0)
    stability.save(whole, tmp_path / "adaptive.nc")
    assert_cf_compliant(tmp_path / "adaptive.nc")
    stored = run(store=tmp_path / "store", chunk_members=7)
    for name in whole.data_vars:
        assert np.array_equal(whole[name].values, stored[name].values, equal_nan=True), name
    assert stored.sizes["member"] == 24


def test_one_thread_two_threads_and_two_dask_workers_give_the_same_bits(tmp_path):
    """Members of one chunk take different numbers of steps, and who runs them changes nothing:
    one Numba thread, two, and two worker processes of a dask cluster (each chunk of 7 a task,
    the loop loaded from the disk cache there) give bitwise the same Dataset."""
    distributed = pytest.importorskip("distributed")
    two = run(threads=2)
    assert len(np.unique(two.accepted_steps)) > 10  # the lanes end at different steps
    one = run(threads=1)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        there = run(store=tmp_path / "store", chunk_members=7, scheduler=client)
    for name in two.data_vars:
        assert np.array_equal(one[name].values, two[name].values, equal_nan=True), name
        assert np.array_equal(there[name].values, two[name].values, equal_nan=True), name
