"""The Earth's study kinds, one module each: :mod:`.earth_wobble` (a rigid Earth's free wobble
against Euler's period) and :mod:`.equinoxes` (the precession and nutation of its axis under the
Sun and the Moon, against the averaged formula and the published values).

The kinds are registered in :data:`stability.study.STUDIES`, and importing any module of the
framework (``stability.study.config``) runs that package first, which imports the kinds. So the
framework is imported here, before a kind's module starts: a kind imported first (``import
stability.earth.studies.equinoxes`` in a fresh process) is then complete when the registry
reads its ``STUDY``, instead of half-initialised.
"""

from ... import study  # noqa: F401  (the registry first: see above)
