"""Engine artefacts: each update rule's effect on the flip, measured against the exact motion."""


import numpy as np

import stability
from stability.engine_body.measure import measure_rule, step_for_accuracy
from stability.ensemble.starts import perturbed_starts


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

