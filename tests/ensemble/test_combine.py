"""Measured chunks joined: the series sample, log histograms and their quantiles, and the join
of a store's chunk files (stability.ensemble.combine)."""

import math

import numpy as np
import pytest
import xarray as xr

from stability.ensemble.combine import (
    LOG_BIN_WIDTH, SERIES_MEMBER, SUMMED, combine_chunks, histogram_quantiles, log_edges,
    log_histogram, sampled_in, series_sample,
)
from stability.output.io import save
from stability.util import conventions as cv

#: Relative width of one bin: the bound on a quantile's error.
BIN = 10.0**LOG_BIN_WIDTH - 1.0


@pytest.mark.parametrize("members, count", [(10, 3), (1000, 256), (7, 7), (7, 50), (5, 1)])
def test_series_sample_is_the_same_however_the_run_is_cut(members, count):
    sample = series_sample(members, count)
    assert sample.size == min(count, members) and sample[0] == 0
    assert np.all(np.diff(sample) > 0) and sample[-1] == (members - 1 if count > 1 else 0)
    for chunk in (1, 3, 64):
        pieces = [sampled_in(sample, lo, min(lo + chunk, members)) + lo
                  for lo in range(0, members, chunk)]
        np.testing.assert_array_equal(np.concatenate(pieces), sample)


def test_series_sample_all_and_none():
    np.testing.assert_array_equal(series_sample(6, "all"), np.arange(6))
    assert series_sample(6, 0).size == 0
    for bad in ("some", -1):
        with pytest.raises(ValueError, match="series_members must be"):
            series_sample(6, bad)


@pytest.mark.parametrize("n", [1, 2, 7, 1000, 100_000])
@pytest.mark.parametrize("seed", [0, 1])
def test_histogram_quantiles_are_within_one_bin_of_numpys(n, seed):
    """Log-normal values over five decades: each quantile from the counts lies within one bin
    (0.46 %) of numpy's linear quantile of the values themselves."""
    rng = np.random.default_rng(seed)
    values = np.exp(rng.normal(-3.0, 2.0, (n, 4)))
    values[rng.random((n, 4)) < 0.05] = np.nan  # members left out
    edges = log_edges(1e-8, 1e6)  # spanning every value (the ends catch the rest)
    q = [0.0, 0.1, 0.5, 0.9, 1.0]
    got = histogram_quantiles(log_histogram(values, edges), edges, q)
    for t in range(4):
        finite = values[:, t][np.isfinite(values[:, t])]
        if finite.size == 0:
            assert np.all(np.isnan(got[t]))
            continue
        exact = np.quantile(finite, q)
        assert np.all(np.abs(got[t] / exact - 1.0) <= BIN), (got[t], exact)


def test_histogram_of_identical_values_and_of_values_outside_the_edges():
    edges = log_edges(1e-3, 1e1)
    same = np.full((50, 1), 0.2)
    assert abs(histogram_quantiles(log_histogram(same, edges), edges, [0.5])[0, 0] / 0.2
               - 1) <= BIN
    outside = np.array([[1e-9], [1e9], [0.0], [-1.0]])
    counts = log_histogram(outside, edges)
    assert counts[0, 0] == 1 and counts[0, -1] == 1 and counts.sum() == 2  # 0 and -1: no log


def test_histograms_add_up_over_members():
    rng = np.random.default_rng(3)
    values = np.exp(rng.uniform(-5, 1, (300, 6)))
    edges = log_edges(1e-3, 10.0)
    whole = log_histogram(values, edges)
    parts = log_histogram(values[:120], edges) + log_histogram(values[120:], edges)
    np.testing.assert_array_equal(whole, parts)
    assert whole.dtype == np.int32 and whole.sum() == values.size


def test_log_edges_refuse_an_empty_range():
    for low, high in ((1.0, 1.0), (0.0, 1.0), (2.0, 1.0), (1.0, math.inf)):
        with pytest.raises(ValueError, match="0 < low < high"):
            log_edges(low, high)


def _chunk(lo, hi, counts):
    n = hi - lo
    members = np.arange(lo, hi)
    kept = members[members % 4 == 0]
    return xr.Dataset(
        {"x": ((cv.MEMBER,), members * 1.5), "pair": ((cv.MEMBER, "two"), np.ones((n, 2)) * lo),
         "w": ((SERIES_MEMBER, cv.TIME), kept[:, None] * np.ones((kept.size, 3))),
         "count": ((cv.TIME, "bin"), counts, {SUMMED: 1}),
         "level": (("bin",), np.arange(2.0))},
        coords={cv.MEMBER: members, SERIES_MEMBER: kept, cv.TIME: np.arange(3.0)},
        attrs={"wall_time": float(lo)})


def test_combine_joins_members_and_sample_and_sums_the_reductions(tmp_path):
    bounds = [(0, 5), (5, 10), (10, 12)]
    paths = []
    for k, (lo, hi) in enumerate(bounds):
        paths.append(save(_chunk(lo, hi, np.full((3, 2), k + 1, dtype=np.int32)),
                          tmp_path / f"c{k}.nc", compress=False))
    ds, attrs = combine_chunks(paths, 12)
    np.testing.assert_array_equal(ds.x.values, np.arange(12) * 1.5)
    np.testing.assert_array_equal(ds[cv.MEMBER].values, np.arange(12))
    np.testing.assert_array_equal(ds.pair.values[:, 0], [0] * 5 + [5] * 5 + [10] * 2)
    np.testing.assert_array_equal(ds[SERIES_MEMBER].values, [0, 4, 8])
    np.testing.assert_array_equal(ds.w.values[:, 0], [0, 4, 8])
    np.testing.assert_array_equal(ds["count"].values, np.full((3, 2), 6))
    np.testing.assert_array_equal(ds.level.values, [0.0, 1.0])  # neither: the first chunk's
    assert [a["wall_time"] for a in attrs] == [0.0, 5.0, 10.0]


def test_combine_refuses_chunks_that_do_not_make_the_run(tmp_path):
    a = save(_chunk(0, 5, np.ones((3, 2), dtype=np.int32)), tmp_path / "a.nc", compress=False)
    b = save(_chunk(5, 10, np.ones((3, 2), dtype=np.int32)).drop_vars("pair"),
             tmp_path / "b.nc", compress=False)
    with pytest.raises(ValueError, match="other variables than the run's first chunk"):
        combine_chunks([a, b], 10)
    with pytest.raises(ValueError, match="the chunks hold 5 members, the run 6"):
        combine_chunks([a], 6)
    with pytest.raises(ValueError, match="beyond the run's 4"):
        combine_chunks([a], 4)
