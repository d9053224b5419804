"""Grouped runs of every scene through the one stored path (stability.ensemble.chunks): cut into
chunks, resumed, or run on a dask cluster, every member is bitwise the run in one piece, raw or
measured into the scene's Dataset (stability.run_scene)."""

import os
import signal
import threading
from dataclasses import replace

import numpy as np
import pytest

import stability
from stability import RunOptions
from stability.ensemble.chunks import run_plan
from stability.ensemble.plan import Plan
from stability.registry import SCENES

from ..helpers import assert_declared

#: Every registered scene with its first method (every method's loop is checked for groups and
#: chunks in time by tests/engine/test_driver.py; here the question is the cut into member chunks).
CASES = [(scene.name, next(iter(scene.methods))) for scene in SCENES.values()]


def grouped(scene_name: str, method: str) -> Plan:
    """Three groups of unequal sizes, steps and horizons, with tracking and saved samples."""
    scene = SCENES[scene_name]
    spec = scene.method(method)
    sizes = [7, 5, 4]
    hs = [0.05, 0.02, 0.04]
    x0 = np.concatenate([scene.example(n, seed=k)[0] for k, n in enumerate(sizes)])
    params = np.array([spec.params(p, h) for p, h in zip(scene.example(1)[1], hs)])
    return Plan(scene, method, x0, params, sizes, hs, [40, 60, 25], save_every=10,
                axes=[[1, 0, 2]] * 3, levels=[[1e-2, 5e-2, 0.3]] * 3)


def assert_bitwise(a, b):
    for name in ("x_final", "saved", "status", "fail_step", "iterations", "steps_done"):
        assert np.array_equal(getattr(a, name), getattr(b, name), equal_nan=True), name
    assert a.extras.keys() == b.extras.keys()
    for name, value in a.extras.items():
        assert np.array_equal(value, b.extras[name], equal_nan=True), name


@pytest.mark.parametrize("scene,method", CASES, ids=[f"{s}-{m}" for s, m in CASES])
def test_a_stored_run_cut_into_chunks_is_bitwise_the_run_in_one_piece(tmp_path, scene, method):
    run = grouped(scene, method)
    whole = run_plan(run, RunOptions(progress=False))
    stored = run_plan(run, RunOptions(store=tmp_path / "store", chunk_members=3, progress=False))
    assert_bitwise(stored, whole)
    assert stored.saved.shape == whole.saved.shape == (16, 6, SCENES[scene].width)
    here = run_plan(run, RunOptions(chunk_members=3, progress=False))  # in memory, in chunks
    assert_bitwise(here, whole)


def test_ctrl_c_during_a_run_in_memory_keeps_the_member_chunks_finished_before_it():
    """A real SIGINT, during the second of six member chunks of about 0.3 s each here: the
    result is the chunks finished before it, bitwise those members' run, or (had it come during
    the first) the first chunk up to the steps it did."""
    scene = SCENES["free_body"]
    spec = scene.method("rk4")
    x0, params = scene.example(6 * 500, seed=3)
    run = Plan(scene, "rk4", x0, spec.params(params[0], 0.01), [x0.shape[0]], 0.01,
               300_000, axes=[[1, 0, 2]], levels=[[1e-2, 0.1]])
    run_plan(replace(run, n_steps=10), RunOptions(progress=False))  # compiled before the timing
    timer = threading.Timer(0.45, os.kill, (os.getpid(), signal.SIGINT))
    timer.start()
    try:
        kept = run_plan(run, RunOptions(chunk_members=500, progress=False), partial=True)
    finally:
        timer.cancel()
    n = kept.x_final.shape[0]
    assert kept.interrupted and n % 500 == 0 and 0 < n < run.members
    steps = int(kept.steps_done[0])
    if steps == run.n_steps[0]:
        assert n >= 500
    else:  # the signal came during the first chunk
        assert n == 500 and 0 < steps < run.n_steps[0]
    alone = replace(run.part(0, n), n_steps=steps).propagate()
    assert_bitwise(kept, alone)
    with pytest.raises(ValueError, match="needs a store"):
        run_plan(run, RunOptions(scheduler="dask"))
    for bad, message in ((0, "chunk_members must be >= 1, got 0"),
                         (-3, "chunk_members must be >= 1, got -3"),
                         (2.5, "chunk_members must be a whole number, got 2.5")):
        with pytest.raises(ValueError, match=message):
            run_plan(run, RunOptions(chunk_members=bad))


