"""The twisting racket: Montgomery's geometric phase and the twist of rackets tossed about the
middle axis.

- :mod:`.geometric_phase`: Montgomery's angle and the twist, exact and from a run;
- :mod:`.measure`: an ensemble of tossed bodies, the angle and the twist per member;
- :mod:`.study`: the study kind ``twisting_racket``;
- :mod:`.figures`: its figures.
"""
