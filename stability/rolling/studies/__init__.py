"""Rolling's study kind: :mod:`.rolling` (bodies rolling or slipping down inclines, and balls
launched along a floor, beside the formulas).

The kinds are registered in :data:`stability.study.STUDIES`, which reads each when it is asked
for (so that a kind's module may be imported first).
"""
