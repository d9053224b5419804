"""The dispersion study's Dataset: each member's draws and outputs, and the Sobol' indices."""

from ...ensemble.schema import (
    AXIS, KG_M2, MEMBER, ONE, PER_SECOND, RADIAN, RAD_PER_S, SECOND, member_coordinate,
    status_variable, variable
)
from ...uncertainty.schema import SENSITIVITY

_AXES_NOTE = "dispersions of the axes (axes)"
_RUN = "run"
_RUN_NOTE = "runs that integrate members ([integration] members > 0)"

DISPERSION = SENSITIVITY.extend(
    "dispersion", "a dispersed free body tossed about its middle axis: draws, outputs, indices",
    ("stability.free_body.dispersion.measure.dispersion_dataset",), "dispersion.nc", {
        MEMBER: member_coordinate("design point (member) of the Saltelli design"),
        "moments": variable((MEMBER, AXIS), KG_M2, "principal moments the member ran with "
                            "(column k nearest design axis k)"),
        "w0": variable((MEMBER, AXIS), RAD_PER_S, "initial angular velocity in the member's "
                       "principal axes"),
        "rate": variable(MEMBER, RAD_PER_S, "spin W about the middle axis, as drawn"),
        "epsilon": variable(MEMBER, ONE, "nudge across the middle axis relative to W, as drawn"),
        "direction": variable(MEMBER, RADIAN, "direction of the nudge across the middle axis"),
        "axes_angle": variable(MEMBER, RADIAN, "misalignment angle of the principal axes",
                               optional=_AXES_NOTE),
        "axes_axis": variable((MEMBER, "frame_axis"), ONE, "unit axis of the misalignment, "
                              "design frame", optional=_AXES_NOTE),
        "principal_axes": variable((MEMBER, "frame_axis", AXIS), ONE, "principal axes (columns) "
                                   "in the design frame", optional=_AXES_NOTE),
        "inertia_tensor": variable((MEMBER, "frame_axis", "frame_axis_2"), KG_M2,
                                   "dispersed inertia tensor R diag(I) R^T, design frame",
                                   optional=_AXES_NOTE),
        "flip_interval": variable(MEMBER, SECOND, "exact flip interval 2K/nu"),
        "growth_rate": variable(MEMBER, PER_SECOND, "linear growth rate about the middle axis, "
                                "sqrt(-Omega^2)"),
        "run_flip_interval": variable(_RUN, SECOND, "flip interval of the integrated motion "
                                      "(mean spacing of sign changes)", optional=_RUN_NOTE),
        "run_status": status_variable(_RUN, optional=_RUN_NOTE),
        "run_parameters": variable((_RUN, AXIS), KG_M2, "moments the run reports its member's "
                                   "group ran with", optional=_RUN_NOTE),
        "run_m_start": variable((_RUN, AXIS), "kg m2 s-1", "body angular momentum the run "
                                "reports its member started from", optional=_RUN_NOTE),
    })
