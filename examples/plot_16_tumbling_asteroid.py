r"""
A tumbling asteroid: Apophis from its two periods to its light curve
====================================================================

Apophis tumbles in a short-axis mode (Pravec et al., Icarus 233, 48 (2014)): from its moment
ratios :math:`I_1/I_3 = 0.61`, :math:`I_2/I_3 = 0.965` and its periods
:math:`P_\psi = 263` h (rotation about the short axis) and :math:`P_\phi = 27.38` h (mean
precession of that axis about :math:`L`), :func:`stability.asteroid.model.spin_states`
finds the states they fit, with their :math:`E/E_0`. The synthetic Lommel-Seeliger light curve
of the SAM state (a uniform ellipsoid of those moments, the attitude exact) has its strongest
line at :math:`2 (f_\phi - f_\psi)`, the :math:`P_1 = 30.56` h of the paper.
"""

import matplotlib.pyplot as plt
import numpy as np

from stability.asteroid.lightcurve import lightcurve, main_frequencies, spectrum
from stability.asteroid.model import spin_states

states = spin_states((0.61, 0.965, 1.0), 263.0, 27.38)
for s in states:
    print(f"{s.mode}: E/E0 = {s.energy_ratio:.4f}, |L| / I3 = {s.momentum:.4f} rad/h")
sam = states[0]

# %%
# Its light curve over twenty rotation periods, seen with the Sun and the observer off its
# angular momentum, and the spectrum's lines against the frequency the theory gives the mode:

t = np.linspace(0.0, 20 * 263.0, 2048)
flux = lightcurve(sam, t, sun=(1.0, 0.0, 0.3), observer=(1.0, 0.2, 0.3))
f, a = spectrum(t, flux)

fig, (top, bottom) = plt.subplots(2, 1, figsize=(7, 6), layout="constrained")
top.plot(t / 24.0, flux / flux.mean())
top.set_xlim(0, 60)
top.set_xlabel("time (d)")
top.set_ylabel("relative brightness (1)")
bottom.plot(24.0 * f, a)
for k, line in enumerate(24.0 * main_frequencies(sam)):
    bottom.axvline(line, color="k", ls="--", label="2 (f_phi - f_psi)" if k == 0 else None)
bottom.set_xlim(0, 4)
bottom.set_xlabel("frequency (d-1)")
bottom.set_ylabel("amplitude (1)")
bottom.legend()
print(f"strongest light-curve period: {2 / f[np.argmax(a)]:.2f} h (paper: P1 = 30.56 h)")
