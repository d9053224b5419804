"""The declarations of the Earth's Datasets: the free wobble and the precession of the equinoxes,
registered from the family's ``DATASETS`` (:mod:`stability.registry`)."""

from ..ensemble.schema import (
    ARCSEC, ARCSEC_PER_YEAR, AXIS, DAY, DEGREE, MEMBER, ONE, RAD_PER_S, YEAR, coordinate, declare,
    member_coordinate, variable,
)

__all__ = ["EARTH_WOBBLE", "EQUINOXES"]


# The Earth's free wobble (stability.earth.wobble.measure_free_wobble) -------------------------

_CONE_TIME = "cone_time"
EARTH_WOBBLE = declare(
    "earth_wobble",
    "the free wobble of a rigid Earth: its period measured against Euler's, and one member's cones",
    "stability.earth.wobble.measure_free_wobble",
    {
        "wobble_period_measured": variable(
            (),
            DAY,
            "period of the rotation axis about the figure axis (body frame), mean over members",
        ),
        "wobble_period_stderr": variable((), DAY, "standard error of the measured period"),
        "member_wobble_period": variable(MEMBER, DAY, "measured wobble period of each member"),
        "wobble_period_euler": variable(
            (), DAY, "Euler period 2 pi / (W sqrt((C - A)(C - B) / (A B)))"
        ),
        "wobble_period_oblate": variable(
            (), DAY, "A / (C - A) turns, A the mean equatorial moment"
        ),
        "relative_error": variable((), ONE, "(measured - Euler) / Euler period"),
        "w_body": variable(
            (_CONE_TIME, AXIS), RAD_PER_S, "angular velocity in the body frame (cone member)"
        ),
        "w_space": variable(
            (_CONE_TIME, AXIS), RAD_PER_S, "angular velocity in space (cone member)"
        ),
        "body_cone_angle": variable(
            _CONE_TIME, ARCSEC, "angle of the rotation axis from the figure axis"
        ),
        "space_cone_angle": variable(
            _CONE_TIME, ARCSEC, "angle of the rotation axis from the angular momentum"
        ),
        "figure_axis_angle": variable(
            _CONE_TIME, ARCSEC, "angle of the figure axis from the angular momentum"
        ),
        MEMBER: member_coordinate(),
        _CONE_TIME: coordinate(_CONE_TIME, DAY, "time"),
        AXIS: coordinate(AXIS, ONE, "principal axis", kind="i"),
    },
)

# The precession of the equinoxes (stability.earth.precession.measure_equinoxes) ----------------

_MTM = ("model", "torque", MEMBER)
_CYCLE = "a long run (cycle_years above 0; not in quick mode)"
EQUINOXES = declare(
    "equinoxes",
    "the precession and nutation of the Earth's axis under the Sun and the "
    "Moon, full and orbit-averaged, per torque and member",
    "stability.earth.precession.measure_equinoxes",
    {
        "precession_rate": variable(
            _MTM, ARCSEC_PER_YEAR, "precession of the equinox -dphi/dt, fitted"
        ),
        "nutation_longitude": variable(
            _MTM, ARCSEC, "amplitude of the 18.6-year nutation in longitude"
        ),
        "nutation_obliquity": variable(
            _MTM, ARCSEC, "amplitude of the 18.6-year nutation in obliquity"
        ),
        "obliquity_rate": variable(_MTM, ARCSEC_PER_YEAR, "secular rate of the obliquity, fitted"),
        "fit_residual": variable(_MTM, ARCSEC, "rms residual of the longitude fit"),
        "precession_rate_formula": variable(
            "torque",
            ARCSEC_PER_YEAR,
            "averaged formula (3/2) H cos(eps) / W G M / (a^3 (1 - e^2)^(3/2)) f",
        ),
        "step_error": variable(
            MEMBER,
            ARCSEC_PER_YEAR,
            "estimated integration error of the precession rate (Richardson, steps halved)",
        ),
        "longitude": variable(
            ("torque", "full_time"),
            ARCSEC,
            "longitude of the equinox phi - phi(0), member 0, full model",
        ),
        "obliquity": variable(("torque", "full_time"), ARCSEC, "obliquity, member 0, full model"),
        "longitude_averaged": variable(
            ("torque", "averaged_time"),
            ARCSEC,
            "longitude of the equinox phi - phi(0), member 0, averaged model",
        ),
        "obliquity_averaged": variable(
            ("torque", "averaged_time"), ARCSEC, "obliquity, member 0, averaged model"
        ),
        "cycle_longitude": variable(
            "cycle_time", DEGREE, "longitude of the equinox phi - phi(0), long run", optional=_CYCLE
        ),
        "cycle_obliquity": variable("cycle_time", DEGREE, "obliquity, long run", optional=_CYCLE),
        "model": coordinate("model", ONE, "full (spin, orbits) or orbit-averaged model", kind="U"),
        "torque": coordinate("torque", ONE, "bodies whose torque acts", kind="U"),
        MEMBER: member_coordinate("member (0: J2000 phases)"),
        # Julian years, which CF's time units (s, d ... since a date) cannot hold exactly and
        # xarray cannot decode: plain coordinates, none named "time" (CF's time axis name).
        "full_time": coordinate("full_time", YEAR, "time since J2000, full model"),
        "averaged_time": coordinate("averaged_time", YEAR, "time since J2000, averaged model"),
        "cycle_time": coordinate(
            "cycle_time", YEAR, "time since J2000, averaged model's long run", optional=_CYCLE
        ),
    },
)
