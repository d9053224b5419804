"""
A heavy top's nutation
======================

A spinning disk top released at rest at a tilt of 60 degrees nods between two tilts while it
precesses: the nutation. Its exact tilt (elliptic functions, ``stability.heavy_top.exact``) beside
the gyroscopic approximations: the slow precession rate m g l / (C w3) and the nutation
frequency C w3 / A.
"""

import matplotlib.pyplot as plt
import numpy as np

from stability.heavy_top.exact import cos_theta, nutation_period
from stability.heavy_top.model import (HeavyTop, gyroscopic_nutation_frequency,
                           gyroscopic_precession_rate, tilted_starts)

top = HeavyTop.disk(mass=0.1, radius=0.03, length=0.04)
spin = 150.0  # rad/s about the figure axis
x0 = tilted_starts(spin, np.radians(60.0), 1, top=top)
A, _, C = top.pivot_moments
t = np.linspace(0.0, 0.5, 2000)
tilt = np.degrees(np.arccos(cos_theta(t, x0[0], A, C, top.mgl)))
period = float(nutation_period(x0[0], A, C, top.mgl))
print(f"nutation period: exact {period * 1e3:.3f} ms, gyroscopic 2 pi A / (C w3) "
      f"{2 * np.pi / gyroscopic_nutation_frequency(top, spin) * 1e3:.3f} ms")
print(f"slow precession rate m g l / (C w3): {gyroscopic_precession_rate(top, spin):.4f} rad/s")

# %%
# The tilt of the figure axis against time: nutation between two tilts. Its lowest tilts come
# every exact period (dashed); the gyroscopic period (dotted) is shorter, and it drifts off.

gyro_period = 2 * np.pi / gyroscopic_nutation_frequency(top, spin)
fig, ax = plt.subplots(figsize=(7, 3.5), layout="constrained")
ax.plot(t * 1e3, tilt, label="exact tilt")
for k in range(1, int(t[-1] / period) + 1):
    ax.axvline(k * period * 1e3, color="k", ls="--", lw=0.7,
               label="exact nutation period" if k == 1 else None)
for k in range(1, int(t[-1] / gyro_period) + 1):
    ax.axvline(k * gyro_period * 1e3, color="C3", ls=":", lw=0.9,
               label="gyroscopic 2 pi A / (C w3)" if k == 1 else None)
ax.legend(loc="lower right", fontsize=8)
ax.set_xlabel("time (ms)")
ax.set_ylabel("tilt of the figure axis (degree)")
ax.set_title("a disk top released at 60 degrees: nutation between two tilts")
