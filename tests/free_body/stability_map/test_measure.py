"""The stability map's pieces: one ensemble's estimates, the arrays they go in, the map's runs."""

import math

import numpy as np
import pytest

import stability
from stability.free_body.stability_map import measure as smap
from stability.free_body.measure import exact_flip_intervals
from stability.util.conventions import REGIME_EXPONENTIAL
from stability.free_body.stability_map.shapes import amplitude_levels

BODY = stability.RigidBody(1.0, 2.0, 3.0)
SPIN, EPS = 1.0, 1e-7


def summaries(axis, members=16, t_end=120.0, h=0.1):
    return stability.run_ensemble(
        BODY, axis, SPIN, EPS, members, h=h, t_end=t_end, seed=1, method="rk4",
        keep=stability.Keep(save_every=0, levels=amplitude_levels(SPIN, EPS, 8)),
        options=stability.RunOptions(progress=False))


def test_ensemble_estimates_of_an_unstable_axis():
    run = summaries(2)
    analytic = float(stability.omega_squared(BODY, 2, SPIN))
    exact, asymptote = exact_flip_intervals(BODY, 2, run.w0.values)
    x = smap.ensemble_estimates(run, analytic, exact, asymptote, low_factor=300.0,
                                high_fraction=1e-2)
    assert x["regime"] == REGIME_EXPONENTIAL and x["sign_agrees"]
    assert abs(x["relative_error"]) < 1e-3
    assert x["members_failed"] == 0 and x["status"] == 0
    assert x["n_flips_mean"] >= 2 and abs(x["flip_interval_relative_error"]) < 1e-3
    assert 0 <= x["energy_error_max"] < 1e-6


def test_estimates_of_many_ensembles_are_bitwise_those_of_each_alone(monkeypatch):
    """batch_estimates fits the members of many ensembles together (in stacks, each row as
    alone): every estimate of every ensemble is bitwise ensemble_estimates' of it alone, over
    stable and unstable axes, two level grids, member counts that cut the stacks, a
    time-series ensemble and a failed member."""
    from stability.analysis import estimates
    from stability.analysis.members import members as gather_members

    monkeypatch.setattr(estimates, "_STACK_ROWS", 40)  # stacks of two or three ensembles
    runs, analytic, flips = [], [], []
    for k, (axis, members, per_decade) in enumerate(
            [(2, 16, 8), (1, 16, 8), (3, 9, 8), (2, 20, 4), (1, 16, 4), (2, 16, 8)]):
        run = stability.run_ensemble(
            BODY, axis, SPIN, EPS, members, h=0.1, t_end=60.0, seed=k, method="rk4",
            keep=stability.Keep(save_every=0, levels=amplitude_levels(SPIN, EPS, per_decade)),
            options=stability.RunOptions(progress=False))
        runs.append(run)
        analytic.append(float(stability.omega_squared(BODY, axis, SPIN)))
        flips.append(exact_flip_intervals(BODY, axis, run.w0.values) if axis == 2
                     else (None, None))
    runs[0]["status"][3] = 2  # a member that failed
    runs.append(stability.run_ensemble(BODY, 2, SPIN, 1e-3, 8, h=0.1, t_end=40.0, seed=9,
                                       method="rk4", options=stability.RunOptions(progress=False)))
    analytic.append(analytic[0])
    flips.append((None, None))
    kw = dict(low_factor=30.0, high_fraction=0.03)
    together = smap.batch_estimates(runs, analytic, flips, **kw)
    # By level grid, at most 40 members a stack, the time series alone.
    assert estimates._stacks([gather_members(r) for r in runs]) == [[0, 1], [2, 5],
                                                                          [3, 4], [6]]
    for run, a, (exact, asymptote), x in zip(runs, analytic, flips, together):
        alone = smap.ensemble_estimates(run, a, exact, asymptote, **kw)
        assert alone.keys() == x.keys()
        for key in alone:
            assert np.array_equal(alone[key], x[key], equal_nan=True), key
    assert together[0]["members_failed"] == 1
    assert together[1]["regime"] != together[0]["regime"]  # stable and unstable both in


