"""run_ensemble: reproducibility, its Dataset, summaries against known answers, interruption and
bad input."""

import math
from dataclasses import replace

import numba
import numpy as np
import pytest

import stability
from stability.util import conventions as cv
from stability.ensemble.plan import Plan
from stability.output.dataset import LEVEL, SUMMARIES
from stability.free_body.spin_ensembles import run_ensemble
from stability.output.dataset import LOOP_THREADS

BODY = stability.RigidBody(1.0, 2.0, 3.0, name="I=(1,2,3)")
#: Growth rate about the intermediate axis for spin W = 1: sqrt((I2-I1)(I3-I2)/(I1 I3)).
LAMBDA = math.sqrt((2.0 - 1.0) * (3.0 - 2.0) / (1.0 * 3.0))


def _bits(ds):
    """Every data variable and coordinate as raw bytes, for bitwise comparison."""
    return {name: np.ascontiguousarray(var.values).tobytes() for name, var in ds.variables.items()}


# --- reproducibility --------------------------------------------------------------------------

RUN = dict(h=0.02, t_end=40.0, method="lp2")
#: The series those runs keep.
SERIES = stability.Keep(save_every=5)


@pytest.fixture(scope="module")
def reference():
    """150 members (not a multiple of the 64-member block) on the unstable axis: two flips."""
    return run_ensemble(BODY, 2, 1.0, 1e-3, 150, seed=11, options=stability.RunOptions(threads=1),
                        keep=SERIES, **RUN)


@pytest.mark.skipif(numba.config.NUMBA_NUM_THREADS < 2, reason="needs 2 Numba threads")
def test_bitwise_identical_across_threads_and_chunks(reference):
    before = numba.get_num_threads()
    other = run_ensemble(
        BODY, 2, 1.0, 1e-3, 150, seed=11,
        options=stability.RunOptions(threads=2, chunk_members=37, chunk_steps=15), keep=SERIES,
        **RUN
    )
    assert numba.get_num_threads() == before  # restored
    assert other.attrs["numba_num_threads"] == 2 and reference.attrs["numba_num_threads"] == 1
    assert _bits(other) == _bits(reference)
    assert np.all(reference.flip_count.values >= 1)  # the case is sensitive: the members flip


def test_summaries_only_matches_the_time_series_run(reference):
    summaries = run_ensemble(
        BODY, 2, 1.0, 1e-3, 150, seed=11, keep=stability.Keep(save_every=0),
        options=stability.RunOptions(chunk_members=64), **RUN
    )
    assert "w" not in summaries and "time" not in summaries.dims
    assert summaries.attrs["time_series"] == 0 and reference.attrs["time_series"] == 1
    assert _bits(summaries) == _bits(reference.drop_vars(["w", "time"]))


def test_different_seeds_differ(reference):
    other = run_ensemble(BODY, 2, 1.0, 1e-3, 150, seed=12, keep=SERIES, **RUN)
    assert not np.any(np.all(other.w0.values == reference.w0.values, axis=1))
    assert not np.any(other.first_flip_time.values == reference.first_flip_time.values)
    assert other.attrs["seed_entropy"] == "12" and reference.attrs["seed_entropy"] == "11"


def test_fresh_entropy_is_recorded_and_repeats_the_run():
    first = run_ensemble(BODY, 2, 1.0, 1e-3, 20, seed=None, keep=SERIES, **RUN)
    again = run_ensemble(BODY, 2, 1.0, 1e-3, 20, seed=int(first.attrs["seed_entropy"]),
                         keep=SERIES, **RUN)
    np.testing.assert_array_equal(first.w.values, again.w.values)


# --- the Dataset ------------------------------------------------------------------------------