def test_ctrl_c_while_the_first_member_chunk_is_set_up_stops_the_run_at_once(monkeypatch):
    """A real SIGINT while the first of six member chunks is being set up (before its loop
    starts): the run stops there, with none of the 300,000 steps done (before, that whole
    chunk ran first), and without ``partial`` it raises KeyboardInterrupt."""
    scene = SCENES["free_body"]
    x0, params = scene.example(6 * 50, seed=3)
    run = Plan(scene, "rk4", x0, scene.method("rk4").params(params[0], 0.01),
               [x0.shape[0]], 0.01, 300_000, axes=[[1, 0, 2]], levels=[[1e-2, 0.1]])
    run_plan(replace(run, n_steps=10), RunOptions(progress=False))  # compiled before
    part = Plan.part

    def part_and_ctrl_c(self, lo, hi):
        if lo == 0:
            os.kill(os.getpid(), signal.SIGINT)  # handled here, in the main thread
        return part(self, lo, hi)

    monkeypatch.setattr(Plan, "part", part_and_ctrl_c)
    kept = run_plan(run, RunOptions(chunk_members=50, progress=False), partial=True)
    assert kept.interrupted and kept.x_final.shape[0] == 50
    assert int(kept.steps_done[0]) == 0
    assert np.array_equal(kept.x_final, x0[:50])
    with pytest.raises(KeyboardInterrupt):
        run_plan(run, RunOptions(chunk_members=50, progress=False))


def test_a_resumed_run_runs_only_what_is_missing_and_is_bitwise_the_same(tmp_path):
    run = grouped("heavy_top", next(iter(SCENES["heavy_top"].methods)))
    whole = run_plan(run, RunOptions(progress=False))
    store = tmp_path / "store"
    run_plan(run, RunOptions(store=store, chunk_members=4, progress=False))
    kept = {p.name: p.stat().st_mtime_ns for p in store.glob("chunk-*.nc")}
    for name in ("chunk-000001.nc", "chunk-000001.nc.sha256"):  # as a stopped run leaves it
        (store / name).unlink()
    with pytest.raises(ValueError, match="pass --resume"):
        run_plan(run, RunOptions(store=store, chunk_members=4, progress=False))
    again = run_plan(run, RunOptions(store=store, chunk_members=4, resume=True, progress=False))
    assert_bitwise(again, whole)
    rerun = {p.name for p in store.glob("chunk-*.nc")
             if kept.get(p.name) != p.stat().st_mtime_ns}
    assert rerun == {"chunk-000001.nc"}


def test_a_changed_run_is_refused_by_its_store(tmp_path):
    run = grouped("heavy_top", next(iter(SCENES["heavy_top"].methods)))
    run_plan(run, RunOptions(store=tmp_path / "store", chunk_members=4, progress=False))
    run.x0[0, 0] += 1e-12
    with pytest.raises(ValueError, match="the settings changed since the run kept in"):
        run_plan(run,
                 RunOptions(store=tmp_path / "store", chunk_members=4, resume=True,
                            progress=False))


def test_the_chunks_run_on_a_dask_cluster_bitwise_as_here(tmp_path):
    distributed = pytest.importorskip("distributed")
    run = grouped("heavy_top", next(iter(SCENES["heavy_top"].methods)))
    whole = run_plan(run, RunOptions(progress=False))
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        there = run_plan(run,
                         RunOptions(store=tmp_path / "store", chunk_members=5, scheduler=client,
                                    progress=False))
    assert_bitwise(there, whole)


def test_a_scenes_dataset_made_on_a_dask_cluster_is_bitwise_the_one_made_here(tmp_path):
    """run_scene on a registered scene: the Dataset's final states are the loop's, and its
    chunks measured by dask workers join into the Dataset made here, bitwise."""
    distributed = pytest.importorskip("distributed")
    scene = SCENES["heavy_top"]
    sizes = [7, 5, 4]
    x0 = np.concatenate([scene.example(n, seed=k)[0] for k, n in enumerate(sizes)])
    tops = scene.example(1)[1]
    kwargs = dict(sizes=sizes, h=[0.05, 0.02, 0.04], n_steps=[40, 60, 25], axes=[1, 0, 2],
                  levels=[1e-2, 5e-2, 0.3], tracked_units="1")
    here = stability.run_scene("heavy_top", "lp2", x0, tops, **kwargs,
                               options=RunOptions(progress=False))
    raw = run_plan(grouped("heavy_top", "lp2"), RunOptions(progress=False))
    assert np.array_equal(np.column_stack([here[f"{c}_final"] for c in scene.components]),
                          raw.x_final)
    assert np.array_equal(here.passage_time, raw.extras["passage_time"], equal_nan=True)
    assert list(here.data_vars).count("energy_drift") == 1 and "time" not in here.dims
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        there = stability.run_scene("heavy_top", "lp2", x0, tops,
                                    options=stability.RunOptions(store=tmp_path / "store",
                                                                 chunk_members=5,
                                                                 scheduler=client,
                                                                 progress=False), **kwargs)
    assert there.attrs["wall_time"] > 0 and there.attrs["chunk_time"] > 0  # elapsed, summed
    for name in here.variables:
        assert np.array_equal(there[name].values, here[name].values, equal_nan=True), name
    assert_declared(stability.save(there, tmp_path / "top.nc"), "scene_run")

