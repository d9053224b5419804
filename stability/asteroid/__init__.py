"""Tumbling asteroids: non-principal-axis rotators seen from their light curves.

A tumbling asteroid is the torque-free rigid body of :mod:`stability.free_body`, described by
planetary scientists through the two periods of its light curve and its moment ratios. The
family builds on the free body's exact solution and exact attitude
(:mod:`stability.free_body.exact`, :mod:`stability.free_body.exact_attitude`), which it inverts
and observes. Its modules, each importing only downward:

- :mod:`.methods`: the equations of a tumbler whose interior dissipates its energy at fixed
  angular momentum until it spins about its major axis, and their method;
- :mod:`.exact`: their exact solution for an axisymmetric tumbler;
- :mod:`.model`: the physics: the spin state (mode SAM or LAM, E/E0, |L|) from the periods and
  back, the mass properties of a closed shape mesh (OBJ, STL; the ``shapes`` extra), and the
  linear theory of the relaxation;
- :mod:`.scene`: the scene ``relaxing_tumbler``;
- :mod:`.lightcurve`: synthetic Lommel-Seeliger and Lambert light curves from the exact
  attitude, their spectrum and the frequencies theory predicts;
- :mod:`.measure`: periods read off a computed attitude; the tumbler ensemble;
- :mod:`.schema`: its Dataset's declaration;
- :mod:`.studies`: the study kind ``tumbler``; :mod:`.figures`: its figure.

The tumbler of the light curves moves exactly, and nothing of it is integrated; the relaxing
tumbler is integrated by the member loop like every scene. This package's ``__init__`` imports
nothing, so that the registry can read what it declares without the rest.
"""

#: What the family registers (:mod:`stability.registry`).
SCENES = ("scene:RELAXING_TUMBLER",)
STUDIES = {"tumbler": "studies.tumbler:STUDY"}
DATASETS = ("schema:TUMBLER",)