def test_dataset_schema(reference):
    ds = reference
    assert ds.w.dims == (cv.MEMBER, cv.TIME, cv.AXIS)
    assert ds.w.shape == (150, 401, 3)
    np.testing.assert_array_equal(ds.axis.values, [1, 2, 3])
    assert ds.member.attrs["standard_name"] == "realization" and ds.member.attrs["units"] == "1"
    assert ds.time.dtype == np.float64 and ds.time.attrs["units"] == "s since 1970-01-01 00:00:00"
    assert ds.time.attrs["standard_name"] == "time" and ds.time.attrs["axis"] == "T"
    np.testing.assert_allclose(ds.time.values, np.arange(401) * 0.1, rtol=1e-15)
    np.testing.assert_array_equal(ds.w.values[:, 0], ds.w0.values)
    for name, var in ds.variables.items():
        assert var.attrs.get("long_name"), name
        if name not in (cv.MEMBER, cv.AXIS):
            assert var.attrs.get("units"), name
    assert ds.w.attrs["units"] == "rad s-1"
    assert ds.status.dtype == np.int8
    assert ds.status.attrs["flag_meanings"].split() == ["ok", "non_finite", "diverged",
                                                        "not_converged", "step_too_large"]
    np.testing.assert_array_equal(ds.status.attrs["flag_values"], [0, 1, 2, 3, 4])
    assert ds.status.attrs["flag_values"].dtype == np.int8
    assert set(SUMMARIES) <= set(ds.data_vars)
    assert ds.passage_time.dims == (cv.MEMBER, LEVEL)
    attrs = ds.attrs
    assert attrs["Conventions"] == "CF-1.10"
    assert attrs["source"] == f"stability {stability.__version__}"
    for key in ("title", "history", "references", "I1", "I2", "I3", "method", "method_order",
                "h", "seed_entropy", "seed_spawn_scheme", "epsilon", "axis", "spin",
                "numba_version", "numba_threading_layer", "config_toml"):
        assert key in attrs, key
    assert attrs["method_order"] == 2 and attrs["axis"] == 2 and attrs["epsilon"] == 1e-3
    assert attrs["numba_threading_layer"] == LOOP_THREADS
    assert attrs["history"].count("\n") == 0 and "run_ensemble" in attrs["history"]
    for value in attrs.values():
        assert isinstance(value, (str, int, float, np.ndarray)) and not isinstance(value, bool)


def test_config_toml_holds_the_resolved_arguments(reference):
    import tomllib

    config = tomllib.loads(reference.attrs["config_toml"])["run_ensemble"]
    assert config["members"] == 150 and config["seed"] == 11 and config["method"] == "lp2"
    assert config["body"] == {"name": "I=(1,2,3)", "I1": 1.0, "I2": 2.0, "I3": 3.0,
                              "physical": True}
    np.testing.assert_array_equal(config["levels"], reference.level.values)


# --- summaries against known answers ----------------------------------------------------------


def _euler_rhs(t, w, moments=BODY.moments):
    I1, I2, I3 = moments
    return [(I2 - I3) * w[1] * w[2] / I1, (I3 - I1) * w[2] * w[0] / I2,
            (I1 - I2) * w[0] * w[1] / I3]


def test_flips_match_dop853_zero_crossings():
    from scipy.integrate import solve_ivp

    # Perturbation along axis 1, along axis 3, and a mixed one with negative spin.
    starts = np.array([[0.01, 1.0, 0.0], [0.0, 1.0, 0.01], [0.003, -1.0, 0.004]])
    ds = run_ensemble(BODY, 2, starts=starts, method="rk4", h=0.01, t_end=100.0)
    assert np.all(ds.status.values == cv.STATUS_OK)
    for j, w0 in enumerate(starts):
        sol = solve_ivp(_euler_rhs, (0.0, 100.0), w0, method="DOP853", rtol=1e-12, atol=1e-14,
                        events=(lambda t, w: w[1], lambda t, w: w[0]))  # w_b = w1 here
        flips, perp = sol.t_events
        assert ds.flip_count.values[j] == len(flips) >= 4
        np.testing.assert_allclose(ds.first_flip_time.values[j], flips[0], rtol=1e-7)
        np.testing.assert_allclose(ds.last_flip_time.values[j], flips[-1], rtol=1e-7)
        np.testing.assert_allclose(
            ds.mean_flip_interval.values[j], (flips[-1] - flips[0]) / (len(flips) - 1),
            rtol=1e-7,
        )
        assert ds.perp_crossing_count.values[j] == len(perp)
        if len(perp):
            np.testing.assert_allclose(ds.last_perp_crossing.values[j], perp[-1], rtol=1e-7)
    # The exact flip interval 2K/nu for the start (0.01, 1, 0) (literature notes, sec. 1.5).
    np.testing.assert_allclose(ds.mean_flip_interval.values[0], 20.754610, rtol=1e-7)


