"""The Earth's study kinds, one module each: :mod:`.earth_wobble` (a rigid Earth's free wobble
against Euler's period) and :mod:`.equinoxes` (the precession and nutation of its axis under the
Sun and the Moon, against the averaged formula and the published values).

The kinds are registered in :data:`stability.study.STUDIES`, which reads each when it is asked
for (so that a kind's module may be imported first).
"""
