"""Tumbling asteroids: non-principal-axis rotators seen from their light curves.

A tumbling asteroid is the torque-free rigid body of :mod:`stability.free_body`, described by
planetary scientists through the two periods of its light curve and its moment ratios. The
family builds on the free body's exact solution and exact attitude
(:mod:`stability.free_body.exact`, :mod:`stability.free_body.exact_attitude`), which it inverts
and observes. Its modules, each importing only downward:

- :mod:`.model`: the physics: the spin state (mode SAM or LAM, E/E0, |L|) from the periods and
  back, and the mass properties of a closed shape mesh (OBJ, STL; the ``shapes`` extra);
- :mod:`.lightcurve`: synthetic Lommel-Seeliger and Lambert light curves from the exact
  attitude, their spectrum and the frequencies theory predicts;
- :mod:`.measure`: periods read off a computed attitude; the tumbler ensemble;
- :mod:`.schema`: its Dataset's declaration;
- :mod:`.studies`: the study kind ``tumbler``; :mod:`.figures`: its figure.

It registers no scene (the motion is exact, nothing is integrated), so it has no ``scene.py`` and
no ``methods.py``. This package's ``__init__`` imports nothing, so that the registry can read
what it declares without the rest.
"""

#: What the family registers (:mod:`stability.registry`).
SCENES = ()
STUDIES = {"tumbler": "studies.tumbler:STUDY"}
DATASETS = ("schema:TUMBLER",)
