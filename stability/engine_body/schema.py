"""The declarations of the engine artefacts study's Dataset, registered from the family's
``DATASETS`` (:mod:`stability.registry`)."""

from ..ensemble.schema import (
    ONE, PER_SECOND, RADIAN, RAD_PER_S, SECOND, TIME, coordinate, declare, time_coordinate,
    variable,
)

__all__ = ["ENGINE_ARTEFACTS"]


# The engine's artefacts (stability.engine_body.measure) ---------------------------------------

_RULE_STEP = ("rule", "step")
_SEARCHED = (
    "searched at h / 2^(k/2) from the largest step; NaN: not reached down to the "
    "search's smallest step"
)
ENGINE_ARTEFACTS = declare(
    "engine_artefacts",
    "what each update rule or method does to the tennis racket's flips, "
    "growth and invariants, per step",
    "stability.engine_body.measure.measure_artefacts",
    {
        "fraction_flipping": variable(
            _RULE_STEP, ONE, "fraction of members that flip at least once"
        ),
        "flip_interval": variable(_RULE_STEP, SECOND, "median flip interval"),
        "flip_interval_error": variable(
            _RULE_STEP, ONE, "mean relative error of the flip interval against the exact 2K/nu"
        ),
        "growth_rate": variable(
            _RULE_STEP, PER_SECOND, "growth rate of the perpendicular amplitude"
        ),
        "growth_rate_error": variable(
            _RULE_STEP, ONE, "relative error of the growth rate against sqrt(-Omega^2)"
        ),
        "energy_drift": variable(_RULE_STEP, ONE, "median relative energy error at the end"),
        "momentum_drift": variable(_RULE_STEP, ONE, "median relative |L| error at the end"),
        "l_direction_drift": variable(
            _RULE_STEP, RADIAN, "median angle turned by the spatial angular momentum at the end"
        ),
        "cost_per_step": variable(
            _RULE_STEP, SECOND, "measured wall time per member-step (tracking included)"
        ),
        "members_ok": variable(_RULE_STEP, ONE, "members whose run stayed finite"),
        "evaluations_per_second": variable(
            _RULE_STEP,
            PER_SECOND,
            "right-hand-side evaluations (or sub-flows) per simulated second",
        ),
        "step_needed": variable(
            "rule",
            SECOND,
            "largest step with the flip interval within {tolerance:g} of the exact",
            comment=_SEARCHED,
        ),
        "step_needed_energy": variable(
            "rule",
            SECOND,
            "largest step with the energy at the end within {tolerance:g} of the start",
            comment=_SEARCHED,
        ),
        "spin_component": variable(
            ("rule", TIME), RAD_PER_S, "member's spin-axis angular velocity w2 at h = {h:g} s"
        ),
        "spin_component_exact": variable(TIME, RAD_PER_S, "the same member's exact w2"),
        "family": variable("rule", ONE, "family of the rule", kind="U"),
        "rule": coordinate("rule", ONE, "update rule or method", kind="U"),
        "step": coordinate("step", SECOND, "time step"),
        TIME: time_coordinate("time"),
    },
)
