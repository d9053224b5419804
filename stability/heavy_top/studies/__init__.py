"""The heavy top's study kinds, one module each: :mod:`.sleeping_top` (a top spun upright, across
the critical spin) and :mod:`.gyroscope` (released tops' precession and nutation); :mod:`.common`
holds what both read from a study file (the symmetric top's keys, its methods, the spins' checks).

The kinds are registered in :data:`stability.study.STUDIES`, and importing any module of the
framework (``stability.study.config``) runs that package first, which imports the kinds. So the
framework is imported here, before a kind's module starts: a kind imported first (``import
stability.heavy_top.studies.gyroscope`` in a fresh process) is then complete when the registry
reads its ``STUDY``, instead of half-initialised.
"""

from ... import study  # noqa: F401  (the registry first: see above)