def test_store_fills_the_arrays_it_knows():
    out, half = smap.empty_estimates(2, 3)
    assert set(smap.MAP_FLOATS) <= set(out) and set(half) == {"omega_squared_measured", "regime"}
    assert out["regime"].dtype == np.int8 and out["members_failed"].dtype == np.int32
    smap.store(half, (1, 2, 0), {"omega_squared_measured": -0.5, "regime": 3, "other": 1.0})
    assert half["omega_squared_measured"][1, 2, 0] == -0.5 and half["regime"][1, 2, 0] == 3
    assert np.isnan(half["omega_squared_measured"][0]).all()


def test_a_kept_batch_reads_back_bit_for_bit(tmp_path):
    """write_batch / read_batch, as --resume uses them: every estimate of every cell, ints,
    floats, NaN and per-member arrays, comes back exactly; a column whose arrays differ in
    length between cells too; and a batch of many cells stays a few variables."""
    import xarray as xr

    from stability.output.store import ChunkStore

    analytic = float(stability.omega_squared(BODY, 2, SPIN))
    batch = []
    for axis, members in ((2, 16), (1, 16), (3, 16)):
        run = summaries(axis, members=members, t_end=60.0)
        exact, asymptote = (exact_flip_intervals(BODY, axis, run.w0.values) if axis == 2
                            else (None, None))
        x = smap.ensemble_estimates(run, analytic, exact, asymptote, low_factor=300.0,
                                    high_fraction=1e-2)
        x["ragged"] = np.arange(axis, dtype=float)  # a column of arrays of unequal lengths
        batch.append((members * 600, 0.001 * axis, x))
    store = ChunkStore(tmp_path / "store", {"test": 1}, 1, 1, unit="batches")
    smap.write_batch(store, 0, batch)
    back = smap.read_batch(store.path(0), len(batch))
    for (steps, seconds, x), (steps2, seconds2, x2) in zip(batch, back):
        assert (steps2, seconds2) == (steps, seconds) and set(x2) == set(x)
        for name, value in x.items():
            value = np.asarray(value)
            np.testing.assert_array_equal(x2[name], value.astype(np.int8)
                                          if value.dtype == bool else value, strict=False)
            assert np.asarray(x2[name]).shape == value.shape, name
    with xr.open_dataset(store.path(0)) as ds:
        assert len(ds.data_vars) == len(batch[0][2]) + 3  # + steps, seconds, ragged lengths


def test_first_flip_relative_error_is_a_finite_mean():
    first = np.array([1.1, 2.0, np.nan])
    reference = np.array([1.0, 2.0, 3.0])
    assert smap.first_flip_relative_error(first, reference) == pytest.approx(0.05)
    assert math.isnan(smap.first_flip_relative_error(first[2:], reference[2:]))


def test_measure_map_runs_every_ensemble_and_the_half_steps():
    moments = np.array([[0.5, 0.75, 1.0]])
    bodies = [stability.RigidBody(*moments[0])]
    omega2 = np.array([[float(stability.omega_squared(moments[0], a, SPIN)) for a in (1, 2, 3)]])
    t_end = np.full((1, 3), 120.0)
    specs = [stability.method_spec("exact"), stability.method_spec("rk4")]
    runs = [(0, 0.1, np.arange(1), False), (1, 0.1, np.arange(1), False),
            (1, 0.05, np.arange(1), True)]
    out, half, work = smap.measure_map(
        bodies, omega2, t_end, amplitude_levels(SPIN, EPS, 8), specs, runs, spin=SPIN,
        epsilon=EPS, members=8, seed=1, low_factor=300.0, high_fraction=1e-2, progress=False)
    assert work["member_steps"] == 8 * 3 * (1200 + 1200 + 2400) and work["loop_time"] > 0
    np.testing.assert_array_less(np.abs(out["relative_error"]), 1e-3)
    assert np.all(np.isfinite(half["omega_squared_measured"][1]))
    assert np.all(np.isnan(half["omega_squared_measured"][0]))  # no bias run of the exact flow
    # The rk4 first flip on the unstable axis against the exact flow's, member by member.
    assert abs(out["first_flip_time_relative_error"][1, 0, 1]) < 1e-3
    assert np.isnan(out["first_flip_time_relative_error"][0, 0, 1])
