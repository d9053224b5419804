"""The declaration of the asteroid family's Dataset: an ensemble of tumblers drawn from a
published spin state's uncertainties, registered from the family's ``DATASETS``
(:mod:`stability.registry`)."""

from ..ensemble.schema import MEMBER, ONE, declare, member_coordinate, variable

__all__ = ["TUMBLER"]

HOUR = "h"
PER_DAY = "d-1"
RAD_PER_HOUR = "rad h-1"

TUMBLER = declare(
    "tumbler",
    "spin states and light-curve frequencies of a tumbler's ensemble over its uncertain "
    "moment ratios and periods",
    "stability.asteroid.measure.measure_tumblers",
    {
        "moment_ratio_13": variable(MEMBER, ONE, "ratio I1 / I3 of the smallest to the largest "
                                    "principal moment"),
        "moment_ratio_23": variable(MEMBER, ONE, "ratio I2 / I3 of the intermediate to the "
                                    "largest principal moment"),
        "period_psi": variable(MEMBER, HOUR, "rotation period P_psi about the reference axis"),
        "period_phi": variable(MEMBER, HOUR, "mean precession period P_phi of the reference "
                               "axis about the angular momentum"),
        "energy_ratio": variable(MEMBER, ONE, "rotational energy over the lowest at that "
                                 "angular momentum, E / E0 = 2 E I3 / L^2"),
        "momentum_per_i3": variable(MEMBER, RAD_PER_HOUR, "angular momentum over the largest "
                                    "moment, |L| / I3"),
        "frequency_predicted": variable(MEMBER, PER_DAY, "main light-curve frequency by theory: "
                                        "2 (f_phi - f_psi) in SAM, 2 f_phi in LAM"),
        "frequency_measured": variable(MEMBER, PER_DAY, "strongest frequency of the member's "
                                       "synthetic light curve"),
        "fitted": variable(MEMBER, ONE, "1 where a state of the mode fits the member's draws, "
                           "0 where none does (its values NaN)", kind="i"),
        "member": member_coordinate(),
    },
)
