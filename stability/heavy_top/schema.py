"""The declarations of the heavy top's Datasets: the released gyroscopes and the sleeping tops,
registered from the family's ``DATASETS`` (:mod:`stability.registry`)."""

from ..ensemble.schema import (
    DEGREE, KG_M2, METRE, ONE, PER_SECOND, RADIAN, RAD_PER_S, SECOND, coordinate, declare,
    status_variable, variable,
)

__all__ = ["GYROSCOPE", "SLEEPING_TOP"]


# The gyroscope (stability.heavy_top.measure.measure_gyroscopes) ----------------------------------

_TSR = ("tilt", "spin", "release")
_PATH = ("release", "path_time")
GYROSCOPE = declare(
    "gyroscope",
    "the heavy symmetric top's precession and nutation measured against the "
    "exact motion and the fast-top formulas, per tilt, spin and release",
    "stability.heavy_top.measure.measure_gyroscopes",
    {
        "precession_rate_measured": variable(
            _TSR,
            RAD_PER_S,
            "mean precession rate of the figure axis, from the run (weighted mean of phi')",
        ),
        "precession_rate_exact": variable(
            _TSR, RAD_PER_S, "exact mean precession rate over a nutation period"
        ),
        "precession_rate_error": variable(
            _TSR, ONE, "(measured - exact) / exact mean precession rate"
        ),
        "precession_rate_gyroscopic": variable(
            "spin", RAD_PER_S, "fast-top precession rate M g l / (C w3)"
        ),
        "nutation_frequency_measured": variable(
            _TSR, RAD_PER_S, "nutation frequency 2 pi / T, from the run"
        ),
        "nutation_frequency_exact": variable(_TSR, RAD_PER_S, "exact nutation frequency 2 pi / T"),
        "nutation_frequency_error": variable(
            _TSR, ONE, "(measured - exact) / exact nutation frequency"
        ),
        "nutation_frequency_gyroscopic": variable(
            "spin", RAD_PER_S, "fast-top nutation frequency C w3 / A"
        ),
        "nutation_amplitude_measured": variable(
            _TSR, RADIAN, "nutation amplitude theta_max - theta_min, from the run"
        ),
        "nutation_amplitude_exact": variable(
            _TSR, RADIAN, "exact nutation amplitude (turning points of the cubic)"
        ),
        "nutation_amplitude_error": variable(
            _TSR, ONE, "(measured - exact) / exact nutation amplitude"
        ),
        "nutation_amplitude_gyroscopic": variable(
            _TSR,
            RADIAN,
            "fast-top nutation amplitude 2 |1 - release| A M g l sin(theta0) / (C w3)^2",
        ),
        "status": status_variable(_TSR),
        "step": variable(("tilt", "spin"), SECOND, "integration step h"),
        "t_end": variable(("tilt", "spin"), SECOND, "run time"),
        "path_theta": variable(_PATH, RADIAN, "tilt theta of the figure axis, from the run"),
        "path_phi": variable(
            _PATH, RADIAN, "precession angle phi of the figure axis, from the run"
        ),
        "path_theta_exact": variable(_PATH, RADIAN, "exact tilt theta of the figure axis"),
        "path_phi_exact": variable(_PATH, RADIAN, "exact precession angle phi of the figure axis"),
        "tilt": coordinate("tilt", DEGREE, "release tilt from the vertical"),
        "spin": coordinate("spin", RAD_PER_S, "spin w3 about the symmetry axis"),
        "release": coordinate(
            "release", ONE, "initial precession rate / (M g l / (C w3)) (0: released at rest)"
        ),
        "path_time": coordinate("path_time", SECOND, "time of the kept paths"),
    },
)

# The sleeping top (stability.heavy_top.measure.measure_sleeping_tops) ----------------------------

_LS = ("length", "spin")
SLEEPING_TOP = declare(
    "sleeping_top",
    "the growth rate of a sleeping top's tilt measured against linear theory, per length and spin",
    "stability.heavy_top.measure.measure_sleeping_tops",
    {
        "growth_rate_measured": variable(
            _LS, PER_SECOND, "measured growth rate of the tilt (0: bounded)"
        ),
        "growth_rate_stderr": variable(
            _LS, PER_SECOND, "standard error of the measured growth rate"
        ),
        "growth_rate_analytic": variable(
            _LS, PER_SECOND, "sqrt(4 A M g l - C^2 w3^2) / (2 A), 0 above w_c"
        ),
        "relative_error": variable(_LS, ONE, "(measured - analytic) / analytic growth rate"),
        "rate_fraction": variable(_LS, ONE, "analytic growth rate / its value at zero spin"),
        "tilt_amplification": variable(
            _LS, ONE, "largest sin(tilt) / initial sin(tilt) over members"
        ),
        "slow_frequency": variable(_LS, RAD_PER_S, "slow precession frequency of a stable tilt"),
        "fast_frequency": variable(_LS, RAD_PER_S, "fast (nutation) frequency of a stable tilt"),
        "step": variable(_LS, SECOND, "integration step h"),
        "t_end": variable(_LS, SECOND, "run time"),
        "n_fitted": variable(_LS, ONE, "members with a fitted growth rate", kind="i"),
        "members_failed": variable(_LS, ONE, "members whose status is not ok", kind="i"),
        "critical_spin": variable("length", RAD_PER_S, "critical spin 2 sqrt(A M g l) / C"),
        "mgl": variable("length", "N m", "M g l"),
        "pivot_moment_transverse": variable("length", KG_M2, "transverse moment about the pivot A"),
        "length": coordinate("length", METRE, "pivot to centre of mass"),
        "spin": coordinate("spin", RAD_PER_S, "spin about the symmetry axis"),
    },
)
