"""
A stability map in a few lines of xarray
========================================

The sign of Omega^2 for spin about each axis of bodies across the triangle of shapes: only the
middle axis is unstable. Small ensembles per shape, run together with ``run_ensembles`` so both
cores are busy, and their measured Omega^2 against the formula.
"""

import matplotlib.pyplot as plt
import numpy as np
import xarray as xr

import stability

ratios = np.linspace(1.2, 3.0, 7)  # I3 / I1 with I2 halfway: (1, (1 + r) / 2, r)
calls = [dict(body=stability.RigidBody(1.0, (1.0 + r) / 2, r), axis=axis, spin=1.0,
              epsilon=1e-4, members=16, h=0.01, t_end=30.0, keep=stability.Keep(save_every=0),
              seed=3)
         for r in ratios for axis in (1, 2, 3)]
runs = stability.run_ensembles(calls)
measured = xr.DataArray(
    np.array([float(ds.stability.measured_omega_squared(low_factor=10.0, high_fraction=0.03)
                    .omega_squared_measured) for ds in runs]).reshape(ratios.size, 3),
    dims=("ratio", "axis"), coords={"ratio": ratios, "axis": [1, 2, 3]},
    attrs={"long_name": "measured Omega^2", "units": "s-2"})
analytic = xr.DataArray(
    [[stability.omega_squared(c["body"], c["axis"], 1.0) for c in calls[3 * i:3 * i + 3]]
     for i in range(ratios.size)], dims=measured.dims, coords=measured.coords)
print((measured / analytic).round(3).to_pandas())

# %%
# Measured against analytic Omega^2 across the shapes. Near I3/I1 = 1 the moments are close and
# Omega^2 is small: 30 s hold less than one oscillation or e-folding, too little to measure,
# and those points are missing (NaN in the table above).

fig, ax = plt.subplots(figsize=(7, 3.5), layout="constrained")
for axis in (1, 2, 3):
    (line,) = ax.plot(ratios, analytic.sel(axis=axis), "-", label=f"axis {axis}: formula")
    ax.plot(ratios, measured.sel(axis=axis), "o", color=line.get_color())
ax.plot([], [], "o", color="0.4", label="measured (its axis's colour)")
ax.set_title("Omega^2 about each axis: negative (unstable) for the middle one only")
ax.axhline(0.0, color="black", lw=0.8)
ax.set_xlabel("I3 / I1 (1)")
ax.set_ylabel("Omega^2 (s-2)")
ax.legend()
