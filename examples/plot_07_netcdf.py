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
                            t_end=5.0, save_every=10, progress=False)
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
