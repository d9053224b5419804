"""The engine rules' study kind: :mod:`.engine_artefacts` (what each engine's update rule does
to the tennis-racket flip at the frame rates engines use, beside the package's integrators).

The kinds are registered in :data:`stability.study.STUDIES`, which reads each when it is asked
for (so that a kind's module may be imported first).
"""
