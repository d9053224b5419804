"""Monte Carlo over what is uncertain: dispersions of any parameter, and which one matters.

A generic layer beside :mod:`stability.analysis` (families and studies import it; it imports
only the layers below):

- :mod:`.distributions`: uniform, log-uniform, normal and truncated normal, as inverse CDFs;
- :mod:`.designs`: random, Sobol' and Latin-hypercube designs of the unit cube, each member's
  row independent of chunks, threads and workers;
- :mod:`.dispersions`: named parameters with their distributions, the moments kept physical;
- :mod:`.inertia`: the inertia tensor dispersed as a tensor (a small rotation of the axes);
- :mod:`.sobol`, :mod:`.morris`: Sobol' indices and Morris screening by SALib, as Datasets over
  (output, parameter) (:mod:`.schema`); :mod:`.figures`: their figures.

This package's ``__init__`` imports nothing, so that the registry can read :mod:`.schema`
without SALib and SciPy (the command line's start-up time).
"""
