"""The dissipation study kinds, one module each: :mod:`.explorer` (a long satellite spun about
its minor axis turns over into a flat spin) and :mod:`.dual_spin` (where a damper on a gyrostat's
platform or in its rotor makes the nutation decay); :mod:`.common` holds what both use (keys of a
number > 0, the worst of a measured error). The dispersed Explorer, a study of several modules,
is the sub-package :mod:`stability.dissipation.dispersion`.

The kinds are registered in :data:`stability.study.STUDIES`, which reads each when it is asked
for (so that a kind's module may be imported first).
"""
