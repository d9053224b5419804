r"""
A stability map from tangents: the FTLE over the shapes of bodies
=================================================================

Each cell of a 12 x 12 grid of inertia ratios :math:`(I_1/I_3, I_2/I_3)` that is a real body
spins at :math:`W = 1` rad/s about its intermediate axis, started :math:`10^{-8} W` off it, and
carries the state-transition matrix :math:`\Phi` of its RK4 map
(:func:`stability.free_body.stability_map.ftle_map.ftle_map`). Its finite-time Lyapunov exponent
:math:`\log \sigma_{\max}(\Phi(T)) / T` over :math:`T = 10` s lies between the analytic rate
:math:`\sigma = \sqrt{-\Omega^2}` and :math:`\sigma + \log((1 + \rho)/2)/T`, the second term the
alignment of the saddle's eigenvectors (aspect ratio :math:`\rho`), which fades as :math:`1/T`.
"""

import matplotlib.pyplot as plt
import numpy as np

from stability.free_body.stability_map.figures import ftle_map_figure
from stability.free_body.stability_map.ftle_map import ftle_map

ds = ftle_map(12, axis=2, spin=1.0, horizon=10.0)
body = ds.physical.values == 1
sigma = ds.growth_rate_analytic.values[body]
excess = ds.ftle.values[body] - sigma
alignment = np.log((1.0 + ds.eigenvector_aspect.values[body]) / 2.0) / 10.0
print(f"{body.sum()} bodies; FTLE - sigma from {excess.min():.2e} to {excess.max():.3f} s-1, "
      f"under the alignment term by at least {np.min(alignment - excess):.1e} s-1")

# %%
# The map, coloured by the FTLE, with the analytic rate's contours over it: the fastest
# growth is near the rod corner (I1 small, I2 near I3), the slowest along the symmetric edges.

fig = ftle_map_figure(ds, fig=plt.figure())
