"""
Growth against Omega^2
======================

Linearising Euler's equations about a steady spin W about axis 3 gives
w1'' = -Omega^2 w1 with Omega^2 = (I3 - I1)(I3 - I2) W^2 / (I1 I2). About the middle axis
Omega^2 < 0 and a nudge grows like exp(sqrt(-Omega^2) t): measured here from an ensemble's
linear phase and compared with the formula.
"""

import matplotlib.pyplot as plt
import numpy as np

import stability

body = stability.RigidBody(1.0, 2.0, 3.0)
ds = stability.run_ensemble(body, axis=2, spin=1.0, epsilon=1e-6, members=100, h=0.01,
                            t_end=20.0, keep=stability.Keep(save_every=10), method="rk4", seed=2,
                            options=stability.RunOptions(progress=False))
measured = ds.stability.measured_growth_rate(low_factor=10.0, high_fraction=0.03)
analytic = stability.growth_rate(body, axis=2, spin=1.0)
print(f"Omega^2 = {stability.omega_squared(body, 2, 1.0):+.4f} s-2")
print(f"growth rate: measured {float(measured.growth_rate):.6f}, analytic {analytic:.6f} 1/s")

amplitude = np.hypot(ds.w.sel(axis=1), ds.w.sel(axis=3)).median("member")
# %%
# The median perpendicular amplitude against time, beside the analytic slope.

fig, ax = plt.subplots(figsize=(7, 3.5), layout="constrained")
ax.semilogy(ds.time, amplitude, label="median perpendicular amplitude")
ax.semilogy(ds.time, 1e-6 * np.exp(analytic * ds.time), "--", label="exp(sqrt(-Omega^2) t)")
ax.set_ylim(1e-7, 2)
ax.set_xlabel("time (s)")
ax.set_ylabel("amplitude (rad/s)")
ax.legend()
