"""Plan: the one small frozen object every run is, run by run_plan the same wherever it runs."""

import dataclasses

import numpy as np
import pytest

from stability import RunOptions
from stability.ensemble.chunks import run_plan
from stability.ensemble.plan import Plan
from stability.registry import SCENES


def test_a_plan_is_frozen_and_the_same_result_whatever_the_options(tmp_path):
    """The plan holds what is run; the options never change a number (here: chunks in a store
    against one piece in memory, bitwise)."""
    scene = SCENES["heavy_top"]
    x0, tops = scene.example(6)
    spec = scene.method("lp2")
    plan = Plan(scene, "lp2", x0, [spec.params(tops[0], 0.05)], [6], 0.05, 30)
    with pytest.raises(dataclasses.FrozenInstanceError):
        plan.n_steps = np.array([3])
    whole = run_plan(plan, RunOptions(progress=False))
    stored = run_plan(plan, RunOptions(store=tmp_path / "s", chunk_members=4, progress=False))
    assert np.array_equal(whole.x_final, stored.x_final)


def test_a_plan_refuses_starts_given_twice_and_an_unknown_device():
    scene = SCENES["heavy_top"]
    x0, tops = scene.example(2)
    row = [scene.method("lp2").params(tops[0], 0.05)]
    with pytest.raises(ValueError, match="give the starts as x0 or as a rule, starts=, not both"):
        Plan(scene, "lp2", x0, row, [2], 0.05, 3, starts=lambda lo, hi: x0[lo:hi])
    with pytest.raises(ValueError, match="device must be 'cpu' or 'gpu', got 'tpu'"):
        Plan(scene, "lp2", x0, row, [2], 0.05, 3, device="tpu")


def test_grouped_run_refuses_an_unknown_device():
    from stability.ensemble.plan import Plan
    from stability.free_body.scene import FREE_BODY

    with pytest.raises(ValueError, match="device must be 'cpu' or 'gpu', got 'tpu'"):
        Plan(FREE_BODY, "rk4", [[0.0, 1.0, 0.0]], [[1.0] * 9], [1], 0.1, 1,
             device="tpu")
