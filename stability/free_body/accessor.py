"""The ``ds.stability`` accessor: the estimators as methods of an ensemble Dataset.

A thin, stateless namespace over :mod:`stability.analysis` and :mod:`.measure` (the xarray
"composition over inheritance" pattern): every method calls the plain function of the same name on
the Dataset and returns what it returns, so ``ds.stability.measured_growth_rate()`` is
``stability.measured_growth_rate(ds)``. Nothing is stored on the accessor; everything an estimator
needs lives in the Dataset's variables, coordinates and attributes. Registered when ``stability``
is imported.
"""

from __future__ import annotations

import xarray as xr

from ..analysis import estimates, regimes
from ..output import plain
from . import measure


@xr.register_dataset_accessor("stability")
class StabilityAccessor:
    """Estimators of one ensemble Dataset (time series or summaries only); see the functions."""

    def __init__(self, ds: xr.Dataset):
        self._ds = ds

    def member_regimes(self, **kwargs) -> xr.Dataset:
        """Per-member regime; see :func:`stability.analysis.regimes.member_regimes`."""
        return regimes.member_regimes(self._ds, **kwargs)

    def measured_growth_rate(self, **kwargs) -> xr.Dataset:
        """Growth rate on the linear phase; see
        :func:`stability.analysis.estimates.measured_growth_rate`."""
        return estimates.measured_growth_rate(self._ds, **kwargs)

    def measured_frequency(self, **kwargs) -> xr.Dataset:
        """Oscillation frequency; see :func:`stability.analysis.estimates.measured_frequency`."""
        return estimates.measured_frequency(self._ds, **kwargs)

    def measured_omega_squared(self, **kwargs) -> xr.Dataset:
        """Measured Omega^2 and regime; see
        :func:`stability.free_body.measure.measured_omega_squared`."""
        return measure.measured_omega_squared(self._ds, **kwargs)

    def flip_statistics(self, **kwargs) -> xr.Dataset:
        """First flip and flip interval; see :func:`stability.free_body.measure.flip_statistics`."""
        return measure.flip_statistics(self._ds, **kwargs)

    def in_seconds(self) -> xr.Dataset:
        """A file opened with plain ``xarray.open_dataset`` as :func:`stability.load` reads it:
        ``time`` in seconds since the start (CF units kept), series (member, time, axis); see
        :func:`stability.output.plain.in_seconds`."""
        return plain.in_seconds(self._ds)
