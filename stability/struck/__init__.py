"""The struck bat: a bat or racket struck across its axis, held at the hands or free, and its
centre of percussion.

The family's modules, each importing only downward:

- :mod:`.methods`: the planar strike's equations, a half-sine contact force, its RK4 step, the
  held body's exact motion, and their MethodSpecs;
- :mod:`.scene`: the scene ``struck_body`` (the state, what the loop tracks, the invariants
  after the contact, the held body's exact solution);
- :mod:`.model`: :class:`~.model.StruckBody` and its presets (a tapered wooden baseball bat, the
  tennis racket), the formulas (centre of percussion, reaction at the hands, the free hands'
  velocity);
- :mod:`.measure`: the strikes run and measured against them (:func:`~.measure.measure_strikes`);
- :mod:`.studies`: the study kind ``bat``;
- :mod:`.figures`: its figure, drawn from the Dataset.

It builds on the shared layers: :mod:`stability.core` (the rigid body and its presets),
:mod:`stability.util` (conventions, input checks, threads), :mod:`stability.integrators`
(MethodSpec), :mod:`stability.engine.scene` (the scene contract), the scene-generic ensembles
(:mod:`stability.ensemble.chunks`), the estimators (:mod:`stability.analysis`), the Dataset
register (:mod:`stability.ensemble.schema`), :mod:`stability.study` (the study framework) and
:mod:`stability.plotting`.

This package's ``__init__`` imports nothing, so that the scene registry (:mod:`stability.registry`) can import
:mod:`.scene` without the rest.
"""

#: What the family registers (:mod:`stability.registry`): its scenes, its study kinds and the
#: declarations of the Datasets they write, each as ``"module:name"`` inside this package.
SCENES = ("scene:STRUCK_BODY",)
STUDIES = {"bat": "studies.bat:STUDY"}
DATASETS = ("schema:BAT",)
