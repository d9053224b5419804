"""Energy dissipation: why Explorer 1 tumbled. Rigid bodies that keep |H| but lose energy.

A truly rigid body spins stably about its largest and its smallest axis; one that flexes
(antennas, fuel, a damper) spins stably only about the largest: at fixed |H| that spin has the
least energy (the major-axis rule). The family's modules, each importing only downward:

- :mod:`.methods`: the step kernels and their MethodSpecs (RK4; splittings of the damper's exact
  relaxation and the exact free flow, which keep |H| to round-off);
- :mod:`.scene`: the scenes ``sphere_damper`` (a viscous spherical damper) and ``whip_damper``
  (four whip antennas: spring-mass dampers on booms);
- :mod:`.model`: steady spins, their linear theory (eigenvalues in closed form and from the
  Jacobian), the energy-sink estimate, the energy a flat spin sheds, the Explorer 1 preset;
- :mod:`.measure`: what the studies read from a run (nutation angle, fitted rates, times to a
  flat spin, the end state);
- :mod:`.explorer`: the Explorer-like ensembles and their Dataset;
- :mod:`.studies`: the study kind ``explorer``; :mod:`.figures`: its figures.

This package's ``__init__`` imports nothing, so that the scene registry
(:mod:`stability.scenes`) can import :mod:`.scene` without the rest.
"""
