"""The free rigid body: torque-free rotation, the tennis-racket effect and the methods that
integrate it.

The family's modules, each importing only downward:

- :mod:`.scene`, :mod:`.scene_attitude`: the scenes ``free_body`` (the body angular momentum
  alone) and ``free_body_attitude`` (with a unit quaternion per member);
- :mod:`.model`: the closed forms: invariants, Omega^2 and the linear stability of each axis;
- :mod:`.exact`, :mod:`.exact_attitude`: the exact motion in Jacobi elliptic functions, and the
  exact attitude by quadrature;
- :mod:`.propagate`, :mod:`.attitude`, :mod:`.integrate`: the body's angular momentum (and its
  attitude) advanced by the engine, and one trajectory of any method;
- :mod:`.spin_ensembles`: ``run_ensemble``, perturbed ensembles about a steady spin, and their
  per-member summaries;
- :mod:`.timescales`, :mod:`.accuracy`, :mod:`.polhodes`: a step and a horizon from the physics,
  references to score a run against, the polhodes;
- :mod:`.figures`: Poinsot's construction, drawn from a body and a start;
- one sub-package per study, each with its measurements, its study kind and its figures:
  :mod:`.tennis_racket`, :mod:`.stability_map`, :mod:`.work_precision`, :mod:`.twisting_racket`,
  :mod:`.dispersion` (a dispersed body, :mod:`stability.uncertainty`);
- :mod:`.methods`: its methods by name (``stability.METHODS``): RK4, the Lie-Poisson
  splittings, DMV, LGVI, RKMK4 and the midpoint rule, the methods on Euler's equations of
  :mod:`stability.integrators` that other families build on, and its own exact flow.

This package's ``__init__`` imports nothing, so that the scene registry can import
:mod:`.scene` without the rest.
"""

#: What the family registers (:mod:`stability.registry`): its scenes, its study kinds and the
#: declarations of the Datasets they write, each as ``"module:name"`` inside this package.
SCENES = ("scene:FREE_BODY", "scene_attitude:FREE_BODY_ATTITUDE")
STUDIES = {
    "tennis_racket": "tennis_racket.study:STUDY",
    "stability_map": "stability_map.study:STUDY",
    "work_precision": "work_precision.study:STUDY",
    "twisting_racket": "twisting_racket.study:STUDY",
    "dispersion": "dispersion.study:STUDY",
}
DATASETS = (
    "schema:TRAJECTORY",
    "schema:TENNIS_RACKET",
    "schema:STABILITY_MAP",
    "schema:FTLE_MAP",
    "schema:WORK_PRECISION",
    "schema:TWISTING_RACKET",
    "schema:FLIP_SENSITIVITY",
    "dispersion.schema:DISPERSION",
)
