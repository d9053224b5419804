r"""
Poinsot's construction
======================

The torque-free motion as Poinsot drew it (1834; Landau & Lifshitz, *Mechanics*, section 37).
The scaled angular velocity :math:`\rho = \omega / \sqrt{2E}` lies on the ellipsoid
:math:`x \cdot I x = 1`, fixed in the body; the tangent plane there is perpendicular to
:math:`L` at the distance :math:`\sqrt{2E} / |L|` from the centre, so it is fixed in space: the
*invariable plane*. The ellipsoid rolls on it without slipping; :math:`\rho` traces the polhode
on the ellipsoid and the herpolhode on the plane, between two circles whose radii follow from
the invariants (:func:`stability.free_body.polhodes.herpolhode_radii`).
"""

import matplotlib.pyplot as plt
import numpy as np

import stability
from stability.free_body.figures import poinsot_figure
from stability.free_body.polhodes import herpolhode

body = stability.RigidBody.preset("tennis_racket")
w0 = np.array([0.3, 10.0, 0.2])  # rad/s, near the intermediate axis: a flip
t = np.linspace(0.0, 20.0, 5001)
h = herpolhode(body, w0, t)
r = np.linalg.norm(h.plane, axis=1)
print(f"plane at sqrt(2E)/|L| = {h.distance:.6f}; the points' distance from it: "
      f"{np.abs(h.points @ h.normal - h.distance).max():.1e}")
print(f"radii on the plane: {r.min():.4f} to {r.max():.4f} (closed form "
      f"{h.radii[0]:.4f} to {h.radii[1]:.4f}), in kg^-1/2 m^-1")

# %%
# The polhodes on the ellipsoid, the ellipsoid on the plane, and the herpolhode seen down L.

fig = plt.figure(figsize=(15, 5.8))
poinsot_figure(body, w0, t_end=float(t[-1]), fig=fig)
