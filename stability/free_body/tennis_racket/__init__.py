"""The tennis-racket study: an ensemble spun about the intermediate axis flips, again and again.

- :mod:`.flipsweep`: the flip interval against the perturbation (exact 2K/nu, the ln(1/epsilon)
  law, measured);
- :mod:`.study`: the study kind ``tennis_racket``;
- :mod:`.figures`: its figures.
"""
