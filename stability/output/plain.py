"""A file opened with plain xarray, made what :func:`stability.load` gives: :func:`in_seconds`.

``xarray.open_dataset`` with its defaults decodes a CF time coordinate to dates from its
origin (``time`` counts seconds from the nominal ``1970-01-01 00:00:00``,
:data:`stability.util.conventions.TIME_ORIGIN`, since a run has no date) and shows each series
in the order the file holds it, (member, axis, time). ``ds.stability.in_seconds()`` turns the
dates back into the seconds since the start, with their CF attributes, and puts the series
back in the package's order (:func:`stability.ensemble.schema.held_order`).
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from ..ensemble.schema import held_order
from .io import READ


def in_seconds(ds: xr.Dataset) -> xr.Dataset:
    """``ds`` with its decoded time coordinates as seconds since their origin, CF ``units``
    (and ``calendar``) attributes back on them, and its variables in the package's order.

    Parameters
    ----------
    ds : xarray.Dataset
        As ``xarray.open_dataset`` opened a file the package wrote (lazy arrays stay lazy);
        a Dataset whose times are numbers already is only reordered.

    Returns
    -------
    xarray.Dataset
        What :func:`stability.load` reads from the same file.
    """
    changes = {}
    stored = _as_stored(ds)
    for name, variable in ds.variables.items():
        units = variable.encoding.get("units", "")
        if variable.dtype.kind != "M" or " since " not in units:
            continue
        step, origin = units.split(" since ", 1)
        if step.strip() not in ("s", "second", "seconds"):
            raise ValueError(f"{name}: time units {units!r}; in_seconds reads times the package "
                             "writes, in seconds since an origin")
        if name in stored:  # the numbers in the file, bit for bit
            seconds = stored[name]
        else:  # from the dates, to their nanosecond
            seconds = (variable.values - np.datetime64(origin.strip().replace(" ", "T"), "ns")
                       ) / np.timedelta64(1, "s")
        attrs = {**variable.attrs, "units": units}
        if "calendar" in variable.encoding:
            attrs["calendar"] = variable.encoding["calendar"]
        changes[name] = xr.Variable(variable.dims, seconds, attrs)
    return held_order(ds.assign_coords(changes) if changes else ds)


def _as_stored(ds: xr.Dataset) -> dict:
    """The time coordinates of the file ``ds`` was opened from, as numbers; empty for a
    Dataset made in memory or a file no longer there."""
    source = ds.encoding.get("source")
    names = [n for n, v in ds.variables.items() if v.dtype.kind == "M"]
    if not source or not names:
        return {}
    try:
        with xr.open_dataset(source, **READ) as raw:
            return {n: raw[n].values for n in names if n in raw.variables}
    except (OSError, ValueError):
        return {}


__all__ = ["in_seconds"]
