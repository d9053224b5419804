"""Names, units and codes shared by every Dataset the package writes.

One place for the vocabulary: dimension names, the units of each variable, the per-member
status codes and the CF attributes of the coordinates CF names (time, ensemble member). Code
elsewhere imports these constants instead of spelling the strings again.
"""

# Dimensions.
MEMBER = "member"
TIME = "time"
#: Dimension of the members whose time series a measured ensemble keeps (its series sample).
SERIES_MEMBER = "series_member"
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
#: an adaptive member needed more than its run's ``max_steps`` steps (accepted and rejected)
STATUS_MAX_STEPS = 5
#: an adaptive member's step fell below round-off in t
STATUS_STEP_TOO_SMALL = 6

STATUS_MEANINGS = "ok non_finite diverged not_converged step_too_large"
STATUS_FLAG_VALUES = (STATUS_OK, STATUS_NONFINITE, STATUS_DIVERGED, STATUS_NOT_CONVERGED,
                      STATUS_STEP_TOO_LARGE)

# Regime codes (int8) of a member's or an ensemble's motion (stability.analysis.regimes).
REGIME_UNDETERMINED = 0  #: mixed members, too few points, or a departure fitting neither model
REGIME_NEUTRAL = 1  #: no crossing and no departure within the run
REGIME_OSCILLATION = 2  #: stable: bounded oscillation, Omega^2 > 0
REGIME_EXPONENTIAL = 3  #: unstable: exponential growth, Omega^2 < 0
REGIME_ALGEBRAIC = 4  #: neutral in linear theory (Omega^2 = 0): departure linear in t
REGIME_MEANINGS = "undetermined neutral oscillation exponential_growth algebraic_drift"
REGIME_FLAG_VALUES = (0, 1, 2, 3, 4)

# Edge flags (int8 bit mask) of a shape of the triangle of shapes
# (stability.free_body.stability_map.shapes).
EDGE_EQUAL_12 = 1  #: I1 = I2: oblate symmetric body (the sphere has both equalities)
EDGE_EQUAL_23 = 2  #: I2 = I3: prolate symmetric body
EDGE_FLAT = 4  #: I1 + I2 = I3: flat body (all mass in a plane)
EDGE_MEANINGS = "equal_I1_I2 equal_I2_I3 flat"
EDGE_FLAG_MASKS = (EDGE_EQUAL_12, EDGE_EQUAL_23, EDGE_FLAT)

# CF. Every Dataset the package writes passes the CF checker (``compliance-checker --test
# cf:1.10``); the tests run it on every study's file.

#: The ``Conventions`` global attribute.
CONVENTIONS = "CF-1.10"

#: The date CF time coordinates count from. CF time units need one ("s since <date>"); a run
#: has no date, so its start is put at this nominal one. xarray then decodes such a coordinate
#: to dates unless the file is opened with ``decode_times=False``, as ``stability.load`` does.
TIME_ORIGIN = "1970-01-01 00:00:00"

#: Units of the :data:`TIME` coordinate: seconds from :data:`TIME_ORIGIN`.
UNITS_TIME_COORDINATE = f"{UNITS_TIME} since {TIME_ORIGIN}"

#: CF attributes of the coordinates CF has a standard name for, besides long name and units.
STANDARD_COORDINATES = {
    MEMBER: {"standard_name": "realization"},
    TIME: {"standard_name": "time", "axis": "T"},
}


def time_attrs(long_name: str = "time since the start") -> dict:
    """Attributes of a Dataset's :data:`TIME` coordinate, its time axis: ``long_name``, units
    :data:`UNITS_TIME_COORDINATE`, ``standard_name = "time"`` and ``axis = "T"``.

    Other time-valued coordinates (the sample times of a few kept paths, say) stay plain ones
    with a long name and units: as CF time axes they would break CF's recommended dimension
    order wherever a vector's components follow them.
    """
    return {"long_name": long_name, "units": UNITS_TIME_COORDINATE, **STANDARD_COORDINATES[TIME]}


def member_attrs(long_name: str = "ensemble member") -> dict:
    """Attributes of an ensemble-member coordinate: ``long_name``, ``units = "1"`` and
    ``standard_name = "realization"`` (whose canonical units CF gives as 1)."""
    return {"long_name": long_name, "units": UNITS_DIMENSIONLESS,
            **STANDARD_COORDINATES[MEMBER]}


def perpendicular_axes(axis: int) -> tuple[int, int]:
    """The two principal axes (1-based, ascending) perpendicular to ``axis``.

    Parameters
    ----------
    axis : int
        An axis label, 1, 2 or 3.

    Returns
    -------
    tuple of int
        The other two labels, ascending.
    """
    b, c = (a for a in (1, 2, 3) if a != axis)
    return b, c
