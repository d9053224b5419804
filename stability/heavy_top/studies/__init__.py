"""The heavy top's study kinds, one module each: :mod:`.sleeping_top` (a top spun upright, across
the critical spin) and :mod:`.gyroscope` (released tops' precession and nutation); :mod:`.common`
holds what both read from a study file (the symmetric top's keys, its methods, the spins' checks).

The kinds are registered in :data:`stability.study.STUDIES`, which reads each when it is asked
for (so that a kind's module may be imported first).
"""
