"""Keep: what a free-body ensemble keeps, one frozen object refusing nonsense in one line."""

import dataclasses

import numpy as np
import pytest

import stability
from stability import Keep, RunOptions
from stability.free_body.spin_ensembles import plan_arguments


@pytest.mark.parametrize("kwargs, message", [
    (dict(save_every=-1), "save_every must be >= 0"),
    (dict(save_every=2.5), "save_every must be a whole number"),
    (dict(attitude="yes"), "attitude must be True or False, got 'yes'"),
    (dict(save_every=0, attitude=True), "the attitude is kept with the time series"),
    (dict(divergence_tolerance=0.0), "divergence_tolerance must be finite and > 0"),
])
def test_keep_refuses_nonsense_in_one_line(kwargs, message):
    with pytest.raises(ValueError, match=message) as caught:
        Keep(**kwargs)
    assert "\n" not in str(caught.value)


def test_keep_is_frozen_and_says_what_the_plan_takes():
    keep = Keep(save_every=0, levels=[1e-3, 1e-2])
    with pytest.raises(dataclasses.FrozenInstanceError):
        keep.save_every = 3
    assert keep.summaries_only and keep.scene == "free_body"
    planned = plan_arguments(keep, RunOptions(chunk_members=64, max_memory=1e9))
    assert planned == {"save_every": 1, "summaries_only": True, "levels": [1e-3, 1e-2],
                       "scene": "free_body", "divergence_tolerance": 1e-2, "max_memory": 1e9,
                       "chunk_members": 64, "chunk_steps": None, "device": "cpu"}
    assert Keep(save_every=5, attitude=True).scene == "free_body_attitude"


def test_what_is_kept_never_changes_the_summaries_and_the_record_names_the_call():
    """The summaries of a run keeping the series every 4 steps are bitwise those of the
    summaries-only run; the Dataset's history line is a call that would make it again."""
    body = stability.RigidBody(1.0, 2.0, 3.0)
    run = dict(h=0.05, t_end=20.0, seed=3, options=RunOptions(progress=False))
    series = stability.run_ensemble(body, 2, 1.0, 1e-2, 16, keep=Keep(save_every=4), **run)
    summaries = stability.run_ensemble(body, 2, 1.0, 1e-2, 16, keep=Keep(save_every=0), **run)
    for name in summaries.data_vars:
        assert np.array_equal(series[name].values, summaries[name].values, equal_nan=True), name
    assert "keep=Keep(save_every=4)" in series.attrs["history"]
    assert "keep=Keep(save_every=0)" in summaries.attrs["history"]
    with pytest.raises(ValueError, match="keep must be a stability.Keep, got int"):
        stability.run_ensemble(body, 2, 1.0, 1e-2, 16, keep=4, **run)


def test_run_ensemble_takes_a_dozen_parameters_at_most():
    """What is run (the body, its spin and starts, the method, step and horizon) by name, and
    what is kept and how it runs as one object each."""
    import inspect

    assert len(inspect.signature(stability.run_ensemble).parameters) <= 12
