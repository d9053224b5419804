"""The declarations of the struck bat's Dataset, registered from the family's ``DATASETS``
(:mod:`stability.registry`)."""

from ..ensemble.schema import (
    METRE, METRE_PER_S, NEWTON_SECOND, ONE, RAD_PER_S, coordinate, declare, status_variable,
    variable,
)

__all__ = ["BAT"]


# The struck bat (stability.struck.measure.measure_strikes) --------------------------------------

_HPS = ("hold", "pivot", "strike")
BAT = declare(
    "bat",
    "the centre of percussion of a struck bat or racket, held at the hands or free, "
    "from the runs and by the formulas",
    "stability.struck.measure.measure_strikes",
    {
        "angular_velocity": variable(_HPS, RAD_PER_S, "angular velocity just after the contact"),
        "cm_velocity_across": variable(
            _HPS,
            METRE_PER_S,
            "velocity of the centre of mass across the body, just after the contact",
        ),
        "hand_velocity_across": variable(
            _HPS,
            METRE_PER_S,
            "velocity across the body of its point at the "
            "hands, just after the contact (0 when held)",
        ),
        "reaction_impulse_across": variable(
            _HPS,
            NEWTON_SECOND,
            "reaction impulse across the body at the hands over the contact (0 when free)",
        ),
        "reaction_impulse_along": variable(
            _HPS,
            NEWTON_SECOND,
            "reaction impulse along the body at the hands "
            "over the contact (centripetal; 0 when free)",
        ),
        "reaction_impulse_formula": variable(
            ("pivot", "strike"), NEWTON_SECOND, "held, instantaneous impulse: J (M d s / I_P - 1)"
        ),
        "hand_velocity_formula": variable(
            ("pivot", "strike"),
            METRE_PER_S,
            "free, instantaneous impulse: J / M - d (s - d) J / I_cm",
        ),
        "percussion_centre_measured": variable(
            ("hold", "pivot"),
            METRE,
            "centre of percussion from "
            "the runs (zero reaction held, hands at rest free), "
            "from the end held",
        ),
        "percussion_centre_formula": variable(
            "pivot", METRE, "centre of percussion pivot + I_P / (M d), from the end held"
        ),
        "sweet_zone_measured": variable(
            ("pivot", "edge"),
            METRE,
            "strike points where the reaction across is sting x J, from the runs (held)",
        ),
        "sweet_zone_formula": variable(
            ("pivot", "edge"), METRE, "pivot + (1 -+ sting) I_P / (M d) (NaN: beyond the tip)"
        ),
        "status": status_variable(_HPS),
        "outline": variable(
            ("station", "xy"),
            METRE,
            "outline of the body: stations (x from the end held, half-width)",
        ),
        "hold": coordinate("hold", ONE, "hands: a hinge at the pivot, or none", kind="U"),
        "pivot": coordinate("pivot", METRE, "hands (pivot), from the end held"),
        "strike": coordinate("strike", METRE, "strike point, from the end held"),
        "edge": coordinate("edge", ONE, "edge of the sweet zone", kind="U"),
    },
)
