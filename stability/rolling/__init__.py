"""Rolling and slipping: round bodies under Coulomb friction, released on inclines or launched
along a level floor.

The family's modules, each importing only downward:

- :mod:`.methods`: the equations of a body that rolls or slips, the events where it switches,
  the exact event-located step, and its MethodSpec;
- :mod:`.scene`: the scene ``rolling_body`` (the state, what the loop tracks, the energy with
  the friction's work added back);
- :mod:`.model`: the formulas (roll or slip on an incline, accelerations, a launched body's
  slip time, final speed and heat, the shapes' I / (M R^2));
- :mod:`.measure`: the ensembles run and measured against them (:func:`~.measure.measure_incline`,
  :func:`~.measure.measure_launches`);
- :mod:`.studies`: the study kind ``rolling``;
- :mod:`.figures`: its figures, drawn from the Dataset.

It builds on the shared layers: :mod:`stability.util` (conventions, threads),
:mod:`stability.integrators` (MethodSpec), :mod:`stability.engine.scene` (the scene contract),
:mod:`stability.engine` (the member loop), the scene-generic ensembles
(:mod:`stability.ensemble.chunks`), the Dataset register (:mod:`stability.ensemble.schema`),
:mod:`stability.study` (the study framework) and :mod:`stability.plotting`.

This package's ``__init__`` imports nothing, so that the scene registry (:mod:`stability.registry`) can import
:mod:`.scene` without the rest.
"""

#: What the family registers (:mod:`stability.registry`): its scenes, its study kinds and the
#: declarations of the Datasets they write, each as ``"module:name"`` inside this package.
SCENES = ("scene:ROLLING_BODY",)
STUDIES = {"rolling": "studies.rolling:STUDY"}
DATASETS = ("schema:ROLLING",)
