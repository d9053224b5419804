"""
Saving and loading with netCDF
==============================

An ensemble Dataset is saved as netCDF4 (compressed, written to a temporary file and renamed)
and read back unchanged: values, units, long names and the provenance attributes, including the
whole configuration as TOML.
"""

import tempfile
from pathlib import Path

import xarray as xr

import stability

body = stability.RigidBody(1.0, 2.0, 3.0)
ds = stability.run_ensemble(body, axis=2, spin=1.0, epsilon=1e-3, members=50, h=0.01,
                            t_end=5.0, keep=stability.Keep(save_every=10),
                            options=stability.RunOptions(progress=False))
path = Path(tempfile.mkdtemp()) / "ensemble.nc"
stability.save(ds, path)
back = stability.load(path)

# %%
# What came back: the same numbers (checked below), each variable's units and long name, the
# history and the configuration that made the run.

xr.testing.assert_identical(ds, back)
print(back.w.attrs)
print(back.attrs["history"])
print(back.attrs["config_toml"][:200])

# %%
# The same file opened with plain xarray, as any netCDF tool opens it. CF time units count from
# a date and a run has none, so ``time`` holds seconds from the nominal 1970-01-01: with its
# defaults xarray shows them as dates in 1970, and each series in the order the file holds it,
# (member, axis, time). ``decode_times=False`` keeps the seconds; ``ds.stability.in_seconds()``
# turns a file opened with the defaults into what ``stability.load`` reads (seconds, the
# package's order, the CF attributes kept).

plain = xr.open_dataset(path)
print(plain.time.values[:2], plain.w.dims)  # dates in 1970, (member, axis, time)
seconds = plain.stability.in_seconds()
print(seconds.time.values[:2], seconds.w.dims)  # [0. 0.1] s, (member, time, axis)
xr.testing.assert_identical(seconds.load(), back)
print(xr.open_dataset(path, decode_times=False).time.values[:2])  # the seconds as stored
plain.close()
