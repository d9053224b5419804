"""
Which uncertainty dominates the racket's flip?
==============================================

The tennis racket tossed about its middle axis, uncertain in its moments (2 %), its spin (10 %)
and the size of its start's nudge (two decades): Sobol' indices of the exact flip interval
over a Saltelli design of 1536 members (:mod:`stability.uncertainty`).
"""

import matplotlib.pyplot as plt

import stability
from stability.free_body.dispersion.measure import closed_form, members, nominal
from stability.uncertainty.dispersions import dispersions
from stability.uncertainty.figures import indices_figure
from stability.uncertainty.sobol import sobol_design, sobol_indices

# %%
# The racket's moments, spin and nudge, each drawn over its range, and the exact flip interval
# of every member of a Saltelli design:

body = stability.RigidBody.preset("tennis_racket")
disp = dispersions({"moments": {"distribution": "uniform", "relative": 0.02},
                    "rate": {"distribution": "uniform", "relative": 0.1},
                    "epsilon": {"distribution": "log-uniform", "lower": 1e-4, "upper": 1e-2}},
                   nominal(body.moments, 10.0, 1e-3), truncate=True)
design = sobol_design(disp, 256, seed=1)
out = closed_form(members(disp, design.unit))
# %%
# Their total Sobol' indices: which uncertainty the flip interval and the growth rate follow.

ds = sobol_indices(design, {"flip_interval": (out["flip_interval"], "s", "flip interval 2K/nu"),
                            "growth_rate": (out["growth_rate"], "s-1", "growth rate")})
print(ds.total.sel(output="flip_interval").to_series().round(3))
fig = indices_figure(ds, fig=plt.figure())
ds
