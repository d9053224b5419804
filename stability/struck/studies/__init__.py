"""The struck bat's study kind: :mod:`.bat` (the centre of percussion and the sweet zone of a bat
or racket, from strikes run held and free, beside the formula).

The kinds are registered in :data:`stability.study.STUDIES`, and importing any module of the
framework (``stability.study.config``) runs that package first, which imports the kinds. So the
framework is imported here, before a kind's module starts: a kind imported first (``import
stability.struck.studies.bat`` in a fresh process) is then complete when the registry reads its
``STUDY``, instead of half-initialised.
"""

from ... import study  # noqa: F401  (the registry first: see above)
