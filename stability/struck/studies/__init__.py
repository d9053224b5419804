"""The struck bat's study kind: :mod:`.bat` (the centre of percussion and the sweet zone of a bat
or racket, from strikes run held and free, beside the formula).

The kinds are registered in :data:`stability.study.STUDIES`, which reads each when it is asked
for (so that a kind's module may be imported first).
"""
