"""Rolling's study kind: :mod:`.rolling` (bodies rolling or slipping down inclines, and balls
launched along a floor, beside the formulas).

The kinds are registered in :data:`stability.study.STUDIES`, and importing any module of the
framework (``stability.study.config``) runs that package first, which imports the kinds. So the
framework is imported here, before a kind's module starts: a kind imported first (``import
stability.rolling.studies.rolling`` in a fresh process) is then complete when the registry reads
its ``STUDY``, instead of half-initialised.
"""

from ... import study  # noqa: F401  (the registry first: see above)
