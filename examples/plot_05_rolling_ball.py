"""
A rolling ball
==============

Billiard balls launched sliding, with top- or backspin: kinetic friction works on the slip
v - R w until it vanishes, after which the ball rolls. The time to rolling, the distance and the
final speed 5/7 v0 + 2/7 R w0 from the runs (scene ``rolling_body``, events found inside the
step) against the formulas.
"""

import matplotlib.pyplot as plt
import numpy as np

import stability
from stability.rolling.measure import measure_launches
from stability.rolling.model import launch_formulas

ds = measure_launches(radius=0.0286, mass=0.17, k=0.4, mu_k=0.2, speeds=(0.5, 4.0),
                      spin_ratios=(-1.5, 2.5), members=200,
                      options=stability.RunOptions(progress=False))
formula = launch_formulas(ds.v0.values, ds.w0.values, 0.4, 0.0286, ds.mu_k.values, 0.17)
for name in ("t_roll", "x_roll", "v_final"):
    error = np.max(np.abs(ds[name].values / formula[name] - 1.0))
    print(f"{name}: worst relative error against the formula {error:.1e}")

# %%
# The final speed of each ball against its spin ratio, beside the formula.

fig, ax = plt.subplots(figsize=(7, 3.5), layout="constrained")
ax.plot(ds.spin_ratio, ds.v_final / ds.v0, ".", label="runs")
ratio = np.linspace(-1.5, 2.5, 50)
ax.plot(ratio, (5 + 2 * ratio) / 7, "--", label="5/7 + 2/7 R w0 / v0")
ax.set_xlabel("R w0 / v0 (1)")
ax.set_ylabel("final speed / launch speed (1)")
ax.legend()