def test_mean_flip_interval_matches_the_exact_2k_over_nu():
    # Random directions give each member its own k' and so its own 2K/nu (18.9 to 27.8 s here).
    ds = run_ensemble(BODY, 2, 1.0, 1e-2, 64, h=0.01, t_end=150.0, method="rk4", seed=5,
                      keep=stability.Keep(save_every=0))
    exact = np.array([stability.flip_interval(BODY, w0) for w0 in ds.w0.values])
    assert np.ptp(exact) > 5.0 and np.all(ds.flip_count.values >= 5)
    np.testing.assert_allclose(ds.mean_flip_interval.values, exact, rtol=1e-8)


def test_perpendicular_amplitude_grows_at_the_linear_rate():
    # Amplitude from 1e-8 W: the passages of 1e-6 W and 1e-3 W lie in the linear phase, where
    # the amplitude grows like exp(lambda t); lp2's O(h^2) bias in the rate is ~2e-6 here.
    # A start near the stable eigendirection grows late: 40 s leave room for the slowest.
    ds = run_ensemble(BODY, 2, 1.0, 1e-8, 128, h=0.01, t_end=40.0,
                      keep=stability.Keep(save_every=0, levels=[1e-6, 1e-3]))
    t = ds.passage_time.values
    rate = math.log(1e3) / (t[:, 1] - t[:, 0])
    np.testing.assert_allclose(rate, LAMBDA, rtol=1e-4)
    flips = ds.first_flip_time.values
    assert np.all(np.isnan(flips) | (flips > t[:, 1]))  # flips come after the linear phase


def test_stable_axes_oscillate_at_omega_and_never_flip():
    # Omega^2 = (Ia - Ib)(Ia - Ic) W^2 / (Ib Ic) about axis a: 1/3 about axis 1, 1 about axis 3;
    # the perpendicular component crosses zero twice per period 2 pi / Omega.
    for axis, omega in ((1, math.sqrt(1.0 / 3.0)), (3, 1.0)):
        ds = run_ensemble(BODY, axis, 1.0, 1e-3, 64, h=0.02, t_end=100.0,
                          keep=stability.Keep(save_every=0, levels=[1e-4, 5e-3]))
        assert np.all(ds.status.values == cv.STATUS_OK)
        assert np.all(ds.passage_time.values[:, 0] == 0.0)  # the start is above 1e-4
        assert np.all(np.isnan(ds.passage_time.values[:, 1]))  # never reaches 5e-3
        assert np.all(ds.flip_count.values == 0)
        assert np.all(np.isnan(ds.first_flip_time.values + ds.mean_flip_interval.values))
        # Bounded: the perturbation ellipse's axes differ by sqrt of moment ratios (< 3 here).
        assert np.all(ds.max_perp_amplitude.values < 3e-3)
        count = ds.perp_crossing_count.values
        span = ds.last_perp_crossing.values - ds.first_perp_crossing.values
        np.testing.assert_allclose(math.pi * (count - 1) / span, omega, rtol=1e-4)


def test_passage_times_are_zero_below_the_start_and_increase_above(reference):
    below = reference.level.values < 1e-3 * (1 - 1e-9)  # epsilon * spin = 1e-3
    assert below.any() and not below.all()
    t = reference.passage_time.values
    assert np.all(t[:, below] == 0.0)
    reached = reference.level.values <= reference.max_perp_amplitude.values.min()
    assert np.all(np.diff(t[:, ~below & reached], axis=1) > 0)
    never = reference.level.values[None, :] > reference.max_perp_amplitude.values[:, None]
    assert np.all(np.isnan(t) == never)


# --- interruption -----------------------------------------------------------------------------


