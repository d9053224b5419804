"""Streamed runs: chunk files, resume after a real kill, damaged chunks, dask.distributed.

Every comparison is bitwise: a member's numbers do not depend on the chunk it runs in, the
process, or the machine of the cluster that ran it.
"""

import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import stability
from stability.output.store import read_progress

from ..helpers import STOP_GUARD_S, wait_until

ROOT = Path(__file__).resolve().parents[2]
BODY = stability.RigidBody(1.0, 2.0, 3.0)
RUN = dict(body=BODY, axis=2, spin=1.0, epsilon=1e-3, members=700, h=0.01, t_end=30.0, seed=4,
           method="rk4", keep=stability.Keep(save_every=0))


def assert_same_members(a: xr.Dataset, b: xr.Dataset):
    assert set(a.data_vars) == set(b.data_vars)
    for name in a.variables:
        assert np.array_equal(a[name].values, b[name].values, equal_nan=True), name


@pytest.fixture(scope="module")
def in_memory():
    return stability.run_ensemble(**RUN)


@pytest.mark.parametrize("chunk, save, attitude",
                         [(256, None, False), (700, None, False), (100, 50, False),
                          (300, 50, True)])
def test_stored_run_is_the_in_memory_run(in_memory, tmp_path, chunk, save, attitude):
    run = dict(RUN, keep=stability.Keep(save_every=save or 0, attitude=attitude))
    reference = in_memory if save is None else stability.run_ensemble(**run)
    ds = stability.run_ensemble(**run,
                                options=stability.RunOptions(store=tmp_path / "s",
                                                             chunk_members=chunk))
    assert ds.flip_count.chunks is None  # no time axis: loaded
    assert save is None or ds.w.chunks is not None  # dask arrays: read a chunk at a time
    assert_same_members(reference, ds.load())
    assert ds.attrs["members"] == 700 and ds.attrs["chunks"] == -(-700 // chunk)
    assert ds.attrs["title"].startswith("700-member ensemble")
    assert ds.attrs["scene"] == ("free_body_attitude" if attitude else "free_body")
    assert ("q" in ds) == attitude
    progress = read_progress(tmp_path / "s")
    assert progress["state"] == "finished" and progress["members_done"] == 700


def test_damaged_chunk_is_found_and_run_again(in_memory, tmp_path):
    stability.run_ensemble(**RUN,
                           options=stability.RunOptions(store=tmp_path / "s", chunk_members=256))
    chunk = tmp_path / "s" / "chunk-000001.nc"
    data = bytearray(chunk.read_bytes())
    data[len(data) // 2] ^= 0xFF  # one flipped byte, as a bad disk or a partial copy gives
    chunk.write_bytes(bytes(data))
    others = {k: (tmp_path / "s" / f"chunk-00000{k}.nc").stat().st_mtime_ns for k in (0, 2)}
    ds = stability.run_ensemble(**RUN,
                                options=stability.RunOptions(store=tmp_path / "s",
                                                             chunk_members=256, resume=True))
    assert_same_members(in_memory, ds.load())
    for k, mtime in others.items():  # only the damaged chunk ran again
        assert (tmp_path / "s" / f"chunk-00000{k}.nc").stat().st_mtime_ns == mtime


KILLED = """
import sys, numpy as np, stability
body = stability.RigidBody(1.0, 2.0, 3.0)
stability.run_ensemble(body, 2, 1.0, 1e-3, 4096 * {chunks}, h=0.01, t_end={t_end}, seed=4,
                       method="rk4", keep=stability.Keep(save_every=0),
                       options=stability.RunOptions(store=sys.argv[1], chunk_members=4096,
                                                    progress=False))
"""


def _start(script, *args, env=None):
    return subprocess.Popen([sys.executable, "-c", textwrap.dedent(script), *args],
                            cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            env={**os.environ, **(env or {})})


@pytest.mark.parametrize("how", ["SIGKILL", "SIGINT"])
def test_resume_after_a_real_kill_is_bitwise_the_uninterrupted_run(tmp_path, how):
    chunks, t_end = 6, 60.0
    store = tmp_path / "s"
    proc = _start(KILLED.format(chunks=chunks, t_end=t_end), str(store))
    wait_until(lambda: (read_progress(store) or {}).get("chunks_done", 0) >= 2, proc,
               show_stderr=True)
    proc.send_signal(getattr(signal, how))
    proc.wait(timeout=STOP_GUARD_S)
    progress = read_progress(store)
    assert 2 <= progress["chunks_done"] < chunks, progress  # killed mid-run
    if how == "SIGINT":  # stopped cleanly: says what it kept and how to continue
        assert proc.returncode != 0
        assert "run again with --resume" in proc.stderr.read().decode()
    assert not list(store.glob(".*.tmp")) or how == "SIGKILL"
    kept = {p.name: p.stat().st_mtime_ns for p in store.glob("chunk-*.nc")}
    run = dict(RUN, members=4096 * chunks, t_end=t_end)
    resumed = stability.run_ensemble(**run,
                                     options=stability.RunOptions(store=store, chunk_members=4096,
                                                                  resume=True))
    for name, mtime in kept.items():  # finished chunks were not run again
        assert (store / name).stat().st_mtime_ns == mtime
    assert_same_members(stability.run_ensemble(**run), resumed.load())
    assert not list(store.glob(".*.tmp"))  # the killed run's partial file is gone


def test_dask_local_cluster_gives_the_local_result(in_memory, tmp_path):
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client, \
            distributed.get_task_stream(client) as tasks:
        ds = stability.run_ensemble(**RUN,
                                    options=stability.RunOptions(store=tmp_path / "s",
                                                                 chunk_members=128,
                                                                 scheduler=client))
        assert_same_members(in_memory, ds.load())
        workers = set(cluster.scheduler.workers)  # the cluster's own worker addresses
    # every chunk (700 members in chunks of 128: 6) ran as a task on one of those workers,
    # none in this process
    ran = {t["key"]: t["worker"] for t in tasks.data if "stability-chunk-" in str(t["key"])}
    assert len(ran) == 6, ran
    assert set(ran.values()) <= workers and workers, (ran, workers)


def test_unreachable_scheduler_is_one_clear_error(tmp_path, monkeypatch):
    from stability.output import stream

    # a refused connection is tried again for the connect timeout: 1 s here, not the 10 s a
    # user gets, which the test spent waiting (the error is the same)
    monkeypatch.setattr(stream.scheduler_client, "__defaults__", (1.0,))
    with pytest.raises(OSError, match="cannot reach the dask scheduler at tcp://127.0.0.1:9"):
        stability.run_ensemble(**RUN,
                               options=stability.RunOptions(store=tmp_path / "s",
                                                            scheduler="tcp://127.0.0.1:9"))
    with pytest.raises(ValueError, match="scheduler must be 'dask'"):
        stability.run_ensemble(**RUN,
                               options=stability.RunOptions(store=tmp_path / "t",
                                                            scheduler="somewhere"))


def test_a_stored_run_prints_and_numbers_its_members_without_an_array(tmp_path):
    import pandas as pd

    ds = stability.run_ensemble(**RUN,
                                options=stability.RunOptions(store=tmp_path / "s",
                                                             chunk_members=256))
    text = repr(ds)  # as a notebook shows it: the repr sums every variable's bytes
    assert "member" in text and "700" in text
    assert "<div" in ds._repr_html_()
    # member numbers: a range, not 8 bytes a member read from every file
    assert isinstance(ds.indexes["member"], pd.RangeIndex)
    np.testing.assert_array_equal(ds.member, np.arange(700))
    assert isinstance(ds.isel(member=slice(100, 300)).indexes["member"], pd.RangeIndex)


def test_history_and_status_tell_how_the_run_went(tmp_path):
    ds = stability.run_ensemble(**RUN,
                                options=stability.RunOptions(store=tmp_path / "s",
                                                             chunk_members=256))
    last = ds.attrs["history"].splitlines()[-1]
    assert f"streamed to {tmp_path / 's'}: 3 chunks of 256 members (3 run by this call)" in last
    assert "members/s" in last
    done = subprocess.run([sys.executable, "-m", "stability", "status", str(tmp_path / "s")],
                          cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0
    assert done.stdout.splitlines()[:2] == [
        f"{tmp_path / 's'}: 700 members in 3 chunks of 256", "complete: every chunk is done"]


def test_a_lost_worker_has_its_chunks_run_again(in_memory, tmp_path):
    distributed = pytest.importorskip("distributed")
    store = tmp_path / "s"
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        pids = list(client.run(os.getpid).values())
        killer = None

        def kill_one_worker():  # once the first chunk is in, a worker dies (kill -9)
            t0 = time.monotonic()
            while (read_progress(store) or {}).get("chunks_done", 0) < 1:
                if time.monotonic() - t0 > 120:
                    return
                time.sleep(0.01)
            os.kill(pids[0], signal.SIGKILL)

        import threading

        killer = threading.Thread(target=kill_one_worker, daemon=True)
        killer.start()
        run = dict(RUN, members=700, t_end=300.0)
        ds = stability.run_ensemble(**run,
                                    options=stability.RunOptions(store=store, chunk_members=32,
                                                                 scheduler=client))
        killer.join(timeout=5)
        with pytest.raises(ProcessLookupError):
            os.kill(pids[0], 0)  # it did die
        assert_same_members(stability.run_ensemble(**run), ds.load())


def test_a_stored_run_saves_as_one_file(in_memory, tmp_path):
    ds = stability.run_ensemble(**RUN,
                                options=stability.RunOptions(store=tmp_path / "s",
                                                             chunk_members=256))
    path = stability.save(ds, tmp_path / "whole.nc")  # dask arrays, range-indexed members
    assert_same_members(in_memory, stability.load(path))


def test_a_stored_runs_summaries_come_back_loaded_and_its_series_lazy(in_memory, tmp_path):
    """What has no time axis is NumPy, as from a run in memory (.median() works; it raised
    inside dask), while the time series stay dask arrays over the chunk files."""
    import dask.array

    stored = stability.run_ensemble(**{**RUN, "keep": stability.Keep(save_every=100)},
                                    options=stability.RunOptions(store=tmp_path / "run",
                                                                 chunk_members=256,
                                                                 progress=False))
    assert isinstance(stored.w.data, dask.array.Array)
    for name, variable in stored.variables.items():
        if "time" not in variable.dims:
            assert isinstance(variable.data, np.ndarray), name
    assert float(stored.max_perp_amplitude.median()) == float(
        in_memory.max_perp_amplitude.median())
    summaries = stability.run_ensemble(**RUN,
                                       options=stability.RunOptions(store=tmp_path / "summaries",
                                                                    chunk_members=256,
                                                                    progress=False))
    assert isinstance(summaries.flip_count.data, np.ndarray)

