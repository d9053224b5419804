"""
How the flip depends on the toss
================================

A phone tossed spinning about its middle axis (the width: axis 2) turns its screen over at a
regular interval. How long that interval is depends on the toss: on the spin W and on the
wobble epsilon, the nudge across the spin relative to it. Here a small ensemble (members nudged
in random directions) is run for each toss, all together with :func:`stability.run_ensembles`,
and each member's measured interval between flips is set beside the exact 2K/nu of its start.

The interval goes as 1/W (Euler's equations are homogeneous in w: a toss twice as fast is the
same motion twice as fast) and grows only as ln(1/epsilon): ten times less wobble adds the same
time, (2/lambda) ln 10, at each step. Set ``PRESET`` to any name of
``stability.RigidBody.presets()`` (``"book"``, ``"tennis_racket"``, ``"t_handle"``) to see
another body.
"""

import matplotlib.pyplot as plt
import numpy as np

import stability

PRESET = "phone"
body = stability.RigidBody.preset(PRESET)
axis = 2  # every preset's intermediate axis
SPINS = np.array([2.0, 4.0, 8.0, 16.0, 32.0])  # rad/s, at EPSILON
EPSILONS = np.logspace(-1, -6, 6)  # at SPIN
SPIN, EPSILON = 10.0, 1e-3
tosses = [(w, EPSILON) for w in SPINS] + [(SPIN, e) for e in EPSILONS]

# One summaries-only ensemble of 32 members per toss; h and t_end are run_ensemble's own
# (a step that resolves the spin, four exact flip intervals), every ensemble in one batch.
runs = stability.run_ensembles(
    [dict(body=body, axis=axis, spin=w, epsilon=e, members=32, seed=1, method="rk4",
          keep=stability.Keep(save_every=0)) for w, e in tosses], progress=False)
measured, exact = [], []
for run in runs:
    flips = run.stability.flip_statistics()  # each member's interval and its exact 2K/nu
    measured.append(np.quantile(flips.flip_interval.values, [0.1, 0.5, 0.9]))
    exact.append(float(np.median(flips.flip_interval_exact.values)))
measured, exact = np.array(measured), np.array(exact)
for (w, e), m, x in zip(tosses, measured[:, 1], exact):
    print(f"spin {w:5.1f} rad/s, epsilon {e:.0e}: flip interval {m:7.4f} s (exact {x:7.4f} s)")

# %%
# Left: against the spin, at one wobble; right: against the wobble, at one spin. Dots: the
# median measured interval over the members, bars from the 10th to the 90th percentile (the
# direction of the nudge changes it); line: the median exact 2K/nu.

fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4), layout="constrained")
for ax, x, rows in ((left, SPINS, slice(0, SPINS.size)),
                    (right, EPSILONS, slice(SPINS.size, None))):
    low, mid, high = measured[rows].T
    ax.errorbar(x, mid, yerr=(mid - low, high - mid), fmt="o", capsize=3,
                label="measured (median, 10-90 %)")
    ax.plot(x, exact[rows], "-", color="black", lw=1.0, label="exact 2K/ν (median)")
    ax.set_xscale("log")
    ax.set_ylabel("flip interval (s)")
    ax.legend()
left.set_yscale("log")
left.set_xticks(SPINS, [f"{w:g}" for w in SPINS], minor=False)
left.xaxis.set_minor_locator(plt.NullLocator())
left.set_xlabel("spin W (rad/s)")
left.set_title(f"{PRESET}: faster toss, shorter interval (∝ 1/W), ε = {EPSILON:g}")
right.set_xlabel("wobble ε, the nudge relative to the spin (dimensionless)")
right.set_title(f"less wobble, longer wait (∝ ln(1/ε)), W = {SPIN:g} rad/s")
plt.show()
