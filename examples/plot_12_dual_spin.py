"""
Dual spin: a damper on the platform rescues a minor-axis spin
=============================================================

A spinner with a damper is stable only about its major axis (the Explorer example). Dual-spin
satellites get round the rule: a rotor carries the spin's angular momentum, and the nutation
damper sits on a platform that turns slowly or not at all. Likins (1967) and Iorillo (1965)
gave the rule: with a damper dissipating :math:`D_i` on body :math:`i`, which sees the nutation
at the frequency :math:`\\lambda_i = h / A_t - \\omega_i`, the nutation decays iff
:math:`D_p / \\lambda_p + D_r / \\lambda_r > 0`.

Here the body is the registered scene ``gyrostat``
(:mod:`stability.dissipation.model_gyrostat`): an axisymmetric platform spinning at 1 rad/s, a
rotor on a free bearing along its axis, a viscous spherical damper on the platform or in the
rotor. First a despun platform, by the
eigenvalues; then a small map over the inertia ratio and the rotor's speed, each cell run
with RK4 and its nutation's rate measured against the eigenvalue.
"""

import matplotlib.pyplot as plt
import numpy as np

import stability
from stability.dissipation import model_gyrostat
from stability.dissipation.figures import dual_spin_map_figure
from stability.dissipation.measure_gyrostat import measure_dual_spin
from stability.dissipation.model_gyrostat import DualSpinBody

# %%
# A despun platform (:math:`\omega_p = 0`) on a minor-axis body (:math:`A_3 / A_t = 0.6`), the
# rotor at 3 rad/s: the platform sees the nutation turn forwards, the rotor backwards. The
# same damper stabilises on the platform and destabilises in the rotor.
for where, values in (("platform", [100.0, 100.0, 60.0, 25.0, 5.0, 0.4, 5.0, 0.0]),
                      ("rotor", [100.0, 100.0, 60.0, 25.0, 5.0, 0.0, 5.0, 0.4])):
    rate = model_gyrostat.growth_rate(model_gyrostat.eigenvalues(values, 0.0, 3.0))
    sink = model_gyrostat.energy_sink_rate(values, 0.0, 3.0)
    print(f"damper on the {where}: growth rate {rate:+.5f} 1/s (energy sink {sink:+.5f})")
h, lam_p, lam_r = model_gyrostat.nutation_frequencies(values, 0.0, 3.0)
print(f"h = {h:g} kg m2/s, lambda_p = {lam_p:+.3f} rad/s, lambda_r = {lam_r:+.3f} rad/s")

# %%
# The map: each damper at its energy-sink optimum :math:`c^* = J h / A_t` (the rotor's at
# 0.3 of it), every cell one member started 0.001 degrees off the rotor's axis. The solid
# line is where the eigenvalues change sign, the dashed one the energy-sink criterion's; the
# markers are the measured verdicts.
body = DualSpinBody(transverse_moment=100.0, rotor_moment=25.0, damper_moment=5.0,
                    platform_spin=1.0, platform_damping=1.0, rotor_damping=0.3)
ds = measure_dual_spin(body, np.linspace(0.55, 1.45, 5), np.linspace(-1.4, 4.4, 5),
                       np.radians([0.001]), samples=300,
                       options=stability.RunOptions(progress=False))
for placement in ds.placement.values:
    d = ds.sel(placement=placement)
    agree = int((d.verdict_measured == d.verdict_linear).sum())
    print(f"{placement:>8}: measured = eigenvalues in {agree} of {d.verdict_linear.size} "
          f"cells, fitted rates within {float(np.abs(d.rate_error).max()):.1e} of them")
fig = dual_spin_map_figure(ds, fig=plt.figure())
ds
