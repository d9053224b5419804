"""
The twist of a racket
=====================

While the handle of a tossed racket turns once about the angular momentum L, its face turns by
nearly, not exactly, half a turn about the handle. The twist from a run with the attitude,
checked against the exact motion, and its defect from pi, for a few nudges.
"""

import matplotlib.pyplot as plt

import stability
from stability.free_body.twisting_racket.measure import measure_twisting, tossed_members

body = stability.RigidBody.preset("tennis_racket")
moments, w0, epsilon = tossed_members(body.moments, 12, 10.0, (1e-4, 1e-1), 0.0, seed=1)
ds = measure_twisting(moments, w0, epsilon=epsilon, steps_per_period=1000)
print(f"twist, run against exact: {float(ds.twist_error.max()):.1e} rad")
print(f"Montgomery's angle, run against 2 E T / |L| - S: {float(ds.montgomery_error.max()):.1e}")

# %%
# The defect ``pi - |twist|`` over one turn of the handle against the nudge epsilon. Each member is
# nudged in a random direction across the middle axis, so two nudges of one size can leave
# different defects (the two near epsilon = 0.07).

fig, ax = plt.subplots(figsize=(7, 3.5), layout="constrained")
ax.semilogx(ds.epsilon, ds.twist_defect, "o")
ax.set_xlabel("nudge epsilon (1)")
ax.set_ylabel("pi - |twist| (rad)")
ax.set_title("the twist's defect from pi over one turn of the racket's handle")
