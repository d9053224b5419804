"""The ds.stability accessor returns exactly what the plain estimator functions return."""

import numpy as np
import pytest
import xarray as xr

import stability
from stability.analysis.estimates import measured_growth_rate
from stability.free_body.accessor import StabilityAccessor

from ..helpers import (
    oscillation,
    separatrix,
    series_dataset,
    summaries_from_separatrix,
)

#: Methods of the accessor that read a file back rather than estimate
#: (tests/output/test_plain.py holds them).
READERS = {"in_seconds"}
#: Every estimator of the accessor.
NAMES = [name for name in vars(StabilityAccessor)
         if not name.startswith("_") and name not in READERS]


def datasets():
    t, w, _, _ = separatrix(6)
    yield series_dataset(w, t, axis=2)
    t, w = oscillation(5, omega=0.8)
    yield series_dataset(w, t, axis=3)
    yield summaries_from_separatrix(7, np.logspace(-7, -1, 25))


def test_every_accessor_method_is_an_estimator_of_the_package():
    assert NAMES and all(name in stability.__all__ for name in NAMES)


@pytest.mark.parametrize("name", NAMES)
def test_accessor_matches_function(name):
    for ds in datasets():
        xr.testing.assert_identical(getattr(ds.stability, name)(), getattr(stability, name)(ds))


def test_accessor_passes_arguments_through():
    t, w, _, _ = separatrix(4)
    ds = series_dataset(w, t, axis=2)
    via_accessor = ds.stability.measured_growth_rate(high_fraction=0.5, low_factor=10.0)
    direct = measured_growth_rate(ds, high_fraction=0.5, low_factor=10.0)
    xr.testing.assert_identical(via_accessor, direct)
    # the arguments change the result, so an accessor that dropped them would differ
    assert not via_accessor.identical(ds.stability.measured_growth_rate())
    # the package exports the same function at the top level
    assert stability.measured_growth_rate is measured_growth_rate
    # numbers held in 0-d arrays and scalar DataArrays (another estimate's result) are numbers
    xr.testing.assert_identical(
        ds.stability.measured_growth_rate(high_fraction=np.array(0.5),
                                          low_factor=xr.DataArray(10.0)), direct)
    xr.testing.assert_identical(
        ds.stability.measured_omega_squared(analytic=xr.DataArray(-0.3), axis=np.array(2)),
        ds.stability.measured_omega_squared(analytic=-0.3, axis=2))


def test_accessor_is_stateless():
    # A new Dataset made from an old one (a member subset) gets a fresh accessor whose answer
    # depends on the new data only.
    t, w, _, _ = separatrix(6)
    ds = series_dataset(w, t, axis=2)
    first = ds.stability.member_regimes()
    sub = ds.isel(member=slice(0, 3))
    xr.testing.assert_identical(sub.stability.member_regimes(), first.isel(member=slice(0, 3)))
