"""The engine rules' study kind: :mod:`.engine_artefacts` (what each engine's update rule does
to the tennis-racket flip at the frame rates engines use, beside the package's integrators).

The kinds are registered in :data:`stability.study.STUDIES`, and importing any module of the
framework (``stability.study.config``) runs that package first, which imports the kinds. So the
framework is imported here, before a kind's module starts: a kind imported first (``import
stability.engine_body.studies.engine_artefacts`` in a fresh process) is then complete when the
registry reads its ``STUDY``, instead of half-initialised.
"""

from ... import study  # noqa: F401  (the registry first: see above)
