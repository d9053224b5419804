"""The tennis-racket study measured chunk by chunk (stability.free_body.tennis_racket.measure):
the numbers of the run cut into chunks, on a store, are those of the whole ensemble held in
memory, only the sample's series are kept, and the analysis's headline is what the accessor
gives."""

import pickle

import numpy as np
import pytest

import stability
from stability import RunOptions
from stability.ensemble.combine import LOG_BIN_WIDTH, series_sample
from stability.analysis.members import perpendicular_amplitude
from stability.free_body.tennis_racket.measure import (TennisChunks, analyse_ensemble,
                                                      finish_analysis)
from stability.free_body.spin_ensembles import plan_arguments
from stability.free_body.streamed import run_streamed
from stability.util import conventions as cv

BODY = stability.RigidBody.preset("tennis_racket")
RUN = dict(body=BODY, axis=2, spin=10.0, epsilon=1e-4, members=700, h=2e-3, t_end=4.0, seed=3,
           method="rk4", keep=stability.Keep(save_every=25))
#: The same ensemble as the free body's plan takes it, in chunks of 256.
PLANNED = {**{k: v for k, v in RUN.items() if k != "keep"},
           **plan_arguments(RUN["keep"], RunOptions(chunk_members=256))}
WINDOW = (10.0, 0.03)


@pytest.fixture(scope="module")
def both(tmp_path_factory):
    """The ensemble in memory, analysed whole; and streamed in chunks of 256, sample of 9."""
    whole = stability.run_ensemble(**RUN, options=stability.RunOptions(progress=False))
    analysed = analyse_ensemble(whole, BODY, 2, 10.0, 1e-4, low_factor=WINDOW[0],
                                high_fraction=WINDOW[1])
    store = tmp_path_factory.mktemp("tennis") / "store"
    chunked = run_streamed(PLANNED, RunOptions(store=store, progress=False),
                           compress=False,
                           measurement=lambda kw, plan: TennisChunks(kw, WINDOW, 9, plan))
    chunked = finish_analysis(chunked, BODY, 2, 10.0, 1e-4, low_factor=WINDOW[0],
                              high_fraction=WINDOW[1])
    return whole, analysed, chunked


def test_per_member_numbers_do_not_depend_on_the_chunks(both):
    _, analysed, chunked = both
    assert chunked.attrs["chunks"] == 3
    for name in ("status", "mean_flip_interval", "first_flip_time", "energy_error",
                 "exact_flip_interval", "flip_interval_asymptote", "complementary_modulus",
                 "member_growth_rate", "passage_time"):
        np.testing.assert_array_equal(chunked[name].values, analysed[name].values, name)
    np.testing.assert_array_equal(chunked.perp_amplitude_count.values,
                                  analysed.perp_amplitude_count.values)
    for name in ("growth_rate_fitted", "growth_rate_fitted_stderr", "growth_fit_intercept"):
        assert chunked.attrs[name] == analysed.attrs[name], name


def test_the_fit_is_the_one_over_every_members_series(both):
    """The mean of the per-member rates is measured_growth_rate over the full series (to
    rounding: the compiled fit sums in sample order), the accessor gives the headline."""
    whole, analysed, chunked = both
    reference = stability.measured_growth_rate(whole, low_factor=WINDOW[0],
                                               high_fraction=WINDOW[1])
    assert chunked.attrs["growth_rate_fitted"] == pytest.approx(
        float(reference.growth_rate), rel=1e-13)
    assert chunked.attrs["growth_rate_fitted_members"] == int(reference.n_fitted) == 700
    assert float(chunked.stability.measured_growth_rate().growth_rate) == \
        chunked.attrs["growth_rate_fitted"]


def test_quantiles_are_within_one_bin_of_those_over_every_members_series(both):
    whole, _, chunked = both
    amp = perpendicular_amplitude(whole.w.where(whole.status == cv.STATUS_OK), 2)
    exact = amp.quantile([0.1, 0.5, 0.9], dim=cv.MEMBER, skipna=True).values
    for k, name in enumerate(("p10", "median", "p90")):
        got = chunked[f"perp_amplitude_{name}"].values
        assert np.max(np.abs(got / exact[k] - 1.0)) <= 10.0**LOG_BIN_WIDTH - 1.0, name


