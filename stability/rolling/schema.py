"""The declarations of the rolling and slipping study's Dataset, registered from the family's
``DATASETS`` (:mod:`stability.registry`)."""

from ..util import conventions as cv
from ..ensemble.schema import (
    DEGREE, MEMBER, METRE, METRE_PER_S, ONE, RAD_PER_S, RAD_PER_S2, SECOND, TIME, coordinate,
    declare, member_coordinate, status_variable, time_coordinate, variable,
)

__all__ = ["ROLLING"]


# Rolling and slipping (stability.rolling.measure.measure_incline and measure_launches) ----------

_CELL = ("shape", "angle", "mu_s")
_SAMR = _CELL + ("replica",)
ROLLING = declare(
    "rolling",
    "balls, cylinders and hoops on inclines (roll or slip, per shape, angle, "
    "friction and replica) and launched along a floor (per member), from the runs and by the "
    "formulas",
    ("stability.rolling.measure.measure_incline", "stability.rolling.measure.measure_launches"),
    {
        "slipped": variable(_SAMR, ONE, "slipped (friction did work) in the run", kind="i"),
        "rolls_formula": variable(
            _SAMR, ONE, "rolls: tan(theta) <= mu_s (1 + M R^2 / I), own mu_s and k", kind="i"
        ),
        "acceleration": variable(
            _SAMR, "m s-2", "acceleration along the incline, 2 x(T) / T^2 from the run"
        ),
        "acceleration_formula": variable(
            _SAMR,
            "m s-2",
            "g sin(theta) / (1 + k) rolling, g (sin(theta) - mu_k cos(theta)) slipping",
        ),
        "spin_rate": variable(_SAMR, RAD_PER_S2, "angular acceleration w(T) / T from the run"),
        "spin_rate_formula": variable(
            _SAMR, RAD_PER_S2, "a / R rolling, mu_k M g R cos(theta) / I slipping"
        ),
        "member_mu_s": variable(_SAMR, ONE, "member's static friction coefficient"),
        "member_k": variable(_SAMR, ONE, "member's I / (M R^2)"),
        "slip_fraction": variable(_CELL, ONE, "fraction of the cell's members that slipped"),
        "rolls_nominal": variable(
            _CELL, ONE, "rolls by the formula at the cell's nominal mu_s and shape", kind="i"
        ),
        "scatter_straddles": variable(
            _CELL, ONE, "the cell's scatter spans the rolling boundary", kind="i"
        ),
        "wrong_side": variable(
            _CELL,
            ONE,
            "cell's majority regime against the formula, scatter not spanning the boundary",
            kind="i",
        ),
        "boundary_mu_s": variable(
            ("shape", "angle"), ONE, "mu_s on the boundary, tan(theta) / (1 + M R^2 / I)"
        ),
        "incline_status": status_variable(_SAMR, "member status (inclines)"),
        "shape": coordinate("shape", ONE, "shape", kind="U"),
        "shape_factor": coordinate("shape", ONE, "nominal I / (M R^2)"),
        "angle": coordinate("angle", DEGREE, "incline angle theta"),
        "mu_s": coordinate("mu_s", ONE, "nominal static friction coefficient"),
        "replica": member_coordinate("member of the cell (own mu_s, mu_k and shape)", "replica"),
        "v0": variable(MEMBER, METRE_PER_S, "launch speed"),
        "w0": variable(MEMBER, RAD_PER_S, "launch spin (negative: backspin)"),
        "spin_ratio": variable(MEMBER, ONE, "R w0 / v0 (1: launched rolling)"),
        "mu_k": variable(MEMBER, ONE, "kinetic friction coefficient"),
        "t_roll": variable(MEMBER, SECOND, "time pure rolling starts, from the run"),
        "t_roll_formula": variable(MEMBER, SECOND, "|v0 - R w0| / (mu_k g (1 + M R^2 / I))"),
        "x_roll": variable(MEMBER, METRE, "distance to pure rolling, from the run"),
        "x_roll_formula": variable(MEMBER, METRE, "v0 t - sign(u0) mu_k g t^2 / 2 at t = t_roll"),
        "v_final": variable(MEMBER, METRE_PER_S, "speed at the end, from the run"),
        "v_final_formula": variable(MEMBER, METRE_PER_S, "(v0 + k R w0) / (1 + k)"),
        "heat": variable(MEMBER, cv.UNITS_ENERGY, "work done by kinetic friction, from the run"),
        "energy_lost": variable(MEMBER, cv.UNITS_ENERGY, "kinetic energy lost, from the run"),
        "energy_lost_formula": variable(MEMBER, cv.UNITS_ENERGY, "M (v0 - R w0)^2 k / (2 (1 + k))"),
        "switches": variable(MEMBER, ONE, "switches of regime in the run", kind="i"),
        "launch_status": status_variable(MEMBER, "member status (launches)"),
        "path_v": variable(("path", TIME), METRE_PER_S, "speed of the centre v (kept members)"),
        "path_rw": variable(
            ("path", TIME), METRE_PER_S, "R w, the speed rolling would need (kept members)"
        ),
        "path_member": variable("path", ONE, "member of each kept path", kind="i"),
        MEMBER: member_coordinate("member"),
        TIME: time_coordinate("time"),
    },
)
