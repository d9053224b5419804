"""The dispersed free body's measurements (stability.free_body.dispersion.measure): draws that are a
function of the seed alone, the closed-form flip interval, and runs whose members are bitwise the
draws, in chunks, resumed and on dask."""

import numpy as np
import pytest

import stability
from stability import RunOptions
from stability.free_body.dispersion import measure as M
from stability.free_body.exact import flip_interval
from stability.uncertainty.designs import unit_design
from stability.uncertainty.dispersions import dispersions

BODY = (1.0, 2.0, 2.5)


def test_the_closed_form_flip_interval_is_the_exact_modules():
    nominal = M.nominal(BODY, 10.0, 1e-3, 0.3)
    disp = dispersions({"moments": {"distribution": "uniform", "relative": 0.05}}, nominal)
    draws = M.members(disp, unit_design("random", 20, 3, 5))
    got = M.closed_form(draws)["flip_interval"]
    want = [flip_interval(stability.RigidBody(*I), w) for I, w in zip(draws["moments"],
                                                                      draws["w0"])]
    assert np.array_equal(got, want)


RACKET = stability.RigidBody.preset("tennis_racket")


SPEC = {"moments": {"distribution": "uniform", "relative": 0.02},
        "axes": {"distribution": "uniform", "lower": 0.0, "upper": 0.01},
        "rate": {"distribution": "normal", "relative": 0.1},
        "epsilon": {"distribution": "log-uniform", "lower": 1e-4, "upper": 1e-2}}


def racket_draws(n=12, design="random"):
    disp = dispersions(SPEC, M.nominal(RACKET.moments, 10.0, 1e-3), truncate=True)
    return disp, M.members(disp, unit_design(design, n, len(disp.columns()), 7))


def test_a_members_draw_is_a_function_of_the_seed_and_its_number_alone():
    disp, few = racket_draws(10)
    _, many = racket_draws(5000)
    for key in ("moments", "w0", "tensor", "rate", "epsilon"):
        assert np.array_equal(few[key], many[key][:10]), key
    one = disp.draw(unit_design("random", 5000, len(disp.columns()), 7)[4321:4322])
    assert one["I3"][0] == many["I3"][4321]


def test_the_stored_draws_are_bitwise_what_the_kernels_ran_with(tmp_path):
    """The moments each run's group reports back, and each member's start, equal the draws:
    in one piece, in chunks of 5, and resumed after a chunk is lost."""
    _, draws = racket_draws(12)
    want_I, want_m = draws["moments"], draws["w0"] * draws["moments"]
    whole = M.integrated(draws, 12, steps_per_flip=64, flips=2)
    store = tmp_path / "store"
    chunked = M.integrated(draws, 12, steps_per_flip=64, flips=2,
                           options=RunOptions(store=store, chunk_members=5, progress=False))
    chunks = sorted(p for p in store.rglob("*.nc"))
    assert len(chunks) >= 3
    chunks[1].unlink()
    resumed = M.integrated(draws, 12, steps_per_flip=64, flips=2, options=RunOptions(
        store=store, chunk_members=5, resume=True, progress=False))
    for ds in (whole, chunked, resumed):
        assert np.array_equal(ds.parameters.values, want_I)
        got_m = np.column_stack([ds[f"m{k}_start"].values for k in (1, 2, 3)])
        assert np.array_equal(got_m, want_m)
        assert np.array_equal(ds.flip_interval_run.values, whole.flip_interval_run.values)
    exact = M.closed_form(draws)["flip_interval"]
    assert np.nanmax(np.abs(whole.flip_interval_run.values / exact - 1.0)) < 1e-4


def test_the_stored_draws_are_what_the_kernels_ran_with_on_dask_workers(tmp_path):
    """The same members in chunks of 5 on a local dask cluster of two processes: the moments
    and starts each chunk reports back are the draws, and every output is the one-piece
    run's, bitwise."""
    distributed = pytest.importorskip("distributed")
    _, draws = racket_draws(12)
    kwargs = dict(steps_per_flip=64, flips=2)
    whole = M.integrated(draws, 12, **kwargs)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        there = M.integrated(draws, 12, **kwargs, options=RunOptions(
            store=tmp_path / "store", chunk_members=5, scheduler=client, progress=False))
    assert len(list((tmp_path / "store").rglob("*.nc"))) >= 3
    assert np.array_equal(there.parameters.values, draws["moments"])
    got_m = np.column_stack([there[f"m{k}_start"].values for k in (1, 2, 3)])
    assert np.array_equal(got_m, draws["w0"] * draws["moments"])
    for name in ("flip_interval_run", "axis_crossings", "status"):
        assert np.array_equal(there[name].values, whole[name].values, equal_nan=True), name