def test_only_the_samples_series_are_kept(both):
    whole, _, chunked = both
    kept = series_sample(700, 9)
    np.testing.assert_array_equal(chunked[cv.SERIES_MEMBER].values, kept)
    assert chunked.w.dims == (cv.SERIES_MEMBER, cv.TIME, cv.AXIS)
    np.testing.assert_array_equal(chunked.w.values, whole.w.values[kept])
    assert cv.MEMBER not in chunked.w.dims and chunked.sizes[cv.MEMBER] == 700


def test_the_measurement_travels_to_a_worker():
    """Pickled for a dask worker: its window and sample go with it, its plan is made there."""
    from stability.free_body.ensemble_plan import plan_ensemble

    chunks = TennisChunks(PLANNED, WINDOW, 9, plan_ensemble(**PLANNED, defer_starts=True))
    back = pickle.loads(pickle.dumps(chunks))
    assert back.window == WINDOW and back.series_members == 9 and back._plan is None
    own = chunks.identity(None)["tennis_racket"]
    assert back.identity(None)["tennis_racket"] == own == {"window": [10.0, 0.03],
                                                             "series_members": 9}
    assert TennisChunks(PLANNED, (10.0, 0.02), 9).identity(None)["tennis_racket"] != own


def test_on_a_dask_cluster_only_the_sample_leaves_the_workers(both, tmp_path):
    """Two worker processes run the chunks: each chunk file they write (all that comes back)
    holds the members' summaries and the sample's series alone, and the joined Dataset is the
    local one, bitwise."""
    distributed = pytest.importorskip("distributed")
    import xarray as xr

    _, _, local = both
    store = tmp_path / "store"
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        remote = run_streamed(PLANNED,
                              RunOptions(store=store, scheduler=client, progress=False),
                              compress=False,
                              measurement=lambda kw, plan: TennisChunks(kw, WINDOW, 9, plan))
    for path in sorted(store.glob("chunk-*.nc")):
        with xr.open_dataset(path, engine="netcdf4", decode_times=False) as chunk:
            for name, var in chunk.variables.items():
                assert not {cv.MEMBER, cv.TIME} <= set(var.dims), (path.name, name)
            assert chunk.sizes[cv.SERIES_MEMBER] <= 3  # of the 9, at most 3 in a chunk
    remote = finish_analysis(remote, BODY, 2, 10.0, 1e-4, low_factor=WINDOW[0],
                             high_fraction=WINDOW[1])
    assert set(remote.variables) == set(local.variables)
    for name in local.variables:
        np.testing.assert_array_equal(remote[name].values, local[name].values, err_msg=name)
    assert remote.attrs["growth_rate_fitted"] == local.attrs["growth_rate_fitted"]


def test_analyse_ensemble_headline_is_what_the_accessor_gives():
    body = stability.RigidBody.preset("tennis_racket")
    ds = stability.run_ensemble(body, 2, 10.0, 1e-4, 32, h=2e-3, t_end=3.0, seed=3,
                                method="rk4", keep=stability.Keep(save_every=25),
                                options=stability.RunOptions(progress=False))
    out = analyse_ensemble(ds, body, 2, 10.0, 1e-4, low_factor=10.0, high_fraction=0.03)
    headline = out.attrs["growth_rate_fitted"]
    assert headline == float(out.stability.measured_growth_rate().growth_rate)
    assert out.attrs["growth_rate_fitted_members"] == 32
    assert abs(out.attrs["growth_rate_fitted"] / out.attrs["growth_rate_analytic"] - 1) < 1e-3
    t0, t1 = out.attrs["growth_fit_window"]
    assert 0 < t0 < t1 < 3.0 and np.isfinite(out.attrs["growth_fit_intercept"])
    for name in ("exact_flip_interval", "flip_interval_asymptote", "complementary_modulus"):
        assert out[name].dims == ("member",)
    assert out.perp_amplitude_median.dims == ("time",)
