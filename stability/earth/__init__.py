"""The Earth as a rigid body: its free (Euler) wobble, and the precession and nutation of its
axis under the Sun's and the Moon's torques (the precession of the equinoxes).

The family's modules, each importing only downward:

- :mod:`.methods`: the step kernels and their MethodSpecs (the Lie-Poisson splittings of the
  torqued Earth, exact in each part, and RK4 of the orbit-averaged axis);
- :mod:`.scene`: the scenes ``lunisolar_earth`` (angular momentum, attitude and time under the
  Sun and the Moon on their Kepler orbits) and ``precessing_axis`` (the orbit-averaged figure
  axis);
- :mod:`.model`: the Earth from published moments, its spin, Euler's wobble period; the Sun's
  and the Moon's orbits, the starts and parameters of both scenes, the averaged precession
  formula;
- :mod:`.measure`: the free wobble measured (an ensemble for the period, one member's cones),
  and the precession and nutation measured from runs of both scenes;
- :mod:`.schema`: the declarations of the Datasets;
- :mod:`.studies`: the study kinds ``earth_wobble`` and ``equinoxes``;
- :mod:`.figures`: their figures, drawn from the Datasets.

It builds on the free body, as the design allows a family to build on another: the wobble is a
free rigid body's, run by its ensembles (:mod:`stability.free_body.spin_ensembles`, with what they keep,
:mod:`stability.free_body.keep`, their memory bound, :mod:`stability.free_body.ensemble_plan`, and the
methods that carry the attitude, :mod:`stability.free_body.attitude`) and its integration
(:mod:`stability.free_body.integrate`), measured by the estimators (:mod:`stability.analysis`),
with Euler's period from :mod:`stability.free_body.model`. Besides, it uses the shared layers:
:mod:`stability.core` (the rigid body, vectorizable trigonometry), :mod:`stability.util`
(conventions, threads), :mod:`stability.integrators` (the composition coefficients, rotations,
MethodSpec), :mod:`stability.engine.scene` (the scene contract), the scene-generic ensembles
(:mod:`stability.ensemble.chunks`), the Dataset register (:mod:`stability.ensemble.schema`),
:mod:`stability.study` (the study framework) and :mod:`stability.plotting`.

This package's ``__init__`` imports nothing of the family, so that the scene registry
(:mod:`stability.registry`) can import :mod:`.scene` without the rest.
"""

#: What the family registers (:mod:`stability.registry`): its scenes, its study kinds and the
#: declarations of the Datasets they write, each as ``"module:name"`` inside this package.
SCENES = ("scene:LUNISOLAR_EARTH", "scene:PRECESSING_AXIS")
STUDIES = {"earth_wobble": "studies.earth_wobble:STUDY", "equinoxes": "studies.equinoxes:STUDY"}
DATASETS = ("schema:EARTH_WOBBLE", "schema:EQUINOXES")
