"""The names, units and codes every Dataset of the package shares (stability.util.conventions):
each unit is one UDUNITS reads (cf_units, as the CF checker does), the time coordinate's units
are a time reference, the coordinates' standard names are CF's, and each set of codes is
distinct and has one meaning per value."""

import cf_units
import pytest

from stability.util import conventions as cv

UNITS = [getattr(cv, name) for name in dir(cv) if name.startswith("UNITS_")]


@pytest.mark.parametrize("units", UNITS)
def test_every_unit_is_udunits(units):
    cf_units.Unit(units)  # raises on a string UDUNITS cannot read


def test_the_time_axis_and_the_members_are_cf_coordinates():
    time = cf_units.Unit(cv.UNITS_TIME_COORDINATE)
    assert time.is_time_reference() and time.origin == cv.UNITS_TIME_COORDINATE
    attrs = cv.time_attrs("time since release")
    assert attrs == {"long_name": "time since release", "units": cv.UNITS_TIME_COORDINATE,
                     "standard_name": "time", "axis": "T"}
    member = cv.member_attrs()
    assert member["standard_name"] == "realization" and member["units"] == "1"
    assert cv.CONVENTIONS == "CF-1.10"


def test_each_set_of_codes_is_distinct_with_one_meaning_per_value():
    for values, meanings in ((cv.STATUS_FLAG_VALUES, cv.STATUS_MEANINGS),
                             (cv.REGIME_FLAG_VALUES, cv.REGIME_MEANINGS),
                             (cv.EDGE_FLAG_MASKS, cv.EDGE_MEANINGS)):
        assert len(set(values)) == len(values) == len(meanings.split())
    statuses = [cv.STATUS_OK, cv.STATUS_NONFINITE, cv.STATUS_DIVERGED, cv.STATUS_NOT_CONVERGED,
                cv.STATUS_STEP_TOO_LARGE, cv.STATUS_MAX_STEPS, cv.STATUS_STEP_TOO_SMALL]
    assert len(set(statuses)) == len(statuses) and cv.STATUS_OK == 0
    masks = cv.EDGE_FLAG_MASKS
    assert all(a & b == 0 for i, a in enumerate(masks) for b in masks[i + 1:])  # bits apart


def test_the_axes_perpendicular_to_each_axis():
    assert [cv.perpendicular_axes(a) for a in cv.AXES] == [(2, 3), (1, 3), (1, 2)]