def test_interrupted_run_is_marked_partial(monkeypatch):
    real = Plan.propagate

    def stopped_halfway(run, progress=None, partial=False):
        result = real(replace(run, n_steps=run.n_steps // 2), progress, partial)
        result.interrupted = True
        return result

    monkeypatch.setattr(Plan, "propagate", stopped_halfway)
    ds = run_ensemble(BODY, 2, 1.0, 1e-3, 10, keep=SERIES, **RUN)
    assert ds.attrs["interrupted"] == 1 and ds.attrs["steps_done"] == 1000
    assert "partial" in ds.attrs["title"]
    assert ds.time.values[-1] == pytest.approx(20.0) and ds.member.size == 10
    assert np.all(np.isfinite(ds.w.values))


def test_interrupted_chunked_run_keeps_the_completed_chunks(monkeypatch):
    real = Plan.propagate
    calls = []

    def stopped_in_second_chunk(run, progress=None, partial=False):
        calls.append(run.members)
        result = real(replace(run, n_steps=run.n_steps // len(calls)), progress, partial)
        result.interrupted = len(calls) > 1
        return result

    monkeypatch.setattr(Plan, "propagate", stopped_in_second_chunk)
    ds = run_ensemble(BODY, 2, 1.0, 1e-3, 25, options=stability.RunOptions(chunk_members=10),
                      keep=stability.Keep(save_every=0), **RUN)
    assert calls == [10, 10]
    assert ds.attrs["interrupted"] == 1 and ds.attrs["steps_done"] == 2000
    assert ds.member.size == 10 and ds.attrs["members_requested"] == 25


# --- bad input --------------------------------------------------------------------------------

GOOD = dict(body=BODY, axis=2, spin=1.0, epsilon=1e-3, members=4, h=0.01, t_end=1.0)


@pytest.mark.parametrize(
    "change, message",
    [
        (dict(body=(1.0, 2.0, 3.0)), "RigidBody"),
        (dict(axis=0), "axis must be the principal axis 1, 2 or 3"),
        (dict(axis=True), "axis must be"),
        (dict(axis=2.0), "axis must be"),
        (dict(spin=-1.0), "spin must be finite and > 0"),
        (dict(epsilon=-0.1), "epsilon must be finite and >= 0"),
        (dict(epsilon=float("nan")), "epsilon must be finite"),
        (dict(members=0), "members must be >= 1"),
        (dict(members=2.5), "members must be a whole number"),
        (dict(h=0.0), "h must be finite and > 0"),
        (dict(t_end=1.005), "whole number of steps"),
        (dict(keep=dict(save_every=3)), "not a multiple of save_every"),
        (dict(method="euler"), "unknown method 'euler'; known methods: rk4, lp2"),
        (dict(seed=-1), "seed must be an integer >= 0"),
        (dict(seed=1.5), "seed must be"),
        (dict(starts=[[0.0, 1.0, 0.0]]), "leave spin and epsilon out"),
        (dict(spin=None, epsilon=None, members=3, starts=[[0.0, 1.0, 0.0]]), "3 rows|1 rows"),
        (dict(spin=None, epsilon=None, starts=[0.0, 1.0, 0.0]), r"shape \(members, 3\)"),
        (dict(spin=None, epsilon=None, members=None, starts=[[0.0, 0.0, 0.0]]), "at rest"),
        (dict(spin=None), "give spin, the spin rate in rad/s"),
        (dict(spin=None, h=None, t_end=None), "give spin, the spin rate in rad/s"),
        (dict(spin=-1.0, h=None), "spin must be finite and > 0"),
        (dict(axis=4, t_end=None), "axis must be the principal axis 1, 2 or 3"),
        (dict(keep=dict(levels=[1e-3, 1e-4])), "strictly ascending"),
        (dict(keep=dict(levels=[])), "levels must be"),
        (dict(options=dict(threads=0)), "threads must be >= 1"),
        (dict(options=dict(threads=10**6)), "threads must be between 1 and"),
        (dict(keep=dict(attitude="yes")), "attitude must be True or False"),
        (dict(keep=dict(save_every=-1)), "save_every must be >= 0"),
        (dict(keep=dict(divergence_tolerance=0.0)), "divergence_tolerance must be finite and > 0"),
        (dict(options=dict(chunk_members=0)), "chunk_members must be >= 1"),
    ],
)
def test_bad_input_is_one_clear_value_error(change, message):
    """Each bad argument is one ValueError, the choices of what to keep and how to run
    (Keep, RunOptions) refused as they are made."""
    change = dict(change)
    keep, options = change.pop("keep", None), change.pop("options", None)
    with pytest.raises(ValueError, match=message):
        run_ensemble(**{**GOOD, **change}, keep=None if keep is None else stability.Keep(**keep),
                     options=None if options is None else stability.RunOptions(**options))


def test_ensembles_run_together_are_bitwise_the_ensembles_run_alone():
    """run_ensembles: bodies, axes, steps, horizons and starts of every kind in one batch give
    Datasets whose variables are bitwise those of run_ensemble one call at a time."""
    from stability.free_body.spin_ensembles import run_ensembles

    calls = [
        dict(body=BODY, axis=2, spin=1.0, epsilon=1e-3, members=70, h=0.02, t_end=30.0,
             keep=stability.Keep(save_every=0), method="rk4"),
        dict(body=stability.RigidBody(1.0, 1.5, 2.5), axis=1, spin=2.0, epsilon=1e-2,
             members=9, h=0.01, t_end=12.0, keep=stability.Keep(save_every=0), method="rk4",
             seed=4),
        dict(body=BODY, axis=3, starts=[[0.01, 0.0, 1.0], [0.0, 0.02, -1.0]], h=0.05,
             t_end=40.0, keep=stability.Keep(save_every=0), method="rk4"),
        dict(body=BODY, axis=2, spin=1.0, epsilon=1e-3, members=5, h=0.02, t_end=2.0,
             keep=stability.Keep(save_every=10), method="rk4"),  # a time series: run on its own
        dict(body=BODY, axis=2, spin=1.0, epsilon=1e-3, members=6, h=0.05, t_end=5.0,
             keep=stability.Keep(save_every=0), method="lp2"),
    ]
    together = run_ensembles(calls)
    for call, ds in zip(calls, together):
        alone = run_ensemble(**call)
        assert ds.attrs["interrupted"] == 0 and ds.attrs["steps_done"] == alone.attrs["steps"]
        for name in alone.variables:
            a, b = alone[name].values, ds[name].values
            assert np.array_equal(a, b, equal_nan=a.dtype.kind == "f"), name


def test_summaries_without_datasets_are_what_the_estimators_read_from_the_datasets():
    """run_ensembles(datasets=False): each EnsembleSummary holds bitwise the Members,
    status and energy errors the Dataset of the same ensemble gives, for random and given
    starts, and the map's estimates of both are the same numbers."""
    import dataclasses

    from stability.analysis.members import members
    from stability.free_body.spin_ensembles import EnsembleSummary, run_ensembles
    from stability.free_body.stability_map.measure import ensemble_estimates

    calls = [
        dict(body=BODY, axis=2, spin=1.0, epsilon=1e-3, members=70, h=0.02, t_end=30.0,
             keep=stability.Keep(save_every=0), method="rk4"),
        dict(body=BODY, axis=3, starts=[[0.01, 0.0, 1.0], [0.0, 0.02, -1.0]], h=0.05,
             t_end=40.0, keep=stability.Keep(save_every=0), method="rk4"),
        dict(body=BODY, axis=1, spin=2.0, epsilon=0.05, members=9, h=0.05, t_end=20.0,
             keep=stability.Keep(save_every=0), method="rk4", seed=3),
    ]
    for call, ds, summary in zip(calls, run_ensembles(calls), run_ensembles(calls,
                                                                             datasets=False)):
        assert isinstance(summary, EnsembleSummary) and not summary.interrupted
        assert summary.member_steps == ds.attrs["members"] * ds.attrs["steps_done"]
        np.testing.assert_array_equal(summary.status, ds.status.values)
        np.testing.assert_array_equal(summary.energy_error, ds.energy_error.values)
        mem = members(ds)
        for field in dataclasses.fields(mem):
            a, b = getattr(mem, field.name), getattr(summary.members, field.name)
            if isinstance(a, np.ndarray):
                assert a.dtype == b.dtype and np.array_equal(a, b, equal_nan=a.dtype.kind == "f"
                                                             ), field.name
            else:
                assert a == b, field.name
        kw = dict(low_factor=10.0, high_fraction=0.03)
        x, y = ensemble_estimates(ds, -1.0, **kw), ensemble_estimates(summary, -1.0, **kw)
        assert x.keys() == y.keys()
        for key in x:
            assert np.array_equal(x[key], y[key], equal_nan=True), key
    with pytest.raises(ValueError, match=r"calls\[0\]: datasets=False needs the summaries only"):
        run_ensembles([dict(calls[0], keep=stability.Keep(save_every=1))], datasets=False)


def test_run_ensembles_refuses_settings_of_the_whole_batch_per_call():
    from stability.free_body.spin_ensembles import run_ensembles

    with pytest.raises(ValueError, match="chunk_steps is set for the whole batch"):
        run_ensembles([dict(body=BODY, axis=2, spin=1.0, epsilon=1e-3, members=5, h=0.1,
                            t_end=1.0, options=stability.RunOptions(chunk_steps=3))])


def test_run_ensembles_takes_run_ensembles_defaults_and_names_the_call_it_refuses():
    """A call without h, t_end, epsilon or members gets run_ensemble's defaults (the same
    Dataset, its rules included); a wrong call is refused by its index, before anything runs."""
    from stability.free_body.spin_ensembles import run_ensembles

    call = dict(body=BODY, axis=2, spin=1.0, members=4, keep=stability.Keep(save_every=0))
    (together,) = run_ensembles([call])
    alone = run_ensemble(**call)
    assert together.attrs["h_rule"] == alone.attrs["h_rule"]
    assert together.attrs["t_end_rule"] == alone.attrs["t_end_rule"]
    for name in alone.variables:
        a, b = alone[name].values, together[name].values
        assert np.array_equal(a, b, equal_nan=a.dtype.kind == "f"), name
    ok = dict(body=BODY, axis=2, spin=1.0, members=3, h=0.1, t_end=1.0)
    for calls, message in (
            (ok, "calls must be a list of dicts, each the keyword arguments of run_ensemble "
                 "for one ensemble; got a dict"),
            (None, "got a NoneType"),
            ([ok, 3], r"calls\[1\] must be a dict of run_ensemble's keyword arguments, got a int"),
            ([dict(ok, sppin=1.0)], r"calls\[0\]: unknown argument 'sppin' of run_ensemble "
                                    r"\(did you mean 'spin'\?\)"),
            ([ok, dict(ok, axis=7)], r"calls\[1\]: axis must be the principal axis 1, 2 or 3"),
            ([{k: v for k, v in ok.items() if k != "body"}], r"calls\[0\]: give body"),
            ([dict(ok, options=stability.RunOptions(store="somewhere"))],
             r"calls\[0\]: store is for a streamed run"),
            ([dict(ok, options=stability.RunOptions(resume=True))],
             r"calls\[0\]: resume is for a streamed run"),
            ([dict(ok, options=stability.RunOptions(threads=1))],
             r"calls\[0\]: threads is set for the whole batch")):
        with pytest.raises(ValueError, match=message):
            run_ensembles(calls)
    assert len(run_ensembles([dict(ok, options=stability.RunOptions(max_memory=1e9))])) == 1


def test_run_ensemble_takes_the_spin_axis_by_the_name_of_its_moment():
    """As study files do ([spin] axis = "intermediate"): the same run as by its label, in
    run_ensemble and run_ensembles; a name not known is one line listing them."""
    racket = stability.RigidBody.preset("tennis_racket")
    kwargs = dict(spin=10.0, members=4, h=0.01, t_end=1.0, keep=stability.Keep(save_every=0),
                  options=stability.RunOptions(progress=False))
    named = run_ensemble(racket, axis="intermediate", **kwargs)
    assert named.attrs["axis"] == 2
    numbered = run_ensemble(racket, axis=2, **kwargs)
    assert np.array_equal(named.flip_count.values, numbered.flip_count.values)
    (batch,) = stability.run_ensembles([dict(body=racket, axis="intermediate", **{
        k: v for k, v in kwargs.items() if k != "options"})], progress=False)
    assert batch.attrs["axis"] == 2
    with pytest.raises(ValueError) as info:
        run_ensemble(racket, axis="middle", **kwargs)
    assert str(info.value) == ("axis must be the principal axis 1, 2 or 3, or the name of its "
                               "moment (smallest, intermediate, largest), got 'middle'")

