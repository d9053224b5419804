"""The heavy top: a rigid body on a fixed pivot in uniform gravity, from the sleeping top to the
gyroscope.

The family's modules, each importing only downward:

- :mod:`.methods`: the step kernels and their MethodSpecs (RK4 and the Lie-Poisson splittings,
  exact in each part, which keep the Casimirs |g| and g . m to round-off);
- :mod:`.scene`: the scene ``heavy_top`` (the state (m, g), what the loop tracks, the
  invariants, the exact solution of a symmetric top);
- :mod:`.model`: :class:`~.model.HeavyTop` (a top from what one measures), the linear theory of
  the sleeping top, the fast-top (gyroscopic) formulas, tilted starts;
- :mod:`.exact`: the exact motion of the symmetric (Lagrange) top, in elliptic functions;
- :mod:`.measure`: what the studies measure from ensemble runs (the sleeping top's tilt growth,
  released gyroscopes' precession and nutation);
- :mod:`.studies`: the study kinds ``gyroscope`` and ``sleeping_top``;
- :mod:`.figures`: their figures, drawn from the Datasets.

It builds on the shared layers: :mod:`stability.core` (the rigid body, elliptic functions),
:mod:`stability.util` (conventions, input checks, threads), :mod:`stability.integrators` (the
composition coefficients, rotations, the Euler right-hand side, MethodSpec),
:mod:`stability.engine.scene` (the scene contract), the scene-generic ensembles
(:mod:`stability.ensemble.chunks`), the estimators and periodic-signal measures
(:mod:`stability.analysis`, :mod:`stability.analysis.periodic`), the Dataset register
(:mod:`stability.ensemble.schema`), :mod:`stability.study` (the study framework) and
:mod:`stability.plotting`.

This package's ``__init__`` imports nothing, so that the scene registry
(:mod:`stability.registry`) can import :mod:`.scene` without the rest.
"""

#: What the family registers (:mod:`stability.registry`): its scenes, its study kinds and the
#: declarations of the Datasets they write, each as ``"module:name"`` inside this package.
SCENES = ("scene:HEAVY_TOP",)
STUDIES = {"gyroscope": "studies.gyroscope:STUDY", "sleeping_top": "studies.sleeping_top:STUDY"}
DATASETS = ("schema:GYROSCOPE", "schema:SLEEPING_TOP")
