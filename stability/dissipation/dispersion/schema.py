"""The dispersed Explorer's Dataset: each member's draws and outputs, and the analysis."""

from ...ensemble.schema import (
    AXIS, DEGREE, KG_M2, MEMBER, METRE, PER_SECOND, RAD_PER_S, SECOND, member_coordinate,
    status_variable, variable
)
from ...uncertainty.schema import SENSITIVITY

_RUN = "run"
_RUN_NOTE = "runs that integrate members ([integration] members > 0)"

EXPLORER_DISPERSION = SENSITIVITY.extend(
    "explorer_dispersion", "a dispersed Explorer-like body with a spherical damper spun about "
    "its minor axis: draws, growth rates and times to the flat spin, and their analysis",
    ("stability.dissipation.dispersion.measure.dispersion_dataset",),
    "explorer_dispersion.nc", {
        MEMBER: member_coordinate("design point (member) of the design"),
        "length": variable(MEMBER, METRE, "length of the cylinder, as drawn"),
        "diameter": variable(MEMBER, METRE, "diameter of the cylinder, as drawn"),
        "mass": variable(MEMBER, "kg", "mass of the cylinder, as drawn"),
        "spin": variable(MEMBER, RAD_PER_S, "spin W about the long axis the member ran with"),
        "inertia": variable(MEMBER, KG_M2, "moment of inertia J of the damper's sphere"),
        "damping": variable(MEMBER, "N m s", "viscous coefficient c of the damper"),
        "angle": variable(MEMBER, DEGREE, "initial nutation angle, as drawn"),
        "moments": variable((MEMBER, AXIS), KG_M2, "principal moments of the shell (I_s, I_t, "
                            "I_t), the long axis first"),
        "growth_rate": variable(MEMBER, PER_SECOND, "growth rate of the nutation by the linear "
                                "eigenvalue"),
        "flat_time": variable(MEMBER, SECOND, "time to the flat spin at the linear growth rate, "
                              "tan(theta) = tan(theta0) exp(rate t)"),
        "run_growth_rate": variable(_RUN, PER_SECOND, "growth rate of the nutation angle fitted "
                                    "in the linear regime of the integrated motion",
                                    optional=_RUN_NOTE),
        "run_flat_time": variable(_RUN, SECOND, "time the integrated nutation angle passes the "
                                  "flat-spin angle", optional=_RUN_NOTE),
        "run_start_angle": variable(_RUN, DEGREE, "nutation angle of the state the run started "
                                    "from", optional=_RUN_NOTE),
        "run_status": status_variable(_RUN, optional=_RUN_NOTE),
    })
