"""Estimators on ensembles, whatever the scene: the members, fits on them, their regimes and the
measured rates.

- :mod:`.members`: an ensemble's members from a Dataset (time series or summaries) or from the
  loop's tracking;
- :mod:`.fits`: lines and exponentials fitted row by row, means with standard errors,
  Richardson's bias;
- :mod:`.regimes`: each member's regime (neutral, oscillation, exponential growth, algebraic
  drift) and the ensemble's;
- :mod:`.estimates`: growth rate, oscillation frequency, measured Omega^2 and flip statistics.

A family fills in its theory where an estimate is set beside it: the free body's analytic
Omega^2 and exact flip intervals are in :mod:`stability.free_body.measure`.
"""
