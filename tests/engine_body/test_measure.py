"""Engine artefacts: each update rule's effect on the flip, measured against the exact motion."""

from pathlib import Path

import numpy as np

import stability
from stability.engine_body.measure import measure_rule, step_for_accuracy
from stability.free_body.starts import perturbed_starts

from ..helpers import assert_cf_compliant, assert_declared, assert_readable

ROOT = Path(__file__).resolve().parents[2]
RACKET = np.sort(stability.RigidBody.preset("tennis_racket").moments)
STARTS = perturbed_starts(2, 10.0, 1e-4, 24, 3)


def test_the_exact_flow_and_rk4_reproduce_the_flip_the_engine_rules_do_not():
    exact = measure_rule("exact", RACKET, STARTS, 1 / 60, 10.0)
    assert exact["fraction_flipping"] == 1.0 and abs(exact["flip_interval_error"]) < 1e-6
    assert abs(exact["growth_rate_error"]) < 1e-4  # the fit's own bias
    rk4 = measure_rule("rk4", RACKET, STARTS, 1 / 240, 10.0)
    assert abs(rk4["flip_interval_error"]) < 1e-6 and abs(rk4["l_direction_drift"]) < 1e-6
    none = measure_rule("no_gyroscopic", RACKET, STARTS, 1 / 60, 10.0)
    assert none["fraction_flipping"] == 0.0 and abs(none["energy_drift"]) < 1e-14
    assert none["l_direction_drift"] > 1e-6  # the spatial angular momentum is not kept
    semi = measure_rule("semi_implicit_euler", RACKET, STARTS, 1 / 60, 10.0)
    implicit = measure_rule("implicit_euler", RACKET, STARTS, 1 / 60, 10.0)
    assert semi["energy_drift"] > 0.1 and implicit["energy_drift"] < -0.1
    jolt = measure_rule("rescaled_momentum", RACKET, STARTS, 1 / 60, 10.0)
    assert abs(jolt["momentum_drift"]) < 1e-13 and jolt["flip_interval_error"] > 0.05


def test_step_needed_for_a_one_percent_flip_interval_shrinks_with_the_rule():
    rk4 = step_for_accuracy("rk4", RACKET, STARTS[:8], 10.0, 1 / 60, 0.01, 4)
    jolt = step_for_accuracy("rescaled_momentum", RACKET, STARTS[:8], 10.0, 1 / 60, 0.01, 8)
    none = step_for_accuracy("no_gyroscopic", RACKET, STARTS[:8], 10.0, 1 / 60, 0.01, 2)
    assert rk4 == 1 / 60 and 1e-4 < jolt < 1 / 240 and np.isnan(none)
    check = measure_rule("rescaled_momentum", RACKET, STARTS[:8], jolt, 10.0)
    assert abs(check["flip_interval_error"]) <= 0.01


def test_study_engine_artefacts_quick(tmp_path):
    from stability.engine_body.figures import artefacts_figure
    from stability.study import run_study

    summary = run_study(ROOT / "studies" / "engine_artefacts.toml", tmp_path, quick=True,
                        progress=False, overrides=[("output.formats", "['png']")])
    rules = summary.values["rules"]
    assert rules["no_gyroscopic"]["fraction_flipping"] == 0.0
    assert rules["exact"]["fraction_flipping"] == 1.0
    assert abs(rules["rk4"]["flip_interval_error"]) < 1e-4
    assert np.isnan(rules["no_gyroscopic"]["step_needed"])
    text = summary.table()  # one column per quantity, words where there is no number
    header = next(line for line in text.splitlines() if line.startswith("rule "))
    assert header.split("  ")[0] == "rule" and "step for energy" in header
    no_gyro = next(line for line in text.splitlines() if line.startswith("no_gyroscopic "))
    assert "no flip" in no_gyro and "not reached" in no_gyro and "nan" not in text
    ds = stability.load(tmp_path / "engine_artefacts.nc")
    for name, var in {**ds.data_vars, **ds.coords}.items():
        assert var.attrs.get("units") and var.attrs.get("long_name"), name
    assert_readable(artefacts_figure(ds))
    assert_cf_compliant(tmp_path / "engine_artefacts.nc")
    assert_declared(tmp_path / "engine_artefacts.nc", "engine_artefacts")


def test_progress_false_silences_every_bar_of_the_study(capfd):
    """``--no-progress`` reaches every run the study makes (they showed their bars)."""
    from stability.engine_body.measure import measure_artefacts

    args = (["rk4", "semi_implicit_euler"], RACKET, STARTS[:4], [1 / 60], 1.0)
    measure_artefacts(*args, halvings=1, search_members=4,
                      options=stability.RunOptions(progress=True))
    assert "step" in capfd.readouterr().err  # bars with units of steps, when asked for
    measure_artefacts(*args, halvings=1, search_members=4,
                      options=stability.RunOptions(progress=False))
    assert capfd.readouterr().err == ""
