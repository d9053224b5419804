"""Energy dissipation: why Explorer 1 tumbled. Rigid bodies that keep |H| but lose energy.

A truly rigid body spins stably about its largest and its smallest axis; one that flexes
(antennas, fuel, a damper) spins stably only about the largest: at fixed |H| that spin has the
least energy (the major-axis rule), unless the damper sits on a part that does not spin with
the rest (dual-spin stabilisation). The family's modules, each importing only downward:

- :mod:`.methods`: the step kernels and their MethodSpecs (RK4; splittings of the damper's exact
  relaxation and the exact free flow, which keep |H| to round-off);
- :mod:`.scene`: the scenes ``sphere_damper`` (a viscous spherical damper), ``whip_damper``
  (four whip antennas: spring-mass dampers on booms) and ``gyrostat`` (a dual-spin body: a
  platform and a rotor on a free bearing, a spherical damper on each);
- :mod:`.model`: steady spins, their linear theory (eigenvalues in closed form and from the
  Jacobian), the energy-sink estimate, the energy a flat spin sheds, the Explorer 1 preset;
- :mod:`.model_gyrostat`: the gyrostat's steady spins, their linear theory and Likins'
  energy-sink criterion, and the dual-spin map's body (:class:`~.model_gyrostat.DualSpinBody`);
- :mod:`.measure`: what the studies read from a run (nutation angle, fitted rates, times to a
  flat spin, the end state), and the Explorer-like ensembles run and measured;
  :mod:`.measure_gyrostat`: the dual-spin maps run and measured;
- :mod:`.schema`: the declarations of the Datasets;
- :mod:`.studies`: the study kinds ``explorer`` and ``dual_spin``, one module each;
  :mod:`.figures`: their figures;
- :mod:`.dispersion`: the study kind ``explorer_dispersion``, the Explorer uncertain in its
  body, spin, damper and start (:mod:`stability.uncertainty`), a study of several modules.

This package's ``__init__`` imports nothing, so that the scene registry
(:mod:`stability.registry`) can import :mod:`.scene` without the rest.
"""

#: What the family registers (:mod:`stability.registry`): its scenes, its study kinds and the
#: declarations of the Datasets they write, each as ``"module:name"`` inside this package.
SCENES = ("scene:SPHERE_DAMPER", "scene:WHIP_DAMPER", "scene:GYROSTAT")
STUDIES = {"explorer": "studies.explorer:STUDY", "dual_spin": "studies.dual_spin:STUDY",
           "explorer_dispersion": "dispersion.study:STUDY"}
DATASETS = ("schema:EXPLORER", "schema:DUAL_SPIN", "dispersion.schema:EXPLORER_DISPERSION")
