"""Physics engines' update rules: what the steps that game and robotics engines take do to a
rigid body's rotation (the tennis-racket flip), measured against the exact motion.

The family's modules, each importing only downward:

- :mod:`.methods`: the engines' update rules (explicit, semi-implicit and implicit Euler, |L| or
  the energy rescaled, no gyroscopic term; each spec names the engines and threads it stands
  for), the family's registry :data:`~.methods.ENGINE_RULES`;
- :mod:`.scene`: the scene ``engine_body`` (the state as engines hold it: the space angular
  velocity and the body-to-space quaternion);
- :mod:`.model`: that state and its conversions from and to the body-frame ``(m, q)``; the
  physics itself is the free body's (its equations, exact motion and linear theory);
- :mod:`.measure`: the artefacts measured per rule and step (flips, the flip interval, the
  growth rate, the drift of the invariants, the cost), and the step each rule needs;
- :mod:`.schema`: the declaration of its Dataset;
- :mod:`.studies`: the study kind ``engine_artefacts``;
- :mod:`.figures`: its figure, drawn from the Dataset.

It builds on the free body, whose flip it measures and whose scenes it shares the state with
(:mod:`stability.free_body.scene_attitude`, the exact solution and its flip intervals
:mod:`stability.free_body.exact`, the linear theory :mod:`stability.free_body.model`, the
scenes of the methods it compares :mod:`stability.free_body.attitude`), and on the shared
layers: :mod:`stability.core`, :mod:`stability.util`, :mod:`stability.integrators`
(MethodSpec, rotations), :mod:`stability.engine.scene` (the scene contract), the scene-generic
ensembles (:mod:`stability.ensemble.chunks`) and their start rule
(:mod:`stability.ensemble.starts`), the estimators (:mod:`stability.analysis`),
:mod:`stability.output`, the Dataset register (:mod:`stability.ensemble.schema`),
:mod:`stability.study` (the study framework) and :mod:`stability.plotting`.

This package's ``__init__`` imports nothing, so that the scene registry (:mod:`stability.registry`)
can import :mod:`.scene` without the rest.
"""

#: What the family registers (:mod:`stability.registry`): its scenes, its study kinds and the
#: declarations of the Datasets they write, each as ``"module:name"`` inside this package.
SCENES = ("scene:ENGINE_BODY",)
STUDIES = {"engine_artefacts": "studies.engine_artefacts:STUDY"}
DATASETS = ("schema:ENGINE_ARTEFACTS",)
