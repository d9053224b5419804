"""Names, units and codes shared by every Dataset the package writes.

One place for the vocabulary: dimension names, the units of each variable and the per-member
status codes. Code elsewhere imports these constants instead of spelling the strings again.
"""

# Dimensions.
MEMBER = "member"
TIME = "time"
AXIS = "axis"
QUATERNION = "quaternion_component"

#: Coordinate values of the ``axis`` dimension: the principal axes 1, 2, 3.
AXES = (1, 2, 3)

# Units (UDUNITS spelling, as CF asks).
UNITS_ANGULAR_VELOCITY = "rad s-1"
UNITS_ANGULAR_MOMENTUM = "kg m2 s-1"
UNITS_MOMENT_OF_INERTIA = "kg m2"
UNITS_TIME = "s"
UNITS_ENERGY = "J"
UNITS_RATE = "s-1"
UNITS_RATE_SQUARED = "s-2"
UNITS_DIMENSIONLESS = "1"
UNITS_ANGLE = "rad"

# Per-member status codes (int8). A member whose status is not OK has its numbers masked.
STATUS_OK = 0
STATUS_NONFINITE = 1  #: the state became inf or NaN
STATUS_DIVERGED = 2  #: energy or |L| left the divergence tolerance (step too large)
STATUS_NOT_CONVERGED = 3  #: an implicit step's nonlinear solver did not converge
#: the step angle h max|w| exceeds what the method resolves (``MethodSpec.max_step_angle``):
#: the numbers may look sane (|L| and energy kept) but are not trustworthy
STATUS_STEP_TOO_LARGE = 4

STATUS_MEANINGS = "ok non_finite diverged not_converged step_too_large"
STATUS_FLAG_VALUES = (STATUS_OK, STATUS_NONFINITE, STATUS_DIVERGED, STATUS_NOT_CONVERGED,
                      STATUS_STEP_TOO_LARGE)
