"""Tumbling asteroids: non-principal-axis rotators seen from their light curves.

A tumbling asteroid is the torque-free rigid body of :mod:`stability.free_body`, described by
planetary scientists through the two periods of its light curve and its moment ratios. The
family builds on the free body's exact solution and exact attitude
(:mod:`stability.free_body.exact`, :mod:`stability.free_body.exact_attitude`), which it inverts
and observes. Its modules,
each importing only downward:

- :mod:`.spin_state`: the state (mode SAM or LAM, E/E0, |L|) from the periods and back;
- :mod:`.lightcurve`: synthetic Lommel-Seeliger and Lambert light curves from the exact
  attitude, their spectrum and the frequencies theory predicts;
- :mod:`.shape`: mass properties of a closed shape mesh (OBJ, STL; the ``shapes`` extra);
- :mod:`.measure`: periods read off a computed attitude; the tumbler ensemble;
- :mod:`.studies`: the study kind ``tumbler``; :mod:`.figures`: its figure;
  :mod:`.schema`: its Dataset's declaration.

It registers no scene (the motion is exact, nothing is integrated). This package's ``__init__``
imports nothing, so that the registry can read what it declares without the rest.
"""

#: What the family registers (:mod:`stability.registry`).
SCENES = ()
STUDIES = {"tumbler": "studies.tumbler:STUDY"}
DATASETS = ("schema:TUMBLER",)
