"""The Dataset of a tangent run (:func:`stability.tangents.ftle.run_tangents`), declared as
every Dataset of the package is (:mod:`stability.ensemble.schema`) and added to the register by
:mod:`stability.registry`."""

from __future__ import annotations

from ..ensemble.schema import (MEMBER, ONE, PER_SECOND, TIME, coordinate, declare,
                               member_coordinate, status_variable, time_coordinate, variable)

#: The dimension of the tangent vectors.
TANGENT = "tangent"

SEVERAL = "runs with more than one tangent vector"
MATRIX = "runs carrying the whole state-transition matrix (as many tangents as components)"

TANGENTS = declare("tangents", "finite-time Lyapunov exponents of each member, from its "
                   "tangent vectors renormalised at fixed intervals",
                   "stability.tangents.ftle.run_tangents", {
    MEMBER: member_coordinate(),
    TIME: time_coordinate("end of the renormalisation window"),
    TANGENT: coordinate(TANGENT, ONE, "tangent vector (1: the leading one)", kind="i"),
    "group": variable(MEMBER, ONE, "parameter set of the member (numbered from 0)", kind="i"),
    "status": status_variable(MEMBER, comment=(
        "ok: the member's state and tangents stayed finite; the numbers of members whose "
        "status is not ok are NaN")),
    "ftle": variable(MEMBER, PER_SECOND, "finite-time Lyapunov exponent of the leading "
                     "tangent over the run, log(|v(T)| / |v(0)|) / T"),
    "ftle_running": variable((MEMBER, TIME), PER_SECOND, "finite-time Lyapunov exponent of the "
                             "leading tangent from the start to the time"),
    "window_rate": variable((MEMBER, TIME), PER_SECOND, "growth rate of the leading tangent "
                            "over the window ending at the time, log(|v(t)| / |v(t - dt)|) / "
                            "dt"),
    "growth_rate": variable((MEMBER, TIME), PER_SECOND, "instantaneous growth rate of the "
                            "leading tangent at the time, v . J v / |v|^2"),
    "exponents": variable((MEMBER, TANGENT), PER_SECOND, "finite-time Lyapunov exponents of "
                          "the tangents over the run (Gram-Schmidt renormalisation)",
                          optional=SEVERAL),
    "stm_log_singular_value": variable(MEMBER, ONE, "natural logarithm of the largest singular "
                                       "value of the state-transition matrix over the run",
                                       optional=MATRIX),
}, file="")
