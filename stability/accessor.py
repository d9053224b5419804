"""The ``ds.stability`` accessor: the estimators as methods of an ensemble Dataset.

A thin, stateless namespace over :mod:`stability.estimators` (the xarray "composition over
inheritance" pattern): every method calls the plain function of the same name on the Dataset and
returns what it returns, so ``ds.stability.measured_growth_rate()`` is
``stability.measured_growth_rate(ds)``. Nothing is stored on the accessor; everything an estimator
needs lives in the Dataset's variables, coordinates and attributes. Registered when ``stability``
is imported.
"""

from __future__ import annotations

import xarray as xr

from . import estimators


@xr.register_dataset_accessor("stability")
class StabilityAccessor:
    """Estimators of one ensemble Dataset (time series or summaries only); see the functions."""

    def __init__(self, ds: xr.Dataset):
        self._ds = ds

    def member_regimes(self, **kwargs) -> xr.Dataset:
        """Per-member regime; see :func:`stability.estimators.member_regimes`."""
        return estimators.member_regimes(self._ds, **kwargs)

    def measured_growth_rate(self, **kwargs) -> xr.Dataset:
        """Growth rate on the linear phase; :func:`stability.estimators.measured_growth_rate`."""
        return estimators.measured_growth_rate(self._ds, **kwargs)

    def measured_frequency(self, **kwargs) -> xr.Dataset:
        """Oscillation frequency; see :func:`stability.estimators.measured_frequency`."""
        return estimators.measured_frequency(self._ds, **kwargs)

    def measured_omega_squared(self, **kwargs) -> xr.Dataset:
        """Measured Omega^2 and regime; see :func:`stability.estimators.measured_omega_squared`."""
        return estimators.measured_omega_squared(self._ds, **kwargs)

    def flip_statistics(self, **kwargs) -> xr.Dataset:
        """First flip and flip interval; see :func:`stability.estimators.flip_statistics`."""
        return estimators.flip_statistics(self._ds, **kwargs)
